# SPDX-License-Identifier: GPL-3.0-or-later
"""The formats Phong Nodes reads and writes, in one table.

Each :class:`Format` holds its file name suffixes, its labels, its importer and its exporter;
the File ▸ Import / Export menu entries and the file browser's filters (``ui/``), the drop
handlers of the 3D Viewport (``ui/file_io.py``) and the command line (``phong compare
FILE``: ``cli/inputs.py``) all read them here, so a suffix is written once (in the pure
column ``core/suffixes.py``, where the command line's help reads them without ``bpy``).

Every importer has one signature, ``import_file(context, filepath, **options)``, and one
answer, an :class:`ImportResult` (objects, materials, warnings); a file that cannot be
imported raises an :class:`InterchangeError` (each format's own error is one: its message
names the file) and leaves the scene as it was.  Every importer ends through
``lighting.sync.session``: the scene's Phong materials relinked, as Relink Phong Lights
leaves them.  Every exporter has one signature too,
``export(context, filepath, use_selection=False, **options)`` -> warnings, and reads the
Phong materials through ``lighting.feeds.feeds``; no exporter imports an importer.
"""

from __future__ import annotations

import os
from dataclasses import dataclass
from typing import Callable, Optional

from ...core.suffixes import SUFFIXES
from . import (collada_export, collada_import, fbx_export, fbx_import, mtl_export, obj_import,
               threejs_export, x3d_export, x3d_import)
from .native import ImportResult, InterchangeError

__all__ = ["FORMATS", "Format", "ImportResult", "InterchangeError", "by_key", "by_suffix",
           "import_file", "importable_suffixes"]


@dataclass(frozen=True)
class Format:
    """One format: what the UI, the drop handler and the command line need of it."""

    key: str
    #: the file name endings it reads and writes, its default first ("model.wrl.gz" ends in
    #: ".gz": gzipped X3D and VRML97): ``core.suffixes.SUFFIXES`` (the command line's help
    #: reads them there, without bpy)
    suffixes: tuple
    #: ``import_file(context, filepath, **options)`` -> ImportResult, or None
    importer: Optional[Callable]
    #: ``export(context, filepath, use_selection=False, **options)`` -> warnings, or None
    exporter: Optional[Callable]
    #: File ▸ Import / File ▸ Export entries (None: not in that menu)
    import_menu: Optional[str] = None
    export_menu: Optional[str] = None
    #: the operators (``bpy.ops`` id names) of those entries
    import_operator: Optional[str] = None
    export_operator: Optional[str] = None
    #: how the operators' reports begin ("Import X3D: ...")
    import_report: str = ""
    export_report: str = ""
    #: the drop handler's label: files dropped on the 3D Viewport are imported (where the
    #: release has ``bpy.types.FileHandler``); None: not dropped
    drop_label: Optional[str] = None
    #: the file brings its own lights (an import reports the scene's lights only for a
    #: format without them, OBJ, as Apply reports them)
    has_lights: bool = True

    @property
    def glob(self) -> str:
        """The file browser's filter: ``*.wrl;*.wrz;...``."""
        return ";".join(f"*{suffix}" for suffix in self.suffixes)


FORMATS = (
    Format("obj", SUFFIXES["obj"], obj_import.import_file, mtl_export.export_obj,
           import_menu="Wavefront (.obj) as Phong",
           export_menu="Wavefront (.obj) with Phong Materials",
           import_operator="phong.import_obj", export_operator="phong.export_obj",
           import_report="Import OBJ as Phong", export_report="Export OBJ with Phong",
           has_lights=False),
    Format("mtl", SUFFIXES["mtl"], None, mtl_export.export_library,
           export_menu="Phong Materials (.mtl)", export_operator="phong.export_mtl",
           export_report="Export Phong MTL"),
    Format("collada", SUFFIXES["collada"], collada_import.import_file, collada_export.export,
           import_menu="COLLADA (Phong) (.dae)", export_menu="COLLADA (Phong) (.dae)",
           import_operator="phong.import_collada", export_operator="phong.export_collada",
           import_report="Import COLLADA", export_report="Export COLLADA",
           drop_label="COLLADA (Phong)"),
    Format("fbx", SUFFIXES["fbx"], fbx_import.import_file, fbx_export.export,
           import_menu="FBX (Phong) (.fbx)", export_menu="FBX (.fbx) with Phong Materials",
           import_operator="phong.import_fbx", export_operator="phong.export_fbx",
           import_report="Import FBX (Phong)", export_report="Export FBX (Phong)",
           drop_label="FBX (Phong)"),
    Format("x3d", SUFFIXES["x3d"], x3d_import.import_file, x3d_export.export,
           import_menu="X3D / VRML97 (Phong)", export_menu="X3D / VRML97 (Phong)",
           import_operator="phong.import_x3d", export_operator="phong.export_x3d",
           import_report="Import X3D", export_report="Export X3D",
           drop_label="X3D / VRML97 (Phong)"),
    Format("threejs", SUFFIXES["threejs"], None, threejs_export.export,
           export_menu="three.js Page (.html)", export_operator="phong.export_threejs",
           export_report="Export three.js page"),
)


def by_key(key: str) -> Format:
    return next(f for f in FORMATS if f.key == key)


def by_suffix(filepath: str) -> Format | None:
    """The format that imports *filepath* (by its suffix, any case), or None."""
    suffix = os.path.splitext(filepath)[1].lower()
    return next((f for f in FORMATS if f.importer is not None and suffix in f.suffixes), None)


def importable_suffixes() -> list:
    """Every suffix an importer reads, in the table's order."""
    return [s for f in FORMATS if f.importer is not None for s in f.suffixes]


def import_file(context, filepath, **options) -> ImportResult:
    """Import *filepath* by the format its suffix names: objects, materials, warnings.
    Raises InterchangeError (the scene unchanged) when it cannot be imported, or when no
    format reads it."""
    found = by_suffix(filepath)
    if found is None:
        known = ", ".join(importable_suffixes())
        raise InterchangeError(f"{filepath}: not a file Phong Nodes imports ({known})")
    return found.importer(context, filepath, **options)
