# SPDX-License-Identifier: GPL-3.0-or-later
"""``phong compare FILE.blend`` on the .blend files artists have: several scenes (each one
compared, not only the window's), a scene without a camera (framed), Cycles with Open
Shading Language (rendered with SVM for the comparison), a camera that sees nothing (fails,
saying why).  The files are built here with bpy, saved, and given to the command."""

import hashlib
import json
import os

import pytest

import blender_env as be
from test_cli import run_cli


def _phong_scene(bpy, name, camera=True, look_at=(0.0, 0.0, 0.0)):
    """A scene *name*: a sphere whose Principled material became a Phong material (Apply
    Phong Material, the scene shown in the window meanwhile), a point light, a camera
    looking at *look_at* unless not *camera*."""
    scene = bpy.data.scenes.new(name)
    scene.render.resolution_x, scene.render.resolution_y = 48, 32
    world = bpy.data.worlds.new(name)
    be.compat().black_world(world)
    scene.world = world
    world.phong.ambient_intensity = 0.1
    material = bpy.data.materials.new(f"{name} paint")
    be.compat().new_material_tree(material)
    ball = be.add_uv_sphere(scene, f"{name} ball", (0.0, 0.0, 0.0), 1.0, material,
                            segments=24, rings=12)
    lamp = bpy.data.objects.new(f"{name} lamp", bpy.data.lights.new(f"{name} lamp", "POINT"))
    lamp.data.use_shadow = False
    lamp.data.phong.intensity = 5.0
    scene.collection.objects.link(lamp)
    lamp.location = (2.0, -3.0, 3.0)
    if camera:
        be.add_persp_camera(scene, (0.0, -6.0, 1.0), look_at)
    bpy.context.window.scene = scene
    be.apply_phong(scene, [ball])
    return scene


def _save(bpy, path, window_scene):
    """Save the file with *window_scene* in the window; Blender's empty start-up scene
    goes (it has no Phong object)."""
    bpy.context.window.scene = window_scene
    for scene in list(bpy.data.scenes):
        if scene.name == "Scene":
            bpy.data.scenes.remove(scene)
    bpy.ops.wm.save_as_mainfile(filepath=str(path), copy=True)
    return hashlib.sha256(path.read_bytes()).hexdigest()


def _metrics(out, name):
    return json.loads((out / name / "metrics.json").read_text())


@pytest.mark.slow
@pytest.mark.cycles
@pytest.mark.eevee
def test_every_scene_of_a_file_is_compared_framed_and_with_svm(bpy_clean, tmp_path):
    """Two scenes: "Shown" (the window's, Cycles on OSL) and "Hidden" (no window shows it,
    so Blender keeps no depsgraph for it; no camera).  Both are compared, each with its
    verdict and notes; the file is not written."""
    bpy = bpy_clean
    shown = _phong_scene(bpy, "Shown")
    shown.render.engine = "CYCLES"
    shown.cycles.shading_system = True
    _phong_scene(bpy, "Hidden", camera=False)
    path = tmp_path / "two scenes.blend"
    digest = _save(bpy, path, shown)

    out = tmp_path / "out"
    result = run_cli(tmp_path, "compare", str(path), "--resolution", "32", "--out", str(out))
    assert result.returncode == 0, result.stdout[-3000:] + result.stderr[-3000:]
    assert "Traceback" not in result.stderr
    assert "] Shown: build" in result.stdout and "] Hidden: build" in result.stdout
    assert "every engine matches the reference; 2 scene(s)" in result.stdout
    assert "scene 'Hidden' has no camera: added one that frames its Phong objects" in \
        result.stderr
    shown_m, hidden_m = _metrics(out, "Shown"), _metrics(out, "Hidden")
    for metrics in (shown_m, hidden_m):
        assert metrics["ok"], metrics["verdict"]
        assert metrics["pairs"]["cycles-reference"]["max_abs"] <= 1e-4
        assert set(metrics["verdict"]) == {"cycles", "eevee"}
    # OSL writes no AOVs: rendered with SVM, said, and compared on the sphere's pixels
    assert shown_m["notes"] == ["Cycles rendered with SVM: the scene's Open Shading Language "
                                "writes no AOVs (its setting is put back afterwards)"]
    assert shown_m["pixels"]["compared"] > 100
    assert hidden_m["notes"] == ["framed: the scene has no camera"]
    assert hidden_m["coverage"]["pixels"] / (48 * 32) > 0.1, "the framed sphere fills it"
    assert "framed: the scene has no camera" in result.stdout
    assert "Open Shading Language" in (out / "index.html").read_text()
    assert hashlib.sha256(path.read_bytes()).hexdigest() == digest, "the file is never written"

    # the scene no window shows, alone (nothing rendered before it made its depsgraph)
    alone = tmp_path / "alone"
    result = run_cli(tmp_path, "compare", str(path), "--scenes", "Hidden", "--engines",
                     "cycles", "--resolution", "24", "--out", str(alone))
    assert result.returncode == 0, result.stdout[-3000:] + result.stderr[-3000:]
    assert _metrics(alone, "Hidden")["ok"] and not (alone / "Shown").exists()


@pytest.mark.slow
@pytest.mark.cycles
def test_a_scene_whose_camera_sees_nothing_fails_beside_one_that_passes(bpy_clean, tmp_path):
    """A file with a good scene, one whose camera looks away from its sphere, one whose
    camera object is not set as its camera, and one of Per Vertex materials: the first three
    get their own verdicts, the run exits 1 saying which scene sees nothing; the last is
    left out, saying why."""
    bpy = bpy_clean
    good = _phong_scene(bpy, "Good")
    _phong_scene(bpy, "Away", look_at=(0.0, -12.0, 1.0))
    _phong_scene(bpy, "Gouraud")
    bpy.data.materials["Phong Gouraud paint"].phong.shading = "VERTEX"
    _phong_scene(bpy, "Unset").camera = None   # a camera object, not the scene's camera
    path = tmp_path / "away.blend"
    _save(bpy, path, good)
    out = tmp_path / "out"
    result = run_cli(tmp_path, "compare", str(path), "--engines", "cycles", "--resolution", "24",
                     "--out", str(out))
    assert result.returncode == 1, result.stdout[-3000:] + result.stderr[-3000:]
    assert "Traceback" not in result.stderr
    # a scene of Per Vertex materials only is left out, saying why
    assert "away.blend: left out: scene 'Gouraud': its Phong materials shade Per Vertex or " \
        "Per Face" in result.stderr and not (out / "Gouraud").exists()
    assert "3 scene(s) of 3" in result.stdout
    assert "FAIL: the camera sees 0 of" in result.stdout
    assert "NOTHING TO COMPARE (Away: the camera sees no Phong surface)" in result.stdout
    assert _metrics(out, "Good")["ok"]
    away = _metrics(out, "Away")
    assert not away["ok"] and not away["coverage"]["ok"]
    # its own camera object, where the scene sets none
    assert "scene 'Unset' has no scene camera: used its camera object 'Unset pcam'" in \
        result.stderr
    unset = _metrics(out, "Unset")
    assert unset["ok"] and unset["notes"] == ["camera: the scene sets none; its camera object "
                                              "'Unset pcam'"]


@pytest.mark.slow
@pytest.mark.cycles
def test_a_scene_linked_from_a_library_is_left_out_saying_why(bpy_clean, tmp_path):
    """A file whose second scene is linked from another .blend: its own scene is compared,
    the linked one (whose settings cannot be changed here) left out with a line."""
    bpy = bpy_clean
    library = tmp_path / "library.blend"
    _save(bpy, library, _phong_scene(bpy, "Shared"))
    be.reset_empty_file()
    local = _phong_scene(bpy, "Local")
    with bpy.data.libraries.load(str(library), link=True) as (_source, target):
        target.scenes = ["Shared"]
    path = tmp_path / "with link.blend"
    _save(bpy, path, local)
    out = tmp_path / "out"
    result = run_cli(tmp_path, "compare", str(path), "--engines", "cycles", "--resolution", "24",
                     "--out", str(out))
    assert result.returncode == 0, result.stdout[-3000:] + result.stderr[-3000:]
    assert "Traceback" not in result.stderr
    assert "left out: scene 'Shared' is linked from the library" in result.stderr
    assert _metrics(out, "Local")["ok"] and not (out / "Shared").exists()


@pytest.mark.cycles
def test_osl_is_put_back_after_the_comparison(bpy_clean, tmp_path):
    """In Blender (Compare Phong Scene's engine): the scene's Open Shading Language is off for
    the comparison's renders only, and said."""
    bpy = bpy_clean
    from phong_nodes.addon.comparison import engine  # noqa: PLC0415
    scene = _phong_scene(bpy, "Osl")
    scene.render.engine = "CYCLES"
    scene.cycles.shading_system = True
    metrics = engine.run(scene, str(tmp_path / "osl"), engines=("cycles",), resolution=16)
    assert metrics["ok"] and metrics["pixels"]["compared"] > 20
    assert any("Open Shading Language" in note for note in metrics["notes"])
    assert scene.cycles.shading_system is True and scene.render.engine == "CYCLES"
