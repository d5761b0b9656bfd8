# SPDX-License-Identifier: GPL-3.0-or-later
"""Drag and drop of .fbx files into the 3D Viewport, imported by FBX (Phong) (issue 35), where
the release has ``bpy.types.FileHandler``; the operator is ``interchange.fbx_import``'s."""

import bpy

classes = []

if hasattr(bpy.types, "FileHandler"):
    class PHONG_FH_fbx(bpy.types.FileHandler):
        bl_idname = "PHONG_FH_fbx"
        bl_label = "FBX (Phong)"
        bl_import_operator = "phong.import_fbx"
        bl_file_extensions = ".fbx"

        @classmethod
        def poll_drop(cls, context):
            return context.area is not None and context.area.type == "VIEW_3D"

    classes.append(PHONG_FH_fbx)


def register():
    for cls in classes:
        bpy.utils.register_class(cls)


def unregister():
    for cls in reversed(classes):
        bpy.utils.unregister_class(cls)
