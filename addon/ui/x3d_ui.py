# SPDX-License-Identifier: GPL-3.0-or-later
"""File ▸ Import ▸ X3D / VRML97 (Phong), File ▸ Export ▸ X3D / VRML97 (Phong), drag and drop
of VRML97 / X3D files into the 3D Viewport (where the release has ``bpy.types.FileHandler``),
and Add ▸ Light ▸ Headlight (``phong.add_headlight``): a Sun that follows the scene camera,
the headlight of VRML97 / X3D (docs/x3d.md)."""

import bpy
from bpy.props import BoolProperty, StringProperty
from bpy_extras.io_utils import ExportHelper

from ..interchange import x3d_export, x3d_import
from ..lighting import headlight, rig
from ..lighting import sync as sync_mod
from . import file_io

#: The file names the importer reads (gzipped too) and the drop handler takes.
EXTENSIONS = (".wrl", ".wrz", ".x3d", ".x3dz", ".x3dv", ".x3dvz", ".gz")
GLOB = ";".join(f"*{e}" for e in EXTENSIONS)


class PHONG_OT_import_x3d(bpy.types.Operator, file_io.DroppableImport):
    """Import a VRML97 or X3D file (.wrl, .x3d, .x3dv, gzipped too): its materials as exact \
Phong materials in the X3D lighting model, its lights (attenuation, radius, beam, scope, \
headlight), shapes, instances and viewpoint"""

    bl_idname = "phong.import_x3d"
    bl_label = "Import X3D / VRML97 (Phong)"

    filename_ext = ".wrl"
    filter_glob: StringProperty(default=GLOB, options={"HIDDEN"})

    def execute(self, context):
        path = bpy.path.abspath(self.filepath)
        return file_io.run_import(self, "Import X3D", path,
                                  lambda: x3d_import.import_x3d(context, path),
                                  x3d_import.X3DImportError)


class PHONG_OT_export_x3d(bpy.types.Operator, ExportHelper):
    """Export meshes, Phong materials, lights (attenuation, radius, beam, scope, headlight) and \
the camera as X3D (.x3d, .x3dv) or VRML97 (.wrl), gzipped for .x3dz, .x3dvz, .wrz, .gz"""

    bl_idname = "phong.export_x3d"
    bl_label = "Export X3D / VRML97 (Phong)"
    bl_options = {"REGISTER"}

    filename_ext = ".x3d"
    check_extension = False   # .x3d, .x3dv, .wrl, ... all stay as typed
    filter_glob: StringProperty(default=GLOB, options={"HIDDEN"})
    use_selection: BoolProperty(name="Selected Objects Only", default=False,
                                description="Only the selected objects")

    def execute(self, context):
        path = bpy.path.abspath(self.filepath)
        return file_io.run_export(self, "Export X3D", path, lambda: x3d_export.export(
            context, path, self.use_selection))


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
           *file_io.drop_handler("PHONG_FH_x3d", "X3D / VRML97 (Phong)", "phong.import_x3d",
                                 EXTENSIONS)]


def _draw_import(self, _context):
    self.layout.operator(PHONG_OT_import_x3d.bl_idname, text="X3D / VRML97 (Phong)")


def _draw_export(self, _context):
    self.layout.operator(PHONG_OT_export_x3d.bl_idname, text="X3D / VRML97 (Phong)")


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
