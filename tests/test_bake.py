# SPDX-License-Identifier: GPL-3.0-or-later
"""build_demo_scene and bake_comparison, on the enabled extension."""

import json
import os

import pytest



def test_every_scene_builds_into_a_new_scene(bpy_clean):
    bpy = bpy_clean
    from phong_nodes.core import scenes  # noqa: PLC0415
    mine = bpy.data.scenes[0]
    mine_objects = len(mine.objects)
    names = scenes.available()
    assert len(names) >= 8
    for name in names:
        before = set(bpy.data.scenes)
        assert bpy.ops.phong.build_demo_scene(name=name, resolution=16) == {"FINISHED"}
        (scene,) = set(bpy.data.scenes) - before
        data = scenes.load(os.path.join(scenes.SCENES_DIR, f"{name}.toml"))
        meshes = [o for o in scene.objects if o.type == "MESH"]
        lights = [o for o in scene.objects if o.type == "LIGHT"]
        assert sorted(o.name.split(".")[0] for o in meshes) == sorted(
            o["name"] for o in data["objects"]), name
        assert len(lights) == len(data["lights"]), name
        materials = {o.active_material for o in meshes}
        assert len(materials) == 1, f"{name}: one shared material per scene"
        assert scene.camera is not None
        assert scene.render.resolution_y == 16
        assert scene.render.resolution_x == max(1, round(16 * data["aspect"]))
    assert len(mine.objects) == mine_objects, "the user's scene is untouched"


@pytest.mark.slow
@pytest.mark.cycles
@pytest.mark.eevee
def test_bake_comparison_writes_a_complete_folder(bpy_clean, tmp_path):
    bpy = bpy_clean
    bpy.ops.phong.build_demo_scene(name="spot_edges", resolution=24)
    scene = next(s for s in bpy.data.scenes if s.name.startswith("Phong spot_edges"))
    with bpy.context.temp_override(scene=scene):
        assert bpy.ops.phong.bake_comparison(directory=str(tmp_path)) == {"FINISHED"}
    folder = tmp_path / "spot_edges"
    files = set(os.listdir(folder))
    for name in ("eevee.png", "cycles.png", "reference.png", "sheet.png", "metrics.json",
                 "diff_eevee_reference.png", "diff_cycles_reference.png",
                 "diff_eevee_cycles.png", "term_irradiant.png", "term_ambient.png",
                 "term_diffuse.png", "term_specular.png", "plot_spot_edge.svg",
                 "plot_falloff.svg"):
        assert name in files, name
    assert not [f for f in os.listdir(tmp_path) if f.startswith(".")], "no temp folder left"
    metrics = json.loads((folder / "metrics.json").read_text())
    assert set(metrics["pairs"]) == {"eevee-reference", "cycles-reference", "eevee-cycles"}
    for pair in metrics["pairs"].values():
        assert {"max_abs", "mean_abs", "psnr_db", "share_over_1_255"} <= set(pair)
    assert metrics["pairs"]["cycles-reference"]["max_abs"] <= 1e-4
    assert metrics["verdict"]["cycles"]["ok"]
    assert metrics["pixels"]["compared"] > 0.5 * metrics["pixels"]["total"]
    assert metrics["parameters"]["lights"][3]["edge_exponent"] == 20


@pytest.mark.cycles
def test_interrupted_bake_leaves_nothing(bpy_clean, tmp_path, monkeypatch):
    bpy = bpy_clean
    from phong_nodes.addon.demos import bake, builder  # noqa: PLC0415  (needs bpy)
    from phong_nodes.core import report, scenes  # noqa: PLC0415
    data = scenes.load(os.path.join(scenes.SCENES_DIR, "lambert_vs_phong.toml"))
    scene = builder.build(data, 12)

    def boom(*_args, **_kwargs):
        raise KeyboardInterrupt

    monkeypatch.setattr(report, "write_scene", boom)
    (tmp_path / "lambert_vs_phong").mkdir()
    (tmp_path / "lambert_vs_phong" / "metrics.json").write_text("{}")  # an older bake
    with pytest.raises(KeyboardInterrupt):
        bake.bake(scene, str(tmp_path / "lambert_vs_phong"), engines=("cycles",))
    assert sorted(os.listdir(tmp_path)) == ["lambert_vs_phong"]
    assert os.listdir(tmp_path / "lambert_vs_phong") == ["metrics.json"], "old bake kept whole"
    bpy.data.scenes.remove(scene)


def test_bake_refuses_a_scene_that_is_not_a_demo(bpy_clean):
    bpy = bpy_clean
    assert not bpy.ops.phong.bake_comparison.poll()
