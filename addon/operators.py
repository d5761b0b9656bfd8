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
        if (space is not None and space.type == "NODE_EDITOR"
                and space.tree_type == "ShaderNodeTree" and space.edit_tree is not None):
            return True
        cls.poll_message_set("Add Phong Node Group: open a material's node tree in the "
                             "Shader Editor first")
        return False

    @classmethod
    def description(cls, context, properties):
        group = GROUPS.get(properties.group_name)
        return group.description if group else cls.__doc__

    def execute(self, context):
        space = context.space_data
        try:
            add_group_node(space.edit_tree, self.group_name, space.cursor_location)
        except ValueError as error:
            self.report({"ERROR"}, f"Add Phong Node Group: {error}")
            return {"CANCELLED"}
        return {"FINISHED"}

    def invoke(self, context, event):
        result = self.execute(context)
        if result == {"FINISHED"}:  # follow the mouse, like Blender's own Add menu
            bpy.ops.node.translate_attach_remove_on_cancel("INVOKE_DEFAULT")
        return result


def add_group_node(tree, group_name: str, location):
    """Add a node of the Phong group *group_name* (loaded or upgraded as needed) to *tree*."""
    if group_name not in GROUPS:
        raise ValueError(f"Unknown Phong group {group_name!r}; expected one of: {', '.join(GROUPS)}")
    group, _status = loader.ensure_group(group_name)
    for node in tree.nodes:
        node.select = False
    node = tree.nodes.new("ShaderNodeGroup")
    node.node_tree = group
    node.location = location
    node.width = 200
    node.select = True
    tree.nodes.active = node
    return node


classes = (PHONG_OT_load_node_groups, PHONG_OT_add_node_group)


register, unregister = bpy.utils.register_classes_factory(classes)
