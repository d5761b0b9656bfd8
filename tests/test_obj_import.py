# SPDX-License-Identifier: GPL-3.0-or-later
"""File ▸ Import ▸ Wavefront (.obj) as Phong: MTL materials as exact Phong materials.

Cycles pixels of the three illumination models against the MTL formula worked out here from
Ka, Kd, Ks, Ns, Ke and the scene's lights; files written by Blender's own exporter and by
trimesh; the round trip import ▸ export ▸ import; bad files refused with file and line and
nothing imported; what MTL says that Phong cannot is reported, never dropped silently."""

from __future__ import annotations

import math
import os
import shutil

import numpy as np
import pytest

import blender_env as be
from phong_nodes.core import mtl
from phong_scene import _light, render

DATA = os.path.join(os.path.dirname(os.path.abspath(__file__)), "data", "obj")
THETA = math.radians(40.0)   # the sun's tilt from the vertical
AMBIENT = 0.25


def _import(bpy, path):
    return bpy.ops.phong.import_obj(filepath=path)


def _controls(material):
    nodes = material.node_tree.nodes
    lights = nodes["phong_lights"]

    def colour(name):
        link = lights.inputs[name].links[0]
        return tuple(link.from_node.outputs[0].default_value)[:3]

    return {"Object Color": colour("Object Color"),
            "Ambient Object Color": colour("Ambient Object Color"),
            "Specular Color": colour("Specular Color"),
            "Irradiant Color": colour("Irradiant Color"),
            "Exponent": nodes["phong_exponent"].outputs[0].default_value,
            "Blinn": nodes["phong_blinn"].outputs[0].default_value}


def _lit_scene(bpy, name):
    scene = be.new_scene(name, 66, 20)
    bpy.context.window.scene = scene
    scene.world.phong.ambient_intensity = AMBIENT
    sun = _light(bpy, scene, "Sun", "SUN", (0.0, 0.0, 5.0), rotation=(0.0, THETA, 0.0))
    be.add_ortho_camera(scene, (0.0, 0.0), 6.6, 2.0)
    return scene, sun


def expected(values):
    """MTL illum 2 / 1 / 0 on a plane facing the camera, lit by the tilted sun (i = 1) and the
    ambient light; Blinn's highlight: h·n = cos(θ/2)."""
    ka, kd, ks, ke = (np.array(values.get(k, (0.0, 0.0, 0.0)), dtype=np.float32)
                      for k in ("Ka", "Kd", "Ks", "Ke"))
    illum = values["illum"]
    if illum == 0:
        return kd
    colour = ke + AMBIENT * ka + math.cos(THETA) * kd
    if illum == 2:
        colour = colour + math.cos(THETA / 2) ** values["Ns"] * ks
    return np.minimum(colour, 1.0)


ILLUM = {"flat": {"Kd": (0.9, 0.5, 0.1), "illum": 0},
         "matte": {"Ka": (0.2, 0.3, 0.4), "Kd": (0.6, 0.5, 0.4), "Ke": (0.02, 0.01, 0.0),
                   "illum": 1},
         "shiny": {"Ka": (0.1, 0.1, 0.1), "Kd": (0.3, 0.4, 0.5), "Ks": (0.6, 0.6, 0.5),
                   "Ns": 20.0, "Ke": (0.0, 0.0, 0.05), "illum": 2}}


@pytest.mark.cycles
def test_each_illumination_model_renders_the_mtl_formula(bpy_clean, blender_tmp):
    bpy = bpy_clean
    scene, _sun = _lit_scene(bpy, "Illum")
    before = set(bpy.data.materials)
    assert _import(bpy, os.path.join(DATA, "illum.obj")) == {"FINISHED"}
    objects = {o.name: o for o in scene.objects if o.type == "MESH"}
    assert sorted(objects) == ["flat", "matte", "shiny"]
    assert bpy.ops.phong.add_term_passes() == {"FINISHED"}
    passes, _seconds = render(bpy, scene, str(blender_tmp / "illum.exr"))
    for column, name in ((11, "flat"), (33, "matte"), (55, "shiny")):
        got = passes["Phong Color"][10, column, :3]
        np.testing.assert_allclose(got, expected(ILLUM[name]), atol=2e-6, err_msg=name)
    # the importer's materials are kept as the sources: Restore puts them back
    material = objects["shiny"].active_material
    assert material.name == "Phong shiny" and material["phong_source"] in set(
        bpy.data.materials) - before


def test_files_from_blender_and_trimesh_import_with_their_values(bpy_clean, capfd):
    bpy = bpy_clean
    _lit_scene(bpy, "Others")
    capfd.readouterr()
    assert _import(bpy, os.path.join(DATA, "blender_tile.obj")) == {"FINISHED"}
    assert _import(bpy, os.path.join(DATA, "trimesh_box.obj")) == {"FINISHED"}
    logged = "".join(capfd.readouterr())
    tile = bpy.data.objects["Tile"].active_material
    got = _controls(tile)
    f32 = lambda v: pytest.approx(tuple(np.float32(v)), abs=0)  # noqa: E731
    assert got["Object Color"] == f32((0.1, 0.3, 0.6))
    assert got["Ambient Object Color"] == f32((1.0, 1.0, 1.0))
    assert got["Specular Color"] == f32((0.5, 0.5, 0.5))
    assert (got["Exponent"], got["Blinn"]) == (562.5, 1.0)
    assert "blender_tile.mtl:4 (Glazed_tile): not representable, left out: Ni 1.5 (refraction)" \
        in logged
    box = next(o for o in bpy.data.objects if o.name.startswith("box") or
               o.name.startswith("trimesh")).active_material
    got = _controls(box)
    assert got["Object Color"] == f32((0.8, 0.4, 0.2))
    assert got["Ambient Object Color"] == f32((0.2, 0.2, 0.2))
    assert got["Specular Color"] == f32((0.50196078, 0.50196078, 0.50196078))
    assert (got["Exponent"], got["Blinn"]) == (40.0, 1.0), "no illum line: illum 2"
    assert "box.mtl" not in logged, "nothing of trimesh's file left out"


def test_round_trip_import_export_import(bpy_clean, tmp_path):
    bpy = bpy_clean
    _lit_scene(bpy, "Trip")
    assert _import(bpy, os.path.join(DATA, "illum.obj")) == {"FINISHED"}
    first = {m.name: _controls(m) for m in bpy.data.materials if m.name.startswith("Phong ")}
    out = tmp_path / "again.mtl"
    assert bpy.ops.phong.export_mtl(filepath=str(out)) == {"FINISHED"}
    written = {m.name: m for m in mtl.load(str(out))}
    shiny = written["Phong_shiny"]
    for key in ("Ka", "Kd", "Ks", "Ke"):
        assert shiny.colors[key] == tuple(float(np.float32(v)) for v in ILLUM["shiny"][key])
    assert shiny.scalars["Ns"] == 20.0 and shiny.illum == 2
    assert written["Phong_matte"].illum == 1
    # import the exported library again (same geometry, the new MTL): same controls
    obj = tmp_path / "again.obj"
    text = open(os.path.join(DATA, "illum.obj")).read().replace("mtllib illum.mtl",
                                                                  "mtllib again.mtl")
    for name in ILLUM:
        text = text.replace(f"usemtl {name}", f"usemtl Phong_{name}")
    obj.write_text(text)
    be.reset_empty_file()
    _lit_scene(bpy, "Trip again")
    assert _import(bpy, str(obj)) == {"FINISHED"}
    again = {m.name.replace("Phong Phong_", "Phong "): _controls(m)
             for m in bpy.data.materials if m.name.startswith("Phong Phong_")}
    assert again == first


def test_maps_multiply_their_colour_and_missing_files_are_named(bpy_clean, tmp_path, capfd):
    bpy = bpy_clean
    _lit_scene(bpy, "Maps")
    image = bpy.data.images.new("tiles", 2, 2)
    image.filepath_raw = str(tmp_path / "tiles.png")
    image.file_format = "PNG"
    image.save()
    shutil.copy(os.path.join(DATA, "illum.obj"), tmp_path / "m.obj")
    (tmp_path / "illum.mtl").write_text(
        "newmtl flat\nKd 1 1 1\nillum 0\n"
        "newmtl matte\nKd 0.5 0.25 1\nmap_Kd tiles.png\nbump -bm 0.5 tiles.png\nillum 1\n"
        "newmtl shiny\nKd 1 1 1\nKs 1 1 1\nmap_Ks gone.png\nd 0.5\nillum 2\n")
    capfd.readouterr()
    assert _import(bpy, str(tmp_path / "m.obj")) == {"FINISHED"}
    logged = "".join(capfd.readouterr())
    matte = bpy.data.materials["Phong matte"].node_tree
    feed = matte.nodes["phong_lights"].inputs["Object Color"].links[0].from_node
    assert feed.bl_idname == "ShaderNodeVectorMath" and feed.operation == "MULTIPLY"
    image_used = feed.inputs[1].links[0].from_node.image
    assert os.path.samefile(bpy.path.abspath(image_used.filepath), tmp_path / "tiles.png")
    assert matte.nodes["phong_lights"].inputs["Normal"].links[0].from_node.bl_idname == \
        "ShaderNodeBump"
    assert f"{tmp_path / 'illum.mtl'}:9 (shiny): texture gone.png not found" in logged
    assert "(shiny): not representable, left out: d 0.5 (transparency)" in logged
    out = tmp_path / "maps.mtl"
    assert bpy.ops.phong.export_mtl(filepath=str(out)) == {"FINISHED"}
    matte_out = {m.name: m for m in mtl.load(str(out))}["Phong_matte"]
    assert matte_out.colors["Kd"] == (0.5, 0.25, 1.0)
    assert matte_out.maps["map_Kd"].path == "tiles.png"


@pytest.mark.parametrize("mtl_text, where, message", [
    ("newmtl flat\nKd 0.5 oops 0.1\n", "illum.mtl:2", "Kd: 'oops' is not a number"),
    ("newmtl flat\nillum 12\n", "illum.mtl:2", "illum needs an integer from 0 to 10, got '12'"),
    (None, "m.obj:3", "material library"),
])
def test_bad_files_are_refused_and_nothing_is_imported(bpy_clean, tmp_path, mtl_text, where,
                                                       message):
    bpy = bpy_clean
    scene, _sun = _lit_scene(bpy, "Bad")
    shutil.copy(os.path.join(DATA, "illum.obj"), tmp_path / "m.obj")
    if mtl_text is not None:
        (tmp_path / "illum.mtl").write_text(mtl_text)
    objects, materials = len(bpy.data.objects), len(bpy.data.materials)
    with pytest.raises(RuntimeError) as excinfo:
        _import(bpy, str(tmp_path / "m.obj"))
    text = str(excinfo.value)
    assert f"Import OBJ as Phong: {tmp_path}" in text and where in text and message in text
    assert text.rstrip().endswith("nothing imported")
    assert (len(bpy.data.objects), len(bpy.data.materials)) == (objects, materials)


def test_missing_obj_file(bpy_clean, tmp_path):
    bpy = bpy_clean
    with pytest.raises(RuntimeError, match=r"Import OBJ as Phong: .*nowhere.obj: file not found"):
        _import(bpy, str(tmp_path / "nowhere.obj"))


@pytest.mark.cycles
@pytest.mark.parametrize("file_name, values", [
    ("blender_tile.obj", {"Ka": (1.0, 1.0, 1.0), "Kd": (0.1, 0.3, 0.6), "Ks": (0.5, 0.5, 0.5),
                          "Ns": 562.5, "Ke": (0.0, 0.0, 0.0), "illum": 2}),
    ("trimesh_box.obj", {"Ka": (0.2, 0.2, 0.2), "Kd": (0.8, 0.4, 0.2),
                         "Ks": (0.50196078,) * 3, "Ns": 40.0, "illum": 2}),
])
def test_files_of_other_programs_render_the_mtl_formula(bpy_clean, blender_tmp, file_name,
                                                        values):
    """The centre of the upward face (the tile, the box's top) against the formula of the
    values read from the file by hand (see tests/data/obj)."""
    bpy = bpy_clean
    scene, _sun = _lit_scene(bpy, file_name)
    assert _import(bpy, os.path.join(DATA, file_name)) == {"FINISHED"}
    assert bpy.ops.phong.add_term_passes() == {"FINISHED"}
    passes, _seconds = render(bpy, scene, str(blender_tmp / f"{file_name}.exr"))
    np.testing.assert_allclose(passes["Phong Color"][10, 33, :3], expected(values), atol=2e-6)


def test_a_file_without_geometry_says_so(bpy_clean, tmp_path, capfd):
    bpy = bpy_clean
    _lit_scene(bpy, "Empty")
    path = tmp_path / "nothing.obj"
    path.write_text("# no vertices, no faces\n")
    objects = len(bpy.data.objects)
    capfd.readouterr()
    assert _import(bpy, str(path)) == {"FINISHED"}
    assert f"Import OBJ as Phong: no mesh in {path}" in "".join(capfd.readouterr())
    assert len(bpy.data.objects) == objects


def test_a_scene_without_lights_is_named_in_a_warning(bpy_clean, capfd):
    bpy = bpy_clean
    scene = be.new_scene("Dark", 8, 8)
    bpy.context.window.scene = scene
    capfd.readouterr()
    assert _import(bpy, os.path.join(DATA, "illum.obj")) == {"FINISHED"}
    assert "the scene has no Point, Sun or Spot light" in "".join(capfd.readouterr())
