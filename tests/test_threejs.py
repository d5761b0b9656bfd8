# SPDX-License-Identifier: GPL-3.0-or-later
"""The three.js model in Blender (model switch, scene files, lights groups) and three.js as a
peer of the comparison: the exported page in headless Chromium against Cycles.

The browser tests skip on a machine without Chromium or three.js, except under CI (``CI``
set), where they fail with what to install: CI must really run them."""

import json
import os
import subprocess
import sys

import numpy as np
import pytest

import blender_env as be
from phong_nodes.core import browser, compare, scenes, threejs

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
#: The `phong` command of this environment (what tools/phong.sh runs).
CLI = [sys.executable, "-m", "phong_nodes.cli"]
#: The seeds' three labs and the two scenes of three.js's light settings.
THREEJS_SCENES = ("threejs_lab05", "threejs_lab06", "threejs_phong_lab",
                  "threejs_spot_penumbra", "threejs_point_cutoff")


def need_browser():
    problem = threejs.unavailable()
    if problem is not None:
        if os.environ.get("CI"):
            pytest.fail(problem)
        pytest.skip(problem)


def run_cli(tmp_path, *args, env=None):
    env = dict(os.environ, BLENDER_USER_RESOURCES=str(tmp_path / "user"), **(env or {}))
    return subprocess.run([*CLI, *args], capture_output=True, text=True,
                          env=env, timeout=600)


# -- scene files ------------------------------------------------------------------------

def test_shipped_threejs_scenes_use_three_js_settings_and_defaults():
    for name in THREEJS_SCENES:
        data = scenes.load(os.path.join(scenes.SCENES_DIR, f"{name}.toml"))
        assert data["model"] == "threejs"
    lab05 = scenes.load(os.path.join(scenes.SCENES_DIR, "threejs_lab05.toml"))
    assert lab05["objects"][0]["material"]["type"] == "lambert"
    # 0xFF8855 decoded from sRGB, as three.js's Color.set does
    np.testing.assert_allclose(lab05["objects"][0]["material"]["color"],
                               [1.0, ((0x88 / 255 + 0.055) / 1.055) ** 2.4,
                                ((0x55 / 255 + 0.055) / 1.055) ** 2.4])
    lab06 = scenes.load(os.path.join(scenes.SCENES_DIR, "threejs_lab06.toml"))
    green = lab06["lights"][1]
    assert (green["intensity"], green["distance"], green["decay"]) == (1.0, 0.0, 2.0)
    phong = scenes.load(os.path.join(scenes.SCENES_DIR, "threejs_phong_lab.toml"))
    mat = phong["objects"][0]["material"]
    assert mat["type"] == "phong" and mat["exponent"] == 100.0


def test_threejs_defaults_of_a_minimal_file():
    data = scenes.parse({"title": "t", "model": "threejs", "camera": {"location": [0, -5, 0]},
                         "lights": [{"type": "spot", "position": [0, 0, 2],
                                     "direction": [0, 0, -1]}],
                         "objects": [{"name": "a"}]})
    spot, mat = data["lights"][0], data["objects"][0]["material"]
    assert (spot["half_angle"], spot["penumbra"], spot["decay"], spot["distance"]) == \
        (60.0, 0.0, 2.0, 0.0)  # three.js SpotLight: angle π/3, penumbra 0, decay 2
    assert mat["type"] == "phong" and mat["color"] == [1.0, 1.0, 1.0] and mat["exponent"] == 30
    np.testing.assert_allclose(mat["specular_color"], [((17 / 255 + 0.055) / 1.055) ** 2.4] * 3)


@pytest.mark.parametrize("patch, message", [
    ({"model": "three"}, "model: expected one of 'seeds', 'threejs', 'x3d', got 'three'"),
    ({"model": "threejs", "lights": [{"type": "point", "position": [0, 0, 1], "quadratic": 1}]},
     "lights[0].quadratic: unknown key"),
    ({"model": "threejs", "lights": [{"type": "spot", "position": [0, 0, 1],
                                      "direction": [0, 0, -1], "penumbra": 1.5}]},
     "lights[0].penumbra: expected a number"),
    ({"model": "threejs", "objects": [{"name": "a", "material": {"blinn": 1}}]},
     "objects[0].material.blinn: unknown key"),
    ({"objects": [{"name": "a", "material": {"type": "lambert"}}]},
     "objects[0].material.type: unknown key"),
])
def test_bad_model_keys_name_file_and_key(patch, message):
    raw = {"title": "t", "camera": {"location": [0, -5, 0]}, "objects": [{"name": "a"}], **patch}
    with pytest.raises(scenes.SceneError) as error:
        scenes.parse(raw, "f.toml")
    assert str(error.value).startswith("f.toml: ") and message in str(error.value)


def test_wrong_model_in_a_scene_file_exits_2_naming_file_and_key(tmp_path):
    bad = tmp_path / "bad.toml"
    bad.write_text('title = "t"\nmodel = "webgl"\n[camera]\nlocation = [0, -5, 0]\n'
                   '[[objects]]\nname = "a"\n')
    out = tmp_path / "out"
    result = run_cli(tmp_path, "demo", "--scenes", str(bad), "--out", str(out))
    assert result.returncode == 2
    assert f"{bad}: model: expected one of 'seeds', 'threejs', 'x3d', got 'webgl'" in result.stderr
    assert not out.exists()


def test_peers_threejs_without_a_browser_exits_2_naming_what_to_install(tmp_path):
    out = tmp_path / "out"
    result = run_cli(tmp_path, "demo", "--scenes", "threejs_lab05", "--peers", "threejs", "--out",
                     str(out), env={"PHONG_CHROMIUM": str(tmp_path / "no-such-browser")})
    assert result.returncode == 2, result.stderr
    line = result.stderr.strip()
    assert len(line.splitlines()) == 1 and "apt-get install -y chromium" in line
    assert not out.exists()


# -- the model switch in Blender --------------------------------------------------------

def _one_sphere_scene(bpy):
    scene = be.new_scene("Switch", 32, 32, "cycles")
    sphere = be.add_uv_sphere(scene, "ball", (0.0, 0.0, 0.0), 1.0, None)
    light = bpy.data.objects.new("lamp", bpy.data.lights.new("lamp", "SPOT"))
    light.location = (0.0, -3.0, 2.0)
    scene.collection.objects.link(light)
    bpy.context.window.scene = scene
    for obj in scene.objects:
        obj.select_set(obj is sphere)
    bpy.context.view_layer.objects.active = sphere
    return scene, sphere, light


def _group_types(material):
    tree = material.node_tree.nodes["phong_lights"].node_tree
    return tree, sorted(n.node_tree.name for n in tree.nodes if n.bl_idname == "ShaderNodeGroup")


def test_apply_with_the_threejs_model_and_switching_back(bpy_clean):
    bpy = bpy_clean
    scene, sphere, light = _one_sphere_scene(bpy)
    bpy.ops.phong.apply_material(model="THREEJS")
    assert scene["phong_model"] == "threejs" and scene.phong.model == "threejs"
    material = sphere.material_slots[0].material
    tree, types = _group_types(material)
    assert tree.name == "three.js Lights Switch"
    shadowed = be.compat().HAS_RAYCAST
    plain = ["three.js Rig Material"] if shadowed else []  # the sums without shadows: Eevee's
    # before 5.3 (no Switch) the group of a spot whose constants are three.js's defaults
    switched = "switch" in be.compat().NODE_FEATURES
    facts = "" if switched else " [no cut-off, decay 2, hard edge]"
    assert types == sorted(["Phong Surface", "Phong Surface Rays", "three.js Ambient",
                            "three.js Rig Material"] + plain + [
        "three.js Rig Spot" + (" with Shadow" if shadowed else "") + facts])
    assert material.node_tree.nodes["phong_specular_strength"].outputs[0].default_value == 1.0
    out = next(n for n in tree.nodes if n.bl_idname == "NodeGroupOutput")
    for name in ("Color", "Irradiant", "Ambient", "Diffuse", "Specular", "Shader"):
        assert out.inputs[name].is_linked, f"the lights group's {name} output is fed"
    assert out.inputs["Color"].links[0].from_node.name == "color"  # min(…, 1), once
    # the light's three.js settings drive the group
    light.data.phong.penumbra = 0.4
    light.data.phong.decay = 1.0
    bpy.context.view_layer.update()
    tree, types = _group_types(material)
    assert ("three.js Rig Spot" + (" with Shadow" if shadowed else "") + (
        "" if switched else " [no cut-off, any decay, penumbra]")) in types
    spot = next(n for n in tree.nodes if n.name == "light:lamp")
    assert spot.inputs["Penumbra"].default_value == pytest.approx(0.4)
    assert spot.inputs["Decay"].default_value == pytest.approx(1.0)
    assert spot.inputs["Angle"].default_value == pytest.approx(light.data.spot_size / 2)
    # Apply without a model keeps the scene's; the scene setting switches back
    bpy.ops.phong.apply_material()
    assert scene["phong_model"] == "threejs"
    scene.phong.model = "seeds"
    tree, types = _group_types(material)
    assert tree.name == "Phong Lights Switch"
    assert any(t.startswith("Phong Rig Spot") for t in types)
    assert not any(t.startswith("three.js") for t in types)
    assert sphere.material_slots[0].material is material, "the material itself is kept"


@pytest.mark.cycles
def test_a_lights_constants_change_its_nodes_and_the_picture_follows(bpy_clean, tmp_path):
    """Before 5.3 a three.js light's group is the one of its constants (a cut-off distance or
    none, decay 2 or another, a penumbra or a hard edge: ``library.LIGHT_FACTS``), and a
    change of them relinks the scene; on 5.3 a Switch inside the one group chooses.  Either
    way Cycles renders the reference after each change."""
    from phong_nodes.addon.comparison import engine

    bpy = bpy_clean
    scene, sphere, light = _one_sphere_scene(bpy)
    be.add_ortho_camera(scene, (0.0, 0.0), 2.4, 2.4)
    light.location = (0.0, -1.0, 3.0)  # pointing down: its cone's edge across the ball
    light.data.spot_size = 1.2
    bpy.ops.phong.apply_material(model="THREEJS")
    material = sphere.material_slots[0].material
    switched = "switch" in be.compat().NODE_FEATURES
    for step, (settings, words) in enumerate((
            ({}, "no cut-off, decay 2, hard edge"),
            ({"penumbra": 0.5, "decay": 1.5}, "no cut-off, any decay, penumbra"),
            ({"distance": 4.0, "decay": 2.0}, "cut-off, decay 2, penumbra"),
            ({"penumbra": 0.0, "distance": 0.0}, "no cut-off, decay 2, hard edge"))):
        for name, value in settings.items():
            setattr(light.data.phong, name, value)
        bpy.context.view_layer.update()
        _tree, types = _group_types(material)
        spot = next(t for t in types if t.startswith("three.js Rig Spot"))
        assert spot.endswith("" if switched else f" [{words}]"), spot
        metrics = engine.run(scene, str(tmp_path / f"step{step}"), engines=("cycles",))
        pair = metrics["pairs"]["cycles-reference"]
        assert pair["pixels"] > 100 and pair["max_abs"] <= 1e-4, (words, pair)
    be.report(f"[light facts] {bpy.app.version_string}: 4 steps, Cycles = reference")


def test_a_lights_facts_are_what_its_sockets_hold(bpy_clean):
    """``properties.facts_of``: before 5.3 the facts of a three.js or X3D light as its light
    group's float32 sockets hold them, and None (the general group) where a setting they read
    is keyframed or a penumbra too small to tell; on 5.3 None always (the Switch chooses)."""
    from phong_nodes.addon.lighting import properties

    bpy = bpy_clean
    light = bpy.data.lights.new("facts", "SPOT")
    properties.ensure_light_props(light)
    if "switch" in be.compat().NODE_FEATURES:
        assert properties.facts_of(light, "threejs") is None
        pytest.skip("5.3 and later: the Switch chooses inside the one group")
    assert properties.facts_of(light, "threejs") == {"cut-off": False, "decay 2": True,
                                                     "penumbra": False}
    assert properties.facts_of(light, "seeds") is None  # no facts in the seeds' model
    light.phong.decay = 2.0000000001  # float32: 2 exactly
    light.phong.distance = 1e-30  # float32: above 0
    light.phong.penumbra = 0.3
    assert properties.facts_of(light, "threejs") == {"cut-off": True, "decay 2": True,
                                                     "penumbra": True}
    light.phong.penumbra = 1e-9  # float32: 1 - 1e-9 is 1, the two cosines equal: hard edge
    assert properties.facts_of(light, "threejs")["penumbra"] is False
    light.phong.penumbra = 1e-6  # the cone's cosines within 1e-6: the general group
    assert properties.facts_of(light, "threejs") is None
    light.phong.penumbra = 0.0
    light.spot_size = 1.0  # X3D's cut-off angle 0.5, below the default beam width 0.7854
    assert properties.facts_of(light, "x3d") == {"ramp": False, "ambient 0": True}
    light.phong.beam_width = 0.3
    light.phong.ambient = 0.2
    assert properties.facts_of(light, "x3d") == {"ramp": True, "ambient 0": False}
    light.keyframe_insert('["phong_decay"]', frame=1)  # animated: any value may come
    assert properties.facts_of(light, "threejs") is None
    assert properties.facts_of(light, "x3d") is not None  # X3D reads no decay
    sun = bpy.data.lights.new("facts sun", "SUN")
    assert properties.facts_of(sun, "threejs") is None  # a three.js sun has no facts
    area = bpy.data.lights.new("facts area", "AREA")  # a spot of 90°, X3D beam 90°: no ramp
    assert properties.facts_of(area, "x3d") == {"ramp": False, "ambient 0": True}


# -- three.js in Chromium ---------------------------------------------------------------

def test_exported_page_loads_in_chromium_without_console_errors(bpy_clean, tmp_path):
    need_browser()
    bpy = bpy_clean
    from phong_nodes.addon.demos import builder

    scene = builder.build(scenes.load(os.path.join(scenes.SCENES_DIR,
                                                   "threejs_phong_lab.toml")), 48)
    bpy.context.window.scene = scene
    page = tmp_path / "export" / "scene.html"
    page.parent.mkdir()
    assert bpy.ops.phong.export_threejs(filepath=str(page)) == {"FINISHED"}
    assert sorted(os.listdir(page.parent)) == ["scene.html", "three.LICENSE", "three.cjs"]
    data = threejs.read_scene(str(page))
    assert (data["width"], data["height"]) == (48, 48)
    assert [m["type"] for m in data["materials"]] == ["phong"]
    assert data["materials"][0]["shininess"] == pytest.approx(100.0)
    assert len(data["meshes"][0]["positions"]) == len(data["meshes"][0]["normals"])
    result = browser.render_page(str(page))
    assert result.errors == [] and result.title == "phong: done"
    assert result.rgba.shape == (48, 48, 4) and (result.rgba[..., 3] == 255).sum() > 300


def test_export_refuses_a_scene_without_phong_objects(bpy_clean, tmp_path):
    bpy = bpy_clean
    scene = be.new_scene("Empty", 16, 16, "cycles")
    be.add_ortho_camera(scene, (0.0, 0.0), 2.0, 2.0)
    bpy.context.window.scene = scene
    page = tmp_path / "page.html"
    with pytest.raises(RuntimeError, match="no object with a Phong material"):
        bpy.ops.phong.export_threejs(filepath=str(page))
    assert not page.exists() and not (tmp_path / "three.cjs").exists()


@pytest.mark.slow
@pytest.mark.cycles
@pytest.mark.parametrize("name", THREEJS_SCENES)
def test_threejs_matches_cycles_in_the_threejs_model(bpy_clean, tmp_path, name):
    """three.js r181 in Chromium against Cycles in the three.js model: ≥ 99 % of the pixels
    both cover within 2/255 (display values)."""
    need_browser()
    from phong_nodes.addon.comparison import engine
    from phong_nodes.addon.demos import builder

    scene = builder.build(scenes.load(os.path.join(scenes.SCENES_DIR, f"{name}.toml")), 96)
    metrics = engine.run(scene, str(tmp_path / name), engines=("cycles",), peers=("threejs",))
    pair = metrics["pairs"]["threejs-cycles"]
    assert pair["pixels"] > 0.1 * metrics["pixels"]["object"]
    assert pair["share_within_2_255"] >= 0.99, pair
    assert metrics["verdict"]["threejs"]["ok"] and metrics["ok"]
    assert metrics["pairs"]["cycles-reference"]["max_abs"] <= 1e-4
    saved = json.loads((tmp_path / name / "metrics.json").read_text())
    assert "threejs-reference" in saved["pairs"] and saved["threejs"]["in_verdict"]
    assert (tmp_path / name / "threejs" / "scene.html").exists()
    assert (tmp_path / name / "threejs.png").exists()


@pytest.mark.slow
@pytest.mark.cycles
def test_three_js_differs_from_the_seeds_model_and_is_not_judged_there(bpy_clean, tmp_path):
    """The comparison can fail: the same lab in the seeds' model is far from three.js."""
    need_browser()
    from phong_nodes.addon.comparison import engine
    from phong_nodes.addon.demos import builder

    data = scenes.load(os.path.join(scenes.SCENES_DIR, "threejs_phong_lab.toml"))
    data["model"] = "seeds"
    scene = builder.build(data, 64)
    metrics = engine.run(scene, str(tmp_path / "seeds"), engines=("cycles",),
                        peers=("threejs",))
    assert metrics["pairs"]["threejs-cycles"]["share_within_2_255"] < 0.5
    assert "threejs" not in metrics["verdict"] and metrics["ok"]
    assert compare.THREEJS_SHARE == 0.99
