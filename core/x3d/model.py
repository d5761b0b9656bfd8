# SPDX-License-Identifier: GPL-3.0-or-later
"""The data model of a VRML97 / X3D file: plain data, no behaviour but small helpers.

Everything is in the file's own axes (Y up, viewer looking along -Z, right-handed) and units
(see ``Document.meter``); angles are radians (a file's ``UNIT angle`` is applied on reading).
Nothing here converts to Blender's Z up: :func:`to_blender_matrix` gives the matrix (a
rotation of +90° about X, times ``Document.meter``) that the Blender side puts in front of
every world matrix, at the root.

* The scene graph: :class:`Transform` (every grouping node: Group, Transform, Anchor,
  Billboard, Collision, StaticGroup, Switch (only its chosen child), LOD (only its first,
  most detailed, level), MatrixTransform, CADAssembly/CADLayer/CADPart/CADFace, HAnim
  humanoid/joint/segment/site, Inline (the inlined file's nodes), a PROTO instance that expands
  to a group) with ``name`` (its DEF, "" without), ``kind`` (the node type read), ``matrix``
  (4×4 local matrix: T·C·R·SR·S·SR⁻¹·C⁻¹ for a Transform) and ``children``: Transform,
  :class:`Shape`, :class:`Light` and :class:`Viewpoint` objects, in file order.

* **DEF/USE is identity**: a USE'd node is the same Python object wherever it is used (a
  Transform, a Shape, a Mesh, an Appearance, a Material, a Texture), so the Blender side can
  share mesh data and materials; so is a PROTO instance USE'd, a file inlined twice, and the
  part of a PROTO's body that no IS field reaches (shared by all its instances).  Arrays may
  be shared too (a USE'd Coordinate, primitives of equal fields): treat them as read-only.

* :class:`Shape`: ``name``, ``geometry`` (a :class:`Mesh`, None when the file gives none:
  KiCad's files define their materials in Shapes without geometry) and ``appearance`` (an
  :class:`Appearance`: ``material``, ``texture``, ``texture_transform``; None when missing).
  ``Shape.material`` is None for a shape without Material: **unlit**, white, or its texture
  or colours (the standard's rule).

* :class:`Material`: ``name`` (its DEF; without one the DEF of its Appearance, else of its
  Shape, else of the nearest named group, else "Material"), ``diffuse``, ``ambient_intensity``,
  ``specular``, ``emissive`` (RGB tuples), ``shininess`` (0..1 as in the file),
  ``transparency``, ``kind`` ("material"; "two_sided": a TwoSidedMaterial, its front values,
  ``back`` a Material of its back values when ``separateBackColor``; "physical": an X3D 4
  PhysicalMaterial, baseColor as diffuse; "unlit": an X3D 4 UnlitMaterial, its colour as
  emissive, everything else black).  :func:`phong_values` maps it to the project's Phong
  parameters.

* :class:`Texture`: ``name`` (its DEF), ``urls`` (as written), ``paths`` (each local
  candidate resolved relative to
  the file that names it, absolute), ``path`` (the first candidate that exists, else None),
  ``repeat_s`` / ``repeat_t``, ``kind`` (ImageTexture or PixelTexture), for a PixelTexture
  ``image`` ((height, width, components) uint8, first row the bottom one, as the file) and
  ``components``.  :class:`TextureTransform` keeps its fields; :meth:`TextureTransform.matrix`
  is the standard's Tc' = -C·S·R·C·T·Tc and :func:`apply_texture_transform` applies it to UVs.

* :class:`Mesh` (every geometry): ``name``, ``kind`` (the node type read: IndexedFaceSet,
  IndexedTriangleSet, ..., Box, Sphere, Cylinder, Cone, ElevationGrid, IndexedLineSet,
  LineSet, PointSet), ``positions`` ((n, 3) float64), ``face_sizes`` ((f,) int64, each ≥ 3),
  ``corners`` ((Σ face_sizes,) int64: each corner's position index, face after face, in the
  file's order: with ``ccw`` False the faces are clockwise, :func:`counter_clockwise` reverses
  them), per corner ``normals`` ((c, 3) or None: the file's normals, per vertex or per face,
  with or without their own index, resolved to corners as the standard says), ``colors``
  ((c, 4) RGBA or None: Color gives alpha 1) and ``uvs`` ((c, 2) or None; an IndexedFaceSet
  whose shape has a texture and no texCoord gets the standard's default bounding-box
  mapping), ``solid``, ``ccw``, ``convex`` (a non-convex polygon stays one n-gon: Blender
  fills concave n-gons correctly), ``crease_angle`` (radians: the Blender side smooths by this
  angle where ``normals`` is None), ``color_per_vertex`` / ``normal_per_vertex`` (as the file
  said), ``edges`` ((e, 2) position indices: IndexedLineSet / LineSet), ``point_colors`` ((n, 4)
  per position: PointSet and line sets whose colours follow their positions), ``primitive``
  (Box / Sphere / Cylinder / Cone / ElevationGrid: their fields as read, so that the writer
  writes the node back; the tessellation has 32 segments around, a sphere 16 rings, with
  normals and the standard's texture coordinates).  An Extrusion is its faces
  (:func:`extrude`: the standard's spine-aligned cross-section planes, caps, texture
  coordinates); a Text has no faces but ``text`` (its strings and FontStyle: the Blender side
  sets them in a font, the writers write a Text back).

* :class:`Light`: ``kind`` ("directional", "point", "spot"), ``name``, ``on``, ``intensity``,
  ``ambient_intensity``, ``color``, ``location``, ``direction``, ``attenuation`` (a0, a1, a2),
  ``radius``, ``beam_width``, ``cut_off_angle``, ``is_global`` (X3D's ``global``), every
  field with the standard's default **of the file's encoding**: a VRML97 SpotLight has
  beamWidth 1.570796 and cutOffAngle 0.785398, an X3D one 0.7854 and 1.570796; VRML97's
  DirectionalLight is scoped and its point and spot lights global, X3D says so in ``global``
  (DirectionalLight default FALSE, the others TRUE).

* :class:`ShapeInstance` (``Document.instances``): ``id`` (its index in that list: document
  order, stable), ``shape`` (shared, as the graph), ``matrix`` (4×4 world matrix in the file's
  axes and units) and ``path`` (the names of the named groups above it, outermost first, at
  most the :data:`PATH_LIMIT` innermost).
  :class:`LightInstance` (``Document.lights``): ``light``, ``matrix`` (its world matrix: the
  light's ``location`` and ``direction`` are in that frame), ``scope`` (None for a global
  light; for a scoped one the ``range`` of instance ids it lights: the shapes under its parent
  group, contiguous in document order) and ``path``.  A light under a group used twice gives
  two instances, each with its own scope.

The file's :class:`Document` that holds them is in :mod:`.document`; the warnings collected while
reading (:class:`_Notes`) are here.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from .numeric import rotation_matrix


#: Deepest nesting of nodes read (deeper ones are left out with a warning).
MAX_DEPTH = 150
ENCODINGS = ("vrml97", "x3d-classic", "x3d-xml")
LIGHT_KINDS = ("directional", "point", "spot")
#: Blender's axes (Z up) from X3D's (Y up): +90° about X.
Y_UP_TO_Z_UP = np.array([[1.0, 0.0, 0.0, 0.0], [0.0, 0.0, -1.0, 0.0],
                         [0.0, 1.0, 0.0, 0.0], [0.0, 0.0, 0.0, 1.0]])
#: SpotLight defaults (beamWidth, cutOffAngle) as each standard gives them.
SPOT_DEFAULTS = {"vrml97": (1.570796, 0.785398), "x3d": (0.7854, 1.570796)}
#: The WorldInfo ``info`` prefix under which the writer keeps exact names (see ``_Names``).
NAME_PREFIX = "phong_nodes:name "


class X3DError(ValueError):
    """A file that cannot be read as VRML97 / X3D at all; names the file."""

    def __init__(self, path: str, message: str):
        self.path = path
        super().__init__(f"{path}: {message}")


# -- the data model --------------------------------------------------------------------------

def _eye():
    return np.eye(4)


@dataclass(eq=False)
class Material:
    name: str = "Material"
    diffuse: tuple = (0.8, 0.8, 0.8)
    ambient_intensity: float = 0.2
    specular: tuple = (0.0, 0.0, 0.0)
    emissive: tuple = (0.0, 0.0, 0.0)
    shininess: float = 0.2
    transparency: float = 0.0
    kind: str = "material"          # material, two_sided, physical, unlit
    back: "Material | None" = None  # a TwoSidedMaterial's back values (separateBackColor)
    metallic: float | None = None   # PhysicalMaterial's (not used by the Phong model)
    roughness: float | None = None


@dataclass(eq=False)
class TextureTransform:
    name: str = ""
    center: tuple = (0.0, 0.0)
    rotation: float = 0.0           # radians
    scale: tuple = (1.0, 1.0)
    translation: tuple = (0.0, 0.0)

    def matrix(self) -> np.ndarray:
        """3×3 matrix of the standard's Tc' = -C × S × R × C × T × Tc (applied to (s, t, 1))."""
        def move(x, y):
            return np.array([[1.0, 0.0, x], [0.0, 1.0, y], [0.0, 0.0, 1.0]])
        c, s = math.cos(self.rotation), math.sin(self.rotation)
        rot = np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])
        scale = np.diag([self.scale[0], self.scale[1], 1.0])
        cx, cy = self.center
        return (move(-cx, -cy) @ scale @ rot @ move(cx, cy)
                @ move(*self.translation))


@dataclass(eq=False)
class Texture:
    name: str = ""
    kind: str = "ImageTexture"      # or PixelTexture
    urls: list = field(default_factory=list)
    paths: list = field(default_factory=list)
    path: str | None = None
    repeat_s: bool = True
    repeat_t: bool = True
    image: np.ndarray | None = None  # PixelTexture: (height, width, components) uint8
    components: int | None = None


@dataclass(eq=False)
class Appearance:
    name: str = ""
    material: Material | None = None
    texture: Texture | None = None
    texture_transform: TextureTransform | None = None


@dataclass(eq=False)
class Mesh:
    name: str = ""
    kind: str = "IndexedFaceSet"
    positions: np.ndarray = field(default_factory=lambda: np.zeros((0, 3)))
    face_sizes: np.ndarray = field(default_factory=lambda: np.zeros(0, np.int64))
    corners: np.ndarray = field(default_factory=lambda: np.zeros(0, np.int64))
    normals: np.ndarray | None = None
    colors: np.ndarray | None = None
    uvs: np.ndarray | None = None
    solid: bool = True
    ccw: bool = True
    convex: bool = True
    crease_angle: float = 0.0
    color_per_vertex: bool = True
    normal_per_vertex: bool = True
    edges: np.ndarray | None = None
    point_colors: np.ndarray | None = None
    primitive: dict | None = None
    text: dict | None = None        # Text: its strings and FontStyle (the Blender side sets it)


@dataclass(eq=False)
class Shape:
    name: str = ""
    geometry: Mesh | None = None
    appearance: Appearance | None = None

    @property
    def material(self) -> Material | None:
        return self.appearance.material if self.appearance is not None else None

    @property
    def texture(self) -> Texture | None:
        return self.appearance.texture if self.appearance is not None else None

    @property
    def texture_transform(self) -> TextureTransform | None:
        return self.appearance.texture_transform if self.appearance is not None else None


@dataclass(eq=False)
class Light:
    kind: str = "point"             # directional, point, spot
    name: str = ""
    on: bool = True
    intensity: float = 1.0
    ambient_intensity: float = 0.0
    color: tuple = (1.0, 1.0, 1.0)
    location: tuple = (0.0, 0.0, 0.0)
    direction: tuple = (0.0, 0.0, -1.0)
    attenuation: tuple = (1.0, 0.0, 0.0)
    radius: float = 100.0
    beam_width: float = SPOT_DEFAULTS["x3d"][0]
    cut_off_angle: float = SPOT_DEFAULTS["x3d"][1]
    is_global: bool = True
    shadows: bool = False           # X3D 3.2+: the light casts shadows (VRML97 has none)


@dataclass(eq=False)
class Viewpoint:
    name: str = ""
    kind: str = "Viewpoint"         # or OrthoViewpoint
    position: tuple = (0.0, 0.0, 10.0)
    orientation: tuple = (0.0, 0.0, 1.0, 0.0)   # axis and angle (radians)
    field_of_view: float = 0.785398
    ortho_field: tuple | None = None            # OrthoViewpoint: (min x, min y, max x, max y)
    center_of_rotation: tuple = (0.0, 0.0, 0.0)
    description: str = ""

    def matrix(self) -> np.ndarray:
        """Its local camera matrix: the camera at ``position`` turned by ``orientation``,
        looking along its own -Z with +Y up (as a Blender camera looks)."""
        out = rotation_matrix(self.orientation[:3], self.orientation[3])
        out[:3, 3] = self.position
        return out


@dataclass(eq=False)
class Transform:
    name: str = ""
    kind: str = "Transform"
    matrix: np.ndarray = field(default_factory=_eye)
    children: list = field(default_factory=list)


@dataclass(eq=False)
class ShapeInstance:
    id: int
    shape: Shape
    matrix: np.ndarray
    path: tuple = ()


@dataclass(eq=False)
class LightInstance:
    light: Light
    matrix: np.ndarray
    scope: range | None = None
    path: tuple = ()

    def world_location(self) -> np.ndarray:
        return (self.matrix @ np.append(np.asarray(self.light.location, float), 1.0))[:3]

    def world_direction(self) -> np.ndarray:
        """The light's direction in world space (normalised; not for a point light)."""
        d = self.matrix[:3, :3] @ np.asarray(self.light.direction, float)
        n = np.linalg.norm(d)
        return d / n if n > 0 else np.array([0.0, 0.0, -1.0])


# -- warnings: each kind once, with a count --------------------------------------------------

class _Notes:
    """Problems by kind: ``add(kind, example)`` counts; ``lines()`` gives one line a kind
    with up to four examples and the count."""

    def __init__(self):
        self.counts = {}
        self.examples = {}

    def add(self, kind: str, example=None, n: int = 1) -> None:
        if kind not in self.counts:
            self.counts[kind] = 0
            self.examples[kind] = {}
        self.counts[kind] += n
        if example is not None:
            examples = self.examples[kind]
            if example in examples:
                examples[example] += n
            elif len(examples) < 4:
                examples[example] = n

    def lines(self) -> list:
        out = []
        for kind, count in self.counts.items():
            examples = self.examples[kind]
            text = kind
            if examples:
                shown = ", ".join(f"{e} ×{c}" if c > 1 else str(e) for e, c in examples.items())
                text += f": {shown}"
                if sum(examples.values()) < count:
                    text += ", ..."
            if count > 1:
                text += f" ({count} in all)"
            out.append(text)
        return out
