# SPDX-License-Identifier: GPL-3.0-or-later
"""File ▸ Import ▸ FBX (Phong) and drag and drop of .fbx files into the 3D Viewport (where the
release has ``bpy.types.FileHandler``) (issue 35)."""

import bpy
from bpy.props import StringProperty

from ..interchange import fbx_import
from . import file_io


class PHONG_OT_import_fbx(bpy.types.Operator, file_io.DroppableImport):
    """Import an FBX file with its Phong and Lambert materials and its lights as exact Phong \
values (binary 7100+ through Blender's importer, ASCII and FBX 6.1 through ufbx)"""

    bl_idname = "phong.import_fbx"
    bl_label = "Import FBX (Phong)"

    filename_ext = ".fbx"
    filter_glob: StringProperty(default="*.fbx", options={"HIDDEN"})

    def execute(self, context):
        path = bpy.path.abspath(self.filepath)
        return file_io.run_import(self, "Import FBX (Phong)", path,
                                  lambda: fbx_import.import_fbx(context, path),
                                  fbx_import.FbxError)


classes = (PHONG_OT_import_fbx, *file_io.drop_handler("PHONG_FH_fbx", "FBX (Phong)",
                                                      "phong.import_fbx", (".fbx",)))


def register():
    for cls in classes:
        bpy.utils.register_class(cls)


def unregister():
    for cls in reversed(classes):
        bpy.utils.unregister_class(cls)
