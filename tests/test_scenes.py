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


# -- the lighting models of the table -------------------------------------------------

def _scene_in(model: str, light: str = "", material: str = "") -> dict:
    text = f"""
title = "t"
model = "{model}"
[camera]
location = [0, -5, 0]
[[lights]]
name = "p"
type = "point"
position = [1, -2, 3]
{light}
[[lights]]
name = "s"
type = "spot"
position = [0, 0, 3]
direction = [0, 0, -1]
[[lights]]
name = "d"
type = "directional"
direction = [0, 1, -1]
[[objects]]
name = "ball"
material = {{ {material} }}
"""
    import tomllib
    return scenes.parse(tomllib.loads(text), "m.toml")


def test_scene_files_read_every_model_of_the_lighting_models_table():
    """A model added to node_groups/models.py is a scene file's model too, with its readers:
    no second list of models here."""
    from phong_nodes.node_groups import models

    assert scenes.MODELS == models.NAMES
    assert set(scenes.LIGHT_READERS) == set(scenes.MATERIAL_READERS) == set(models.NAMES)
    for name in models.NAMES:
        data = _scene_in(name)
        assert data["model"] == name
        assert [light["type"] for light in data["lights"]] == ["point", "spot", "directional"]
        assert len(data["objects"][0]["material"]["ambient_color"]) == 3
    with pytest.raises(scenes.SceneError, match="model: expected one of 'seeds', 'threejs', "
                                                "'x3d', got 'gltf'"):
        _scene_in("gltf")


def test_x3d_scene_files_take_x3ds_fields_and_defaults():
    """X3D's defaults (ISO/IEC 19775-1 §17.4: attenuation 1 0 0, radius 100, beamWidth π/4,
    cutOffAngle π/2; Material: diffuseColor 0.8, ambientIntensity 0.2, shininess 0.2)."""
    import math

    data = _scene_in("x3d")
    point, spot, sun = data["lights"]
    assert (point["constant"], point["linear"], point["quadratic"]) == (1.0, 0.0, 0.0)
    assert point["radius"] == 100.0 and point["ambient"] == sun["ambient"] == 0.0
    assert spot["half_angle"] == 90.0 and spot["beam_width"] == pytest.approx(math.pi / 4, 1e-4)
    assert "edge_exponent" not in spot and "diffuse" not in sun
    material = data["objects"][0]["material"]
    assert material["color"] == [0.8, 0.8, 0.8] and material["ambient_intensity"] == 0.2
    assert material["ambient_color"] == pytest.approx([0.16, 0.16, 0.16])
    assert material["specular_color"] == [0.0, 0.0, 0.0]
    assert material["exponent"] == pytest.approx(25.6) and material["blinn"] == 1.0

    data = _scene_in("x3d", "ambient = 0.25\nconstant = 0\nquadratic = 0.5\nradius = 4",
                     "color = [0.5, 0.2, 0.1], ambient_intensity = 0.5, exponent = 128")
    point = data["lights"][0]
    assert (point["ambient"], point["constant"], point["quadratic"], point["radius"]) == (
        0.25, 0.0, 0.5, 4.0)
    material = data["objects"][0]["material"]
    assert material["ambient_color"] == pytest.approx([0.25, 0.1, 0.05])
    # the other models' ambient light sees the object colour itself
    assert _scene_in("seeds", material="color = [0.5, 0.2, 0.1]")["objects"][0]["material"][
        "ambient_color"] == [0.5, 0.2, 0.1]


@pytest.mark.parametrize("light, material, message", [
    ("edge_exponent = 2", "", "lights[0].edge_exponent: unknown key; expected one of ambient, "
                              "color, constant, intensity, linear, name, position, quadratic, "
                              "radius, shadows, type"),
    ("diffuse = 0.5", "", "lights[0].diffuse: unknown key; expected one of ambient, "),
    ("ambient = 1.5", "", "lights[0].ambient: expected a number <= 1, got 1.5"),
    ("radius = 0", "", "lights[0].radius: expected a number > 0, got 0.0"),
    ("", "blinn = 1", "objects[0].material.blinn: unknown key; expected one of "
                      "ambient_intensity, color, exponent, irradiant, shading, specular_color, "
                      "texture"),
    ("", "ambient_intensity = -0.1", "objects[0].material.ambient_intensity: expected a number "
                                     ">= 0 and <= 1, got -0.1"),
    ("", "exponent = 200", "objects[0].material.exponent: expected a number <= 128, got 200.0"),
])
def test_x3d_scene_files_refuse_other_models_fields_and_out_of_range_values(light, material,
                                                                            message):
    with pytest.raises(scenes.SceneError) as caught:
        _scene_in("x3d", light, material)
    assert str(caught.value).startswith(f"m.toml: {message}"), str(caught.value)
    if light.startswith("diffuse"):  # the seeds' light field, not X3D's
        assert _scene_in("seeds", light)["lights"][0]["diffuse"] == 0.5
