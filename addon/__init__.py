# SPDX-License-Identifier: GPL-3.0-or-later
"""The Blender layer: operators, menus, panels, properties and handlers.

Register and unregister are symmetric."""

from . import demo_ops, handlers, materials, menus, operators, panels, properties

_modules = (operators, menus, properties, materials, panels, demo_ops, handlers)


def register():
    for module in _modules:
        module.register()


def unregister():
    for module in reversed(_modules):
        module.unregister()
