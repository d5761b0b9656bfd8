# SPDX-License-Identifier: GPL-3.0-or-later
"""The Blender layer, by feature; its rooms from the ground up (docs/architecture.md), each
importing only the rooms before it (tests/test_layout.py):

* ``compat``      every difference between Blender releases;
* ``loader``      the library's groups into the file: version stamps, upgrade in place, merge
  of appended copies (their users keep their links by socket name);
* ``lighting``    Phong materials driven by Blender lights: the material recipe, the lights
  groups, Eevee's light loop, the World's copies of the lights' transforms, the lights' and
  World's Phong settings, Apply / Relink / Restore;
* ``shading``     Per Vertex / Per Face shading;
* ``scene``       exact render settings, the scene as plain data, meshes, framing;
* ``interchange`` OBJ/MTL, COLLADA, FBX and X3D import and export, three.js pages;
* ``baking``      Bake Phong Lighting into images and vertex colours, showing the bake, glTF;
* ``comparison``  Eevee, Cycles and the peers against the numpy reference, into a report;
* ``demos``       demo scenes from ``scenes/*.toml``;
* ``ui``          every operator, menu and panel, and the asset library of the groups.

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
