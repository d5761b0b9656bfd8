# SPDX-License-Identifier: GPL-3.0-or-later
"""The file formats of Phong Nodes by name and suffix, without ``bpy``: the pure columns of the
one table of formats (``addon/interchange/formats.py``), which takes each row's suffixes here.
What cannot import ``bpy`` reads them here: the command line's help (``cli/args.py``: parsing
imports no ``bpy``), so that every help names every suffix ``phong compare FILE`` reads.

``tests/test_interchange.py`` holds the two to each other: the same keys, the same suffixes,
and ``IMPORTED`` the rows of the table that have an importer.
"""

from __future__ import annotations

#: each format's file name endings, its default first ("model.wrl.gz" ends in ".gz": gzipped
#: X3D and VRML97), by the table's key
SUFFIXES = {
    "obj": (".obj",),
    "mtl": (".mtl",),
    "collada": (".dae",),
    "fbx": (".fbx",),
    "x3d": (".wrl", ".wrz", ".x3d", ".x3dz", ".x3dv", ".x3dvz", ".gz"),
    "threejs": (".html",),
}

#: the formats an importer reads (File ▸ Import, the drop handlers, ``phong compare FILE``),
#: in the table's order, with the name the help gives each
IMPORTED = {
    "obj": "Wavefront",
    "collada": "COLLADA",
    "fbx": "FBX",
    "x3d": "X3D / VRML97",
}


def importable_suffixes() -> list:
    """Every suffix an importer reads, in the table's order."""
    return [suffix for key in IMPORTED for suffix in SUFFIXES[key]]


def importable_text() -> str:
    """The imported formats for a help text: "Wavefront .obj, COLLADA .dae, ..." (".gz":
    gzipped X3D and VRML97)."""
    return ", ".join(f"{name} {', '.join(SUFFIXES[key])}" for key, name in IMPORTED.items())
