# SPDX-License-Identifier: GPL-3.0-or-later
"""The groups in the Asset Browser: the generated library holds every group as an asset in
its section's catalog, is written without touching the open file, and is rewritten only
when the library changes."""

from __future__ import annotations

import os

import blender_env as be
from phong_nodes.node_groups.library import GROUPS

SECTION_OF = {
    "Phong Directional Light": "Lights", "Phong Point Light": "Lights",
    "Phong Spot Light": "Lights", "Phong Power Falloff": "Lights",
    "Phong Irradiant": "Terms", "Phong Ambient": "Terms", "Phong Diffuse": "Terms",
    "Phong Specular": "Terms", "Phong Blinn Specular": "Terms",
    "Phong Color Add": "Colour", "Phong Color Multiply": "Colour", "Phong Shading": "Model",
    "three.js Point Light": "three.js", "three.js Spot Light": "three.js",
    "three.js Ambient": "three.js", "three.js Phong": "three.js",
    "X3D Directional Light": "X3D", "X3D Point Light": "X3D", "X3D Spot Light": "X3D",
}


def _assets():
    return be.import_bpy(), __import__(f"{be.EXT_MODULE}.addon.ui.assets",
                                       fromlist=["assets"])


def _catalog_file(folder):
    """{uuid: path} from blender_assets.cats.txt, read as Blender's format defines it."""
    out = {}
    with open(os.path.join(folder, "blender_assets.cats.txt")) as fh:
        lines = [line.strip() for line in fh if line.strip() and not line.startswith("#")]
    assert lines[0] == "VERSION 1"
    for line in lines[1:]:
        uid, path, _simple = line.split(":")
        out[uid] = path
    return out


def test_library_holds_every_group_in_its_catalog(bpy_clean):
    bpy, assets = _assets()
    assert set(SECTION_OF) == set(GROUPS), "every group has a section"
    path = assets.ensure_library_file()
    folder = os.path.dirname(path)
    assert os.path.basename(path).startswith("phong_nodes_")
    assert not bpy.data.node_groups, "the open file is not touched"
    (library,) = [lib for lib in bpy.context.preferences.filepaths.asset_libraries
                  if lib.name == "Phong Nodes"]
    assert os.path.normpath(library.path) == os.path.normpath(folder)
    with bpy.data.libraries.load(path, assets_only=True) as (source, _target):
        assert sorted(source.node_groups) == sorted(GROUPS)
    cats = _catalog_file(folder)
    assert sorted(cats.values()) == ["Phong", "Phong/Colour", "Phong/Lights", "Phong/Model",
                                     "Phong/Terms", "Phong/X3D", "Phong/three.js"]
    with bpy.data.libraries.load(path, link=True) as (source, target):
        target.node_groups = list(source.node_groups)
    for tree in target.node_groups:
        assert tree.asset_data is not None, tree.name
        assert cats[tree.asset_data.catalog_id] == f"Phong/{SECTION_OF[tree.name]}", tree.name
        assert tree.asset_data.description == GROUPS[tree.name].description
        assert tree.get("phong_nodes_fingerprint") == GROUPS[tree.name].fingerprint, \
            "the library's own definition, stamped as the loader stamps it"
    shading = next(t for t in target.node_groups if t.name == "Phong Shading")
    assert len(shading.nodes) > 20, "a real group, not a shell"


def test_library_rewritten_only_when_the_library_changes(bpy_clean):
    _bpy, assets = _assets()
    path = assets.ensure_library_file()
    folder = os.path.dirname(path)
    stale = os.path.join(folder, "phong_nodes_1_0000000000.blend")
    with open(stale, "wb") as fh:
        fh.write(b"an older library")
    os.utime(path, (1_000_000_000, 1_000_000_000))
    assert assets.ensure_library_file() == path
    assert os.path.getmtime(path) == 1_000_000_000, "an unchanged library is not rewritten"
    assert os.path.exists(stale), "only a rebuild clears old files"
    os.remove(path)
    assert assets.ensure_library_file() == path and os.path.getmtime(path) > 1_000_000_000
    assert not os.path.exists(stale), "the old version's file is removed"
    assert not [n for n in os.listdir(folder) if "partial" in n], "no half-written file"


def test_unwritable_folder_gives_a_message_and_the_extension_still_works(bpy_clean, capfd,
                                                                         monkeypatch):
    bpy, assets = _assets()

    def refuse(path):
        raise PermissionError(13, "Permission denied")

    monkeypatch.setattr(assets, "_write_library", refuse)
    monkeypatch.setattr(assets, "file_name", lambda: "phong_nodes_0_unwritable.blend")
    assets.unregister()
    assets.register()
    out = capfd.readouterr().out
    assert "Phong Nodes: could not write the asset library in" in out
    assert "Permission denied" in out
    assert bpy.ops.phong.load_node_groups() == {"FINISHED"}
