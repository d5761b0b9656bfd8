# SPDX-License-Identifier: GPL-3.0-or-later
"""Scene files (scenes/*.toml): every shipped scene validates; broken files fail clearly.

Pure python (core/scenes.py, no bpy), so these run in milliseconds.
"""

import os

import pytest

from phong_nodes.core import scenes

GOOD = """
title = "t"
[camera]
location = [0, -5, 0]
[[lights]]
name = "key"
type = "point"
position = [1, -2, 3]
[[objects]]
name = "ball"
material = { exponent = 10 }
"""

#: (replace this, by this, expected fragment of the message)
BROKEN = {
    "missing_key": ('title = "t"\n', "", "title: expected a string (missing)"),
    "missing_camera_location": ("location = [0, -5, 0]", "lens = 35",
                                "camera.location: expected a list of 3 numbers"),
    "wrong_type": ("position = [1, -2, 3]", 'position = "up"',
                   "lights[0].position: expected a list of 3 numbers [x, y, z], got 'up'"),
    "wrong_type_number": ("exponent = 10", 'exponent = "high"',
                          "objects[0].material.exponent: expected a finite number, got 'high'"),
    "negative_exponent": ("exponent = 10", "exponent = -3",
                          "objects[0].material.exponent: expected a number >= 0, got -3.0"),
    "unknown_light_type": ('type = "point"', 'type = "area"',
                           "lights[0].type: expected one of 'point', 'directional', 'spot', "
                           "got 'area'"),
    "unknown_key": ('name = "ball"', 'name = "ball"\ncolour = "#FF0000"',
                    "objects[0].colour: unknown key"),
    "unknown_light_name": ('name = "ball"', 'name = "ball"\nlights = ["sun"]',
                           "objects[0].lights[0]: expected one of 'key', got 'sun'"),
    "bad_colour": ("exponent = 10", 'exponent = 10, color = "#12345"',
                   'objects[0].material.color: expected a colour "#RRGGBB"'),
    "not_toml": ("[camera]", "[camera", "not valid TOML"),
    "falloff_exponent_too_large": ("position = [1, -2, 3]",
                                   "position = [1, -2, 3]\nfalloff_exponent = 17",
                                   "lights[0].falloff_exponent: expected a number <= 16"),
    "falloff_exponent_and_quadratic": ("position = [1, -2, 3]",
                                       "position = [1, -2, 3]\nfalloff_exponent = 1\n"
                                       "quadratic = 2",
                                       "lights[0].falloff_exponent: expected either "
                                       "falloff_exponent or quadratic"),
}


def test_every_shipped_scene_validates():
    names = scenes.available()
    required = {"four_terms", "exponents", "spot_edges", "point_falloff", "lambert_vs_phong",
                "color_product", "two_lights", "textured"}
    assert required <= set(names)
    for path in scenes.resolve(None):
        scene = scenes.load(path)
        assert scene["objects"] and scene["title"]
        assert scene["name"] == os.path.basename(path)[:-5]


def test_seed_figures_are_in_the_scenes():
    exps = scenes.load(os.path.join(scenes.SCENES_DIR, "exponents.toml"))
    pairs = {(o["material"]["exponent"], o["material"]["blinn"]) for o in exps["objects"]}
    assert pairs == {(e, b) for e in (2, 5, 10, 100) for b in (0, 1)}
    spots = scenes.load(os.path.join(scenes.SCENES_DIR, "spot_edges.toml"))
    assert sorted(l["edge_exponent"] for l in spots["lights"]) == [0, 1, 5, 20]
    fall = scenes.load(os.path.join(scenes.SCENES_DIR, "point_falloff.toml"))
    assert sorted(l.get("falloff_exponent", -1) for l in fall["lights"]) == [-1, 0, 1, 2]
    # i0/d^k is the light's γ (k = 0), β (k = 1) or α (k = 2) = 1
    by_k = {l.get("falloff_exponent"): (l["quadratic"], l["linear"], l["constant"])
            for l in fall["lights"]}
    assert by_k[0] == (0, 0, 1) and by_k[1] == (0, 1, 0) and by_k[2] == (1, 0, 0)
    two = scenes.load(os.path.join(scenes.SCENES_DIR, "two_lights.toml"))
    green = next(l for l in two["lights"] if l["type"] == "point")
    assert green["position"] == [2, -5, 1.5]  # three.js (2, 1.5, 5), Y-up -> Z-up
    assert green["color"] == pytest.approx(scenes.hex_to_linear("#66DD66"))
    product = scenes.load(os.path.join(scenes.SCENES_DIR, "color_product.toml"))
    assert product["lights"][0]["color"] == [1, 0, 1]
    textured = scenes.load(os.path.join(scenes.SCENES_DIR, "textured.toml"))
    assert all(o["material"]["texture"] for o in textured["objects"])


def test_good_file_gets_defaults(tmp_path):
    path = tmp_path / "good.toml"
    path.write_text(GOOD)
    scene = scenes.load(str(path))
    assert scene["name"] == "good"
    assert scene["camera"]["type"] == "perspective"
    assert scene["ambient"]["intensity"] == 0.0
    assert scene["lights"][0]["quadratic"] == 1.0
    assert scene["objects"][0]["terms"] == list(scenes.TERMS)
    assert scene["objects"][0]["lights"] == ["key"]
    assert scene["objects"][0]["material"]["exponent"] == 10.0


@pytest.mark.parametrize("case", sorted(BROKEN))
def test_broken_file_names_file_key_and_expectation(tmp_path, case):
    old, new, message = BROKEN[case]
    assert old in GOOD
    path = tmp_path / f"{case}.toml"
    path.write_text(GOOD.replace(old, new, 1))
    with pytest.raises(scenes.SceneError) as info:
        scenes.load(str(path))
    text = str(info.value)
    assert text.startswith(str(path) + ": "), text
    assert message in text, text


def test_resolve_and_shard():
    everything = scenes.resolve(None)
    assert len(everything) == len(scenes.available())
    with pytest.raises(scenes.SceneError, match="unknown scene 'nope'"):
        scenes.resolve("nope")
    items = list(range(7))
    parts = [scenes.shard(items, f"{i}/3") for i in (1, 2, 3)]
    assert sorted(sum(parts, [])) == items
    for bad in ("0/3", "4/3", "x", "1/0"):
        with pytest.raises(scenes.SceneError, match="--shard"):
            scenes.shard(items, bad)


def test_duplicate_scene_names_refused(tmp_path):
    (tmp_path / "a").mkdir()
    (tmp_path / "b").mkdir()
    for sub in "ab":
        (tmp_path / sub / "same.toml").write_text(GOOD)
    with pytest.raises(scenes.SceneError, match="also used by"):
        scenes.load_all([str(tmp_path / "a" / "same.toml"), str(tmp_path / "b" / "same.toml")])


def test_a_falloff_exponent_other_than_0_1_2_is_the_power_falloff(tmp_path):
    """k = 0, 1, 2 stay the light's γ, β or α = 1; any other k (up to 16) is the light's power
    falloff i0/d^k (phong_falloff POWER, phong_power_k)."""
    for k, expected in ((1, {"linear": 1.0}), (1.5, {"falloff": "POWER", "power_k": 1.5}),
                        (3, {"falloff": "POWER", "power_k": 3.0})):
        path = tmp_path / f"k{int(k * 10)}.toml"
        path.write_text(GOOD.replace("position = [1, -2, 3]",
                                     f"position = [1, -2, 3]\nfalloff_exponent = {k}"))
        (light,) = scenes.load(str(path))["lights"]
        assert light["falloff_exponent"] == k
        for key, value in expected.items():
            assert light[key] == value, (k, key)
        assert ("falloff" in light) == (k not in (0, 1, 2))
