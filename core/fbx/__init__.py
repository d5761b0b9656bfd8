# SPDX-License-Identifier: GPL-3.0-or-later
"""FBX's Phong parts read and written without ``bpy``.

The package, each module importing only those before it (``tests/test_layout.py``):
``model`` (the one data model of both directions: :class:`Material`, :class:`Light`,
:class:`Texture`, a read :class:`Scene`, the FBX SDK's defaults), ``read`` (a file read by
ufbx in a child process: :func:`read`, :func:`start`), ``phong`` (the Phong mapping both
ways, pure: a light's, a material's and the ambient's values to the model and back),
``write`` (the Phong parts spliced into the binary FBX that Blender's exporter wrote:
:func:`rewrite`).  ``addon/interchange/fbx_import.py`` and ``fbx_export.py`` are the Blender
side.  Every name callers use is imported here: ``fbx.read(path)``.
"""

from .model import (
    ALIASES, BLACK, LIGHT_DEFAULTS, LIGHT_TYPES, NON_COLOR_USER, OPACITY_MAPS, PROPERTY_OF,
    SLOTS, SURFACE_DEFAULTS, TEXTURE_SLOTS, USER, FbxError, Light, Material, MeshData, Node,
    Scene, Texture)
from .read import (BLENDER_CREATOR, MAX_EMBEDDED, MEMORY_LIMIT, PHONG_ONLY, TIME_LIMIT, Reading,
                   from_scene, items, load, lookup, phong_like, read, read_light, read_material,
                   start, user_props)
from .phong import (COLOURS, EXPORTED, SETTINGS, WRITTEN_TYPES, ambient_of, falloff,
                    keep_unsaid, light_of, light_settings, material_of, material_values,
                    spot_edge_exponent, world_ambient)
from .write import FbxWriteError, material_props, light_props, rewrite

__all__ = [
    "ALIASES", "BLACK", "LIGHT_DEFAULTS", "LIGHT_TYPES", "NON_COLOR_USER", "OPACITY_MAPS",
    "PROPERTY_OF", "SLOTS", "SURFACE_DEFAULTS", "TEXTURE_SLOTS", "USER", "FbxError", "Light",
    "Material", "MeshData", "Node", "Scene", "Texture", "BLENDER_CREATOR", "MAX_EMBEDDED",
    "MEMORY_LIMIT", "PHONG_ONLY", "TIME_LIMIT", "Reading", "from_scene", "items", "load",
    "lookup", "phong_like", "read", "read_light", "read_material", "start", "user_props",
    "COLOURS", "EXPORTED", "SETTINGS", "WRITTEN_TYPES", "ambient_of", "falloff", "keep_unsaid",
    "light_of", "light_settings", "material_of", "material_values", "spot_edge_exponent",
    "world_ambient", "FbxWriteError", "material_props", "light_props", "rewrite",
]
