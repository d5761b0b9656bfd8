# SPDX-License-Identifier: GPL-3.0-or-later
"""The Blender layer: operators and menus.  Register and unregister are symmetric."""

from . import demo_ops, materials, menus, operators, panels, properties

_modules = (operators, menus, properties, materials, panels, demo_ops)


def register():
    for module in _modules:
        module.register()


def unregister():
    for module in reversed(_modules):
        module.unregister()
