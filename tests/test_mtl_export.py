# SPDX-License-Identifier: GPL-3.0-or-later
"""File ▸ Export ▸ Phong Materials (.mtl): each Phong material's values, read back by
core/mtl.py, are the controls' values bit for bit; textures become maps; what MTL cannot
say is said in a comment and a warning; bad input writes nothing."""

from __future__ import annotations

import os

import numpy as np
import pytest

import blender_env as be
from phong_nodes.core import mtl
from phong_scene import _light


def _f32(values):
    """As Blender stores them (and as an MTL written from them reads back, bit for bit)."""
    return tuple(float(np.float32(v)) for v in values)


def _principled(bpy, name, color, image=None, level=0.0):
    """A Principled source; *level* its Specular IOR Level (0: no specular layer, so its
    Phong version keeps the seeds' Ka = Kd, which these tests write and read)."""
    material = bpy.data.materials.new(name)
    tree = be.compat().new_material_tree(material)
    bsdf = tree.nodes["Principled BSDF"]
    bsdf.inputs["Base Color"].default_value = color
    bsdf.inputs["Specular IOR Level"].default_value = level
    if image is not None:
        tex = tree.nodes.new("ShaderNodeTexImage")
        tex.image = image
        tree.links.new(tex.outputs["Color"], bsdf.inputs["Base Color"])
    return material


def _scene(bpy, tmp_path):
    scene = be.new_scene("Export", 8, 8)
    bpy.context.window.scene = scene
    image = bpy.data.images.new("bricks", 4, 4)
    image.filepath_raw = str(tmp_path / "textures" / "bricks.png")
    os.makedirs(tmp_path / "textures")
    image.file_format = "PNG"
    image.save()
    clay = be.add_uv_sphere(scene, "Clay ball", (0, 0, 0), 0.5,
                            _principled(bpy, "Red clay", (0.7, 0.3, 0.1, 1)))
    wall = be.add_uv_sphere(scene, "Wall", (2, 0, 0), 0.5,
                            _principled(bpy, "Bricks", (0.2, 0.2, 0.2, 1), image))
    _light(bpy, scene, "Key", "POINT", (0, -3, 3))
    for obj in scene.objects:
        obj.select_set(obj.type == "MESH")
    assert bpy.ops.phong.apply_material() == {"FINISHED"}
    red, bricks = clay.active_material, wall.active_material
    nodes = red.node_tree.nodes
    nodes["phong_specular_color"].outputs[0].default_value = (0.5, 0.6, 0.7, 1)
    nodes["phong_exponent"].outputs[0].default_value = 12.5
    nodes["phong_irradiant_color"].outputs[0].default_value = (0.01, 0.02, 0.03, 1)
    nodes = bricks.node_tree.nodes
    nodes["phong_specular_color"].outputs[0].default_value = (0, 0, 0, 1)
    nodes["phong_blinn"].outputs[0].default_value = 1.0
    return red, bricks


def test_export_writes_the_controls_exactly(bpy_clean, tmp_path, capfd):
    bpy = bpy_clean
    red, _bricks = _scene(bpy, tmp_path)
    out = tmp_path / "out" / "scene.mtl"
    os.makedirs(out.parent)
    capfd.readouterr()
    assert bpy.ops.phong.export_mtl(filepath=str(out)) == {"FINISHED"}
    logged = "".join(capfd.readouterr())
    text = out.read_text()
    by_name = {m.name: m for m in mtl.load(str(out))}
    assert sorted(by_name) == ["Bricks", "Red_clay"], "the source materials' names"
    clay = by_name["Red_clay"]
    colour = tuple(red.node_tree.nodes["phong_object_color"].outputs[0].default_value)[:3]
    assert _f32(clay.colors["Kd"]) == _f32(clay.colors["Ka"]) == colour == _f32((0.7, 0.3, 0.1))
    assert _f32(clay.colors["Ks"]) == _f32((0.5, 0.6, 0.7))
    assert _f32(clay.colors["Ke"]) == _f32((0.01, 0.02, 0.03))
    assert "Kd 0.7 0.3 0.1\n" in text and "Ke 0.01 0.02 0.03\n" in text, \
        "the shortest decimals of the float32 values"
    assert clay.scalars == {"Ns": 12.5} and clay.illum == 2
    assert "# this material uses the Phong highlight (r·v)^Ns; MTL illum 2 is Blinn's" in text
    assert ("Phong Red clay: the Phong highlight (r·v)^Ns, written as MTL illum 2, which is "
            "Blinn's") in logged
    bricks = by_name["Bricks"]
    assert bricks.illum == 1 and _f32(bricks.colors["Kd"]) == (1.0, 1.0, 1.0)
    assert bricks.maps["map_Kd"].path == os.path.join("..", "textures", "bricks.png")
    assert bricks.maps["map_Kd"].exists and bricks.maps["map_Ka"].exists
    assert "Phong Bricks:" not in logged, "nothing lost for the textured Blinn material"


def test_selection_only_and_bad_input_write_nothing(bpy_clean, tmp_path):
    bpy = bpy_clean
    scene = be.new_scene("Empty", 8, 8)
    bpy.context.window.scene = scene
    out = tmp_path / "none.mtl"
    with pytest.raises(RuntimeError, match="Export Phong MTL: the file has no Phong material; "
                                           "run Apply Phong Material first"):
        bpy.ops.phong.export_mtl(filepath=str(out))
    red, _bricks = _scene(bpy, tmp_path)
    with pytest.raises(RuntimeError, match="is not a file in an existing folder"):
        bpy.ops.phong.export_mtl(filepath=str(tmp_path / "missing" / "x.mtl"))
    for obj in bpy.context.scene.objects:
        obj.select_set(False)
    with pytest.raises(RuntimeError, match="the selected objects have no Phong material"):
        bpy.ops.phong.export_mtl(filepath=str(out), selection_only=True)
    assert not out.exists() and not (tmp_path / "missing").exists()
    bpy.data.objects["Clay ball"].select_set(True)
    assert bpy.ops.phong.export_mtl(filepath=str(out), selection_only=True) == {"FINISHED"}
    assert [m.name for m in mtl.load(str(out))] == ["Red_clay"]
    assert not [n for n in os.listdir(tmp_path) if n.endswith(".partial")]


def test_own_ambient_object_color_is_written_as_ka(bpy_clean, tmp_path):
    bpy = bpy_clean
    red, _bricks = _scene(bpy, tmp_path)
    tree = red.node_tree
    ka = tree.nodes.new("ShaderNodeRGB")
    ka.outputs[0].default_value = (0.05, 0.1, 0.15, 1.0)
    tree.links.new(ka.outputs[0], tree.nodes["phong_lights"].inputs["Ambient Object Color"])
    out = tmp_path / "ka.mtl"
    assert bpy.ops.phong.export_mtl(filepath=str(out)) == {"FINISHED"}
    clay = {m.name: m for m in mtl.load(str(out))}["Red_clay"]
    assert _f32(clay.colors["Ka"]) == _f32((0.05, 0.1, 0.15))
    assert _f32(clay.colors["Kd"]) == _f32((0.7, 0.3, 0.1))


def test_a_principled_sources_ambient_colour_is_written_as_ka(bpy_clean, tmp_path):
    """A Principled source with a specular layer: MTL's Ka is the colour the Phong ambient
    light sees, read off the render (the Phong Ambient pass under a white ambient light of
    intensity 1), not the Kd."""
    bpy = bpy_clean
    scene = be.new_scene("Glossy", 8, 8)
    bpy.context.window.scene = scene
    scene.world.phong.ambient_intensity = 1.0
    scene.world.phong.ambient_color = (1.0, 1.0, 1.0)
    ball = be.add_uv_sphere(scene, "Ball", (0, 0, 0), 0.5,
                            _principled(bpy, "Glaze", (0.1, 0.2, 0.4, 1), level=0.5))
    be.add_ortho_camera(scene, (0.0, 0.0), 1.2, 1.2)
    be.apply_phong(scene, [ball])
    assert bpy.ops.phong.add_term_passes() == {"FINISHED"}
    path = str(tmp_path / "glaze.exr")
    be.render_exr(scene, path)
    seen = be.read_multilayer_exr(path)["Phong Ambient"][4, 4, :3]
    out = tmp_path / "glaze.mtl"
    assert bpy.ops.phong.export_mtl(filepath=str(out)) == {"FINISHED"}
    glaze = {m.name: m for m in mtl.load(str(out))}["Glaze"]
    assert _f32(glaze.colors["Kd"]) == _f32((0.1, 0.2, 0.4))
    assert glaze.colors["Ka"] == pytest.approx(tuple(seen), abs=1e-6)
    assert all(a > d for a, d in zip(glaze.colors["Ka"], glaze.colors["Kd"]))


def test_obj_export_option_writes_exact_phong_entries_and_keeps_the_others(bpy_clean,
                                                                          tmp_path):
    bpy = bpy_clean
    red, _bricks = _scene(bpy, tmp_path)
    scene = bpy.context.scene
    plain = bpy.data.materials.new("Plain paint")
    be.compat().new_material_tree(plain).nodes["Principled BSDF"].inputs[
        "Base Color"].default_value = (0.25, 0.5, 0.75, 1.0)
    be.add_uv_sphere(scene, "Untouched", (4, 0, 0), 0.5, plain)
    out = tmp_path / "scene.obj"
    assert bpy.ops.phong.export_obj(filepath=str(out)) == {"FINISHED"}
    text = out.read_text()
    assert "mtllib scene.mtl" in text and "usemtl Red_clay" in text
    assert "usemtl Phong_" not in text
    by_name = {m.name: m for m in mtl.load(str(tmp_path / "scene.mtl"))}
    assert set(by_name) == {"Red_clay", "Bricks", "Plain_paint"}
    clay = by_name["Red_clay"]
    assert _f32(clay.colors["Kd"]) == _f32((0.7, 0.3, 0.1))
    assert _f32(clay.colors["Ks"]) == _f32((0.5, 0.6, 0.7))
    assert clay.scalars["Ns"] == 12.5 and clay.illum == 2
    assert by_name["Plain_paint"].colors["Kd"] == pytest.approx((0.25, 0.5, 0.75), abs=1e-6), \
        "Blender's own entry for a material that is not Phong"
    # and back in: the Phong controls of the imported copy equal the exported ones
    be.reset_empty_file()
    scene = be.new_scene("Back", 8, 8)
    bpy.context.window.scene = scene
    assert bpy.ops.phong.import_obj(filepath=str(out)) == {"FINISHED"}
    back = bpy.data.materials["Red_clay"].node_tree.nodes
    assert tuple(back["phong_object_color"].outputs[0].default_value)[:3] == \
        _f32((0.7, 0.3, 0.1))
    assert back["phong_exponent"].outputs[0].default_value == 12.5


def test_a_source_name_taken_by_another_material_keeps_the_phong_name(bpy_clean, tmp_path):
    """An object still using the source material "Red clay": Blender writes its own
    Red_clay entry, so the Phong material keeps its own name in the OBJ and the MTL."""
    bpy = bpy_clean
    red, _bricks = _scene(bpy, tmp_path)
    source = bpy.data.materials[red["phong_source"]]
    be.add_uv_sphere(bpy.context.scene, "Still red clay", (4, 0, 0), 0.5, source)
    out = tmp_path / "taken.obj"
    assert bpy.ops.phong.export_obj(filepath=str(out)) == {"FINISHED"}
    by_name = {m.name: m for m in mtl.load(str(tmp_path / "taken.mtl"))}
    assert {"Red_clay", "Phong_Red_clay", "Bricks"} <= set(by_name)
    assert by_name["Phong_Red_clay"].scalars["Ns"] == 12.5
    text = out.read_text()
    assert "usemtl Phong_Red_clay" in text and "usemtl Red_clay" in text
    assert bpy.ops.phong.export_mtl(filepath=str(tmp_path / "only.mtl")) == {"FINISHED"}
    assert sorted(m.name for m in mtl.load(str(tmp_path / "only.mtl"))) == ["Bricks",
                                                                           "Red_clay"]
