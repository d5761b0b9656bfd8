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

import bpy

from . import loader
from .lighting import forwarding as lighting_forwarding
from .lighting import convert, opacity, properties, sync
from .scene import describe
from .shading import forwarding as shading_forwarding
from .shading import modes
from .shading import properties as shading_properties
from .ui import assets, baking, collada_ui, fbx_ui, menus, operators, panels, x3d_ui

_modules = (operators, menus, properties, shading_properties, panels, baking, assets,
            collada_ui, fbx_ui, x3d_ui)

#: Every handler of the extension, (event of ``bpy.app.handlers``, function), in the order
#: Blender runs them: each room's ordered list, the lighting room's last (its relink frees
#: and edits data blocks that the other handlers' depsgraph updates still name:
#: ``sync.HANDLERS``).  Checked by tests/test_register.py.
HANDLERS = (*modes.HANDLERS, *loader.HANDLERS, *sync.HANDLERS)


def connect(on: bool = True) -> None:
    """Set (*on*) or clear the upward calls: a lower module calls a higher one at runtime
    through a callable set here (it never imports it), each named where it is read:

    * ``lighting.sync.AFTER_FINISH``: ``shading.modes.refresh``, at the end of every Apply /
      Relink (the Per Vertex / Per Face groups follow the lights);
    * ``lighting.forwarding`` (the Lighting Model's setter): ``lighting.sync.relink_scene``
      (the switch rebuilds the scene's lights groups; the settings never import the sync
      that builds on them);
    * ``shading.forwarding`` (the Shading's and Opacity's setters, which hold no ``bpy``):
      ``shading.modes.update`` and ``lighting.opacity.set_opacity``;
    * ``lighting.convert.AFTER_APPLY``: ``scene.describe.hollow_notes`` (Apply's report names
      the converted objects that render no Phong surface).
    """
    if modes.refresh in sync.AFTER_FINISH:
        sync.AFTER_FINISH.remove(modes.refresh)
    if describe.hollow_notes in convert.AFTER_APPLY:
        convert.AFTER_APPLY.remove(describe.hollow_notes)
    if on:
        sync.AFTER_FINISH.append(modes.refresh)
        convert.AFTER_APPLY.append(describe.hollow_notes)
    lighting_forwarding.set_model_callback(sync.relink_scene if on else None)
    shading_forwarding.set_callback(modes.update if on else None)
    shading_forwarding.set_opacity_callback(opacity.set_opacity if on else None)


def register():
    for module in _modules:
        module.register()
    connect(True)
    for event, function in HANDLERS:
        getattr(bpy.app.handlers, event).append(function)


def unregister():
    for event, function in reversed(HANDLERS):
        handlers = getattr(bpy.app.handlers, event)
        if function in handlers:
            handlers.remove(function)
    connect(False)
    for module in reversed(_modules):
        module.unregister()
