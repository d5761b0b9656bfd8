# SPDX-License-Identifier: GPL-3.0-or-later
"""Drag and drop of .fbx files into the 3D Viewport, imported by FBX (Phong) (issue 35), where
the release has ``bpy.types.FileHandler``; the operator is ``interchange.fbx_import``'s."""

import bpy

from . import file_io

classes = file_io.drop_handler("PHONG_FH_fbx", "FBX (Phong)", "phong.import_fbx", (".fbx",))


def register():
    for cls in classes:
        bpy.utils.register_class(cls)


def unregister():
    for cls in reversed(classes):
        bpy.utils.unregister_class(cls)
