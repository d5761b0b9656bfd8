# SPDX-License-Identifier: GPL-3.0-or-later
"""The node groups in Blender's Asset Browser: a generated asset library "Phong Nodes".

While the extension is enabled, *Preferences ▸ File Paths ▸ Asset Libraries* holds "Phong
Nodes", a folder in the extension's user folder (``bpy.utils.extension_path_user``; never the
extension's own folder).  The folder holds ``blender_assets.cats.txt`` (the catalog "Phong"
with one sub-catalog per section of the Shift+A menu: Lights, Terms, Colour, Model, three.js,
X3D) and one
.blend with every group of the library marked as an asset in its section's catalog.  The
.blend is named after the library version and a digest of the group definitions, so a new
version writes a new file (and removes the old one); an unchanged library is not rewritten.

The groups are built in temporary data (``bpy.data.temp_data``): the open file is never
touched.  When Blender enables the extension at start-up, ``bpy.data`` is not available yet;
the file is then written by a timer as soon as it is.  Disabling the extension removes the
library from the Preferences (the folder stays with the extension's user data).
"""

from __future__ import annotations

import hashlib
import os
import uuid

import bpy

from .. import loader
from ...core import outputs
from ...node_groups.library import GROUPS, LIBRARY_VERSION
from .menus import SECTIONS

LIBRARY_NAME = "Phong Nodes"
CATALOG_ROOT = "Phong"
CATALOG_FILE = "blender_assets.cats.txt"
_NAMESPACE = uuid.UUID("5f0b6a52-3c1e-4f5e-9d7c-1a2b3c4d5e6f")  # fixed: stable catalog ids


def catalog_id(path: str) -> str:
    """The catalog UUID of *path* ("Phong/Lights"): the same in every build."""
    return str(uuid.uuid5(_NAMESPACE, path))


def catalogs() -> dict:
    """Catalog path -> UUID: the root and one per section."""
    paths = [CATALOG_ROOT] + [f"{CATALOG_ROOT}/{title}" for title, _names in SECTIONS]
    return {path: catalog_id(path) for path in paths}


def folder() -> str:
    """The library's folder, created when missing."""
    package = __package__.rsplit(".addon", 1)[0]
    try:
        return bpy.utils.extension_path_user(package, path="asset_library", create=True)
    except ValueError:  # the source tree enabled as a plain add-on (development, tests)
        return bpy.utils.user_resource("DATAFILES", path=os.path.join(package, "asset_library"),
                                       create=True)


def file_name() -> str:
    digest = hashlib.sha256("".join(GROUPS[name].fingerprint for name in sorted(GROUPS))
                            .encode()).hexdigest()[:10]
    return f"phong_nodes_{LIBRARY_VERSION}_{digest}.blend"


def _write_catalogs(path: str) -> None:
    lines = ["# Asset catalogs of Phong Nodes (written by the extension).", "", "VERSION 1", ""]
    lines += [f"{uid}:{cat}:{cat.replace('/', '-')}" for cat, uid in catalogs().items()]
    outputs.write_file(path, "\n".join(lines) + "\n")


def _write_library(path: str) -> None:
    """Every group, marked as an asset in its section's catalog, into the .blend *path*."""
    ids = catalogs()
    partial = path + ".partial.blend"
    with bpy.data.temp_data() as data:
        trees = set()
        for title, names in SECTIONS:
            for name in names:
                tree = data.node_groups.new(name, loader.TREE_TYPE)
                loader.write_group(tree, name)
                tree.asset_mark()
                tree.asset_data.catalog_id = ids[f"{CATALOG_ROOT}/{title}"]
                tree.asset_data.description = GROUPS[name].description
                tree.asset_data.author = "Phong Nodes"
                trees.add(tree)
        data.libraries.write(partial, trees, fake_user=True)
    os.replace(partial, path)


def ensure_library_file() -> str:
    """The library's .blend and catalogs, written when missing or outdated; returns its path."""
    where = folder()
    path = os.path.join(where, file_name())
    cats = os.path.join(where, CATALOG_FILE)
    if not os.path.isfile(cats):
        _write_catalogs(cats)
    if not os.path.isfile(path):
        _write_library(path)
        for other in os.listdir(where):
            if other.startswith("phong_nodes_") and other.endswith(".blend") and \
                    other != os.path.basename(path):
                os.remove(os.path.join(where, other))
    return path


def _libraries():
    return bpy.context.preferences.filepaths.asset_libraries


def _ours():
    return [lib for lib in _libraries() if lib.name == LIBRARY_NAME]


def add_to_preferences(where: str) -> None:
    """One "Phong Nodes" entry in the Preferences, pointing at *where*."""
    libraries = _ours()
    if not libraries:
        libraries = [_libraries().new(name=LIBRARY_NAME, directory=where)]
    for extra in libraries[1:]:
        _libraries().remove(extra)
    if os.path.normpath(libraries[0].path) != os.path.normpath(where):
        libraries[0].path = where


def _deferred():
    """Timer: write the file once ``bpy.data`` is available (start-up); runs once."""
    if isinstance(bpy.data, bpy.types.BlendData):
        _ensure_quietly()
        return None
    return 0.5


def _ensure_quietly() -> None:
    try:
        ensure_library_file()
    except OSError as error:  # a read-only or full disk: the menus still work
        print(f"Phong Nodes: could not write the asset library in {folder()}: {error}")


def register():
    add_to_preferences(folder())
    if isinstance(bpy.data, bpy.types.BlendData):
        _ensure_quietly()
    elif not bpy.app.timers.is_registered(_deferred):
        bpy.app.timers.register(_deferred, first_interval=0.1, persistent=True)


def unregister():
    if bpy.app.timers.is_registered(_deferred):
        bpy.app.timers.unregister(_deferred)
    for library in _ours():
        _libraries().remove(library)
