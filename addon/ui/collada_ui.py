# SPDX-License-Identifier: GPL-3.0-or-later
"""File ▸ Import ▸ COLLADA (Phong) (.dae), File ▸ Export ▸ COLLADA (Phong) (.dae) and drag and
drop of .dae files into the 3D Viewport (where the release has ``bpy.types.FileHandler``)."""

import os

import bpy
from bpy.props import BoolProperty, StringProperty
from bpy_extras.io_utils import ExportHelper, ImportHelper

from ..interchange import collada_export, collada_import


class PHONG_OT_import_collada(bpy.types.Operator, ImportHelper):
    """Import a COLLADA file: its profile_COMMON materials as exact Phong materials, its lights \
as Phong lights (attenuation, cone, exponent), meshes, cameras and the node tree"""

    bl_idname = "phong.import_collada"
    bl_label = "Import COLLADA (Phong)"
    bl_options = {"REGISTER", "UNDO"}

    filename_ext = ".dae"
    filter_glob: StringProperty(default="*.dae", options={"HIDDEN"})
    # not remembered between runs: a path set before invoke is a file dropped on the viewport
    filepath: StringProperty(subtype="FILE_PATH", options={"SKIP_SAVE"})
    literal_transparency: BoolProperty(
        name="Literal Transparency", default=False,
        description="Follow the spec's transparency formula even where it makes a material "
                    "wholly invisible (several exporters write <transparency>0 meaning opaque)")

    def execute(self, context):
        path = bpy.path.abspath(self.filepath)
        try:
            objects, done, warnings, _sync = collada_import.import_collada(
                context, path, self.literal_transparency)
        except collada_import.ColladaImportError as error:
            self.report({"ERROR"}, f"Import COLLADA: {error}")
            return {"CANCELLED"}
        for warning in warnings:
            self.report({"WARNING"}, f"Import COLLADA: {warning}")
        self.report({"INFO"}, f"Imported {len(objects)} object(s) with {len(done)} Phong "
                              f"material(s) from {os.path.basename(path)}")
        return {"FINISHED"}

    def invoke(self, context, event):
        if self.filepath:   # dropped on the viewport (FileHandler)
            return self.execute(context)
        return ImportHelper.invoke(self, context, event)


class PHONG_OT_export_collada(bpy.types.Operator, ExportHelper):
    """Export meshes, transforms, cameras, lights (attenuation, cone) and Phong materials as \
COLLADA 1.4.1 profile_COMMON phong / blinn / lambert / constant"""

    bl_idname = "phong.export_collada"
    bl_label = "Export COLLADA (Phong)"
    bl_options = {"REGISTER"}

    filename_ext = ".dae"
    filter_glob: StringProperty(default="*.dae", options={"HIDDEN"})
    use_selection: BoolProperty(name="Selected Objects Only", default=False,
                                description="Only the selected objects")

    def execute(self, context):
        path = bpy.path.abspath(self.filepath)
        if not path or os.path.isdir(path) or not os.path.isdir(os.path.dirname(path) or "."):
            self.report({"ERROR"}, f"Export COLLADA: {path!r} is not a file in an existing folder")
            return {"CANCELLED"}
        try:
            warnings = collada_export.export(context, path, self.use_selection)
        except (OSError, ValueError) as error:
            self.report({"ERROR"}, f"Export COLLADA: cannot write {path}: {error}")
            return {"CANCELLED"}
        for warning in warnings:
            self.report({"WARNING"}, f"Export COLLADA: {warning}")
        self.report({"INFO"}, f"Wrote {path}")
        return {"FINISHED"}


classes = [PHONG_OT_import_collada, PHONG_OT_export_collada]

if hasattr(bpy.types, "FileHandler"):
    class PHONG_FH_collada(bpy.types.FileHandler):
        bl_idname = "PHONG_FH_collada"
        bl_label = "COLLADA (Phong)"
        bl_import_operator = "phong.import_collada"
        bl_file_extensions = ".dae"

        @classmethod
        def poll_drop(cls, context):
            return context.area is not None and context.area.type == "VIEW_3D"

    classes.append(PHONG_FH_collada)


def _draw_import(self, _context):
    self.layout.operator(PHONG_OT_import_collada.bl_idname, text="COLLADA (Phong) (.dae)")


def _draw_export(self, _context):
    self.layout.operator(PHONG_OT_export_collada.bl_idname, text="COLLADA (Phong) (.dae)")


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
