# SPDX-License-Identifier: GPL-3.0-or-later
"""The operators of File ▸ Import ▸ COLLADA (Phong) (.dae) and File ▸ Export ▸ COLLADA (Phong)
(.dae), and the drop handler of .dae files (their entries and suffixes from
``interchange/formats.py``)."""

import bpy
from bpy.props import BoolProperty, StringProperty
from bpy_extras.io_utils import ExportHelper

from . import file_io


class PHONG_OT_import_collada(bpy.types.Operator, file_io.DroppableImport):
    """Import a COLLADA file: its profile_COMMON materials as exact Phong materials, its lights \
as Phong lights (attenuation, cone, exponent), meshes, cameras and the node tree"""

    bl_idname = "phong.import_collada"
    bl_label = "Import COLLADA (Phong)"

    filename_ext = ".dae"
    filter_glob: StringProperty(default=file_io.glob("collada"), options={"HIDDEN"})
    literal_transparency: BoolProperty(
        name="Literal Transparency", default=False,
        description="Follow the spec's transparency formula even where it makes a material "
                    "wholly invisible (several exporters write <transparency>0 meaning opaque)")

    def execute(self, context):
        return file_io.run_import(self, context, "collada",
                                  literal_transparency=self.literal_transparency)


class PHONG_OT_export_collada(bpy.types.Operator, ExportHelper):
    """Export meshes, transforms, cameras, lights (attenuation, cone) and Phong materials as \
COLLADA 1.4.1 profile_COMMON phong / blinn / lambert / constant"""

    bl_idname = "phong.export_collada"
    bl_label = "Export COLLADA (Phong)"
    bl_options = {"REGISTER"}

    filename_ext = ".dae"
    filter_glob: StringProperty(default=file_io.glob("collada"), options={"HIDDEN"})
    use_selection: BoolProperty(name="Selected Objects Only", default=False,
                                description="Only the selected objects")

    def execute(self, context):
        return file_io.run_export(self, context, "collada", self.use_selection)


classes = (PHONG_OT_import_collada, PHONG_OT_export_collada, *file_io.drop_handler("collada"))


def _draw_import(self, _context):
    file_io.menu_entry(self, "collada", "import")


def _draw_export(self, _context):
    file_io.menu_entry(self, "collada", "export")


def register():
    for cls in classes:
        bpy.utils.register_class(cls)
    bpy.types.TOPBAR_MT_file_import.append(_draw_import)
    bpy.types.TOPBAR_MT_file_export.append(_draw_export)


def unregister():
    bpy.types.TOPBAR_MT_file_export.remove(_draw_export)
    bpy.types.TOPBAR_MT_file_import.remove(_draw_import)
    for cls in reversed(classes):
        bpy.utils.unregister_class(cls)
