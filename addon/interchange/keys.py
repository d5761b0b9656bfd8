# SPDX-License-Identifier: GPL-3.0-or-later
"""The round-trip keys: what an import leaves on Blender data (custom properties, node names)
for the export of the same format to read back, so that import → export keeps the file's own
values where the Phong controls cannot tell them (docs/contract.md, "Round-trip keys").  The
importers write them and the exporters read them here: no exporter imports an importer."""

from __future__ import annotations

from ...core import fbx, x3d
from ..lighting import recipe

# -- MTL (obj_import → mtl_export) ------------------------------------------------------------
#: material: the MTL illumination model it was read as (0, 1 or 2).
MTL_ILLUM = "phong_mtl_illum"

# -- COLLADA (collada_import → collada_export) -------------------------------------------------
#: material: the file's profile_COMMON technique (constant, lambert, phong, blinn).
COLLADA_TECHNIQUE = "phong_collada_technique"
#: material: the file's <transparent opaque="..."> mode.
COLLADA_OPAQUE = "phong_collada_opaque"
#: material: the file's <transparent> colour (RGBA).
COLLADA_TRANSPARENT = "phong_collada_transparent"
#: material: the file's <transparency> value.
COLLADA_TRANSPARENCY = "phong_collada_transparency"
#: Image Texture node of an imported <texture>: + the lights-group input (or "transparent").
COLLADA_TEXTURE_NODE = "phong_dae_map:"
#: lights-group input -> COLLADA element.
COLLADA_INPUTS = {"Irradiant Color": "emission", recipe.AMBIENT_INPUT: "ambient",
                  "Object Color": "diffuse", "Specular Color": "specular"}

# -- FBX (fbx_import → fbx_export) -------------------------------------------------------------
#: material: the maps of the file whose image was not there ({FBX property: {"path": the
#: file's absolute name, "near": its relative name resolved beside the file read}}): the
#: export writes the references back, as the file had them.
FBX_MISSING_MAPS = "phong_fbx_missing_maps"
#: core.fbx's texture slot -> the FBX property the export writes it on.
FBX_SLOT_PROPS = fbx.PROPERTY_OF

# -- X3D / VRML97 (x3d_import → x3d_export) ----------------------------------------------------
#: material: the file's ambientIntensity.
X3D_AMBIENT = "phong_x3d_ambient_intensity"
#: material: the file's shininess.
X3D_SHININESS = "phong_x3d_shininess"
#: material: the file's TextureTransform (center, rotation, scale, translation).
X3D_TRANSFORM = "phong_x3d_texture_transform"
#: material: made for a shape without Material.
X3D_UNLIT = "phong_x3d_unlit"
#: image: the components of the PixelTexture it was made from (1 grey ... 4 RGBA).
X3D_COMPONENTS = "phong_x3d_components"
#: material: the ImageTexture whose file was not there at import ({"name", "paths": the
#: absolute files its urls name, "repeat_s", "repeat_t"}): the export writes the reference.
X3D_MISSING_TEXTURE = "phong_x3d_missing_texture"
#: the DEF of the DirectionalLight (intensity 0, global) that carries the World's Phong ambient
#: light, which X3D lacks: written by the export, read back into the World by the import.
X3D_WORLD_AMBIENT = x3d.WORLD_AMBIENT
#: spot light: the file's cutOffAngle.
X3D_CUT_OFF = "phong_x3d_cut_off_angle"
#: light object: a scoped light whose scope holds no shape.
X3D_LIGHTS_NOTHING = "phong_x3d_lights_nothing"
#: the Mapping node of a material's texture (its TextureTransform).
X3D_MAPPING_NODE = "phong_x3d_mapping"
#: the UV map of imported texture coordinates.
X3D_UV_MAP = "UVMap"
#: the suffix of a light that is off (``on FALSE``: the light hidden from render).
X3D_OFF = " (off)"
#: X3D light kind -> Blender light type.
X3D_LIGHT_TYPES = {"directional": "SUN", "point": "POINT", "spot": "SPOT"}
