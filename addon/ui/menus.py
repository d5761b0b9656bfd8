# SPDX-License-Identifier: GPL-3.0-or-later
"""Shift+A ▸ Phong in the Shader Editor; the File ▸ Import and File ▸ Export entries of every
format without a module of its own here (OBJ, MTL, three.js; FBX's import), their labels from
``interchange/formats.py``."""

import bpy

from . import file_io
from .operators import PHONG_OT_add_node_group, PHONG_OT_load_node_groups

#: The sections of Shift+A ▸ Phong, also the asset catalogs (``assets.py``).
SECTIONS = (
    ("Lights", ("Phong Directional Light", "Phong Point Light", "Phong Spot Light",
                "Phong Power Falloff")),
    ("Terms", ("Phong Irradiant", "Phong Ambient", "Phong Diffuse", "Phong Specular",
               "Phong Blinn Specular")),
    ("Colour", ("Phong Color Add", "Phong Color Multiply")),
    ("Model", ("Phong Shading",)),
    ("three.js", ("three.js Point Light", "three.js Spot Light", "three.js Ambient",
                  "three.js Phong")),
    ("X3D", ("X3D Directional Light", "X3D Point Light", "X3D Spot Light")),  # and VRML97
)


class NODE_MT_phong_add(bpy.types.Menu):
    """Node groups of the textbook Phong lighting model"""

    bl_idname = "NODE_MT_phong_add"
    bl_label = "Phong"

    def draw(self, context):
        layout = self.layout
        for index, (_title, names) in enumerate(SECTIONS):
            if index:
                layout.separator()
            for name in names:
                op = layout.operator(PHONG_OT_add_node_group.bl_idname,
                                     text=name.removeprefix("Phong "))
                op.group_name = name
        layout.separator()
        layout.operator(PHONG_OT_load_node_groups.bl_idname, icon="FILE_REFRESH")


def _draw_add_menu(self, context):
    space = context.space_data
    if space is not None and getattr(space, "tree_type", None) == "ShaderNodeTree":
        self.layout.separator()
        self.layout.menu(NODE_MT_phong_add.bl_idname)


def _draw_export_menu(self, _context):
    for key in ("obj", "mtl", "threejs"):
        file_io.menu_entry(self, key, "export")


def _draw_import_menu(self, _context):
    for key in ("obj", "fbx"):
        file_io.menu_entry(self, key, "import")


def register():
    bpy.utils.register_class(NODE_MT_phong_add)
    bpy.types.NODE_MT_add.append(_draw_add_menu)
    bpy.types.TOPBAR_MT_file_export.append(_draw_export_menu)
    bpy.types.TOPBAR_MT_file_import.append(_draw_import_menu)


def unregister():
    bpy.types.TOPBAR_MT_file_import.remove(_draw_import_menu)
    bpy.types.TOPBAR_MT_file_export.remove(_draw_export_menu)
    bpy.types.NODE_MT_add.remove(_draw_add_menu)
    bpy.utils.unregister_class(NODE_MT_phong_add)
