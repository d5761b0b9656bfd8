# SPDX-License-Identifier: GPL-3.0-or-later
"""The one data model of FBX's Phong parts, for both directions: what ``read`` makes of a file
(by ufbx) and what ``write`` splices into a file that Blender's exporter wrote, with the FBX
SDK's defaults and names that both use.  ``phong`` maps it to and from the project's Phong
values.

* :class:`Material`: a Phong, Lambert (or, read, another) material: its colours by the lights
  group's input, exponent, opacity (and the SDK's opacity pair where a map gives it), its maps
  by the input (or opacity property) they multiply, the user properties ``PhongNodes|...``;
* :class:`Light`: LightType as Blender's light type, colour, i0 = Intensity / 100, DecayType,
  a spot's full cone angles in degrees, CastShadows;
* :class:`Texture`: an image file (where it is looked for; where it is written);
* :class:`Scene`, :class:`Node`, :class:`MeshData`: what a read of a file holds.

No ``bpy``, no package import: the reader's child process runs ``read`` as a script, which
imports this module as its neighbour.
"""

from __future__ import annotations

import os
from dataclasses import dataclass, field

#: FBX SDK class defaults of FbxSurfaceLambert / FbxSurfacePhong (what the SDK writes in its
#: own PropertyTemplate "FbxSurfacePhong"; Lambert's are the same without the specular ones).
SURFACE_DEFAULTS = {
    "EmissiveColor": (0.0, 0.0, 0.0), "EmissiveFactor": 1.0,
    "AmbientColor": (0.2, 0.2, 0.2), "AmbientFactor": 1.0,
    "DiffuseColor": (0.8, 0.8, 0.8), "DiffuseFactor": 1.0,
    "TransparentColor": (0.0, 0.0, 0.0), "TransparencyFactor": 0.0,
    "SpecularColor": (0.2, 0.2, 0.2), "SpecularFactor": 1.0,
    "ShininessExponent": 20.0,
    "ReflectionColor": (0.0, 0.0, 0.0), "ReflectionFactor": 1.0,
}
#: FBX SDK class defaults of FbxLight (its template as the SDK writes it: InnerAngle 0,
#: OuterAngle 45; fbxlight.h's comment says 45 for InnerAngle too, the SDK writes 0).
LIGHT_DEFAULTS = {"Color": (1.0, 1.0, 1.0), "Intensity": 100.0, "LightType": 0,
                  "DecayType": 0, "InnerAngle": 0.0, "OuterAngle": 45.0, "CastShadows": 1.0}
#: Older names of a property (FBX 6.1 and before), looked up after the current one.
ALIASES = {"InnerAngle": ("InnerAngle", "HotSpot"), "OuterAngle": ("OuterAngle", "Cone angle")}
#: FbxLight::EType and how a Blender light stands in for it.
LIGHT_TYPES = {0: "POINT", 1: "SUN", 2: "SPOT", 3: "AREA", 4: "VOLUME"}
#: The colour slots of the Phong model: lights-group input -> (colour, factor) properties.
SLOTS = {
    "Object Color": ("DiffuseColor", "DiffuseFactor"),
    "Ambient Object Color": ("AmbientColor", "AmbientFactor"),
    "Specular Color": ("SpecularColor", "SpecularFactor"),
    "Irradiant Color": ("EmissiveColor", "EmissiveFactor"),
}
#: Texture slots read (a texture on the colour multiplies colour × factor; one on the factor
#: too): property -> lights-group input.
TEXTURE_SLOTS = {"DiffuseColor": "Object Color", "AmbientColor": "Ambient Object Color",
                 "SpecularColor": "Specular Color", "EmissiveColor": "Irradiant Color",
                 # the legacy names some older files connect textures to
                 "Diffuse": "Object Color", "Ambient": "Ambient Object Color",
                 "Specular": "Specular Color", "Emissive": "Irradiant Color",
                 # scalar and opacity slots: the map multiplies its property
                 "TransparentColor": "TransparentColor", "TransparencyFactor": "TransparencyFactor",
                 "ShininessExponent": "Exponent", "Shininess": "Exponent"}
#: The keys of ``Material.textures`` that are not colour inputs of the lights group: the two
#: properties of the opacity (1 − TransparencyFactor × mean(TransparentColor)) and the exponent.
OPACITY_MAPS = ("TransparentColor", "TransparencyFactor")
#: The FBX property of each key of :attr:`Material.textures` (the inverse of the primary names
#: of :data:`TEXTURE_SLOTS`): what a map multiplies, written on that property.
PROPERTY_OF = {"Object Color": "DiffuseColor", "Ambient Object Color": "AmbientColor",
               "Specular Color": "SpecularColor", "Irradiant Color": "EmissiveColor",
               "Exponent": "ShininessExponent", "TransparentColor": "TransparentColor",
               "TransparencyFactor": "TransparencyFactor"}
#: The prefix of the user properties Phong Nodes' FBX export writes for what FBX cannot say
#: (``write``), read back into :attr:`Material.user`, :attr:`Light.user` and
#: :attr:`Scene.user`: a Phong material's Blinn, Specular Strength and a Lambert's exponent;
#: a light's Phong settings; the World's ambient intensity.
USER = "PhongNodes|"
#: The user property (+ the FBX property) Phong Nodes' export writes for a colour map whose
#: image is data (Non-Color), read back in that colour space.
NON_COLOR_USER = "NonColor"


class FbxError(ValueError):
    """A file that cannot be read as FBX: names the file and what is wrong."""

    def __init__(self, path: str, message: str):
        self.path = path
        super().__init__(f"{path}: {message}")


@dataclass
class Texture:
    """An image file that multiplies a material property (FBX Texture and Video objects)."""
    name: str                 # the file name as the file states it (read) or its base name
    candidates: tuple = ()    # where it is looked for, first existing wins (written: its path)
    content: bytes | None = None   # the file's bytes (FBX Video Content), or None
    prop: str = ""            # read: the material property it is connected to
    element: str = ""         # read: the Texture element's name
    relative: str = ""        # written: its path relative to the FBX file's folder
    data: bool = False        # written: the image is read as data (Non-Color), not a colour

    @property
    def path(self) -> str:
        """Its absolute path (written), the first place it is looked for (read)."""
        return self.candidates[0] if self.candidates else ""

    @property
    def resolved(self) -> str | None:
        for path in self.candidates:
            if path and os.path.isfile(path):
                return path
        return None


#: The colours of a material before a file or a Phong material gives them: black.
BLACK = (0.0, 0.0, 0.0)


def _no_colours() -> dict:
    return {slot: BLACK for slot in SLOTS}


@dataclass
class Material:
    """A material as FBX says it (linear colours), read from a file or to be written."""
    name: str = ""
    kind: str = "PHONG"       # "PHONG", "LAMBERT" or (read) "OTHER" (PBR, Arnold, ShaderFX ...)
    shading: str = ""         # the file's ShadingModel (or ufbx's shader name)
    colors: dict = field(default_factory=_no_colours)   # lights-group input -> (r, g, b)
    exponent: float = 20.0
    opacity: float = 1.0
    blinn: bool = False
    # the opacity is the alpha of the TransparencyFactor / TransparentColor map, as Blender's
    # importer reads it (a file of Blender's exporter, which writes its alpha texture there)
    alpha_map: bool = False
    user: dict = field(default_factory=dict)     # USER properties: key -> float
    #: the SDK's opacity pair 1 − TransparencyFactor × mean(TransparentColor): read, the
    #: file's (for its maps); written, where a map gives the opacity (None: 1 − opacity and
    #: white, the pair for the Opacity alone)
    transparent_color: tuple | None = None
    transparency_factor: float | None = None
    textures: dict = field(default_factory=dict)  # key of PROPERTY_OF -> Texture
    raw: dict = field(default_factory=dict)      # read: property -> value used
    sources: dict = field(default_factory=dict)  # read: property -> object/template/default
    unsupported: list = field(default_factory=list)

    @property
    def lambert(self) -> bool:
        return self.kind == "LAMBERT"


@dataclass
class Light:
    """A light as FBX says it."""
    type: str                 # POINT, SUN, SPOT (read: AREA and VOLUME become POINT)
    color: tuple = (1.0, 1.0, 1.0)
    intensity: float = 1.0    # the Phong i0: FBX Intensity / 100
    decay: int = 0            # FbxLight::EDecayType 0..3 (k of 1/d^k)
    outer_angle: float = 45.0     # degrees, full cone (spot)
    inner_angle: float = 0.0      # degrees, full cone (spot)
    cast_shadows: bool = True  # CastShadows (the SDK's default: true): Blender's Cast Shadow
    user: dict = field(default_factory=dict)     # USER properties: key -> float
    name: str = ""            # read: the light (NodeAttribute) name
    nodes: tuple = ()         # read: names of the nodes (objects) that hold it
    fbx_type: int = -1        # read: FbxLight::EType
    sources: dict = field(default_factory=dict)


@dataclass
class Scene:
    path: str
    version: int
    ascii: bool
    creator: str
    ambient: tuple
    materials: list
    lights: list
    warnings: list
    nodes: list = field(default_factory=list)    # Node, parents first (with geometry only)
    meshes: dict = field(default_factory=dict)   # mesh id -> MeshData
    user: dict = field(default_factory=dict)     # GlobalSettings' USER properties

    def material(self, name):
        return next((m for m in self.materials if m.name == name), None)

    def light(self, name):
        return next((l for l in self.lights if l.name == name or name in l.nodes), None)


@dataclass
class Node:
    """A node of the file (with geometry): its matrix is relative to its parent node, or the
    world's (Z up, metres) for a top-level node."""
    id: int
    name: str
    parent: int | None
    matrix: tuple             # 4 rows of 4
    kind: str                 # MESH, LIGHT, CAMERA or EMPTY
    data: str                 # name of its mesh / light / camera
    mesh: int | None = None
    materials: tuple = ()     # material names, by slot
    light: dict | None = None     # {"type": POINT/SUN/SPOT}
    camera: dict | None = None    # {"ortho", "fov_x", "ortho_size", "near", "far"}
    visible: bool = True


@dataclass
class MeshData:
    positions: object         # (V, 3) float64
    loop_vertex: object       # (L,) int32
    face_sizes: object        # (F,) int32
    face_material: object     # (F,) int32
    normals: object = None    # (L, 3) float64 or None
    uvs: list = field(default_factory=list)      # (name, (L, 2) float64)
    colors: list = field(default_factory=list)   # (name, (L, 4) float64)
