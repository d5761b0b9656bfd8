# SPDX-License-Identifier: GPL-3.0-or-later
"""The Blender layer, by feature.

* ``loader``   the library's groups into the file: version stamps, upgrade in place, merge
  of appended copies;
* ``lighting`` Phong materials driven by Blender lights: the material recipe, drivers, the
  lights' and world's Phong settings;
* ``demos``    demo scenes from ``scenes/*.toml``, exact render settings, the comparison bake;
* ``baking``   Bake Phong Lighting into images and vertex colours, showing the bake, glTF;
* ``ui``       every operator, menu and panel, and the asset library of the groups;
* ``compat``   every difference between Blender versions.

Register and unregister are symmetric.
"""

from . import loader
from .lighting import properties, sync
from .shading import properties as shading_properties
from .ui import assets, baking, collada_ui, fbx_ui, menus, operators, panels, x3d_ui

_modules = (operators, menus, properties, shading_properties, panels, baking, loader, sync,
            assets, collada_ui, fbx_ui, x3d_ui)


def register():
    for module in _modules:
        if module is properties:
            # the model switch rebuilds the scene's lights groups: the settings are handed
            # the rebuild, so that they never import the sync that builds on them
            module.register(on_model_change=sync.relink_scene)
        else:
            module.register()


def unregister():
    for module in reversed(_modules):
        module.unregister()
