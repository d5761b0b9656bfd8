# SPDX-License-Identifier: GPL-3.0-or-later
"""Phong Nodes: the textbook Phong lighting model as shader node groups.

The package holds two pure packages that never import ``bpy`` (``node_groups``: what each
group computes; ``core``: scene files, comparison, report) and the Blender layer
(``addon``), which Blender imports only when it registers the extension: importing
``phong_nodes`` in a Python without ``bpy`` works.
"""


def register():
    from .addon import register as register_addon

    register_addon()


def unregister():
    from .addon import unregister as unregister_addon

    unregister_addon()
