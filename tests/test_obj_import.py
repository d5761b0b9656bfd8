# SPDX-License-Identifier: GPL-3.0-or-later
"""File ▸ Import ▸ Wavefront (.obj) as Phong: MTL materials as exact Phong materials.

Cycles pixels of the three illumination models against the MTL formula worked out here from
Ka, Kd, Ks, Ns, Ke and the scene's lights; files written by Blender's own exporter, trimesh,
MeshLab, 3ds Max and others (tests/data/obj); the round trip import ▸ export ▸ import (names,
illum, float32 values); only an unreadable library refused, with file and line and nothing
imported; what MTL says that Phong cannot show is reported once, never dropped silently."""

from __future__ import annotations

import math
import os
import shutil

import numpy as np
import pytest

import blender_env as be
from phong_nodes.core import mtl
from phong_scene import _light, linked_controls, render

DATA = os.path.join(os.path.dirname(os.path.abspath(__file__)), "data", "obj")
THETA = math.radians(40.0)   # the sun's tilt from the vertical
AMBIENT = 0.25
# Cycles 5.1+ stores shading normals with 16 bits per component: the imported plane's N is
# (1.5e-5, 1.5e-5, 1) there (its true normal Ng is exact), which moves n·l by up to 1e-5.
# 3e-5 allows that and nothing a formula error would give (5.0 and older: within 1e-7).
ATOL = 3e-5


def _import(bpy, path):
    return bpy.ops.phong.import_obj(filepath=path)


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
        np.testing.assert_allclose(got, expected(ILLUM[name]), atol=ATOL, err_msg=name)
    # the file's materials under the file's names, Phong from birth, nothing else: no
    # Principled copy, no source to restore (issue 35)
    added = set(bpy.data.materials) - before
    assert sorted(m.name for m in added) == ["flat", "matte", "shiny"]
    assert all(m.get("phong_nodes_material") and "phong_source" not in m.keys() for m in added)
    assert objects["shiny"].active_material.name == "shiny"


def test_files_from_blender_and_trimesh_import_with_their_values(bpy_clean, capfd):
    bpy = bpy_clean
    _lit_scene(bpy, "Others")
    capfd.readouterr()
    assert _import(bpy, os.path.join(DATA, "blender_tile.obj")) == {"FINISHED"}
    assert _import(bpy, os.path.join(DATA, "trimesh_box.obj")) == {"FINISHED"}
    logged = "".join(capfd.readouterr())
    tile = bpy.data.objects["Tile"].active_material
    got = linked_controls(tile)
    f32 = lambda v: pytest.approx(tuple(np.float32(v)), abs=0)  # noqa: E731
    assert got["Object Color"] == f32((0.1, 0.3, 0.6))
    assert got["Ambient Object Color"] == f32((1.0, 1.0, 1.0))
    assert got["Specular Color"] == f32((0.5, 0.5, 0.5))
    assert (got["Exponent"], got["Blinn"]) == (562.5, 1.0)
    assert "blender_tile.mtl" not in logged, "Ni 1.5 and d 1 of an opaque material: neutral"
    box = next(o for o in bpy.data.objects if o.name.startswith("box") or
               o.name.startswith("trimesh")).active_material
    got = linked_controls(box)
    assert got["Object Color"] == f32((0.8, 0.4, 0.2))
    assert got["Ambient Object Color"] == f32((0.2, 0.2, 0.2))
    assert got["Specular Color"] == f32((0.50196078, 0.50196078, 0.50196078))
    assert (got["Exponent"], got["Blinn"]) == (40.0, 1.0), "no illum line: illum 2"
    assert "box.mtl" not in logged, "nothing of trimesh's file left out"


def _written(path):
    """{name: (colours, Ns, illum)} of an MTL file, colours as float32 bytes."""
    return {m.name: ({k: np.float32(v).tobytes() for k, v in m.colors.items()},
                     m.scalars.get("Ns"), m.illum) for m in mtl.load(str(path))}


def test_round_trip_import_export_import(bpy_clean, tmp_path):
    """Import ▸ export ▸ import keeps the names, the values (float32 bit for bit) and illum,
    illum 0 included; the second export writes the same text."""
    bpy = bpy_clean
    _lit_scene(bpy, "Trip")
    assert _import(bpy, os.path.join(DATA, "illum.obj")) == {"FINISHED"}
    first = {m.name: linked_controls(m) for m in bpy.data.materials if m.get("phong_nodes_material")}
    out = tmp_path / "again.mtl"
    assert bpy.ops.phong.export_mtl(filepath=str(out)) == {"FINISHED"}
    text = out.read_text()
    assert "newmtl Phong_" not in text and "0.20000000298023224" not in text
    written = _written(out)
    assert sorted(written) == ["flat", "matte", "shiny"], "the file's names"
    source = {m.name: m for m in mtl.load(os.path.join(DATA, "illum.mtl"))}
    for name, (colors, ns, illum) in written.items():
        want = source[name]
        assert illum == want.illum, name
        assert colors["Kd"] == np.float32(want.colors["Kd"]).tobytes(), name
        if illum:
            for key in ("Ka", "Ks", "Ke"):
                assert colors[key] == np.float32(want.colors.get(key, (0, 0, 0))).tobytes(), \
                    (name, key)
    assert "Kd 0.9 0.5 0.1\nillum 0\n" in text, "illum 0: its Kd, nothing else"
    assert written["shiny"][1] == 20.0
    # import the exported library again (same geometry, the new MTL): same controls
    obj = tmp_path / "again.obj"
    obj.write_text(open(os.path.join(DATA, "illum.obj")).read().replace("mtllib illum.mtl",
                                                                        "mtllib again.mtl"))
    be.reset_empty_file()
    _lit_scene(bpy, "Trip again")
    assert _import(bpy, str(obj)) == {"FINISHED"}
    again = {m.name: linked_controls(m) for m in bpy.data.materials if m.get("phong_nodes_material")}
    assert again == first
    assert bpy.ops.phong.export_mtl(filepath=str(tmp_path / "third.mtl")) == {"FINISHED"}
    assert (tmp_path / "third.mtl").read_text() == text


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
    matte = bpy.data.materials["matte"].node_tree
    feed = matte.nodes["phong_lights"].inputs["Object Color"].links[0].from_node
    assert feed.bl_idname == "ShaderNodeVectorMath" and feed.operation == "MULTIPLY"
    image_used = feed.inputs[1].links[0].from_node.image
    assert os.path.samefile(bpy.path.abspath(image_used.filepath), tmp_path / "tiles.png")
    bump = matte.nodes["phong_lights"].inputs["Normal"].links[0].from_node
    assert bump.bl_idname == "ShaderNodeBump"
    height = bump.inputs["Height"].links[0].from_node.image
    assert (image_used.colorspace_settings.name, height.colorspace_settings.name) == (
        "sRGB", "Non-Color"), "one file as colour and as height: neither changes the other"
    assert (f"{tmp_path / 'illum.mtl'}:9 (shiny): texture gone.png not found (looked for "
            f"{tmp_path / 'gone.png'}); left out of shiny") in logged
    # d is the material's Opacity now (tests/test_controls.py renders it): no warning
    assert "(shiny): not representable" not in logged and "transparency" not in logged
    shiny = bpy.data.materials["shiny"].node_tree.nodes
    assert shiny["phong_opacity"].outputs[0].default_value == 0.5
    out = tmp_path / "maps.mtl"
    assert bpy.ops.phong.export_mtl(filepath=str(out)) == {"FINISHED"}
    matte_out = {m.name: m for m in mtl.load(str(out))}["matte"]
    assert matte_out.colors["Kd"] == (0.5, 0.25, 1.0)
    assert matte_out.maps["map_Kd"].path == "tiles.png"


def test_only_an_unreadable_file_is_refused_and_nothing_is_imported(bpy_clean, tmp_path):
    bpy = bpy_clean
    _lit_scene(bpy, "Bad")
    shutil.copy(os.path.join(DATA, "illum.obj"), tmp_path / "m.obj")
    objects, materials = len(bpy.data.objects), len(bpy.data.materials)
    for make in (lambda: None, lambda: os.mkdir(tmp_path / "illum.mtl")):
        make()
        with pytest.raises(RuntimeError) as excinfo:
            _import(bpy, str(tmp_path / "m.obj"))
        text = str(excinfo.value)
        assert f"Import OBJ as Phong: {tmp_path / 'm.obj'}:3: material library" in text
        assert text.rstrip().endswith("nothing imported")
        assert (len(bpy.data.objects), len(bpy.data.materials)) == (objects, materials)


def test_statements_that_cannot_be_read_are_left_out_with_a_warning(bpy_clean, tmp_path,
                                                                    capfd):
    bpy = bpy_clean
    _lit_scene(bpy, "Lenient")
    shutil.copy(os.path.join(DATA, "illum.obj"), tmp_path / "m.obj")
    (tmp_path / "illum.mtl").write_text("newmtl flat\nKd 0.5 oops 0.1\nKd 0.25\n"
                                        "newmtl matte\nKd 0.5 0.5 0.5\nillum 12\n")
    capfd.readouterr()
    assert _import(bpy, str(tmp_path / "m.obj")) == {"FINISHED"}
    logged = "".join(capfd.readouterr())
    mtl_path = tmp_path / "illum.mtl"
    assert f"{mtl_path}:2: Kd: 'oops' is not a number; left out" in logged
    assert (f"{mtl_path}:6: illum '12' is not an illumination model (0 to 10); read as "
            "illum 2") in logged
    assert linked_controls(bpy.data.materials["flat"])["Object Color"] == (0.25,) * 3
    assert linked_controls(bpy.data.materials["matte"])["Blinn"] == 1.0


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
    np.testing.assert_allclose(passes["Phong Color"][10, 33, :3], expected(values), atol=ATOL)


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
    assert "the scene has no light that renders" in "".join(capfd.readouterr())


REAL = os.path.join(DATA, "real")
TRIANGLES = "v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 0 1\n"


def _obj(path, library, names, separator=" "):
    """An OBJ file of one triangle per material (*separator* between keyword and name)."""
    lines = [f"mtllib{separator}{library}", TRIANGLES.rstrip()]
    for index, name in enumerate(names):
        lines += [f"o part{index}", f"usemtl{separator}{name}", "f 1/1 2/2 3/3"]
    path.write_text("\n".join(lines) + "\n")
    return str(path)


def test_3ds_max_file_with_tabs_and_a_texture_found_by_its_bare_name(bpy_clean, tmp_path,
                                                                      capfd):
    """guruware's 3ds Max exporter (tests/data/obj/real/mustang-y.mtl): tab-indented, neutral
    Ni/d/Tr/Tf, map_Ka and map_Kd naming cars/texture-y.jpg, a path from the OBJ's parent
    folder.  The OBJ names its library after a tab.  Missing, the texture is named once;
    beside the MTL, it is found by its bare name."""
    bpy = bpy_clean
    _lit_scene(bpy, "Max")
    shutil.copy(os.path.join(REAL, "mustang-y.mtl"), tmp_path / "mustang-y.mtl")
    obj = _obj(tmp_path / "car.obj", "mustang-y.mtl",
               ["_mustang01Car_interior", "wire_028089177"], separator="\t")
    capfd.readouterr()
    assert _import(bpy, obj) == {"FINISHED"}
    logged = "".join(capfd.readouterr())
    assert logged.count("texture cars/texture-y.jpg not found") == 1, logged
    assert ("; left out of _mustang01Car_interior, wire_028089177" in logged)
    assert "not representable" not in logged, "Ni 1.5, d 1, Tr 0, Tf 1 1 1: neutral"
    wire = linked_controls(bpy.data.materials["wire_028089177"])
    assert wire["Specular Color"] == pytest.approx(tuple(np.float32([0.35] * 3)), abs=0)
    assert wire["Exponent"] == 32.0
    # the texture beside the MTL
    be.reset_empty_file()
    _lit_scene(bpy, "Max again")
    image = bpy.data.images.new("texture-y", 2, 2)
    image.filepath_raw = str(tmp_path / "texture-y.jpg")
    image.file_format = "PNG"
    image.save()
    capfd.readouterr()
    assert _import(bpy, obj) == {"FINISHED"}
    ours = [l for l in "".join(capfd.readouterr()).splitlines() if "Import OBJ as Phong" in l]
    assert not [line for line in ours if "texture" in line], ours
    tree = bpy.data.materials["wire_028089177"].node_tree
    feed = tree.nodes["phong_lights"].inputs["Object Color"].links[0].from_node
    used = feed.inputs[1].links[0].from_node.image
    assert os.path.samefile(bpy.path.abspath(used.filepath), tmp_path / "texture-y.jpg")


def test_windows_texture_paths(bpy_clean, tmp_path):
    """assimp's spider.mtl: map_Kd .\\wal67ar_small.jpg."""
    bpy = bpy_clean
    _lit_scene(bpy, "Spider")
    shutil.copy(os.path.join(REAL, "spider.mtl"), tmp_path / "spider.mtl")
    image = bpy.data.images.new("wal", 2, 2)
    image.filepath_raw = str(tmp_path / "wal67ar_small.jpg")
    image.file_format = "PNG"
    image.save()
    assert _import(bpy, _obj(tmp_path / "spider.obj", "spider.mtl", ["Skin"])) == {"FINISHED"}
    tree = bpy.data.materials["Skin"].node_tree
    feed = tree.nodes["phong_lights"].inputs["Object Color"].links[0].from_node
    assert feed.bl_idname == "ShaderNodeVectorMath"


#: The forms that refused whole files before (issue: Blender's older exporter, Tinkercad,
#: MeshLab, 3ds Max); written here by hand, one statement each.
REPORTED = ("newmtl\tOld Blender\n"
            "Ns -1.960784\nKa 0.000000 0.000000 0.000000\nKd 0.640000 0.640000 0.640000\n"
            "Ks 0.500000 0.500000 0.500000\nNi -1.000000\nd 123.0\nillum 2\n"
            "newmtl color_16089887\nKa 0 0 0\nKd\t0.9372549019607843 0.3764705882352941 "
            "0.19215686274509805\nd 1\nillum 0.0\n"
            "newmtl painted\nKd 1 1 1\nmap_Kd -colorspace sRGB -o 0 0 paint.png\n"
            "bump -colorspace linear -bm 0.25 -halftone 3 height.png\n")


def test_forms_other_readers_accept_are_read(bpy_clean, tmp_path, capfd):
    bpy = bpy_clean
    _lit_scene(bpy, "Reported")
    (tmp_path / "r.mtl").write_text(REPORTED)
    for name in ("paint", "height"):
        image = bpy.data.images.new(name, 2, 2)
        image.filepath_raw = str(tmp_path / f"{name}.png")
        image.file_format = "PNG"
        image.save()
    obj = _obj(tmp_path / "r.obj", "r.mtl", ["Old Blender", "color_16089887", "painted"])
    capfd.readouterr()
    assert _import(bpy, obj) == {"FINISHED"}
    logged = "".join(capfd.readouterr())
    mtl_path = tmp_path / "r.mtl"
    assert f"{mtl_path}:2: Ns -1.960784 is below 0; read as 0" in logged
    assert (f"{mtl_path}:17: bump: unknown option -halftone: '-halftone 3' left out, file name "
            "'height.png'") in logged
    ours = [line for line in logged.splitlines() if "Import OBJ as Phong: /" in line]
    assert len(ours) == 2, ours   # nothing else to say
    old = linked_controls(bpy.data.materials["Old Blender"])
    assert old["Exponent"] == 0.0 and old["Object Color"] == tuple(np.float32([0.64] * 3))
    flat = linked_controls(bpy.data.materials["color_16089887"])
    assert flat["Irradiant Color"] == tuple(np.float32(
        [0.9372549019607843, 0.3764705882352941, 0.19215686274509805]))
    assert flat["Object Color"] == flat["Specular Color"] == (0.0, 0.0, 0.0)
    painted = bpy.data.materials["painted"].node_tree.nodes["phong_lights"]
    assert painted.inputs["Normal"].links[0].from_node.inputs["Strength"].default_value == 0.25


@pytest.mark.parametrize("library", [
    os.path.join(REAL, "verify.mtl"), os.path.join(REAL, "male02.mtl"),
    os.path.join(REAL, "mustang-y.mtl"), os.path.join(REAL, "regr01.mtl"),
    os.path.join(DATA, "meshlab_two.obj.mtl"), os.path.join(DATA, "blender_tile.mtl"),
    os.path.join(DATA, "box.mtl")])
def test_files_of_other_programs_round_trip(bpy_clean, tmp_path, library):
    """Import ▸ export ▸ import of real files: the written names, illumination models and
    values are the file's (float32 bit for bit; illum 2 even where Ks is black), and
    importing the written file gives the same controls."""
    bpy = bpy_clean
    _lit_scene(bpy, "Real trip")
    shutil.copy(library, tmp_path / "source.mtl")
    source = mtl.load(str(tmp_path / "source.mtl"))
    obj = _obj(tmp_path / "m.obj", "source.mtl", [m.name for m in source])
    assert _import(bpy, obj) == {"FINISHED"}
    first = {m.name: linked_controls(m) for m in bpy.data.materials if m.get("phong_nodes_material")}
    out = tmp_path / "written.mtl"
    assert bpy.ops.phong.export_mtl(filepath=str(out)) == {"FINISHED"}
    written = {m.name: m for m in mtl.load(str(out))}
    assert sorted(written) == sorted(m.name for m in source)
    f32 = lambda v: np.float32(v).tobytes()   # noqa: E731
    for material in source:
        back = written[material.name]
        illum = 2 if material.illum is None else material.illum
        assert back.illum == illum, material.name
        for key in ("Ka", "Kd", "Ks", "Ke"):
            if key == "Ks" and illum == 1:
                continue
            assert f32(back.colors[key]) == f32(material.colors.get(key, (0, 0, 0))), \
                (material.name, key)
        assert f32(back.scalars["Ns"]) == f32(material.scalars.get("Ns", 30.0))
    (tmp_path / "m.obj").write_text(open(obj).read().replace("mtllib source.mtl",
                                                             "mtllib written.mtl"))
    be.reset_empty_file()
    _lit_scene(bpy, "Real trip again")
    assert _import(bpy, obj) == {"FINISHED"}
    assert {m.name: linked_controls(m) for m in bpy.data.materials
            if m.get("phong_nodes_material")} == first


@pytest.mark.cycles
def test_map_offset_and_scale_place_the_texture_and_are_written_back(bpy_clean, blender_tmp,
                                                                     tmp_path, capfd):
    """``map_Kd -s 2 1 1 -o 0.25 0 0``: the map is sampled at uv × s + o (File Formats 4.2;
    Blender's own importer and three.js's MTLLoader read it so), checked on rendered pixels
    against a texture of a red and a blue half; export writes the options back."""
    bpy = bpy_clean
    scene, _sun = _lit_scene(bpy, "Placed")
    image = bpy.data.images.new("stripes", 8, 2)
    row = [(1.0, 0.0, 0.0, 1.0)] * 4 + [(0.0, 0.0, 1.0, 1.0)] * 4
    image.pixels = [c for pixel in row * 2 for c in pixel]
    image.filepath_raw = str(tmp_path / "stripes.png")
    image.file_format = "PNG"
    image.save()
    (tmp_path / "placed.mtl").write_text(
        "newmtl placed\nKa 0 0 0\nKd 1 1 1\nmap_Kd -s 2 1 1 -o 0.25 0 0 stripes.png\nillum 1\n")
    (tmp_path / "placed.obj").write_text(
        "mtllib placed.mtl\nvn 0 1 0\nv -3 0 1\nv 3 0 1\nv 3 0 -1\nv -3 0 -1\n"
        "vt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\no tile\nusemtl placed\nf 1/1/1 2/2/1 3/3/1 4/4/1\n")
    capfd.readouterr()
    assert _import(bpy, str(tmp_path / "placed.obj")) == {"FINISHED"}
    assert "not applied" not in "".join(capfd.readouterr())
    assert bpy.ops.phong.add_term_passes() == {"FINISHED"}
    passes, _seconds = render(bpy, scene, str(blender_tmp / "placed.exr"))
    red, blue = expected({"Kd": (1, 0, 0), "illum": 1}), expected({"Kd": (0, 0, 1), "illum": 1})
    checked = {"red": 0, "blue": 0}
    for column in range(4, 62):
        u = (-3.3 + (column + 0.5) * 0.1 + 3.0) / 6.0      # the tile spans x = -3..3
        placed = (u * 2.0 + 0.25) % 1.0
        # bilinear filtering of 8 texels: pure colours 1/16 away from the halves' edges
        if 1 / 16 + 0.01 <= placed <= 7 / 16 - 0.01:
            want, key = red, "red"
        elif 9 / 16 + 0.01 <= placed <= 15 / 16 - 0.01:
            want, key = blue, "blue"
        else:
            continue
        np.testing.assert_allclose(passes["Phong Color"][10, column, :3], want, atol=ATOL,
                                   err_msg=f"column {column}, u {u:.3f} -> {placed:.3f}")
        checked[key] += 1
    assert min(checked.values()) >= 10, checked
    out = tmp_path / "again.mtl"
    assert bpy.ops.phong.export_mtl(filepath=str(out)) == {"FINISHED"}
    assert "map_Kd -o 0.25 0 0 -s 2 1 1 stripes.png" in out.read_text()
    assert {m.name: m for m in mtl.load(str(out))}["placed"].maps["map_Kd"].placement() == (
        (0.25, 0.0, 0.0), (2.0, 1.0, 1.0))
