# SPDX-License-Identifier: GPL-3.0-or-later
"""Bake Phong Lighting, Show / Restore Phong Bake and File ▸ Export ▸ glTF with Baked Phong
Lighting: operators, the Object menu entries and the Object ▸ Phong Bake panel.  The work is
done by ``addon/baking``."""

from __future__ import annotations

import bpy
from bpy.props import BoolProperty, EnumProperty, IntProperty, StringProperty
from bpy_extras.io_utils import ExportHelper

from ..baking import gltf, lighting, show
from .file_io import export_path as _export_path
from .operators import _selected_meshes

TARGET_ITEMS = (("IMAGE", "Image", "An image per object through its UV map"),
                ("VERTEX", "Vertex Colors", "A colour attribute per vertex, interpolated "
                 "across the faces (Gouraud shading)"))
TERM_ITEMS = (("COLOR", "Phong Color", "The model's colour (the clamped sum of the terms)"),
              ("IRRADIANT", "Irradiant", ""), ("AMBIENT", "Ambient", ""),
              ("DIFFUSE", "Diffuse", ""), ("SPECULAR", "Specular", "Needs View: Camera"))
VIEW_ITEMS = (("CAMERA", "Camera", "The specular as seen from the scene camera"),
              ("NONE", "Without Specular", "Irradiant + ambient + diffuse only: the same "
               "from every viewpoint"))
FORMAT_ITEMS = (("PNG", "PNG (8-bit sRGB)", ""), ("EXR", "OpenEXR (32-bit float)", ""))


class _BakeSettings:
    target: EnumProperty(name="Target", items=TARGET_ITEMS, default="IMAGE")
    term: EnumProperty(name="Bake", items=TERM_ITEMS, default="COLOR")
    view: EnumProperty(name="View", items=VIEW_ITEMS, default="CAMERA")
    resolution: IntProperty(name="Resolution", default=1024, min=16, max=16384,
                            description="Width and height of each object's image")
    file_format: EnumProperty(name="File Format", items=FORMAT_ITEMS, default="PNG")
    directory: StringProperty(name="Folder", default="//", subtype="DIR_PATH",
                              description="Where the images are saved (// : beside the .blend)")
    pack: BoolProperty(name="Pack", default=False, description="Pack the images into the .blend "
                       "instead of saving them in the folder")
    smart_uv: BoolProperty(name="Smart UV Project", default=False,
                           description="Give objects without a UV map one (Smart UV Project)")

    def settings(self):
        return lighting.Settings(target=self.target, term=self.term, view=self.view,
                                 resolution=self.resolution, file_format=self.file_format,
                                 directory=self.directory, pack=self.pack,
                                 smart_uv=self.smart_uv)

    def draw_settings(self, layout):
        layout.use_property_split = True
        layout.prop(self, "target")
        layout.prop(self, "term")
        layout.prop(self, "view")
        if self.target == "IMAGE":
            layout.prop(self, "resolution")
            layout.prop(self, "file_format")
            layout.prop(self, "pack")
            if not self.pack:
                layout.prop(self, "directory")
            layout.prop(self, "smart_uv")


def _progress(context, total):
    wm = context.window_manager
    wm.progress_begin(0, total)
    return lambda done, _total, _name: wm.progress_update(done)


class PHONG_OT_bake_lighting(bpy.types.Operator, _BakeSettings):
    """Bake the Phong look of the selected objects into an image per object or into vertex \
colours (Gouraud shading) with Cycles"""

    bl_idname = "phong.bake_lighting"
    bl_label = "Bake Phong Lighting"
    bl_options = {"REGISTER", "UNDO"}

    display: BoolProperty(name="Show the Bake", default=True,
                          description="Switch the objects to an unlit material showing the "
                                      "bake (Restore Phong Bake puts the Phong material back)")

    def draw(self, context):
        self.draw_settings(self.layout)
        self.layout.prop(self, "display")

    def invoke(self, context, event):
        return context.window_manager.invoke_props_dialog(self)

    def execute(self, context):
        meshes = _selected_meshes(self, context, "Bake Phong Lighting")
        if meshes is None:
            return {"CANCELLED"}
        progress = _progress(context, len(meshes))
        try:
            results, warnings = show.bake_objects(context.scene, meshes, self.settings(),
                                                  progress, display=self.display)
        except (lighting.BakeError, OSError) as error:
            self.report({"ERROR"}, f"Bake Phong Lighting: {error}")
            return {"CANCELLED"}
        finally:
            context.window_manager.progress_end()
        for warning in warnings:
            self.report({"WARNING"}, f"Bake Phong Lighting: {warning}")
        seconds = sum(r["seconds"] for r in results)
        where = ("the colour attribute " + repr(lighting.ATTRIBUTE) if self.target == "VERTEX"
                 else "packed images" if self.pack else f"images in {self.directory}")
        self.report({"INFO"}, f"Baked {len(results)} object(s) into {where} in {seconds:.1f} s")
        return {"FINISHED"}


class PHONG_OT_show_bake(bpy.types.Operator):
    """Show the Phong bake of the selected objects with an unlit material (their Phong \
materials are kept)"""

    bl_idname = "phong.show_bake"
    bl_label = "Show Phong Bake"
    bl_options = {"REGISTER", "UNDO"}

    def execute(self, context):
        meshes = _selected_meshes(self, context, "Show Phong Bake")
        if meshes is None:
            return {"CANCELLED"}
        baked = [o for o in meshes if o.get(lighting.INFO_KEY) is not None]
        if not baked:
            self.report({"ERROR"}, "Show Phong Bake: no selected object has a Phong bake "
                                   "(Bake Phong Lighting first)")
            return {"CANCELLED"}
        try:
            slots = sum(show.show(o) for o in baked)
        except lighting.BakeError as error:
            self.report({"ERROR"}, f"Show Phong Bake: {error}")
            return {"CANCELLED"}
        self.report({"INFO"}, f"Showing the Phong bake in {slots} slot(s)")
        return {"FINISHED"}


class PHONG_OT_restore_bake(bpy.types.Operator):
    """Put the Phong materials back on the selected objects that show their bake"""

    bl_idname = "phong.restore_bake"
    bl_label = "Restore Phong Material"
    bl_options = {"REGISTER", "UNDO"}

    def execute(self, context):
        meshes = _selected_meshes(self, context, "Restore Phong Material")
        if meshes is None:
            return {"CANCELLED"}
        shown = [o for o in meshes if show.is_shown(o)]
        if not shown:
            self.report({"WARNING"}, "Restore Phong Material: no selected object shows a "
                                     "Phong bake")
            return {"CANCELLED"}
        slots = sum(show.restore(o) for o in shown)
        self.report({"INFO"}, f"Phong material back in {slots} slot(s)")
        return {"FINISHED"}


class PHONG_OT_export_gltf(bpy.types.Operator, ExportHelper, _BakeSettings):
    """Bake the Phong look of the selected objects (or every object with a Phong material) \
and write glTF through Blender's exporter: unlit materials (KHR_materials_unlit) with the \
baked texture or vertex colours"""

    bl_idname = "phong.export_gltf"
    bl_label = "Export glTF with Baked Phong Lighting"
    bl_options = {"REGISTER"}

    filename_ext = ".glb"
    filter_glob: StringProperty(default="*.glb;*.gltf", options={"HIDDEN"})
    rebake: BoolProperty(name="Bake Again", default=True,
                         description="Bake every object; off: reuse the bake an object has (image "
                                     "or vertex colours) and bake only the others")
    selection_only: BoolProperty(name="Selected Only", default=False)

    def draw(self, context):
        self.draw_settings(self.layout)
        self.layout.prop(self, "rebake")
        self.layout.prop(self, "selection_only")

    def execute(self, context):
        path = _export_path(self, "Export glTF with Baked Phong Lighting")
        if path is None:
            return {"CANCELLED"}
        if not path.lower().endswith((".glb", ".gltf")):
            path += ".glb"
        pool = context.selected_objects if self.selection_only else context.view_layer.objects
        objects = [o for o in pool if lighting.has_phong(o)]
        settings = self.settings()
        if settings.target == "IMAGE" and not bpy.data.filepath and settings.directory == "//":
            settings.pack = True  # an unsaved file: the images go inside the .blend
        progress = _progress(context, len(objects))
        try:
            result = gltf.export(path, context.scene, objects, settings, self.rebake, progress)
        except (lighting.BakeError, OSError) as error:
            self.report({"ERROR"}, f"Export glTF with Baked Phong Lighting: {error}")
            return {"CANCELLED"}
        finally:
            context.window_manager.progress_end()
        for warning in result["warnings"]:
            self.report({"WARNING"}, f"Export glTF: {warning}")
        self.report({"INFO"}, f"Wrote {path} ({len(objects)} object(s), "
                              f"{len(result['baked'])} baked)")
        return {"FINISHED"}


class OBJECT_PT_phong_bake(bpy.types.Panel):
    """Bake Phong Lighting of the selected objects"""

    bl_idname = "OBJECT_PT_phong_bake"
    bl_label = "Phong Bake"
    bl_space_type = "PROPERTIES"
    bl_region_type = "WINDOW"
    bl_context = "object"
    bl_options = {"DEFAULT_CLOSED"}

    @classmethod
    def poll(cls, context):
        return context.object is not None and context.object.type == "MESH"

    def draw(self, context):
        layout = self.layout
        obj = context.object
        info = obj.get(lighting.INFO_KEY)
        if info is None:
            layout.label(text="Not baked")
        else:
            layout.label(text=f"Baked: {info['term'].title()} into "
                              f"{'an image' if info['target'] == 'IMAGE' else 'vertex colours'}"
                              f" (view {info['view'].title()})")
        layout.operator(PHONG_OT_bake_lighting.bl_idname, icon="RENDER_STILL")
        row = layout.row(align=True)
        row.operator(PHONG_OT_show_bake.bl_idname, icon="HIDE_OFF")
        row.operator(PHONG_OT_restore_bake.bl_idname, icon="LOOP_BACK")


def _draw_object_menu(self, _context):
    self.layout.operator(PHONG_OT_bake_lighting.bl_idname, icon="RENDER_STILL")
    self.layout.operator(PHONG_OT_show_bake.bl_idname)
    self.layout.operator(PHONG_OT_restore_bake.bl_idname)


def _draw_export_menu(self, _context):
    self.layout.operator(PHONG_OT_export_gltf.bl_idname,
                         text="glTF with Baked Phong Lighting (.glb/.gltf)")


classes = (PHONG_OT_bake_lighting, PHONG_OT_show_bake, PHONG_OT_restore_bake,
           PHONG_OT_export_gltf, OBJECT_PT_phong_bake)
_register_classes, _unregister_classes = bpy.utils.register_classes_factory(classes)


def register():
    _register_classes()
    bpy.types.VIEW3D_MT_object.append(_draw_object_menu)
    bpy.types.TOPBAR_MT_file_export.append(_draw_export_menu)


def unregister():
    bpy.types.TOPBAR_MT_file_export.remove(_draw_export_menu)
    bpy.types.VIEW3D_MT_object.remove(_draw_object_menu)
    _unregister_classes()
