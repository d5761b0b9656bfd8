# SPDX-License-Identifier: GPL-3.0-or-later
"""Operators on the node-group library."""

import bpy
from bpy.props import StringProperty

from ..node_groups import loader
from ..node_groups.library import GROUPS


class PHONG_OT_load_node_groups(bpy.types.Operator):
    """Put every Phong node group into this file (creates, or upgrades in place)"""

    bl_idname = "phong.load_node_groups"
    bl_label = "Load Phong Node Groups"
    bl_options = {"REGISTER", "UNDO"}

    def execute(self, context):
        summary = loader.load_all()
        parts = [f"{len(names)} {status}" for status, names in summary.items()]
        self.report({"INFO"}, f"Phong node groups: {', '.join(parts)}")
        return {"FINISHED"}


class PHONG_OT_add_node_group(bpy.types.Operator):
    """Add a Phong node group to the active shader node tree"""

    bl_idname = "phong.add_node_group"
    bl_label = "Add Phong Node Group"
    bl_options = {"REGISTER", "UNDO"}

    group_name: StringProperty(name="Group", description="Name of the Phong node group to add")

    @classmethod
    def poll(cls, context):
        space = context.space_data
        return (space is not None and space.type == "NODE_EDITOR"
                and space.tree_type == "ShaderNodeTree" and space.edit_tree is not None)

    @classmethod
    def description(cls, context, properties):
        group = GROUPS.get(properties.group_name)
        return group.description if group else cls.__doc__

    def _check(self):
        if self.group_name not in GROUPS:
            self.report({"ERROR"}, f"Unknown Phong group {self.group_name!r}; "
                                   f"expected one of: {', '.join(GROUPS)}")
            return False
        return True

    def execute(self, context):
        if not self._check():
            return {"CANCELLED"}
        tree, _status = loader.ensure_group(self.group_name)
        edit_tree = context.space_data.edit_tree
        for node in edit_tree.nodes:
            node.select = False
        node = edit_tree.nodes.new("ShaderNodeGroup")
        node.node_tree = tree
        node.location = context.space_data.cursor_location
        node.select = True
        edit_tree.nodes.active = node
        return {"FINISHED"}

    def invoke(self, context, event):
        if not self._check():
            return {"CANCELLED"}
        tree, _status = loader.ensure_group(self.group_name)
        bpy.ops.node.add_node("INVOKE_DEFAULT", type="ShaderNodeGroup", use_transform=True)
        node = context.space_data.edit_tree.nodes.active
        if node is not None and node.bl_idname == "ShaderNodeGroup":
            node.node_tree = tree
        return {"FINISHED"}


classes = (PHONG_OT_load_node_groups, PHONG_OT_add_node_group)


def register():
    for cls in classes:
        bpy.utils.register_class(cls)


def unregister():
    for cls in reversed(classes):
        bpy.utils.unregister_class(cls)
