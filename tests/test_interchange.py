# SPDX-License-Identifier: GPL-3.0-or-later
"""Interchange in one shape (issue 44; addon/interchange/formats.py): one table of formats read
by the File menus' filters, the drop handlers and the command line; one import signature and
result; one error; the import's end as a relink's; one image loader."""

from __future__ import annotations

import ast
import gzip
import os
import re
import shutil

import pytest

import blender_env as be

DATA = os.path.join(os.path.dirname(os.path.abspath(__file__)), "data")
ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
#: one file of each importer's format, from tests/data (files of other programs)
FILES = {"obj": os.path.join(DATA, "obj", "illum.obj"),
         "fbx": os.path.join(DATA, "fbx", "maya_cube_7500_ascii.fbx"),
         "collada": os.path.join(DATA, "collada", "hand_lit.dae"),
         "x3d": os.path.join(DATA, "x3d", "hand_scope.wrl")}
#: the ID collections an import may add to: a refused file adds to none of them
KINDS = ("objects", "meshes", "materials", "images", "node_groups", "lights", "cameras",
         "collections", "worlds")


def _formats():
    from phong_nodes.addon.interchange import formats  # noqa: PLC0415

    return formats


def _counts(bpy) -> dict:
    return {kind: len(getattr(bpy.data, kind)) for kind in KINDS}


def _lit_scene(bpy, name):
    scene = be.new_scene(name, 8, 8)
    bpy.context.window.scene = scene
    sun = bpy.data.objects.new("Sun", bpy.data.lights.new("Sun", "SUN"))
    scene.collection.objects.link(sun)
    return scene


# -- one table ------------------------------------------------------------------------------

def test_the_ui_the_drop_handlers_and_the_command_line_read_the_one_table(extension):
    bpy = extension
    formats = _formats()
    from phong_nodes.cli import inputs  # noqa: PLC0415

    importable = [f for f in formats.FORMATS if f.importer is not None]
    assert {f.key for f in importable} == {"obj", "fbx", "collada", "x3d"}
    assert inputs.suffix_formats() == {s: f for f in importable for s in f.suffixes}
    assert {".wrl", ".wrz", ".x3d", ".x3dz", ".x3dv", ".x3dvz", ".gz", ".obj", ".fbx",
            ".dae"} == set(inputs.suffix_formats())
    for fmt in formats.FORMATS:
        for idname in (fmt.import_operator, fmt.export_operator):
            if idname is None:
                continue
            group, name = idname.split(".")
            rna = getattr(getattr(bpy.ops, group), name).get_rna_type()
            assert rna.properties["filter_glob"].default == fmt.glob, idname
        if fmt.drop_label and hasattr(bpy.types, "FileHandler"):
            handler = getattr(bpy.types, f"PHONG_FH_{fmt.key}")
            assert handler.bl_file_extensions == ";".join(fmt.suffixes)
            assert handler.bl_import_operator == fmt.import_operator
    assert formats.by_suffix("model.WRL.gz").key == "x3d"
    assert formats.by_suffix("scene.blend") is None


def test_the_table_takes_its_suffixes_from_the_pure_column(extension):
    """core/suffixes.py (what the command line's help reads without bpy) and the table agree:
    the same keys and suffixes, and its imported formats are the rows with an importer."""
    formats = _formats()
    from phong_nodes.core import suffixes as pure  # noqa: PLC0415

    assert {f.key: f.suffixes for f in formats.FORMATS} == pure.SUFFIXES
    assert [f.key for f in formats.FORMATS if f.importer is not None] == list(pure.IMPORTED)
    assert formats.importable_suffixes() == pure.importable_suffixes()


def test_no_suffix_is_written_outside_the_table():
    """The UI and the command line hold no list of suffixes or filter of a format of their
    own: they read the table (X3D's modules know which encoding a suffix means: that is the
    format's, not a list of what is read)."""
    suffixes = {".wrl", ".wrz", ".x3d", ".x3dz", ".x3dv", ".x3dvz", ".gz", ".obj", ".fbx", ".dae",
                ".mtl", ".html"}
    written = suffixes | {f"*{s}" for s in suffixes}
    bad = []
    for folder in ("addon/ui", "cli"):
        for name in sorted(os.listdir(os.path.join(ROOT, folder))):
            path = os.path.join(ROOT, folder, name)
            if not name.endswith(".py"):
                continue
            tree = ast.parse(open(path, encoding="utf-8").read())
            for node in ast.walk(tree):
                if isinstance(node, ast.Tuple) and sum(
                        isinstance(e, ast.Constant) and e.value in written
                        for e in node.elts) >= 2:
                    bad.append(f"{folder}/{name}:{node.lineno}: a tuple of suffixes")
                if (isinstance(node, ast.keyword) and node.arg == "default"
                        and isinstance(node.value, ast.Constant) and node.value.value in written):
                    bad.append(f"{folder}/{name}:{node.lineno}: a filter of its own")
    assert not bad, bad


# -- one signature, one result, one error -------------------------------------------------

@pytest.mark.parametrize("key", sorted(FILES))
def test_each_format_imports_through_the_one_signature(bpy_clean, key):
    bpy = bpy_clean
    formats = _formats()
    from phong_nodes.addon.lighting import recipe  # noqa: PLC0415

    _lit_scene(bpy, key)
    objects_before = set(bpy.data.objects)
    result = formats.import_file(bpy.context, FILES[key])
    assert isinstance(result, formats.ImportResult)
    assert result.objects and all(o not in objects_before for o in result.objects)
    assert result.materials and all(recipe.is_phong_material(m) for m in result.materials)
    assert all(isinstance(w, str) for w in result.warnings)
    made = {s.material for o in result.objects for s in getattr(o, "material_slots", ())}
    assert made <= set(result.materials), "every material on the new objects is in the result"


def test_a_gzipped_x3d_file_imports_by_its_suffix(bpy_clean, tmp_path):
    bpy = bpy_clean
    formats = _formats()
    _lit_scene(bpy, "Packed")
    packed = tmp_path / "hand_scope.wrl.gz"
    with open(FILES["x3d"], "rb") as plain, gzip.open(packed, "wb") as out:
        shutil.copyfileobj(plain, out)
    result = formats.import_file(bpy.context, str(packed))
    assert [o.name for o in result.objects if o.type == "MESH"]


BAD = {"obj": ("bad.obj", b"mtllib nowhere.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n",
               "nowhere.mtl"),
       "fbx": ("bad.fbx", b"Kaydara FBX Binary  \x00\x1a\x00\xe8\x1c\x00\x00" + b"\xff" * 40,
               "bad.fbx"),
       "collada": ("bad.dae", b"<?xml version='1.0'?><COLLADA><library_geometries>",
                   "bad.dae"),
       "x3d": ("bad.x3d", b"hello, world\n", "bad.x3d")}   # (a cut file is read leniently)


@pytest.mark.parametrize("key", [pytest.param(k, marks=pytest.mark.slow) if k == "fbx" else k
                                 for k in sorted(BAD)])   # fbx: Blender's own importer, slow
def test_a_bad_file_of_each_format_raises_the_one_error_and_leaves_nothing(bpy_clean,
                                                                          tmp_path, key):
    bpy = bpy_clean
    formats = _formats()
    _lit_scene(bpy, f"Bad {key}")
    name, data, named = BAD[key]
    path = tmp_path / name
    path.write_bytes(data)
    before = _counts(bpy)
    with pytest.raises(formats.InterchangeError) as excinfo:
        formats.import_file(bpy.context, str(path))
    assert named in str(excinfo.value), "the message names the file"
    assert "Traceback" not in str(excinfo.value)
    assert _counts(bpy) == before, "nothing left behind"
    # the operator reports it as every format does: "<report>: <message>", cancelled
    fmt = formats.by_key(key)
    group, op = fmt.import_operator.split(".")
    with pytest.raises(RuntimeError, match=f"{re.escape(fmt.import_report)}: .*{named}"):
        getattr(getattr(bpy.ops, group), op)(filepath=str(path))
    assert _counts(bpy) == before


def test_the_old_error_names_are_the_one_error(extension):
    formats = _formats()
    from phong_nodes.addon.interchange import (collada_import, fbx_import,  # noqa: PLC0415
                                               obj_import, x3d_import)
    from phong_nodes.core import fbx  # noqa: PLC0415

    for error in (x3d_import.X3DImportError, collada_import.ColladaImportError,
                  fbx_import.FbxImportError, obj_import.ObjImportError):
        assert issubclass(error, formats.InterchangeError)
    assert issubclass(fbx_import.FbxImportError, fbx.FbxError), "callers catching FbxError"
    with pytest.raises(formats.InterchangeError, match="not a file Phong Nodes imports"):
        formats.import_file(None, "scene.blend")


# -- the import's end: what a relink does ---------------------------------------------------

def _wiring(scene) -> dict:
    """{(object, slot): (material, its lights group)} of the scene's Phong materials."""
    from phong_nodes.addon.lighting import recipe  # noqa: PLC0415

    out = {}
    for obj in scene.objects:
        for slot in getattr(obj, "material_slots", ()):
            if recipe.is_phong_material(slot.material):
                node = slot.material.node_tree.nodes.get(recipe.LIGHTS_NODE)
                out[(obj.name, slot.slot_index)] = (slot.material.name, node.node_tree.name)
    return out


def test_an_import_leaves_the_scene_as_a_relink_leaves_it(bpy_clean):
    """The second of two X3D files brings lights that reach everything (a DirectionalLight
    outside any group, the headlight): the objects of the first file, whose scoped light set
    reached them alone, are lit by them too, as Relink Phong Lights would light them (the
    import's old end bound only its own objects: they kept the group of the scoped light
    alone, until the next relink).  And the World's copies follow as a relink makes them."""
    bpy = bpy_clean
    formats = _formats()
    from phong_nodes.addon.lighting import sync, world_copies  # noqa: PLC0415

    scene = be.new_scene("Two files", 8, 8)
    bpy.context.window.scene = scene
    formats.import_file(bpy.context, os.path.join(DATA, "x3d", "hand_scope.wrl"))
    scoped = {k: v for k, v in _wiring(scene).items() if "[" in v[1]}
    assert scoped, "the first file's scoped light set has a group of its own"
    formats.import_file(bpy.context, os.path.join(DATA, "x3d", "choreonoid_TunnelLight.wrl"))
    imported = _wiring(scene)
    live = world_copies.is_live(scene.world)
    for key in scoped:   # the lights of the second file reach them
        assert "DirectionalLight.001" in imported[key][1], imported[key]
    sync.relink_scene(scene, bpy.context.view_layer)
    assert _wiring(scene) == imported, "a relink changes nothing after the import"
    assert world_copies.is_live(scene.world) == live


# -- one image loader -----------------------------------------------------------------------

def test_the_image_loader_loads_a_file_once_per_colour_space(bpy_clean, tmp_path):
    bpy = bpy_clean
    from phong_nodes.addon.interchange import native  # noqa: PLC0415

    image = bpy.data.images.new("tile", 2, 2)
    image.filepath_raw = str(tmp_path / "tile.png")
    image.file_format = "PNG"
    image.save()
    bpy.data.images.remove(image)
    images = len(bpy.data.images)
    cache = {}
    colour = native.load_image(str(tmp_path / "tile.png"), cache)
    assert colour is not None and colour.colorspace_settings.name != native.NON_COLOR
    assert native.load_image(str(tmp_path / ".." / tmp_path.name / "tile.png"), cache) is colour
    data = native.load_image(str(tmp_path / "tile.png"), cache, non_color=True)
    assert data is not colour and data.colorspace_settings.name == native.NON_COLOR
    assert colour.colorspace_settings.name != native.NON_COLOR, "the colour image unchanged"
    assert native.load_image(str(tmp_path / "tile.png"), non_color=True) is data, \
        "an image of the file in that colour space is used again"
    own = native.load_image(str(tmp_path / "tile.png"), non_color=True, existing=False,
                            straight_alpha=True)
    assert own not in (colour, data) and own.alpha_mode == "CHANNEL_PACKED"
    assert len(bpy.data.images) == images + 3
    (tmp_path / "broken.png").write_bytes(b"\x89PNG\r\n\x1a\n not an image")
    assert native.load_image(str(tmp_path / "broken.png"), cache) is None
    assert native.load_image(str(tmp_path / "missing.png"), cache) is None
    assert len(bpy.data.images) == images + 3, "an unreadable file leaves no image"
