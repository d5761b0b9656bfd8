# SPDX-License-Identifier: GPL-3.0-or-later
"""The operators of File ▸ Import ▸ X3D / VRML97 (Phong) and File ▸ Export ▸ X3D / VRML97
(Phong) (their entries, suffixes and drop handler from ``interchange/formats.py``), and Add ▸
Light ▸ Headlight (``phong.add_headlight``): a Sun that follows the scene camera, the
headlight of VRML97 / X3D (docs/x3d.md)."""

import bpy
from bpy.props import BoolProperty, StringProperty
from bpy_extras.io_utils import ExportHelper

from ..lighting import headlight, rig
from ..lighting import sync as sync_mod
from . import file_io


class PHONG_OT_import_x3d(bpy.types.Operator, file_io.DroppableImport):
    """Import a VRML97 or X3D file (.wrl, .x3d, .x3dv, gzipped too): its materials as exact \
Phong materials in the X3D lighting model, its lights (attenuation, radius, beam, scope, \
headlight), shapes, instances and viewpoint"""

    bl_idname = "phong.import_x3d"
    bl_label = "Import X3D / VRML97 (Phong)"

    filename_ext = ".wrl"
    filter_glob: StringProperty(default=file_io.glob("x3d"), options={"HIDDEN"})

    def execute(self, context):
        return file_io.run_import(self, context, "x3d")


class PHONG_OT_export_x3d(bpy.types.Operator, ExportHelper):
    """Export meshes, Phong materials, lights (attenuation, radius, beam, scope, headlight) and \
the camera as X3D (.x3d, .x3dv) or VRML97 (.wrl), gzipped for .x3dz, .x3dvz, .wrz, .gz"""

    bl_idname = "phong.export_x3d"
    bl_label = "Export X3D / VRML97 (Phong)"
    bl_options = {"REGISTER"}

    filename_ext = ".x3d"
    check_extension = False   # .x3d, .x3dv, .wrl, ... all stay as typed
    filter_glob: StringProperty(default=file_io.glob("x3d"), options={"HIDDEN"})
    use_selection: BoolProperty(name="Selected Objects Only", default=False,
                                description="Only the selected objects")

    def execute(self, context):
        return file_io.run_export(self, context, "x3d", self.use_selection)


class PHONG_OT_add_headlight(bpy.types.Operator):
    """Add a headlight: a white Sun that follows the scene camera (X3D / VRML97's headlight: \
intensity 1, no ambient, along the view direction); an existing one is pointed at the \
scene camera"""

    bl_idname = "phong.add_headlight"
    bl_label = "Headlight (follows the camera)"
    bl_options = {"REGISTER", "UNDO"}

    @classmethod
    def poll(cls, context):
        if context.scene is not None and context.scene.camera is not None:
            return True
        cls.poll_message_set("Add Headlight: the scene has no camera to follow")
        return False

    def execute(self, context):
        scene = context.scene
        try:
            obj, added = headlight.ensure(scene, context.collection)
        except ValueError as error:
            self.report({"ERROR"}, f"Add Headlight: {error}")
            return {"CANCELLED"}
        context.view_layer.update()
        if rig.groups_of(scene):   # Phong materials: the new light joins them
            sync_mod.relink_scene(scene, context.view_layer)
        verb = "Added" if added else "Pointed"
        self.report({"INFO"}, f"{verb} {obj.name} at camera {scene.camera.name}")
        return {"FINISHED"}


classes = [PHONG_OT_import_x3d, PHONG_OT_export_x3d, PHONG_OT_add_headlight,
           *file_io.drop_handler("x3d")]


def _draw_import(self, _context):
    file_io.menu_entry(self, "x3d", "import")


def _draw_export(self, _context):
    file_io.menu_entry(self, "x3d", "export")


def _draw_light_add(self, _context):
    self.layout.separator()
    self.layout.operator(PHONG_OT_add_headlight.bl_idname, icon="LIGHT_SUN")


def register():
    for cls in classes:
        bpy.utils.register_class(cls)
    bpy.types.TOPBAR_MT_file_import.append(_draw_import)
    bpy.types.TOPBAR_MT_file_export.append(_draw_export)
    bpy.types.VIEW3D_MT_light_add.append(_draw_light_add)


def unregister():
    bpy.types.VIEW3D_MT_light_add.remove(_draw_light_add)
    bpy.types.TOPBAR_MT_file_export.remove(_draw_export)
    bpy.types.TOPBAR_MT_file_import.remove(_draw_import)
    for cls in reversed(classes):
        bpy.utils.unregister_class(cls)
