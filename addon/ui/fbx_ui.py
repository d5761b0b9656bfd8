# SPDX-License-Identifier: GPL-3.0-or-later
"""The operators of File ▸ Import ▸ FBX (Phong) and File ▸ Export ▸ FBX (.fbx) with Phong
Materials, and the drop handler of .fbx files (their entries and suffixes
from ``interchange/formats.py``)."""

import bpy
from bpy.props import BoolProperty, EnumProperty, FloatProperty, StringProperty
from bpy_extras.io_utils import ExportHelper

from . import file_io

_AXES = [(a, a, "") for a in ("X", "Y", "Z", "-X", "-Y", "-Z")]


class PHONG_OT_import_fbx(bpy.types.Operator, file_io.DroppableImport):
    """Import an FBX file with its Phong and Lambert materials and its lights as exact Phong \
values (binary 7100+ through Blender's importer, ASCII and FBX 6.1 through ufbx)"""

    bl_idname = "phong.import_fbx"
    bl_label = "Import FBX (Phong)"

    filename_ext = ".fbx"
    filter_glob: StringProperty(default=file_io.glob("fbx"), options={"HIDDEN"})

    def execute(self, context):
        return file_io.run_import(self, context, "fbx")


class PHONG_OT_export_fbx(bpy.types.Operator, ExportHelper):
    """Export FBX with Blender's own exporter, then every Phong material as an FBX Phong or \
Lambert material, every Phong light with its intensity, decay and cone, and the World's \
Phong ambient"""

    bl_idname = "phong.export_fbx"
    bl_label = "Export FBX with Phong Materials"
    bl_options = {"REGISTER"}

    filename_ext = ".fbx"
    filter_glob: StringProperty(default=file_io.glob("fbx"), options={"HIDDEN"})
    use_selection: BoolProperty(name="Selected Objects Only", default=False,
                                description="Only the selected objects")
    # Blender's FBX options passed through (bpy.ops.export_scene.fbx), as its defaults
    global_scale: FloatProperty(name="Scale", default=1.0, min=0.001, max=1000.0)
    apply_unit_scale: BoolProperty(name="Apply Unit", default=True)
    axis_forward: EnumProperty(name="Forward", items=_AXES, default="-Z")
    axis_up: EnumProperty(name="Up", items=_AXES, default="Y")
    use_mesh_modifiers: BoolProperty(name="Apply Modifiers", default=True)
    use_triangles: BoolProperty(name="Triangulate Faces", default=False)
    use_custom_props: BoolProperty(name="Custom Properties", default=False)
    bake_anim: BoolProperty(name="Baked Animation", default=True)
    path_mode: EnumProperty(name="Path Mode", default="AUTO", items=[
        (m, m.title(), "") for m in ("AUTO", "ABSOLUTE", "RELATIVE", "MATCH", "STRIP", "COPY")])
    embed_textures: BoolProperty(name="Embed Textures", default=False)

    PASSED = ("global_scale", "apply_unit_scale", "axis_forward", "axis_up",
              "use_mesh_modifiers", "use_triangles", "use_custom_props", "bake_anim",
              "path_mode", "embed_textures")

    def execute(self, context):
        options = {key: getattr(self, key) for key in self.PASSED}
        return file_io.run_export(self, context, "fbx", self.use_selection, **options)


classes = (PHONG_OT_import_fbx, PHONG_OT_export_fbx, *file_io.drop_handler("fbx"))


def _draw_export(self, _context):
    file_io.menu_entry(self, "fbx", "export")


def register():
    for cls in classes:
        bpy.utils.register_class(cls)
    bpy.types.TOPBAR_MT_file_export.append(_draw_export)


def unregister():
    bpy.types.TOPBAR_MT_file_export.remove(_draw_export)
    for cls in reversed(classes):
        bpy.utils.unregister_class(cls)
