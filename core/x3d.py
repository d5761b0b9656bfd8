# SPDX-License-Identifier: GPL-3.0-or-later
"""VRML97 and X3D files read and written without ``bpy`` (issue 36).

VRML97 (ISO/IEC 14772-1) and X3D (ISO/IEC 19775-1) shade with a Phong model: ``Material {
diffuseColor ambientIntensity specularColor emissiveColor shininess transparency }`` lit by
DirectionalLight, PointLight and SpotLight (attenuation 1/max(a0 + a1·d + a2·d², 1), a radius, a
cone of ``beamWidth`` / ``cutOffAngle``) and a headlight.  This module reads a file into plain
data (:func:`load` → :class:`Document`) and writes one back (:func:`dumps_x3d`,
:func:`dumps_vrml`, :func:`dumps_x3dv`, :func:`save`); ``addon/interchange/x3d_import.py`` is
the Blender side.

Encodings read: VRML97 (``#VRML V2.0 utf8``), X3D ClassicVRML (``#X3D V3.x utf8``, V4 too) and
X3D XML, each also gzipped (found by its magic bytes, whatever the name: ``.wrz``, ``.x3dz``,
``.x3dvz``, ``.gz``).  VRML 1.0 is refused with an :class:`X3DError` that says so.

Why no third-party library: we know of no Python package that reads VRML97, X3D ClassicVRML
and X3D XML alike into one model with PROTO / EXTERNPROTO expansion, DEF/USE kept as shared
objects and the standard's scoping of lights, and Blender ships none (Blender 5 has no X3D
importer at all); expat and numpy suffice, keep the extension free of another dependency and
keep the hardening in our hands (bounded time and memory, entities refused).

The data model
==============

Everything is in the file's own axes (Y up, viewer looking along -Z, right-handed) and units
(see ``Document.meter``); angles are radians (a file's ``UNIT angle`` is applied on reading).
Nothing here converts to Blender's Z up: :func:`to_blender_matrix` gives the matrix (a
rotation of +90° about X, times ``Document.meter``) that the Blender side puts in front of
every world matrix, at the root.

* :class:`Document` — one file: ``path``, ``encoding`` ("vrml97", "x3d-classic" or
  "x3d-xml"), ``version`` ("2.0", "3.3", "4.0" ...), ``profile``, ``meter`` (metres per length
  unit: X3D 3.3's ``UNIT length``; 1 otherwise), ``root`` (a :class:`Transform`, kind "Scene":
  the file's top-level nodes are its children; ``roots`` is that list), ``headlight`` (the
  first NavigationInfo's, default True), ``navigation_types``, ``viewpoint`` (the bound — first —
  :class:`Viewpoint` or OrthoViewpoint of the file, None without one) and ``viewpoint_matrix``
  (its world matrix: the matrix of the groups above it), ``title`` and ``info`` (WorldInfo),
  ``background`` (Background skyColor[0] or None), ``meta`` ({name: content}), ``warnings``
  (strings: each kind of problem once, with a count), and the flattened scene:
  ``instances`` (:class:`ShapeInstance` list) and ``lights`` (:class:`LightInstance` list),
  computed by :meth:`Document.flatten` (``load`` calls it).

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

Limits (hostile input ends in bounded time and memory)
======================================================

A file larger than :data:`MAX_BYTES` (also once decompressed) is refused.  Nodes nested deeper
than :data:`MAX_DEPTH` in the file are left out with a warning (no RecursionError: the reader
recurses at most that deep, and skips deeper brackets by counting them).  PROTO instances
nest at most :data:`MAX_PROTO_DEPTH` deep, a PROTO that contains itself is left out, and
PROTO expansion copies at most :data:`MAX_NODES` nodes; Inline nests at most
:data:`MAX_INLINE_DEPTH` files and a file that inlines itself is left out.  DEF/USE may
multiply a small file into astronomically many instances (groups that USE each other 2⁴⁰
times): flattening counts them on the shared graph first, places a shared group's instances
with one batched matrix product a use, and **keeps the first :data:`MAX_INSTANCES` shape and
light instances, with a warning giving the total** (under 0.3 s for the 2⁴⁰ file); it
visits at most
:data:`MAX_VISITS` groups (DEF/USE chains nest groups as deep as a file is long: there is no
depth limit there, and paths keep their innermost names).
Indices out of range drop the faces (or the attribute) they name, with a warning; numbers
that are not finite become 0 and magnitudes beyond :data:`MAX_ABS` are clamped, with a
warning.  XML that declares entities is refused before parsing.  Only a file that cannot be
read at all raises :class:`X3DError` (a ValueError); everything else is a warning.

Reading is liberal, as browsers read: commas are whitespace, node and field names that differ
only in case are matched (one warning), a DEF without a node type takes the type its field
implies, USE before DEF is resolved at the end, unknown nodes are skipped with one warning per
type (their ``children`` still read), scripts, routes, sensors, interpolators, fog, sound and
shaders are named once in a warning, ``true``/``TRUE`` and MFString with or without quotes are
accepted in XML.  Numeric arrays are tokenised in bulk by numpy, never number by number (a
50 MB file of one million positions and triangles reads in about 1 s).

Writing
=======

:func:`dumps_x3d` (X3D 3.3 XML, profile Immersive), :func:`dumps_x3dv` (X3D 3.3 ClassicVRML)
and :func:`dumps_vrml` (VRML97, what KiCad reads) write the same graph: an object used more
than once is DEF'd once and USE'd after (so ``load(dumps(doc))`` shares what ``doc`` shares);
every Material is DEF'd (its name); a Transform's matrix is written as translation, rotation,
scale and scaleOrientation (:func:`decompose`: exact for any affine matrix, mirrors included);
a mesh as an IndexedFaceSet with per-corner normals, colours and texture coordinates (each
list de-duplicated, with its index), a primitive as itself; every light field explicitly.
DEF names are identifiers valid in both encodings (other characters become ``_``, a repeated
name gets ``_2`` ...); where that changed a name, the exact name is kept in WorldInfo's
``info`` as ``phong_nodes:name DEF=exact`` (:data:`NAME_PREFIX`), which :func:`loads` reads
back ("Red Paint.001" survives).  Numbers are the shortest decimals that read back as the same
float64.  VRML97 cannot say everything: a scene in other units is wrapped in a Transform
scaling it to metres, ``global`` is its fixed rule, colour alpha is dropped, an OrthoViewpoint
becomes a Viewpoint, a two-sided primitive becomes its faces, and TwoSided / Physical / Unlit
materials become the Material of their values.  :func:`save` writes atomically
(``core.outputs.write_file``) in the encoding of the file name's extension, gzipped for
``.x3dz``, ``.x3dvz``, ``.wrz`` and ``.gz``.
"""

from __future__ import annotations

import gzip
import math
import os
import re
import warnings as _warnings
import xml.etree.ElementTree as ET
import xml.parsers.expat as expat
import zlib
from dataclasses import dataclass, field

import numpy as np

from . import outputs

#: Largest file read, in bytes (also the largest decompressed size of a gzipped file).
MAX_BYTES = 1 << 30
#: Deepest nesting of nodes read (deeper ones are left out with a warning).
MAX_DEPTH = 150
#: Most shape and light instances that flattening keeps (DEF/USE can multiply a file).
MAX_INSTANCES = 100_000
#: Most nodes that PROTO expansion copies in one file (only the nodes of a PROTO body that
#: depend on the instance's fields through IS are copied; the rest is shared).
MAX_NODES = 50_000
#: Deepest nesting of PROTO instances inside PROTO bodies.
MAX_PROTO_DEPTH = 32
#: Deepest nesting of Inline files (and EXTERNPROTO files).
MAX_INLINE_DEPTH = 8
#: Largest magnitude of a number kept (larger ones are clamped, with a warning).
MAX_ABS = 1e30
#: Most groups that flattening visits (shared groups count once per use unless they can be
#: placed whole); with MAX_INSTANCES this bounds the time DEF/USE can cost.
MAX_VISITS = 1_000_000
#: A flattened instance's ``path`` keeps the names of at most this many innermost groups.
PATH_LIMIT = 32
#: Segments around a tessellated Sphere, Cylinder or Cone (a Sphere has half as many rings).
SEGMENTS = 32
#: An Extrusion of more spine × crossSection points is left out (a warning); a convex FALSE
#: cap of more points is one polygon (Blender fills it) rather than triangulated.
MAX_EXTRUSION_POINTS = 2_000_000
MAX_CAP_TRIANGULATION = 20_000

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


@dataclass(eq=False)
class Document:
    path: str = ""
    encoding: str = "x3d-xml"
    version: str = "3.3"
    profile: str = "Immersive"
    meter: float = 1.0
    unit_name: str = ""
    root: Transform = field(default_factory=lambda: Transform(kind="Scene"))
    headlight: bool = True
    navigation_types: list = field(default_factory=lambda: ["EXAMINE", "ANY"])
    viewpoint: Viewpoint | None = None
    viewpoint_matrix: np.ndarray = field(default_factory=_eye)
    title: str = ""
    info: list = field(default_factory=list)
    background: tuple | None = None
    meta: dict = field(default_factory=dict)
    warnings: list = field(default_factory=list)
    instances: list = field(default_factory=list)
    lights: list = field(default_factory=list)

    @property
    def roots(self) -> list:
        return self.root.children

    def warn(self, message: str) -> None:
        if message not in self.warnings:
            self.warnings.append(message)

    def flatten(self):
        """Every shape instance with its world matrix and stable id, and every light
        instance with its world matrix and scope (``instances``, ``lights``; also
        ``viewpoint_matrix``); returns (instances, lights).  At most MAX_INSTANCES."""
        notes = _Notes()
        _flatten(self, notes)
        for line in notes.lines():
            self.warn(line)
        return self.instances, self.lights

    def materials(self) -> list:
        """The distinct materials of the instances, in order of first use."""
        seen, out = set(), []
        for inst in self.instances:
            mat = inst.shape.material
            if mat is not None and id(mat) not in seen:
                seen.add(id(mat))
                out.append(mat)
        return out


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


# -- numbers -------------------------------------------------------------------------------

_NOT_NUMERIC = re.compile(r"[^0-9eE+\-.,\s]")
_NOT_INTEGRAL = re.compile(r"[.eE]")
_NUMERIC_BYTES = np.zeros(256, dtype=bool)
_NUMERIC_BYTES[list(b"0123456789eE+-.,\t\n\r\x0b\x0c ")] = True
_FLOAT_BYTES = np.zeros(256, dtype=bool)
_FLOAT_BYTES[list(b".eE")] = True
_VALUE_BYTES = _NUMERIC_BYTES.copy()
_VALUE_BYTES[list(b",\t\n\r\x0b\x0c ")] = False


def _bulk_numbers(text: str, start: int = 0, end: int | None = None):
    """The numbers of ``text[start:end]`` (whitespace or commas between them) as one numpy
    array, int64 when every one is written as an integer, else float64; None when it holds
    anything that is not a plain decimal number.  numpy checks (a byte table, 64 K characters
    at a time, stopping at the first chunk that is not numbers) and parses at C speed."""
    end = len(text) if end is None else end
    if end - start < 512:
        part = text[start:end]
        if _NOT_NUMERIC.search(part):
            return None
        if "," in part:
            part = part.replace(",", " ")
        if not part.strip():
            return np.zeros(0)
        integral = not _NOT_INTEGRAL.search(part)
        data = part
    else:
        if _NOT_NUMERIC.search(text, start, start + 256):  # most lists of nodes end here
            return None
        chunks, integral, values = [], True, False
        for at in range(start, end, 65536):
            try:
                raw = text[at:min(at + 65536, end)].encode("ascii")
            except UnicodeEncodeError:
                return None
            codes = np.frombuffer(raw, dtype=np.uint8)
            if not _NUMERIC_BYTES[codes].all():
                return None
            integral = integral and not _FLOAT_BYTES[codes].any()
            values = values or bool(_VALUE_BYTES[codes].any())
            chunks.append(raw)
        if not values:
            return np.zeros(0)
        data = b"".join(chunks)
        if b"," in data:
            data = data.replace(b",", b" ")
    try:
        with _warnings.catch_warnings():
            _warnings.simplefilter("error")
            return np.fromstring(data, dtype=np.int64 if integral else np.float64, sep=" ")
    except (ValueError, DeprecationWarning, OverflowError):
        return None


def _word_number(word: str):
    """One number written as *word* (decimal, hexadecimal or nan/inf): a float or int; NaN
    when it cannot be read (the caller replaces non-finite values, with a warning)."""
    try:
        return float(word)
    except ValueError:
        pass
    try:
        return int(word, 0)
    except ValueError:
        return math.nan


def _is_number_word(word: str) -> bool:
    return word[0] in "0123456789+-." or word.lower() in ("nan", "inf", "infinity")


def _numbers_of(words) -> np.ndarray:
    """Numbers of a list of number words (the slow path: small or malformed values)."""
    values = [_word_number(w) for w in words]
    if all(isinstance(v, int) for v in values):
        try:
            return np.array(values, dtype=np.int64)
        except OverflowError:
            pass
    return np.array(values, dtype=np.float64)


def _finite(values, notes, where) -> np.ndarray:
    """*values* as float64 with non-finite numbers replaced by 0 and magnitudes beyond
    MAX_ABS clamped (each with a warning naming *where*)."""
    out = np.asarray(values, dtype=np.float64)
    if out.size <= 16 and all(-MAX_ABS <= v <= MAX_ABS for v in out.flat):
        return out                          # (NaN fails the comparison)
    if out.size and not np.isfinite(out).all():
        out = out.copy()
        bad = ~np.isfinite(out)
        notes.add("numbers that are not finite (NaN, inf) read as 0", where, int(bad.sum()))
        out[bad] = 0.0
    if out.size and np.abs(out).max() > MAX_ABS:
        out = out.copy()
        big = np.abs(out) > MAX_ABS
        notes.add(f"numbers larger than {MAX_ABS:g} clamped", where, int(big.sum()))
        np.clip(out, -MAX_ABS, MAX_ABS, out=out)
    return out


# -- matrices ------------------------------------------------------------------------------

def rotation_matrix(axis, angle) -> np.ndarray:
    """4×4 rotation by *angle* (radians) about *axis* (right-handed); identity for a zero
    axis."""
    axis = np.asarray(axis, dtype=np.float64)[:3]
    norm = float(np.linalg.norm(axis))
    out = np.eye(4)
    if norm == 0.0 or not math.isfinite(norm) or angle == 0.0:
        return out
    x, y, z = axis / norm
    c, s = math.cos(angle), math.sin(angle)
    t = 1.0 - c
    out[:3, :3] = [[t * x * x + c, t * x * y - s * z, t * x * z + s * y],
                   [t * x * y + s * z, t * y * y + c, t * y * z - s * x],
                   [t * x * z - s * y, t * y * z + s * x, t * z * z + c]]
    return out


def _rotation3(axis, angle) -> np.ndarray:
    x, y, z = (float(v) for v in axis[:3])
    norm = math.sqrt(x * x + y * y + z * z)
    if norm == 0.0 or not math.isfinite(norm) or angle == 0.0:
        return np.eye(3)
    x, y, z = x / norm, y / norm, z / norm
    c, s = math.cos(angle), math.sin(angle)
    t = 1.0 - c
    return np.array([[t * x * x + c, t * x * y - s * z, t * x * z + s * y],
                     [t * x * y + s * z, t * y * y + c, t * y * z - s * x],
                     [t * x * z - s * y, t * y * z + s * x, t * z * z + c]])


def transform_matrix(translation=(0, 0, 0), rotation=(0, 0, 1, 0), scale=(1, 1, 1),
                     scale_orientation=(0, 0, 1, 0), center=(0, 0, 0)) -> np.ndarray:
    """A Transform's local matrix exactly as ISO/IEC 14772-1 §6.52 and 19775-1 §10.4.4
    compose it: P' = T × C × R × SR × S × -SR × -C × P (rotations as axis + angle)."""
    out = np.eye(4)
    a = np.diag([float(scale[0]), float(scale[1]), float(scale[2])])
    if scale_orientation[3] != 0.0 and not (scale[0] == scale[1] == scale[2]):
        sr = _rotation3(scale_orientation, scale_orientation[3])
        a = sr @ a @ sr.T
    if rotation[3] != 0.0:
        a = _rotation3(rotation, rotation[3]) @ a
    out[:3, :3] = a
    c = np.array([float(v) for v in center[:3]])
    out[:3, 3] = np.array([float(v) for v in translation[:3]]) + c - a @ c
    return out


def _axis_angle(rot: np.ndarray) -> tuple:
    """(x, y, z, angle) of a 3×3 rotation matrix (angle in [0, π])."""
    m = np.asarray(rot, dtype=np.float64)
    trace = m[0, 0] + m[1, 1] + m[2, 2]
    # quaternion (Shepperd): robust near 0 and π
    if trace > 0:
        s = math.sqrt(trace + 1.0) * 2
        w, x = 0.25 * s, (m[2, 1] - m[1, 2]) / s
        y, z = (m[0, 2] - m[2, 0]) / s, (m[1, 0] - m[0, 1]) / s
    elif m[0, 0] > m[1, 1] and m[0, 0] > m[2, 2]:
        s = math.sqrt(1.0 + m[0, 0] - m[1, 1] - m[2, 2]) * 2
        w, x = (m[2, 1] - m[1, 2]) / s, 0.25 * s
        y, z = (m[0, 1] + m[1, 0]) / s, (m[0, 2] + m[2, 0]) / s
    elif m[1, 1] > m[2, 2]:
        s = math.sqrt(1.0 + m[1, 1] - m[0, 0] - m[2, 2]) * 2
        w, x = (m[0, 2] - m[2, 0]) / s, (m[0, 1] + m[1, 0]) / s
        y, z = 0.25 * s, (m[1, 2] + m[2, 1]) / s
    else:
        s = math.sqrt(1.0 + m[2, 2] - m[0, 0] - m[1, 1]) * 2
        w, x = (m[1, 0] - m[0, 1]) / s, (m[0, 2] + m[2, 0]) / s
        y, z = (m[1, 2] + m[2, 1]) / s, 0.25 * s
    if w < 0:
        w, x, y, z = -w, -x, -y, -z
    sin_half = math.sqrt(x * x + y * y + z * z)
    if sin_half < 1e-15:
        return (0.0, 0.0, 1.0, 0.0)
    angle = 2.0 * math.atan2(sin_half, w)
    return (x / sin_half, y / sin_half, z / sin_half, angle)


def decompose(matrix) -> dict:
    """A 4×4 affine matrix as a Transform's fields (translation, rotation, scale,
    scaleOrientation; center 0) that compose it exactly (up to rounding): the 3×3 part
    A = U·Σ·Vᵀ (SVD) is R·SR·S·SRᵀ with SR = V, S = Σ and R = U·Vᵀ; a mirror gives a
    negative scale."""
    m = np.asarray(matrix, dtype=np.float64)
    a = m[:3, :3]
    u, s, vt = np.linalg.svd(a)
    v = vt.T.copy()
    s = s.copy()
    if np.linalg.det(v) < 0:
        v[:, 2] *= -1
        s[2] *= -1
    if np.linalg.det(u) < 0:
        u[:, 2] *= -1
        s[2] *= -1
    rot = u @ v.T
    if np.allclose(s, s[0], rtol=1e-12, atol=0.0):
        v = np.eye(3)
        rot = a / s[0]
    return {"translation": tuple(m[:3, 3]), "rotation": _axis_angle(rot),
            "scale": tuple(s), "scale_orientation": _axis_angle(v)}


# -- the generic node graph (both encodings parse into it) -----------------------------------

class _N:
    """A node as written: its type, fields (name → value: numbers as an ndarray, strings as a
    list, booleans, nodes (``_N`` or ``_Use``), lists of nodes, ``_IS`` in a PROTO body, or
    an XML attribute's raw text, typed when read), DEF name, PROTO (for an instance), the
    file it comes from and the PROTO expansions it was copied by."""

    __slots__ = ("type", "fields", "name", "proto", "src", "chain")

    def __init__(self, type_, name=None, proto=None, src=None, chain=()):
        self.type = type_
        self.fields = {}
        self.name = name
        self.proto = proto
        self.src = src
        self.chain = chain


class _Use:
    """A USE of a name not (yet) defined where it is read: resolved in *scope* at the end."""

    __slots__ = ("name", "scope")

    def __init__(self, name, scope):
        self.name = name
        self.scope = scope


class _IS:
    __slots__ = ("name",)

    def __init__(self, name):
        self.name = name


class _Raw(str):
    """An XML attribute's text: typed by the field that reads it."""


class _Proto:
    """A PROTO (or a resolved EXTERNPROTO): interface {name: (access, type, default)}, body
    (nodes; the first is the instance), and the scope of the body's DEF names."""

    def __init__(self, name, src):
        self.name = name
        self.src = src
        self.fields = {}
        self.body = []
        self.defs = {}
        self.extern_urls = None     # an EXTERNPROTO not yet resolved
        self.resolved = None
        self.dynamic = None         # ids of body nodes that depend on IS (copied per instance)


class _Scope:
    """DEF names and PROTOs of a file or a PROTO body (PROTOs are looked up outwards)."""

    def __init__(self, parent=None):
        self.defs = {}
        self.protos = {}
        self.parent = parent

    def proto(self, name):
        scope = self
        while scope is not None:
            if name in scope.protos:
                return scope.protos[name]
            scope = scope.parent
        return None

    def proto_ci(self, name):
        lower = name.lower()
        scope = self
        while scope is not None:
            for key, proto in scope.protos.items():
                if key.lower() == lower:
                    return proto
            scope = scope.parent
        return None


class _Source:
    """One file read: where it is, its encoding and version, its units, its top level."""

    def __init__(self, path, encoding, version, depth=0):
        self.path = path
        self.base = os.path.dirname(os.path.abspath(path)) if path and not path.startswith("<") \
            else os.getcwd()
        self.encoding = encoding
        self.version = version
        self.meter = 1.0
        self.unit_name = ""
        self.angle = 1.0
        self.depth = depth
        self.nodes = []
        self.scope = _Scope()
        self.profile = ""
        self.meta = {}

    @property
    def vrml97(self) -> bool:
        return self.encoding == "vrml97"


#: field access keywords of PROTO interfaces and Script / shader declarations
_ACCESS = {"field", "exposedField", "eventIn", "eventOut", "initializeOnly", "inputOutput",
           "inputOnly", "outputOnly"}
_NO_VALUE = {"eventIn", "eventOut", "inputOnly", "outputOnly"}
_EOF = ("eof", None)
_MISSING = object()


# -- ClassicVRML (VRML97 and X3D classic) -------------------------------------------------

_STRIP = re.compile(r'"(?:[^"\\]|\\.)*"|#[^\n\r]*', re.S)
_TOKEN = re.compile(r'[\s,]*(?:([{}\[\]])|"((?:[^"\\]|\\.)*)"|([^\s,{}\[\]"]+)|("))', re.S)
_BLOCK = re.compile(r'[{}\[\]"]')
_UNESCAPE = re.compile(r"\\(.)", re.S)
_STRING_END = re.compile(r'(?:[^"\\]|\\.)*"', re.S)
_OPENERS = np.array([ord("{"), ord("[")], dtype=np.uint32)
_CLOSERS = np.array([ord("}"), ord("]")], dtype=np.uint32)


def _strip_comments(text: str) -> str:
    if "#" not in text:
        return text
    return _STRIP.sub(lambda m: m.group(0) if m.group(0)[0] == '"' else " ", text)


class _Classic:
    """A recursive-descent reader of the classic encoding over one string; nesting is bounded
    by MAX_DEPTH (deeper blocks are skipped by counting brackets, not by recursion)."""

    def __init__(self, text, src, notes, reader):
        self.text = text
        self.pos = 0
        self.src = src
        self.notes = notes
        self.reader = reader
        self.scope = src.scope
        self.truncated = False
        self.line_at, self.line_no = 0, 1
        self.peeked = None          # (position, token, position after): the last peek

    # tokens --------------------------------------------------------------------------
    def next(self):
        if self.peeked is not None and self.peeked[0] == self.pos:
            _start, token, self.pos = self.peeked
            self.peeked = None
            return token
        m = _TOKEN.match(self.text, self.pos)
        if m is None:
            self.pos = len(self.text)
            return _EOF
        self.pos = m.end()
        if m.group(1) is not None:
            return (m.group(1), None)
        if m.group(3) is not None:
            return ("w", m.group(3))
        if m.group(2) is not None:
            s = m.group(2)
            return ("s", _UNESCAPE.sub(r"\1", s) if "\\" in s else s)
        # an unterminated string: the rest of the file
        rest = self.text[self.pos:]
        self.pos = len(self.text)
        self.truncated = True
        return ("s", rest)

    def peek(self):
        pos = self.pos
        if self.peeked is not None and self.peeked[0] == pos:
            return self.peeked[1]
        tok = self.next()
        self.peeked = (pos, tok, self.pos)
        self.pos = pos
        return tok

    def line(self) -> int:
        """The line of the current position (for warnings), counted from the last one asked
        for, so that asking as the reading goes on costs the file's length once."""
        pos = self.pos
        if pos >= self.line_at:
            self.line_no += self.text.count("\n", self.line_at, pos)
        else:
            self.line_no -= self.text.count("\n", pos, self.line_at)
        self.line_at = pos
        return self.line_no

    def skip_block(self, opener):
        """Skip to the bracket closing *opener* (already read), counting brackets without
        recursion: 64 K characters at a time with numpy where they hold no string."""
        depth = 1
        text = self.text
        n = len(text)
        while depth:
            chunk = text[self.pos:self.pos + 65536]
            if not chunk:
                self.truncated = True
                return
            if '"' not in chunk:
                codes = np.frombuffer(chunk.encode("utf-32-le"), dtype=np.uint32)
                change = (np.isin(codes, _OPENERS).astype(np.int64)
                          - np.isin(codes, _CLOSERS).astype(np.int64))
                level = depth + np.cumsum(change)
                closed = np.flatnonzero(level <= 0)
                if len(closed):
                    self.pos += int(closed[0]) + 1
                    return
                depth = int(level[-1])
                self.pos += len(chunk)
                continue
            m = _BLOCK.search(text, self.pos)
            if m is None:
                self.pos = n
                self.truncated = True
                return
            c = m.group(0)
            self.pos = m.end()
            if c == '"':
                end = _STRING_END.match(text, self.pos)
                if end is None:
                    self.pos = n
                    self.truncated = True
                    return
                self.pos = end.end()
            elif c in "{[":
                depth += 1
            else:
                depth -= 1

    # statements ------------------------------------------------------------------------
    def statements(self, out, depth, end=None):
        """Read statements into *out* until *end* ("}" of a PROTO body) or the end of file."""
        while True:
            kind, value = self.peek()
            if kind == "eof":
                if end is not None:
                    self.truncated = True
                return
            if kind == end:
                self.next()
                return
            if kind != "w":
                self.next()
                self.notes.add("unexpected symbols skipped", f"'{kind}' line {self.line()}")
                if kind in "{[":
                    self.skip_block(kind)
                continue
            if value in ("PROTO", "EXTERNPROTO"):
                self.next()
                self.proto(depth, extern=value == "EXTERNPROTO")
            elif value == "ROUTE":
                self.next()
                self.route()
            elif value in ("PROFILE", "COMPONENT", "META", "UNIT", "IMPORT", "EXPORT"):
                self.next()
                self.header_statement(value)
            else:
                node = self.node(depth)
                if node is not None:
                    out.append(node)

    def route(self):
        """ROUTE a.b TO c.d (spaces around the dots tolerated): skipped, counted."""
        self.reader.ignored["ROUTE"] = self.reader.ignored.get("ROUTE", 0) + 1
        for _ in range(8):
            kind, value = self.peek()
            if kind != "w":
                return
            self.next()
            if value == "TO":
                kind, target = self.next()
                if kind != "w":
                    return
                if target.endswith("."):                # "c. d"
                    self.next()
                elif "." not in target and self.peek()[0] == "w" \
                        and self.peek()[1].startswith("."):
                    if self.next()[1] == ".":           # "c . d"
                        self.next()
                return

    def header_statement(self, keyword):
        if keyword == "PROFILE":
            self.src.profile = self.next()[1] or ""
        elif keyword == "COMPONENT":
            self.next()
            if self.peek()[1] == ":":
                self.next()
                self.next()
        elif keyword == "META":
            key, value = self.next(), self.next()
            if key[0] == "s" and value[0] == "s":
                self.src.meta[key[1]] = value[1]
        elif keyword == "UNIT":
            words = [self.next() for _ in range(3)]
            if all(w[0] == "w" for w in words):
                category, name, factor = (w[1] for w in words)
                self.reader.unit(self.src, category, name, factor)
            else:
                self.notes.add("UNIT statements that could not be read", f"line {self.line()}")
        elif keyword == "IMPORT":           # IMPORT inline.exported AS name
            self.next()
            if self.peek()[1] == "AS":
                self.next()
                self.next()
        elif keyword == "EXPORT":           # EXPORT name [AS other]
            self.next()
            if self.peek()[1] == "AS":
                self.next()
                self.next()

    # PROTO ----------------------------------------------------------------------------
    def proto(self, depth, extern=False):
        kind, name = self.next()
        if kind != "w":
            self.notes.add("PROTO statements that could not be read", f"line {self.line()}")
            return
        proto = _Proto(name, self.src)
        if self.next()[0] != "[":
            self.notes.add("PROTO statements that could not be read", f"{name} line {self.line()}")
            return
        while True:
            kind, value = self.next()
            if kind in ("]", "eof"):
                if kind == "eof":
                    self.truncated = True
                break
            if kind != "w" or value not in _ACCESS:
                self.notes.add("PROTO interface declarations that could not be read",
                               f"{name} line {self.line()}")
                if kind in ("{", "["):
                    self.skip_block(kind)
                continue
            ftype, fname = self.next()[1], self.next()[1]
            default = _MISSING
            if not extern and value not in _NO_VALUE:
                default = self.value(depth + 1, fname)
            proto.fields[fname] = (value, ftype, default)
        self.scope.protos[name] = proto     # visible to instances from here on
        if extern:
            urls = self.value(depth + 1, "url")
            proto.extern_urls = [u for u in urls if isinstance(u, str)] \
                if isinstance(urls, list) else []
            return
        if self.next()[0] != "{":
            self.notes.add("PROTO statements that could not be read", f"{name} line {self.line()}")
            return
        outer = self.scope
        self.scope = _Scope(outer)
        proto.defs = self.scope.defs
        self.statements(proto.body, depth + 1, end="}")
        self.scope = outer

    # nodes ----------------------------------------------------------------------------
    def node(self, depth, field_name=None):
        """A node statement (``DEF n Type {...}``, ``USE n``, ``Type {...}``); None when there
        is none (with a warning) or it is nested too deep."""
        kind, word = self.next()
        if kind != "w":
            return None
        if word == "USE":
            kind, name = self.next()
            if kind != "w":
                return None
            found = self.scope.defs.get(name)
            return found if found is not None else _Use(name, self.scope)
        name = None
        if word == "DEF":
            kind, name = self.next()
            if kind != "w":
                return None
            if self.peek()[0] == "{":     # DEF without a node type: its field implies one
                self.notes.add("DEF without a node type: the type its field implies",
                               f"{name} line {self.line()}")
                type_ = _IMPLIED.get(field_name or "", "Group")
            else:
                kind, type_ = self.next()
        else:
            type_ = word
        if self.peek()[0] != "{":
            self.notes.add("words that are not nodes skipped", f"{type_} line {self.line()}")
            return None
        self.next()
        if depth > MAX_DEPTH:
            self.reader.too_deep += 1
            self.skip_block("{")
            return None
        proto = self.scope.proto(type_)
        if proto is None and type_ not in _KNOWN:
            proto = self.scope.proto_ci(type_)
            if proto is not None:
                self.notes.add("node and field names read regardless of case",
                               f"{type_} → {proto.name}")
        node = _N(type_, name, proto, self.src)
        self.body(node, depth)
        if name is not None:
            self.scope.defs[name] = node
        return node

    def body(self, node, depth):
        fields = node.fields
        while True:
            kind, value = self.next()
            if kind == "}":
                return
            if kind == "eof":
                self.truncated = True
                return
            if kind != "w":
                self.notes.add("unexpected symbols skipped", f"'{kind}' line {self.line()}")
                if kind in "{[":
                    self.skip_block(kind)
                continue
            if value == "ROUTE":
                self.route()
                continue
            if value in ("PROTO", "EXTERNPROTO"):
                self.proto(depth, extern=value == "EXTERNPROTO")
                continue
            if value in _ACCESS and self.peek()[0] == "w":
                # a Script / shader field declaration: access type name [value | IS name]
                self.next()                     # the field's type
                fname = self.next()[1]
                if self.peek()[1] == "IS":
                    self.next()
                    fields[fname] = _IS(self.next()[1])
                elif value not in _NO_VALUE:
                    fields[fname] = self.value(depth + 1, fname)
                continue
            result = self.value(depth + 1, value)
            if result is _MISSING:
                self.notes.add("fields without a value skipped", f"{node.type}.{value} line "
                                                                   f"{self.line()}")
                continue
            fields[value] = result

    def value(self, depth, field_name=None):
        """A field value of any type, read by its form: ``[...]``, numbers, strings, a
        boolean, NULL, ``IS name``, or a node."""
        kind, word = self.peek()
        if kind == "[":
            self.next()
            return self.multiple(depth, field_name)
        if kind == "s":
            out = []
            while self.peek()[0] == "s":
                out.append(self.next()[1])
            return out
        if kind == "{":                     # a node with neither type nor DEF
            self.next()
            if depth > MAX_DEPTH:
                self.reader.too_deep += 1
                self.skip_block("{")
                return None
            type_ = _IMPLIED.get(field_name or "", "Group")
            self.notes.add("nodes without a type: the type their field implies",
                           f"{field_name} line {self.line()}")
            node = _N(type_, None, None, self.src)
            self.body(node, depth)
            return node
        if kind != "w":
            return _MISSING
        if _is_number_word(word):
            words = []
            while True:
                kind, word = self.peek()
                if kind != "w" or not _is_number_word(word):
                    break
                self.next()
                words.append(word)
            joined = " ".join(words)
            values = _bulk_numbers(joined)
            return values if values is not None else _numbers_of(words)
        if word in ("TRUE", "FALSE", "true", "false"):
            self.next()
            return word in ("TRUE", "true")
        if word == "NULL":
            self.next()
            return None
        if word == "IS":
            self.next()
            return _IS(self.next()[1])
        if word in ("DEF", "USE"):
            return self.node(depth, field_name)
        pos = self.pos
        self.next()
        follows = self.peek()[0]
        self.pos = pos
        if follows == "{":
            return self.node(depth, field_name)
        return _MISSING

    def multiple(self, depth, field_name):
        """``[ ... ]``: a numeric array in one numpy call when the brackets hold only
        numbers, else item by item (nodes, strings, booleans, numbers)."""
        text = self.text
        end = text.find("]", self.pos)
        if end >= 0:
            values = _bulk_numbers(text, self.pos, end)
            if values is not None:
                self.pos = end + 1
                return values
        items = []
        while True:
            kind, word = self.peek()
            if kind == "]":
                self.next()
                break
            if kind == "eof":
                self.truncated = True
                break
            if kind == "}":                 # a missing "]": let the node end
                self.notes.add("unclosed brackets closed", f"line {self.line()}")
                break
            if kind in ("[", "{"):
                self.next()
                self.notes.add("unexpected brackets skipped", f"line {self.line()}")
                self.skip_block(kind)
                continue
            if kind == "s":
                self.next()
                items.append(word)
                continue
            if _is_number_word(word):
                self.next()
                items.append(_word_number(word))
                continue
            if word in ("TRUE", "FALSE", "true", "false"):
                self.next()
                items.append(word in ("TRUE", "true"))
                continue
            if word == "NULL":
                self.next()
                continue
            node = self.node(depth, field_name)
            if node is not None:
                items.append(node)
        if items and all(isinstance(i, (int, float)) and not isinstance(i, bool)
                         for i in items):
            if all(isinstance(i, int) for i in items):
                try:
                    return np.array(items, dtype=np.int64)
                except OverflowError:
                    pass
            return np.array(items, dtype=np.float64)
        return items


# -- node tables -----------------------------------------------------------------------------

_GROUPS = {"Group", "Transform", "Anchor", "Billboard", "Collision", "StaticGroup", "Switch",
           "LOD", "MatrixTransform", "CADAssembly", "CADLayer", "CADPart", "CADFace",
           "HAnimHumanoid", "HAnimJoint", "HAnimSegment", "HAnimSite", "LayerSet", "Layer",
           "Viewport", "ViewpointGroup"}
_TRANSFORM_LIKE = {"Transform", "CADPart", "HAnimHumanoid", "HAnimJoint", "HAnimSite"}
_FACE_SETS = {"IndexedFaceSet", "IndexedTriangleSet", "TriangleSet", "IndexedTriangleFanSet",
              "TriangleFanSet", "IndexedTriangleStripSet", "TriangleStripSet", "IndexedQuadSet",
              "QuadSet", "ElevationGrid"}
_PRIMITIVES = {"Box", "Sphere", "Cylinder", "Cone"}
_GEOMETRY = _FACE_SETS | _PRIMITIVES | {"IndexedLineSet", "LineSet", "PointSet", "Extrusion",
                                        "Text"}
_GEOMETRY_SKIPPED = {"Arc2D", "ArcClose2D", "Circle2D", "Disk2D",
                     "Polyline2D", "Polypoint2D", "Rectangle2D", "TriangleSet2D", "NurbsCurve",
                     "NurbsPatchSurface", "NurbsTrimmedSurface", "NurbsSweptSurface",
                     "NurbsSwungSurface", "GeoElevationGrid"}
_MATERIALS = {"Material", "TwoSidedMaterial", "PhysicalMaterial", "UnlitMaterial"}
_TEXTURES = {"ImageTexture", "PixelTexture", "MultiTexture"}
_LIGHTS = {"DirectionalLight": "directional", "PointLight": "point", "SpotLight": "spot"}
_VIEWPOINTS = {"Viewpoint", "OrthoViewpoint"}
_BINDABLES = {"NavigationInfo", "Background", "WorldInfo", "TextureBackground"}
_DATA = {"Coordinate", "CoordinateDouble", "Color", "ColorRGBA", "Normal", "TextureCoordinate",
         "MultiTextureCoordinate", "TextureCoordinateGenerator", "TextureTransform",
         "Appearance", "FontStyle", "LineProperties", "FillProperties", "TextureProperties",
         "GeoCoordinate"}
#: read and left out, named once in one warning: behaviour, sound, shaders, fog, scripts
_IGNORED = {
    "Script", "TimeSensor", "TouchSensor", "PlaneSensor", "CylinderSensor", "SphereSensor",
    "ProximitySensor", "VisibilitySensor", "KeySensor", "StringSensor", "TransformSensor",
    "LoadSensor", "GeoTouchSensor", "GeoProximitySensor", "PositionInterpolator",
    "OrientationInterpolator", "ColorInterpolator", "ScalarInterpolator",
    "CoordinateInterpolator", "NormalInterpolator", "PositionInterpolator2D",
    "CoordinateInterpolator2D", "SplinePositionInterpolator", "SplineScalarInterpolator",
    "SquadOrientationInterpolator", "EaseInEaseOut", "GeoPositionInterpolator",
    "BooleanFilter", "BooleanSequencer", "BooleanToggle", "BooleanTrigger",
    "IntegerSequencer", "IntegerTrigger", "TimeTrigger", "Fog", "LocalFog", "FogCoordinate",
    "Sound", "SpatialSound", "AudioClip", "MovieTexture", "ComposedShader", "ProgramShader",
    "PackagedShader", "ShaderPart", "ShaderProgram", "FloatVertexAttribute",
    "Matrix3VertexAttribute", "Matrix4VertexAttribute", "EnvironmentLight",
    "CollisionCollection", "RigidBodyCollection", "ParticleSystem", "EspduTransform",
    "ClipPlane", "GeoLocation", "GeoLOD", "GeoMetadata", "GeoOrigin", "GeoTransform",
    "GeoViewpoint", "HAnimDisplacer", "HAnimMotion", "ROUTE",
}
_KNOWN = (_GROUPS | _GEOMETRY | _GEOMETRY_SKIPPED | _MATERIALS | _TEXTURES | set(_LIGHTS)
          | _VIEWPOINTS | _BINDABLES | _DATA | _IGNORED | {"Shape", "Inline", "CADFace"})
_KNOWN_LOWER = {name.lower(): name for name in _KNOWN}
#: the node type a DEF without a type (or ``{`` without one) takes from its field
_IMPLIED = {"coord": "Coordinate", "color": "Color", "normal": "Normal",
            "texCoord": "TextureCoordinate", "material": "Material", "appearance": "Appearance",
            "texture": "ImageTexture", "textureTransform": "TextureTransform",
            "children": "Group", "geometry": "IndexedFaceSet"}
#: XML: the field a child element goes in when it names no containerField
_CONTAINER = {name: "material" for name in _MATERIALS}
_CONTAINER.update({name: "geometry" for name in _GEOMETRY | _GEOMETRY_SKIPPED})
_CONTAINER.update({name: "texture" for name in _TEXTURES | {"MovieTexture"}})
_CONTAINER.update({
    "Appearance": "appearance", "TextureTransform": "textureTransform",
    "Coordinate": "coord", "CoordinateDouble": "coord", "GeoCoordinate": "coord",
    "Color": "color", "ColorRGBA": "color", "Normal": "normal",
    "TextureCoordinate": "texCoord", "MultiTextureCoordinate": "texCoord",
    "TextureCoordinateGenerator": "texCoord", "FontStyle": "fontStyle",
    "LineProperties": "lineProperties", "FillProperties": "fillProperties",
    "TextureProperties": "textureProperties", "ComposedShader": "shaders",
    "ProgramShader": "shaders", "PackagedShader": "shaders", "ShaderPart": "parts",
    "ShaderProgram": "programs", "FogCoordinate": "fogCoord",
})
_XML_SKIP = {"DEF", "USE", "containerField", "class", "id", "style", "noNamespaceSchemaLocation",
             "xsd", "xmlns"}


# -- reading files -------------------------------------------------------------------------

_GZIP_MAGIC = b"\x1f\x8b"
_HEADER = re.compile(r"#\s*(VRML|X3D)\s+V(\d+(?:\.\d+)?)[ \t]*([^\r\n]*)", re.I)


def _read_file(path: str) -> bytes:
    try:
        size = os.path.getsize(path)
        if size > MAX_BYTES:
            raise X3DError(path, f"{size} bytes: larger than {MAX_BYTES} bytes; refused")
        with open(path, "rb") as handle:
            return handle.read(MAX_BYTES + 1)
    except OSError as error:
        raise X3DError(path, error.strerror or str(error)) from None


def _gunzip(data: bytes, path: str, notes) -> bytes:
    """*data* decompressed when it is gzip (by its magic bytes, whatever the file's name;
    members one after the other), at most MAX_BYTES; a stream that breaks off keeps what
    decompressed, with a warning."""
    if not data.startswith(_GZIP_MAGIC):
        return data
    parts, total, rest = [], 0, data
    while rest.startswith(_GZIP_MAGIC):
        stream = zlib.decompressobj(16 + zlib.MAX_WBITS)
        try:
            chunk = stream.decompress(rest, MAX_BYTES + 1 - total)
        except zlib.error as error:
            if not total:
                raise X3DError(path, f"gzip data that cannot be decompressed ({error})") from None
            notes.add("gzip streams that break off: the part decompressed is read",
                      os.path.basename(path))
            break
        parts.append(chunk)
        total += len(chunk)
        if total > MAX_BYTES or stream.unconsumed_tail:
            raise X3DError(path, f"decompresses to more than {MAX_BYTES} bytes; refused")
        if not stream.eof:
            if not total:
                raise X3DError(path, "gzip data that ends before anything decompressed")
            notes.add("gzip streams that break off: the part decompressed is read",
                      os.path.basename(path))
            break
        rest = stream.unused_data
    return b"".join(parts)


class _Started(Exception):
    pass


def _refuse_entities(data: bytes, path: str) -> None:
    """X3DError when the document type declares an entity (internal or external), found by
    expat itself before the root element; nothing is expanded (no "billion laughs")."""
    scan = expat.ParserCreate()

    def declared(*_args):
        raise X3DError(path, "declares XML entities (<!DOCTYPE ... <!ENTITY>); refused "
                             "(entity expansion and external entities are not read)")

    def started(*_args):
        raise _Started

    scan.EntityDeclHandler = declared
    scan.UnparsedEntityDeclHandler = declared
    scan.StartElementHandler = started
    try:
        scan.Parse(data, True)
    except (_Started, expat.ExpatError):
        return


def _local(tag) -> str:
    return tag.rsplit("}", 1)[-1] if isinstance(tag, str) else ""


def _xml_root(data: bytes, path: str, notes):
    """The root element; XML that breaks off (a truncated file) keeps what came before, with
    a warning; XML with no element at all is an X3DError."""
    parser = ET.XMLPullParser(events=("start",))
    root = None
    try:
        parser.feed(data)
        for _event, element in parser.read_events():
            root = element
            break
        parser.close()
    except ET.ParseError as error:
        if root is None:
            for _event, element in parser.read_events():
                root = element
                break
        if root is None:
            raise X3DError(path, f"not well-formed XML ({error})") from None
        notes.add("XML that is not well-formed: the part before the error is read", str(error))
    return root


class _Xml:
    """X3D's XML encoding into the same generic nodes as the classic one."""

    def __init__(self, src, notes, reader):
        self.src = src
        self.notes = notes
        self.reader = reader

    def statements(self, parent, out, depth, scope):
        for element in parent:
            tag = _local(element.tag)
            if not tag or tag.startswith("Metadata"):
                continue
            if tag == "ROUTE":
                self.reader.ignored["ROUTE"] = self.reader.ignored.get("ROUTE", 0) + 1
            elif tag == "ProtoDeclare":
                self.proto(element, depth, scope)
            elif tag == "ExternProtoDeclare":
                self.extern(element, scope)
            elif tag in ("IMPORT", "EXPORT", "component", "unit", "meta", "head", "field",
                         "IS", "fieldValue"):
                continue
            else:
                node = self.node(element, depth, scope)
                if node is not None:
                    out.append(node)

    def node(self, element, depth, scope):
        tag = _local(element.tag)
        use = element.get("USE")
        if use is not None:
            found = scope.defs.get(use)
            return found if found is not None else _Use(use, scope)
        if depth > MAX_DEPTH:
            self.reader.too_deep += 1
            return None
        if tag == "ProtoInstance":
            return self.instance(element, depth, scope)
        name = element.get("DEF")
        proto = scope.proto(tag)
        node = _N(tag, name, proto, self.src)
        for key, value in element.attrib.items():
            key = _local(key)
            if (key not in _XML_SKIP or (key == "style" and tag in ("FontStyle",
                                                                     "ScreenFontStyle"))) \
                    and not key.startswith("xmlns"):
                node.fields[key] = _Raw(value)
        self.children(element, node, depth, scope)
        if name is not None:
            scope.defs[name] = node
        return node

    def children(self, element, node, depth, scope):
        for child in element:
            tag = _local(child.tag)
            if not tag or tag.startswith("Metadata") or tag in ("field", "fieldValue"):
                continue
            if tag == "IS":
                self.connect(child, node)
                continue
            if tag == "ROUTE":
                self.reader.ignored["ROUTE"] = self.reader.ignored.get("ROUTE", 0) + 1
                continue
            if tag in ("ProtoDeclare", "ExternProtoDeclare"):
                continue
            value = self.node(child, depth + 1, scope)
            if value is None:
                continue
            container = child.get("containerField") or self.container(tag)
            held = node.fields.get(container)
            if not isinstance(held, list):      # (an IS on the same field is kept beside)
                held = [held] if isinstance(held, _IS) else []
                node.fields[container] = held
            held.append(value)

    @staticmethod
    def container(tag):
        if tag in _CONTAINER:
            return _CONTAINER[tag]
        canonical = _KNOWN_LOWER.get(tag.lower())
        return _CONTAINER.get(canonical, "children")

    @staticmethod
    def connect(element, node):
        for connect in element:
            if _local(connect.tag) == "connect":
                node_field, proto_field = connect.get("nodeField"), connect.get("protoField")
                if node_field and proto_field:
                    held = node.fields.get(node_field)
                    if isinstance(held, list):  # child nodes given too: both are kept
                        held.append(_IS(proto_field))
                    else:
                        node.fields[node_field] = _IS(proto_field)

    def instance(self, element, depth, scope):
        name = element.get("name") or ""
        proto = scope.proto(name)
        if proto is None and name:
            proto = scope.proto_ci(name)
            if proto is not None:
                self.notes.add("node and field names read regardless of case",
                               f"{name} → {proto.name}")
        node = _N(name or "ProtoInstance", element.get("DEF"), proto, self.src)
        for child in element:
            tag = _local(child.tag)
            if tag == "fieldValue":
                fname = child.get("name")
                if not fname:
                    continue
                if "value" in child.attrib:
                    node.fields[fname] = _Raw(child.get("value"))
                else:
                    nodes = [self.node(c, depth + 1, scope) for c in child
                             if _local(c.tag) and not _local(c.tag).startswith("Metadata")]
                    node.fields[fname] = [n for n in nodes if n is not None]
            elif tag == "IS":
                self.connect(child, node)
        if node.name is not None:
            scope.defs[node.name] = node
        return node

    def interface(self, element, proto, depth, scope, extern=False):
        for child in element:
            if _local(child.tag) != "field":
                continue
            fname = child.get("name")
            if not fname:
                continue
            access = child.get("accessType", "inputOutput")
            ftype = child.get("type", "")
            default = _MISSING
            if not extern and access not in ("inputOnly", "outputOnly"):
                if "value" in child.attrib:
                    default = _Raw(child.get("value"))
                else:
                    nodes = [self.node(c, depth + 1, scope) for c in child
                             if _local(c.tag) and not _local(c.tag).startswith("Metadata")]
                    nodes = [n for n in nodes if n is not None]
                    if nodes or ftype.upper().startswith("MF"):
                        default = nodes
                    elif ftype.upper() == "SFNODE":
                        default = None
            proto.fields[fname] = (access, ftype, default)

    def proto(self, element, depth, scope):
        name = element.get("name")
        if not name:
            self.notes.add("PROTO statements that could not be read", "a ProtoDeclare without name")
            return
        proto = _Proto(name, self.src)
        inner = _Scope(scope)
        proto.defs = inner.defs
        for child in element:
            tag = _local(child.tag)
            if tag == "ProtoInterface":
                self.interface(child, proto, depth, scope)
        scope.protos[name] = proto
        for child in element:
            if _local(child.tag) == "ProtoBody":
                self.statements(child, proto.body, depth + 1, inner)

    def extern(self, element, scope):
        name = element.get("name")
        if not name:
            return
        proto = _Proto(name, self.src)
        self.interface(element, proto, 0, scope, extern=True)
        proto.extern_urls = _mfstring(element.get("url", ""))
        scope.protos[name] = proto


_QUOTED = re.compile(r'"((?:[^"\\]|\\.)*)"', re.S)


def _mfstring(text: str) -> list:
    """An MFString written in XML: quoted strings (escapes \\" and \\\\), or — as some writers
    write it — one string without quotes."""
    if '"' in text:
        return [_UNESCAPE.sub(r"\1", s) if "\\" in s else s for s in _QUOTED.findall(text)]
    text = text.strip()
    return [text] if text else []


# -- resolving URLs ------------------------------------------------------------------------

def _unquote(text: str) -> str:
    raw = text.encode("utf-8", "surrogateescape")
    decoded = re.sub(rb"%([0-9A-Fa-f]{2})", lambda m: bytes([int(m.group(1), 16)]), raw)
    return decoded.decode("utf-8", "replace")


def resolve_local(url: str, base: str) -> str | None:
    """The default resolver: the local file a URL names, relative to the folder *base* of the
    file that names it (``file:`` URLs and Windows paths included, percent-escapes decoded,
    a ``#fragment`` dropped); None for a URL of another scheme (http, urn, data: nothing is
    fetched).  A resolver is any callable (url, base) → path or None."""
    url = url.strip()
    if not url:
        return None
    lower = url.lower()
    if lower.startswith("file:"):
        path = url[5:]
        if path.startswith("//"):
            path = "/" + path[2:].partition("/")[2]
        if re.match(r"^/[A-Za-z]:", path):
            path = path[1:]
    elif re.match(r"^[a-z][a-z0-9+.\-]+:", lower) and not re.match(r"^[a-z]:[\\/]", lower):
        return None
    else:
        path = url
    path = path.split("#", 1)[0]
    if not path:
        return None
    if "%" in path and not os.path.exists(os.path.join(base, path)):
        path = _unquote(path)
    path = path.replace("\\", "/")
    if not os.path.isabs(path) and not re.match(r"^[A-Za-z]:/", path):
        path = os.path.join(base, path)
    return os.path.normpath(path)


class _Budget(Exception):
    pass


_CASE = "node and field names read regardless of case"


# -- the reader: generic nodes → the data model -------------------------------------------

class _Reader:
    def __init__(self, resolver=None):
        self.resolver = resolver or resolve_local
        self.notes = _Notes()
        self.ignored = {}           # node type → count (behaviour, sound, shaders, ROUTE)
        self.unknown = {}           # unknown node types → count
        self.too_deep = 0
        self.memo = {}              # id(_N) → (_N, built object); the _N is kept alive
        self.busy = set()
        self.copies = 0
        self.expanded = {}          # id(instance) → (instance, copied body root)
        self.files = {}             # real path → _Source (None: failed or being read)
        self.loading = []           # Inline files being built (recursion)
        self.canon = {}             # type as written → canonical type (or None)
        self.doc = None
        self.main = None
        self.bound = set()
        self.arrays = {}
        self.tessellated = {}

    # files ------------------------------------------------------------------------------
    def unit(self, src, category, name, factor):
        value = _word_number(factor) if isinstance(factor, str) else float(factor)
        if not (isinstance(value, (int, float)) and math.isfinite(value) and value > 0):
            self.notes.add("UNIT statements that could not be read", f"{category} {factor}")
            return
        category = category.lower()
        if category == "length":
            src.meter, src.unit_name = float(value), name
        elif category == "angle":
            src.angle = float(value)

    def parse(self, data, path, depth=0):
        """A file's bytes (gzip or not) into a _Source: its top-level nodes and PROTOs."""
        if isinstance(data, str):
            data = data.encode("utf-8")
        if len(data) > MAX_BYTES:
            raise X3DError(path, f"{len(data)} bytes: larger than {MAX_BYTES} bytes; refused")
        data = _gunzip(data, path, self.notes)
        head = data[:256].lstrip(b"\xef\xbb\xbf \t\r\n")
        if head.startswith(b"<"):
            return self.parse_xml(data, path, depth)
        try:
            text = data.decode("utf-8")
        except UnicodeDecodeError:
            text = data.decode("latin-1")
            self.notes.add("files that are not UTF-8, read as Latin-1", os.path.basename(path))
        text = text.lstrip("\ufeff \t\r\n")
        first = text.split("\n", 1)[0]
        match = _HEADER.match(first)
        header = True
        if match is None:
            header = False
            lower = path.lower()
            classic = lower.endswith((".x3dv", ".x3dvz", ".x3dv.gz"))
            encoding, version = ("x3d-classic", "3.0") if classic else ("vrml97", "2.0")
        else:
            kind, version = match.group(1).upper(), match.group(2)
            if kind == "VRML" and not version.startswith("2"):
                raise X3DError(path, f"a VRML {version} file: VRML 1.0 is not read (only VRML97 "
                                     "'#VRML V2.0 utf8' and X3D)")
            encoding = "vrml97" if kind == "VRML" else "x3d-classic"
            text = text[len(first):]
        src = _Source(path, encoding, version, depth)
        parser = _Classic(_strip_comments(text), src, self.notes, self)
        parser.statements(src.nodes, 1)
        if parser.truncated:
            self.notes.add("files that end inside a node, a list or a string (truncated?): "
                           "what came before is read", os.path.basename(path))
        if not header:
            if not src.nodes and not src.scope.protos:
                raise X3DError(path, "not a VRML97 or X3D file (no '#VRML V2.0 utf8' or "
                                     "'#X3D' header, and no node)")
            self.notes.add("files without a '#VRML V2.0 utf8' header, read as " + encoding,
                           os.path.basename(path))
        return src

    def parse_xml(self, data, path, depth):
        _refuse_entities(data, path)
        root = _xml_root(data, path, self.notes)
        tag = _local(root.tag)
        if tag.lower() != "x3d":
            raise X3DError(path, f"not an X3D file (its root element is <{tag}>)")
        src = _Source(path, "x3d-xml", root.get("version", "3.0"), depth)
        src.profile = root.get("profile", "")
        scene = None
        for child in root:
            ctag = _local(child.tag).lower()
            if ctag == "head":
                for item in child:
                    itag = _local(item.tag).lower()
                    if itag == "meta" and item.get("name") is not None:
                        src.meta[item.get("name")] = item.get("content", "")
                    elif itag == "unit":
                        self.unit(src, item.get("category", ""), item.get("name", ""),
                                  item.get("conversionFactor", ""))
            elif ctag == "scene" and scene is None:
                scene = child
        if scene is None:
            self.notes.add("X3D files without a <Scene>", os.path.basename(path))
        else:
            _Xml(src, self.notes, self).statements(scene, src.nodes, 1, src.scope)
        return src

    def parse_file(self, path, depth):
        """An Inline or EXTERNPROTO file (parsed once, cached by real path); None (with a
        warning) when it cannot be read."""
        real = os.path.realpath(path)
        if real in self.files:
            return self.files[real]
        self.files[real] = None
        if depth > MAX_INLINE_DEPTH:
            self.notes.add(f"Inline / EXTERNPROTO files nested deeper than {MAX_INLINE_DEPTH} "
                           "left out", os.path.basename(path))
            return None
        try:
            src = self.parse(_read_file(real), real, depth)
        except X3DError as error:
            self.notes.add("Inline / EXTERNPROTO files that could not be read", str(error))
            return None
        self.files[real] = src
        return src

    # field access ------------------------------------------------------------------------
    def field(self, n, name):
        fields = n.fields
        if name in fields:
            return fields[name]
        if fields:
            lower = name.lower()
            for key, value in fields.items():
                if key.lower() == lower:
                    self.notes.add(_CASE, f"{key} → {name}")
                    return value
        return _MISSING

    def where(self, n, name):
        return f"{n.type}.{name}" + (f" ('{n.name}')" if n.name else "")

    def numbers(self, n, name):
        """The numbers of a field as float64 (None when absent); a value of another kind is
        a warning."""
        value = self.field(n, name)
        if value is _MISSING or value is None:
            return None
        if isinstance(value, np.ndarray):
            arr = value
        elif isinstance(value, _Raw):
            arr = _bulk_numbers(value)
            if arr is None:
                arr = _numbers_of(value.replace(",", " ").split() or ["0"]) if value.strip() \
                    else np.zeros(0)
        elif isinstance(value, bool):
            arr = np.array([float(value)])
        elif isinstance(value, (int, float)):
            arr = np.array([value], dtype=np.float64)
        elif isinstance(value, list) and all(isinstance(v, (int, float)) for v in value):
            arr = np.array([float(v) for v in value])
        else:
            self.notes.add("fields whose value is not numbers: defaults used", self.where(n, name))
            return None
        return _finite(arr, self.notes, self.where(n, name))

    def vec(self, n, name, default):
        arr = self.numbers(n, name)
        if arr is None:
            return default
        if len(arr) < len(default):
            self.notes.add("fields with too few numbers: defaults used", self.where(n, name))
            return default
        return tuple(float(v) for v in arr[:len(default)])

    def num(self, n, name, default):
        return self.vec(n, name, (default,))[0]

    def angle(self, n, name, default):
        """An angle field in radians (the file's UNIT angle applied); *default* is radians."""
        arr = self.numbers(n, name)
        if arr is None or not len(arr):
            return default
        return float(arr[0]) * (n.src.angle if n.src is not None else 1.0)

    def rotation(self, n, name):
        x, y, z, a = self.vec(n, name, (0.0, 0.0, 1.0, 0.0))
        if a != 0.0 and x == y == z == 0.0:
            self.notes.add("rotations about a zero axis read as none", self.where(n, name))
            return (0.0, 0.0, 1.0, 0.0)
        return (x, y, z, a * (n.src.angle if n.src is not None else 1.0))

    def ints(self, n, name):
        """An integer array field (int64; empty when absent); numbers that are not integers
        become an index that is out of range (so the face using them is dropped)."""
        value = self.field(n, name)
        if value is _MISSING or value is None:
            return np.zeros(0, np.int64)
        if isinstance(value, np.ndarray) and value.dtype == np.int64:
            return value
        arr = self.numbers(n, name)
        if arr is None:
            return np.zeros(0, np.int64)
        whole = np.round(arr)
        bad = whole != arr
        if bad.any():
            self.notes.add("indices that are not integers read as out of range",
                           self.where(n, name), int(bad.sum()))
            whole[bad] = 2.0 ** 62
        return np.clip(whole, -(2.0 ** 62), 2.0 ** 62).astype(np.int64)

    def flag(self, n, name, default):
        value = self.field(n, name)
        if value is _MISSING or value is None:
            return default
        if isinstance(value, bool):
            return value
        if isinstance(value, _Raw):
            word = value.strip().strip('"').lower()
            if word in ("true", "false"):
                return word == "true"
        elif isinstance(value, list) and value and isinstance(value[0], (bool, str)):
            first = value[0]
            if isinstance(first, bool):
                return first
            if first.lower() in ("true", "false"):
                return first.lower() == "true"
        elif isinstance(value, np.ndarray) and len(value) == 1:
            return bool(value[0])
        self.notes.add("booleans that could not be read: defaults used", self.where(n, name))
        return default

    def strings(self, n, name):
        value = self.field(n, name)
        if value is _MISSING or value is None:
            return []
        if isinstance(value, _Raw):
            return _mfstring(value)
        if isinstance(value, list):
            return [v for v in value if isinstance(v, str)]
        return []

    def string(self, n, name, default=""):
        value = self.field(n, name)
        if isinstance(value, _Raw):
            text = str(value)
            if len(text) >= 2 and text[0] == text[-1] == '"':
                text = text[1:-1]
            return text
        if isinstance(value, list) and value and isinstance(value[0], str):
            return value[0]
        return default

    def node_value(self, n, name):
        value = self.field(n, name)
        if isinstance(value, list):
            value = next((v for v in value if isinstance(v, (_N, _Use))), None)
        return value if isinstance(value, (_N, _Use)) else None

    def node_values(self, n, name):
        value = self.field(n, name)
        if isinstance(value, (_N, _Use)):
            return [value]
        if isinstance(value, list):
            return [v for v in value if isinstance(v, (_N, _Use))]
        return []

    # nodes --------------------------------------------------------------------------------
    def lookup(self, value):
        """A field's node: a _Use resolved in its scope, a PROTO instance expanded to the node
        it stands for (its body's first node), None when there is none."""
        for _ in range(MAX_PROTO_DEPTH + 2):
            if isinstance(value, _Use):
                found = value.scope.defs.get(value.name)
                if found is None:
                    self.notes.add("USE of names never DEF'd: left out", value.name)
                    return None
                value = found
            if not isinstance(value, _N):
                return None
            if value.proto is None:
                return value
            value = self.expand(value)
        return None

    def type_of(self, n):
        written = n.type
        if written in self.canon:
            return self.canon[written]
        if written in _KNOWN:
            canonical = written
        else:
            canonical = _KNOWN_LOWER.get((written or "").lower())
            if canonical is not None:
                self.notes.add(_CASE, f"{written} → {canonical}")
        self.canon[written] = canonical
        return canonical

    def build(self, value, depth, hint, want):
        """The model object of a node (memoised: a node USE'd twice gives the same object),
        None when it is not one of *want* ("child", "geometry", "appearance", "material",
        "texture", "texture_transform") or cannot be built."""
        n = self.lookup(value)
        if n is None:
            return None
        key = id(n)
        if key in self.memo:
            return self.memo[key][1]
        if key in self.busy:
            self.notes.add("nodes used inside themselves (a USE within its own DEF, a PROTO "
                           "instance within its own PROTO): left out", n.name or n.type)
            return None
        if depth > MAX_DEPTH:
            self.too_deep += 1
            return None
        self.busy.add(key)
        try:
            obj = self.dispatch(n, depth, hint, want)
        finally:
            self.busy.discard(key)
        self.memo[key] = (n, obj)
        return obj

    def dispatch(self, n, depth, hint, want):
        t = self.type_of(n)
        if t is None:
            if want == "child" or want is None:
                self.unknown[n.type] = self.unknown.get(n.type, 0) + 1
                kids = self.node_values(n, "children")
                if kids:
                    return self.group(n, n.type, depth, hint)
            else:
                self.unknown[n.type] = self.unknown.get(n.type, 0) + 1
            return None
        if t in _IGNORED:
            self.ignored[t] = self.ignored.get(t, 0) + 1
            return None
        if t in _GEOMETRY_SKIPPED:
            self.notes.add("geometry nodes not read (not tessellated here): left out", t)
            return None
        if want == "child":
            if t in _GROUPS:
                return self.group(n, t, depth, hint)
            if t == "Shape":
                return self.shape(n, depth, hint)
            if t in _LIGHTS:
                return self.light(n, t)
            if t in _VIEWPOINTS:
                return self.viewpoint(n, t)
            if t in _BINDABLES:
                self.bindable(n, t)
                return None
            if t == "Inline":
                return self.inline(n, depth, hint)
        elif want == "geometry" and t in _GEOMETRY:
            return self.geometry(n, t, hint)
        elif want == "appearance" and t == "Appearance":
            return self.appearance(n, depth, hint)
        elif want == "material" and t in _MATERIALS:
            return self.material(n, t, hint)
        elif want == "texture" and t in _TEXTURES:
            return self.texture(n, t, depth)
        elif want == "texture_transform" and t == "TextureTransform":
            return TextureTransform(
                name=n.name or "", center=self.vec(n, "center", (0.0, 0.0)),
                rotation=self.angle(n, "rotation", 0.0), scale=self.vec(n, "scale", (1.0, 1.0)),
                translation=self.vec(n, "translation", (0.0, 0.0)))
        self.notes.add("nodes where the standard allows none of their type: left out",
                       f"{t} as {want}")
        return None

    # PROTO ---------------------------------------------------------------------------------
    def proto_of(self, inst):
        proto = inst.proto
        if proto.extern_urls is None:
            return proto
        if proto.resolved is None:
            proto.resolved = False
            for url in proto.extern_urls:
                file_part, _, name = url.partition("#")
                if file_part:
                    path = self.resolver(file_part, proto.src.base)
                    src = self.parse_file(path, proto.src.depth + 1) \
                        if path and os.path.isfile(path) else None
                else:
                    src = proto.src
                if src is None:
                    continue
                protos = src.scope.protos
                found = protos.get(name) if name else next(iter(protos.values()), None)
                if found is not None and found.extern_urls is None:
                    proto.resolved = found
                    break
            if not proto.resolved:
                self.notes.add("EXTERNPROTOs whose PROTO was not found: instances left out",
                               proto.name)
        return proto.resolved or None

    def expand(self, inst):
        """The node a PROTO instance stands for: its PROTO's first body node, with the nodes
        that depend on the instance's fields through IS copied (IS fields taking the instance's
        values, else the interface's defaults) and the rest shared between instances, like a
        USE (memoised per instance)."""
        key = id(inst)
        if key in self.expanded:
            return self.expanded[key][1]
        self.expanded[key] = (inst, None)
        proto = self.proto_of(inst)
        if proto is None:
            return None
        if any(p is proto for p in inst.chain):
            self.notes.add("PROTO instances inside their own PROTO: left out", proto.name)
            return None
        if len(inst.chain) >= MAX_PROTO_DEPTH:
            self.notes.add(f"PROTO instances nested deeper than {MAX_PROTO_DEPTH}: left out",
                           proto.name)
            return None
        if not proto.body:
            return None
        values = {name: spec[2] for name, spec in proto.fields.items()}
        lower = {name.lower(): name for name in proto.fields}
        for name, value in inst.fields.items():
            if name not in values:
                if name.lower() in lower:
                    self.notes.add(_CASE, f"{name} → {lower[name.lower()]}")
                    name = lower[name.lower()]
                else:
                    self.notes.add("PROTO instance fields not in the PROTO's interface: ignored",
                                   f"{proto.name}.{name}")
                    continue
            values[name] = value
        try:
            root = self.copy(proto, values, inst.chain + (proto,))
        except _Budget:
            self.notes.add(f"PROTO expansion beyond {MAX_NODES:,} copied nodes: the rest left "
                           "out", proto.name)
            return None
        if root is not None and root.name is None and root is not proto.body[0]:
            root.name = inst.name
        self.expanded[key] = (inst, root)
        return root

    @staticmethod
    def _refs(node):
        """The nodes a node's fields hold (a _Use resolved in its scope), and whether a field
        is an IS."""
        found, has_is = [], False
        for value in node.fields.values():
            for item in (value if isinstance(value, list) else (value,)):
                if isinstance(item, _N):
                    found.append(item)
                elif isinstance(item, _Use):
                    target = item.scope.defs.get(item.name)
                    if target is not None:
                        found.append(target)
                elif isinstance(item, _IS):
                    has_is = True
        return found, has_is

    def dynamic(self, proto) -> set:
        """ids of the body nodes from which an IS can be reached (computed once a PROTO,
        iteratively): only these are copied per instance."""
        if proto.dynamic is not None:
            return proto.dynamic
        dynamic, state = set(), {}
        stack = [(proto.body[0], False)]
        while stack:
            node, done = stack.pop()
            if done:
                found, has_is = self._refs(node)
                if has_is or any(id(n) in dynamic for n in found):
                    dynamic.add(id(node))
                continue
            if id(node) in state:
                continue
            state[id(node)] = True
            stack.append((node, True))
            stack.extend((n, False) for n in self._refs(node)[0] if id(n) not in state)
        proto.dynamic = dynamic
        return dynamic

    def copy(self, proto, values, chain):
        """Copy the body nodes of *proto* that depend on IS (iteratively), sharing within the
        copy what the body shares (DEF/USE); IS fields take *values* (not copied)."""
        root = proto.body[0]
        dynamic = self.dynamic(proto)
        if id(root) not in dynamic:
            return root
        memo = {}
        order = []
        stack = [root]
        while stack:
            node = stack.pop()
            if id(node) in memo or id(node) not in dynamic:
                continue
            self.copies += 1
            if self.copies > MAX_NODES:
                raise _Budget
            new = _N(node.type, node.name, node.proto, node.src, chain)
            memo[id(node)] = new
            order.append((node, new))
            stack.extend(self._refs(node)[0])

        def substitute(value):
            if isinstance(value, _IS):
                if value.name in values:
                    return values[value.name]
                for key in values:
                    if key.lower() == value.name.lower():
                        return values[key]
                self.notes.add("IS naming no field of its PROTO: ignored", value.name)
                return _MISSING
            if isinstance(value, _N):
                return memo.get(id(value), value)
            if isinstance(value, _Use):
                found = value.scope.defs.get(value.name)
                return memo.get(id(found), found) if found is not None else value
            return value

        for node, new in order:
            for key, value in node.fields.items():
                if isinstance(value, list) and value and not isinstance(value, _Raw):
                    out = []
                    for item in value:
                        item = substitute(item)
                        if item is _MISSING or item is None:
                            continue
                        if isinstance(item, list):
                            out.extend(item)
                        else:
                            out.append(item)
                    new.fields[key] = out
                else:
                    value = substitute(value)
                    if value is not _MISSING:
                        new.fields[key] = value
        return memo[id(root)]

    # the scene graph ------------------------------------------------------------------------
    def group(self, n, t, depth, hint):
        name = n.name or ""
        obj = Transform(name=name, kind=t)
        if t in _TRANSFORM_LIKE:
            obj.matrix = transform_matrix(
                self.vec(n, "translation", (0.0, 0.0, 0.0)), self.rotation(n, "rotation"),
                self.vec(n, "scale", (1.0, 1.0, 1.0)), self.rotation(n, "scaleOrientation"),
                self.vec(n, "center", (0.0, 0.0, 0.0)))
        elif t == "MatrixTransform":
            obj.matrix = self.matrix_field(n)
        if t == "Switch":
            kids = self.node_values(n, "choice") or self.node_values(n, "children")
            which = int(self.num(n, "whichChoice", -1.0))
            kids = [kids[which]] if 0 <= which < len(kids) else []
        elif t == "LOD":
            kids = (self.node_values(n, "level") or self.node_values(n, "children"))[:1]
        elif t == "CADFace":        # XML files often leave the Shape's containerField out
            kids = self.node_values(n, "shape") or self.node_values(n, "children")
        elif t == "HAnimHumanoid":
            kids = (self.node_values(n, "skeleton") + self.node_values(n, "skin")
                    or self.node_values(n, "children"))
        else:
            kids = self.node_values(n, "children")
            if t == "Billboard":
                self.notes.add("Billboards read as Groups (a browser turns them towards the "
                               "viewer)", name or None)
        hint = name or hint
        for kid in kids:
            child = self.build(kid, depth + 1, hint, "child")
            if child is not None:
                obj.children.append(child)
        return obj

    def matrix_field(self, n):
        """MatrixTransform's ``matrix`` (16 numbers): written as in Inventor and X3D's
        SFMatrix4f, translation in the 13th to 15th numbers (M = values as 4×4, transposed);
        a matrix written the other way (translation in the 4th, 8th, 12th) is read as such."""
        arr = self.numbers(n, "matrix")
        if arr is None or len(arr) < 16:
            if arr is not None:
                self.notes.add("fields with too few numbers: defaults used",
                               self.where(n, "matrix"))
            return np.eye(4)
        m = arr[:16].reshape(4, 4)
        if m[0, 3] == m[1, 3] == m[2, 3] == 0.0 or (m[3, :3] != 0).any():
            m = m.T
        return m.copy()

    def shape(self, n, depth, hint):
        name = n.name or ""
        hint = name or hint
        appearance = self.build(self.node_value(n, "appearance"), depth + 1, hint, "appearance")
        geometry = self.build(self.node_value(n, "geometry"), depth + 1, hint, "geometry")
        if appearance is not None and appearance.texture is not None and geometry is not None \
                and geometry.uvs is None and len(geometry.corners) \
                and geometry.kind in _FACE_SETS:
            geometry.uvs = _default_uvs(geometry)
        return Shape(name=name, geometry=geometry, appearance=appearance)

    def appearance(self, n, depth, hint):
        name = n.name or ""
        hint = name or hint
        for shader in self.node_values(n, "shaders"):
            found = self.lookup(shader)
            if found is not None:
                kind = self.type_of(found) or found.type
                self.ignored[kind] = self.ignored.get(kind, 0) + 1
        if self.node_value(n, "backMaterial") is not None:
            self.notes.add("Appearance backMaterial (X3D 4) not read: the front material is "
                           "used on both sides", name or None)
        return Appearance(
            name=name,
            material=self.build(self.node_value(n, "material"), depth + 1, hint, "material"),
            texture=self.build(self.node_value(n, "texture"), depth + 1, hint, "texture"),
            texture_transform=self.build(self.node_value(n, "textureTransform"), depth + 1, hint,
                                         "texture_transform"))

    def material(self, n, t, hint):
        mat = Material(name=n.name or hint or "Material")
        if t == "UnlitMaterial":
            mat.kind = "unlit"
            mat.diffuse, mat.ambient_intensity, mat.shininess = (0.0, 0.0, 0.0), 0.0, 0.0
            mat.emissive = self.vec(n, "emissiveColor", (1.0, 1.0, 1.0))
            mat.transparency = self.num(n, "transparency", 0.0)
            return mat
        if t == "PhysicalMaterial":
            mat.kind = "physical"
            mat.diffuse = self.vec(n, "baseColor", (1.0, 1.0, 1.0))
            mat.emissive = self.vec(n, "emissiveColor", (0.0, 0.0, 0.0))
            mat.transparency = self.num(n, "transparency", 0.0)
            mat.metallic = self.num(n, "metallic", 1.0)
            mat.roughness = self.num(n, "roughness", 1.0)
            mat.ambient_intensity, mat.specular, mat.shininess = 0.0, (0.0, 0.0, 0.0), 0.0
            self.notes.add("PhysicalMaterials (X3D 4) read as their baseColor (diffuse) and "
                           "emissiveColor; metallic and roughness kept, not mapped", mat.name)
            return mat
        mat.diffuse = self.vec(n, "diffuseColor", (0.8, 0.8, 0.8))
        mat.ambient_intensity = self.num(n, "ambientIntensity", 0.2)
        mat.specular = self.vec(n, "specularColor", (0.0, 0.0, 0.0))
        mat.emissive = self.vec(n, "emissiveColor", (0.0, 0.0, 0.0))
        mat.shininess = self.num(n, "shininess", 0.2)
        mat.transparency = self.num(n, "transparency", 0.0)
        textures = [f for f in ("diffuseTexture", "emissiveTexture", "specularTexture",
                                "shininessTexture", "ambientTexture", "normalTexture",
                                "occlusionTexture") if self.node_value(n, f) is not None]
        if textures:
            self.notes.add("X3D 4 material textures not read", f"{mat.name}: {', '.join(textures)}")
        if t == "TwoSidedMaterial":
            mat.kind = "two_sided"
            if self.flag(n, "separateBackColor", False):
                mat.back = Material(
                    name=mat.name + " (back)",
                    diffuse=self.vec(n, "backDiffuseColor", (0.8, 0.8, 0.8)),
                    ambient_intensity=self.num(n, "backAmbientIntensity", 0.2),
                    specular=self.vec(n, "backSpecularColor", (0.0, 0.0, 0.0)),
                    emissive=self.vec(n, "backEmissiveColor", (0.0, 0.0, 0.0)),
                    shininess=self.num(n, "backShininess", 0.2),
                    transparency=self.num(n, "backTransparency", 0.0))
        return mat

    def texture(self, n, t, depth):
        if t == "MultiTexture":
            self.notes.add("MultiTextures read as their first texture", n.name or None)
            return self.build(next(iter(self.node_values(n, "texture")), None), depth + 1, "",
                              "texture")
        tex = Texture(name=n.name or "", kind=t, repeat_s=self.flag(n, "repeatS", True),
                      repeat_t=self.flag(n, "repeatT", True))
        if t == "PixelTexture":
            self.pixels(n, tex)
            return tex
        tex.urls = self.strings(n, "url")
        base = n.src.base if n.src is not None else os.getcwd()
        for url in tex.urls:
            path = self.resolver(url, base)
            if path is None:
                continue
            candidates = [path]
            beside = os.path.join(base, os.path.basename(path))
            if beside != path:
                candidates.append(beside)
            for candidate in candidates:
                if candidate not in tex.paths:
                    tex.paths.append(candidate)
                if tex.path is None and os.path.isfile(candidate):
                    tex.path = candidate
        if tex.path is None:
            self.notes.add("texture files not found", (tex.urls or ["(no url)"])[0])
        return tex

    def pixels(self, n, tex):
        """PixelTexture's SFImage: width height components, then one integer a pixel."""
        arr = self.ints(n, "image")
        if len(arr) < 3:
            return
        width, height, comps = (int(v) for v in arr[:3])
        if not (0 < width <= 16384 and 0 < height <= 16384 and 1 <= comps <= 4) \
                or len(arr) < 3 + width * height:
            self.notes.add("PixelTexture images that could not be read", tex.name or None)
            return
        values = arr[3:3 + width * height].astype(np.uint64)
        shifts = np.arange(comps - 1, -1, -1, dtype=np.uint64) * np.uint64(8)
        tex.image = ((values[:, None] >> shifts[None, :]) & np.uint64(255)).astype(
            np.uint8).reshape(height, width, comps)
        tex.components = comps

    def light(self, n, t):
        kind = _LIGHTS[t]
        light = Light(kind=kind, name=n.name or "")
        light.on = self.flag(n, "on", True)
        light.shadows = self.flag(n, "shadows", False)
        light.intensity = self.num(n, "intensity", 1.0)
        light.ambient_intensity = self.num(n, "ambientIntensity", 0.0)
        light.color = self.vec(n, "color", (1.0, 1.0, 1.0))
        if kind != "directional":
            light.location = self.vec(n, "location", (0.0, 0.0, 0.0))
            light.attenuation = self.vec(n, "attenuation", (1.0, 0.0, 0.0))
            light.radius = self.num(n, "radius", 100.0)
        if kind != "point":
            light.direction = self.vec(n, "direction", (0.0, 0.0, -1.0))
        if kind == "spot":
            beam, cut = SPOT_DEFAULTS["vrml97" if n.src.vrml97 else "x3d"]
            light.beam_width = self.angle(n, "beamWidth", beam)
            light.cut_off_angle = self.angle(n, "cutOffAngle", cut)
        light.is_global = self.flag(n, "global", kind != "directional")
        return light

    def viewpoint(self, n, t):
        vp = Viewpoint(name=n.name or "", kind=t)
        vp.position = self.vec(n, "position", (0.0, 0.0, 10.0))
        vp.orientation = self.rotation(n, "orientation")
        if t == "OrthoViewpoint":
            vp.ortho_field = self.vec(n, "fieldOfView", (-1.0, -1.0, 1.0, 1.0))
        else:
            vp.field_of_view = self.angle(n, "fieldOfView", 0.785398)
        vp.center_of_rotation = self.vec(n, "centerOfRotation", (0.0, 0.0, 0.0))
        vp.description = self.string(n, "description", "")
        if n.src is self.main and self.doc.viewpoint is None:
            self.doc.viewpoint = vp
        return vp

    def bindable(self, n, t):
        """The first NavigationInfo, Background and WorldInfo of the main file (an inlined
        file's are not bound, as the standard says)."""
        if n.src is not self.main or t in self.bound:
            return
        self.bound.add(t)
        doc = self.doc
        if t == "NavigationInfo":
            doc.headlight = self.flag(n, "headlight", True)
            if self.field(n, "type") is not _MISSING:
                doc.navigation_types = self.strings(n, "type")
        elif t == "Background":
            sky = self.numbers(n, "skyColor")
            doc.background = tuple(float(v) for v in sky[:3]) if sky is not None \
                and len(sky) >= 3 else (0.0, 0.0, 0.0)
        elif t == "WorldInfo":
            doc.title = self.string(n, "title", "")
            doc.info = self.strings(n, "info")

    def inline(self, n, depth, hint):
        group = Transform(name=n.name or "", kind="Inline")
        if not self.flag(n, "load", True):
            return group
        urls = self.strings(n, "url")
        path = None
        for url in urls:
            candidate = self.resolver(url, n.src.base)
            if candidate and os.path.isfile(candidate):
                path = candidate
                break
        if path is None:
            self.notes.add("Inline files not found: left out", urls[0] if urls else "(no url)")
            return group
        real = os.path.realpath(path)
        if real in self.loading or real == os.path.realpath(self.main.path or "."):
            self.notes.add("Inline files that include themselves: left out",
                           os.path.basename(path))
            return group
        src = self.parse_file(real, len(self.loading) + 1)
        if src is None:
            return group
        if src.meter != n.src.meter:
            ratio = src.meter / n.src.meter
            group.matrix = np.diag([ratio, ratio, ratio, 1.0])
        self.loading.append(real)
        try:
            for kid in src.nodes:
                child = self.build(kid, depth + 1, hint, "child")
                if child is not None:
                    group.children.append(child)
        finally:
            self.loading.pop()
        return group

    # geometry -----------------------------------------------------------------------------
    def data_node(self, n, name, types):
        found = self.lookup(self.node_value(n, name))
        if found is None:
            return None
        t = self.type_of(found)
        if t not in types:
            self.notes.add("nodes where the standard allows none of their type: left out",
                           f"{t or found.type} as {name}")
            return None
        return found

    def array(self, n, name, types, field_name, width):
        """The (k, width) values of a data node (Coordinate, Color, Normal ...), cached per
        node so that a USE'd Coordinate is read once."""
        node = self.data_node(n, name, types)
        if node is None:
            return None, None
        key = (id(node), field_name)
        if key in self.arrays:
            return self.arrays[key][1], node
        t = self.type_of(node)
        if t == "ColorRGBA":
            width = 4
        values = self.numbers(node, field_name)
        if values is None:
            values = np.zeros(0)
        if len(values) % width:
            self.notes.add("lists whose length is not a multiple of their tuple size: the "
                           "rest left out", self.where(node, field_name))
            values = values[:len(values) - len(values) % width]
        values = values.reshape(-1, width)
        if t == "Color":
            values = np.concatenate([values, np.ones((len(values), 1))], axis=1)
        self.arrays[key] = (node, values)
        return values, node

    def coords(self, n):
        points, node = self.array(n, "coord", ("Coordinate", "CoordinateDouble"), "point", 3)
        if points is None:
            found = self.lookup(self.node_value(n, "coord"))
            if found is not None and self.type_of(found) == "GeoCoordinate":
                self.notes.add("GeoCoordinate not read", found.name or None)
            return np.zeros((0, 3))
        return points

    def colors(self, n):
        return self.array(n, "color", ("Color", "ColorRGBA"), "color", 3)[0]

    def normals(self, n):
        return self.array(n, "normal", ("Normal",), "vector", 3)[0]

    def texcoords(self, n):
        found = self.lookup(self.node_value(n, "texCoord"))
        if found is not None and self.type_of(found) == "MultiTextureCoordinate":
            self.notes.add("MultiTextureCoordinate read as its first set", found.name or None)
            first = next(iter(self.node_values(found, "texCoord")), None)
            holder = _N("Shape", src=found.src)
            holder.fields["texCoord"] = first
            return self.array(holder, "texCoord", ("TextureCoordinate",), "point", 2)[0]
        if found is not None and self.type_of(found) == "TextureCoordinateGenerator":
            self.notes.add("TextureCoordinateGenerator not read: no texture coordinates",
                           found.name or None)
            return None
        return self.array(n, "texCoord", ("TextureCoordinate",), "point", 2)[0]

    def geometry(self, n, t, hint):
        mesh = Mesh(name=n.name or hint or t, kind=t)
        if t in _PRIMITIVES:
            self.primitive(n, t, mesh)
            return mesh
        mesh.solid = self.flag(n, "solid", True)
        mesh.ccw = self.flag(n, "ccw", True)
        if t == "IndexedFaceSet":
            self.face_set(n, mesh)
        elif t == "ElevationGrid":
            self.elevation_grid(n, mesh)
        elif t == "Extrusion":
            self.extrusion(n, mesh)
        elif t == "Text":
            self.text(n, mesh)
        elif t in ("IndexedLineSet", "LineSet"):
            self.line_set(n, t, mesh)
        elif t == "PointSet":
            mesh.positions = self.coords(n)
            colors = self.colors(n)
            if colors is not None and len(colors) >= len(mesh.positions):
                mesh.point_colors = colors[:len(mesh.positions)]
            elif colors is not None:
                self.notes.add("colours fewer than their points: left out", mesh.name)
        else:
            self.triangle_set(n, t, mesh)
        return mesh

    def attribute(self, values, index, per_vertex, faces, what, mesh):
        """Per-corner values of a face set attribute as ISO/IEC 14772-1 §6.23 and 19775-1
        §13.3.6 define them: per vertex by its own index (parallel to coordIndex) or else by
        coordIndex; per face by its index (one a face) or else in face order."""
        if values is None:
            return None
        sizes, corners, at, face_no = faces
        if not len(corners):
            return None
        if per_vertex:
            if len(index):
                if len(index) <= at.max():
                    self.notes.add(f"{what} left out: their index is shorter than coordIndex",
                                   mesh.name)
                    return None
                idx = index[at]
            else:
                idx = corners
        else:
            if len(index):
                if len(index) <= face_no.max():
                    self.notes.add(f"{what} left out: their index has fewer entries than faces",
                                   mesh.name)
                    return None
                idx = np.repeat(index[face_no], sizes)
            else:
                idx = np.repeat(face_no, sizes)
        if idx.min() < 0 or idx.max() >= len(values):
            self.notes.add(f"{what} left out: an index is out of range", mesh.name)
            return None
        return values[idx]

    def face_set(self, n, mesh):
        positions = self.coords(n)
        mesh.positions = positions
        mesh.convex = self.flag(n, "convex", True)
        mesh.crease_angle = self.angle(n, "creaseAngle", 0.0)
        mesh.color_per_vertex = self.flag(n, "colorPerVertex", True)
        mesh.normal_per_vertex = self.flag(n, "normalPerVertex", True)
        index = self.ints(n, "coordIndex")
        faces = self.polygons(index, len(positions), mesh)
        mesh.face_sizes, mesh.corners = faces[0], faces[1]
        mesh.normals = self.attribute(self.normals(n), self.ints(n, "normalIndex"),
                                      mesh.normal_per_vertex, faces, "normals", mesh)
        mesh.colors = self.attribute(self.colors(n), self.ints(n, "colorIndex"),
                                     mesh.color_per_vertex, faces, "colours", mesh)
        mesh.uvs = self.attribute(self.texcoords(n), self.ints(n, "texCoordIndex"), True, faces,
                                  "texture coordinates", mesh)

    def polygons(self, index, count, mesh, smallest=3):
        """Faces of an index list with -1 separators (the last may lack it): (sizes, corners,
        where each corner is in *index*, each face's number among the file's faces).  Faces
        with fewer than *smallest* corners or an index out of range are dropped (warned)."""
        index = np.asarray(index, dtype=np.int64)
        valid = np.flatnonzero(index >= 0)
        empty = np.zeros(0, np.int64)
        if not len(valid):
            return empty, empty, empty, empty
        run = np.cumsum(index < 0)[valid]
        starts = np.flatnonzero(np.r_[True, run[1:] != run[:-1]])
        sizes = np.diff(np.r_[starts, len(valid)])
        corners = index[valid]
        outside = np.add.reduceat((corners >= count).astype(np.int64), starts) > 0
        small = sizes < smallest
        if small.any():
            self.notes.add(f"faces or lines with fewer than {smallest} indices: left out",
                           mesh.name, int(small.sum()))
        if (outside & ~small).any():
            self.notes.add("faces or lines with a coordinate index out of range: left out",
                           mesh.name, int((outside & ~small).sum()))
        keep = ~(small | outside)
        if keep.all():
            return sizes, corners, valid, np.arange(len(sizes))
        corner_keep = np.repeat(keep, sizes)
        return sizes[keep], corners[corner_keep], valid[corner_keep], np.flatnonzero(keep)

    def triangle_set(self, n, t, mesh):
        """IndexedTriangleSet, TriangleSet, the fan and strip sets, IndexedQuadSet, QuadSet:
        faces of one index into coord, color, normal and texCoord alike; per-face values are
        one a triangle (or quad)."""
        positions = self.coords(n)
        mesh.positions = positions
        mesh.color_per_vertex = self.flag(n, "colorPerVertex", True)
        mesh.normal_per_vertex = self.flag(n, "normalPerVertex", True)
        indexed = t.startswith("Indexed")
        index = self.ints(n, "index") if indexed else np.arange(len(positions), dtype=np.int64)
        width = 4 if "Quad" in t else 3
        if t in ("IndexedTriangleSet", "TriangleSet", "IndexedQuadSet", "QuadSet"):
            usable = len(index) - len(index) % width
            if usable != len(index):
                self.notes.add("index lists whose length is not a multiple of their face size: "
                               "the rest left out", mesh.name)
            faces = index[:usable].reshape(-1, width)
        else:
            fan = "Fan" in t
            if indexed:
                seq_at = np.flatnonzero(index >= 0)
                run = np.cumsum(index < 0)[seq_at]
                starts = np.flatnonzero(np.r_[True, run[1:] != run[:-1]]) if len(run) else \
                    np.zeros(0, np.int64)
                counts = np.diff(np.r_[starts, len(seq_at)]).astype(np.int64)
                sequence = index[seq_at]
            else:
                counts = self.ints(n, "fanCount" if fan else "stripCount")
                sequence = index
                if counts.sum() > len(sequence) or (counts < 0).any():
                    self.notes.add("fan or strip counts beyond their coordinates: the rest "
                                   "left out", mesh.name)
                    counts = np.clip(counts, 0, None)
                    ends = np.cumsum(counts)
                    counts = counts[ends <= len(sequence)]
                starts = np.r_[0, np.cumsum(counts)[:-1]].astype(np.int64) if len(counts) \
                    else np.zeros(0, np.int64)
            if (counts < 3).any():
                self.notes.add("fans or strips of fewer than 3 vertices: left out", mesh.name)
                keep = counts >= 3
                starts, counts = starts[keep], counts[keep]
            faces = _fans(sequence, starts, counts) if fan else _strips(sequence, starts, counts)
        face_no = np.arange(len(faces))
        if len(faces):
            bad = (faces >= len(positions)).any(axis=1) | (faces < 0).any(axis=1)
            if bad.any():
                self.notes.add("faces or lines with a coordinate index out of range: left out",
                               mesh.name, int(bad.sum()))
                faces, face_no = faces[~bad], face_no[~bad]
        mesh.face_sizes = np.full(len(faces), faces.shape[1] if faces.ndim == 2 else 3, np.int64)
        mesh.corners = faces.reshape(-1).astype(np.int64)
        info = (mesh.face_sizes, mesh.corners, np.zeros(0, np.int64), face_no)
        empty = np.zeros(0, np.int64)
        mesh.normals = self.attribute(self.normals(n), empty, mesh.normal_per_vertex, info,
                                      "normals", mesh)
        mesh.colors = self.attribute(self.colors(n), empty, mesh.color_per_vertex, info,
                                     "colours", mesh)
        mesh.uvs = self.attribute(self.texcoords(n), empty, True, info, "texture coordinates",
                                  mesh)

    def elevation_grid(self, n, mesh):
        nx, nz = int(self.num(n, "xDimension", 0)), int(self.num(n, "zDimension", 0))
        dx, dz = self.num(n, "xSpacing", 1.0), self.num(n, "zSpacing", 1.0)
        heights = self.numbers(n, "height")
        mesh.crease_angle = self.angle(n, "creaseAngle", 0.0)
        mesh.color_per_vertex = self.flag(n, "colorPerVertex", True)
        mesh.normal_per_vertex = self.flag(n, "normalPerVertex", True)
        mesh.primitive = {"xDimension": nx, "zDimension": nz, "xSpacing": dx, "zSpacing": dz}
        if nx < 2 or nz < 2 or nx * nz > 50_000_000 or heights is None \
                or len(heights) < nx * nz:
            if nx * nz:
                self.notes.add("ElevationGrids whose heights do not fill the grid: left out",
                               mesh.name)
            return
        i, j = np.meshgrid(np.arange(nx), np.arange(nz))
        mesh.positions = np.stack([i.ravel() * dx, heights[:nx * nz], j.ravel() * dz], axis=1)
        qi, qj = np.meshgrid(np.arange(nx - 1), np.arange(nz - 1))
        qi, qj = qi.ravel(), qj.ravel()
        quads = np.stack([qi + qj * nx, qi + (qj + 1) * nx, qi + 1 + (qj + 1) * nx,
                          qi + 1 + qj * nx], axis=1)
        mesh.face_sizes = np.full(len(quads), 4, np.int64)
        mesh.corners = quads.reshape(-1).astype(np.int64)
        info = (mesh.face_sizes, mesh.corners, np.zeros(0, np.int64), np.arange(len(quads)))
        empty = np.zeros(0, np.int64)
        mesh.normals = self.attribute(self.normals(n), empty, mesh.normal_per_vertex, info,
                                      "normals", mesh)
        mesh.colors = self.attribute(self.colors(n), empty, mesh.color_per_vertex, info,
                                     "colours", mesh)
        uvs = self.texcoords(n)
        if uvs is None:     # the standard's default: s along x, t along z, 0 to 1
            uvs = np.stack([i.ravel() / (nx - 1), j.ravel() / (nz - 1)], axis=1)
        mesh.uvs = self.attribute(uvs, empty, True, info, "texture coordinates", mesh)

    def line_set(self, n, t, mesh):
        positions = self.coords(n)
        mesh.positions = positions
        mesh.color_per_vertex = self.flag(n, "colorPerVertex", True)
        if t == "IndexedLineSet":
            index = self.ints(n, "coordIndex")
        else:
            counts = self.ints(n, "vertexCount")
            counts = counts[(counts >= 0) & (np.cumsum(np.clip(counts, 0, None)) <= len(positions))]
            index = np.full(int(counts.sum()) + len(counts), -1, np.int64)
            starts = np.r_[0, np.cumsum(counts + 1)[:-1]].astype(np.int64) if len(counts) else \
                np.zeros(0, np.int64)
            offsets = np.r_[0, np.cumsum(counts)[:-1]].astype(np.int64) if len(counts) else \
                np.zeros(0, np.int64)
            within = np.arange(int(counts.sum())) - np.repeat(offsets, counts)
            index[np.repeat(starts, counts) + within] = np.repeat(offsets, counts) + within
        sizes, corners, _at, _face_no = self.polygons(index, len(positions), mesh, smallest=2)
        if len(sizes):
            ends = np.cumsum(sizes)
            first = np.arange(len(corners) - 1)
            keep = np.ones(len(first), bool)
            keep[ends[:-1] - 1] = False
            mesh.edges = np.stack([corners[first[keep]], corners[first[keep] + 1]], axis=1)
        else:
            mesh.edges = np.zeros((0, 2), np.int64)
        colors = self.colors(n)
        if colors is not None:
            if mesh.color_per_vertex and not len(self.ints(n, "colorIndex")) \
                    and len(colors) >= len(positions):
                mesh.point_colors = colors[:len(positions)]
            else:
                self.notes.add("line colours given per line or by colorIndex: left out",
                               mesh.name)

    def primitive(self, n, t, mesh):
        if t == "Box":
            p = {"size": self.vec(n, "size", (2.0, 2.0, 2.0))}
        elif t == "Sphere":
            p = {"radius": self.num(n, "radius", 1.0)}
        elif t == "Cylinder":
            p = {"radius": self.num(n, "radius", 1.0), "height": self.num(n, "height", 2.0),
                 "top": self.flag(n, "top", True), "bottom": self.flag(n, "bottom", True),
                 "side": self.flag(n, "side", True)}
        else:
            p = {"bottomRadius": self.num(n, "bottomRadius", 1.0),
                 "height": self.num(n, "height", 2.0), "side": self.flag(n, "side", True),
                 "bottom": self.flag(n, "bottom", True)}
        mesh.primitive = p
        key = (t,) + tuple(p.values())
        parts = self.tessellated.get(key)
        if parts is None:       # equal primitives share their (read-only) arrays
            maker = {"Box": _box, "Sphere": _sphere, "Cylinder": _cylinder, "Cone": _cone}[t]
            parts = maker(*p.values())
            self.tessellated[key] = parts
        mesh.positions, mesh.face_sizes, mesh.corners, mesh.normals, mesh.uvs = parts
        mesh.solid = self.flag(n, "solid", True)
        mesh.crease_angle = 0.5     # smooth sides, sharp edges (the normals are given anyway)

    def extrusion(self, n, mesh):
        """Extrusion: its faces by :func:`extrude` (ISO/IEC 14772-1 §6.18), smoothed by
        creaseAngle, with the standard's texture coordinates."""
        def pairs(name, width, default):
            values = self.numbers(n, name)
            if values is None:
                return np.asarray(default, dtype=np.float64).reshape(-1, width)
            if len(values) % width:
                self.notes.add("lists whose length is not a multiple of their tuple size: the "
                               "rest left out", self.where(n, name))
            return values[:len(values) - len(values) % width].reshape(-1, width)

        spine = pairs("spine", 3, [(0.0, 0.0, 0.0), (0.0, 1.0, 0.0)])
        cross = pairs("crossSection", 2, [(1, 1), (1, -1), (-1, -1), (-1, 1), (1, 1)])
        scales = pairs("scale", 2, [(1.0, 1.0)])
        orientations = pairs("orientation", 4, [(0.0, 0.0, 1.0, 0.0)]).copy()
        orientations[:, 3] *= n.src.angle if n.src is not None else 1.0
        mesh.convex = self.flag(n, "convex", True)
        mesh.crease_angle = self.angle(n, "creaseAngle", 0.0)
        made = extrude(spine, cross, scales, orientations, self.flag(n, "beginCap", True),
                       self.flag(n, "endCap", True), mesh.convex)
        for line in made["warnings"]:
            self.notes.add(line, mesh.name)
        mesh.positions, mesh.face_sizes = made["positions"], made["face_sizes"]
        mesh.corners, mesh.uvs = made["corners"], made["uvs"]
        if mesh.crease_angle > 0 and len(mesh.corners):   # flat without: Blender's faces
            normals = crease_normals(mesh.positions, mesh.face_sizes, mesh.corners,
                                     mesh.crease_angle)
            mesh.normals = normals if mesh.ccw else -normals

    def text(self, n, mesh):
        """Text: its strings and FontStyle as plain data in ``mesh.text`` (no faces here: the
        Blender side sets the text in its font).  Keys: strings, length (per string, 0: its
        natural length), max_extent, solid, and the FontStyle's family (list), style, size,
        spacing, justify (major, minor), horizontal, left_to_right, top_to_bottom,
        language."""
        style = self.lookup(self.node_value(n, "fontStyle"))
        if style is not None and self.type_of(style) != "FontStyle":
            self.notes.add("Text fontStyle that is not a FontStyle: defaults used",
                           style.name or style.type)
            style = None
        lengths = self.numbers(n, "length")
        font = {"family": ["SERIF"], "style": "PLAIN", "size": 1.0, "spacing": 1.0,
                "justify": ["BEGIN", "FIRST"], "horizontal": True, "left_to_right": True,
                "top_to_bottom": True, "language": ""}
        if style is not None:
            font.update(
                family=self.strings(style, "family") or ["SERIF"],
                style=self.string(style, "style", "PLAIN") or "PLAIN",
                size=self.num(style, "size", 1.0), spacing=self.num(style, "spacing", 1.0),
                justify=self.strings(style, "justify") or ["BEGIN"],
                horizontal=self.flag(style, "horizontal", True),
                left_to_right=self.flag(style, "leftToRight", True),
                top_to_bottom=self.flag(style, "topToBottom", True),
                language=self.string(style, "language", ""))
        words = [str(word).strip().upper() for word in font["justify"][:2]]
        font["justify"] = (words[0] if words and words[0] else "BEGIN",
                           words[1] if len(words) > 1 and words[1] else "FIRST")
        mesh.text = dict(font, strings=self.strings(n, "string"),
                         length=[float(v) for v in lengths] if lengths is not None else [],
                         max_extent=self.num(n, "maxExtent", 0.0),
                         solid=self.flag(n, "solid", False))

    # the end ------------------------------------------------------------------------------
    def finish(self, doc):
        if self.ignored:
            shown = ", ".join(f"{k} ×{v}" if v > 1 else k for k, v in sorted(self.ignored.items()))
            doc.warn("not imported (animation, interaction, scripts, sound, shaders, fog): "
                     + shown)
        if self.unknown:
            shown = ", ".join(f"{k} ×{v}" if v > 1 else k for k, v in sorted(self.unknown.items()))
            doc.warn(f"unknown node types skipped (their children read where they have them): "
                     f"{shown}")
        if self.too_deep:
            doc.warn(f"nodes nested deeper than {MAX_DEPTH} levels left out ({self.too_deep})")
        for line in self.notes.lines():
            doc.warn(line)


# -- tessellation ---------------------------------------------------------------------------

def _fans(sequence, starts, counts) -> np.ndarray:
    """Triangles (v0, vi, vi+1) of each fan."""
    tris = counts - 2
    if not len(tris) or tris.sum() <= 0:
        return np.zeros((0, 3), np.int64)
    owner = np.repeat(np.arange(len(tris)), tris)
    first = np.r_[0, np.cumsum(tris)[:-1]]
    i = np.arange(int(tris.sum())) - first[owner] + 1
    base = starts[owner]
    return np.stack([sequence[base], sequence[base + i], sequence[base + i + 1]], axis=1)


def _strips(sequence, starts, counts) -> np.ndarray:
    """Triangles of each strip, every other one turned so that all keep the strip's winding:
    (v_k, v_k+1, v_k+2) for even k, (v_k+1, v_k, v_k+2) for odd k."""
    tris = counts - 2
    if not len(tris) or tris.sum() <= 0:
        return np.zeros((0, 3), np.int64)
    owner = np.repeat(np.arange(len(tris)), tris)
    first = np.r_[0, np.cumsum(tris)[:-1]]
    k = np.arange(int(tris.sum())) - first[owner]
    base = starts[owner] + k
    a, b, c = sequence[base], sequence[base + 1], sequence[base + 2]
    odd = (k % 2) == 1
    return np.stack([np.where(odd, b, a), np.where(odd, a, b), c], axis=1)


def _box(size):
    """24 corners on 8 positions; each face CCW from outside with the standard's texture
    orientation (s right, t up as seen from outside; top seen with -Z up, bottom with +Z up)."""
    half = np.asarray(size, dtype=np.float64) / 2.0
    faces = [  # normal, s axis, t axis
        ((0, 0, 1), (1, 0, 0), (0, 1, 0)), ((0, 0, -1), (-1, 0, 0), (0, 1, 0)),
        ((1, 0, 0), (0, 0, -1), (0, 1, 0)), ((-1, 0, 0), (0, 0, 1), (0, 1, 0)),
        ((0, 1, 0), (1, 0, 0), (0, 0, -1)), ((0, -1, 0), (1, 0, 0), (0, 0, 1))]
    corner_pos, normals, uvs = [], [], []
    for normal, s_axis, t_axis in faces:
        n, s, t = (np.array(v, dtype=np.float64) for v in (normal, s_axis, t_axis))
        for us, ut in ((0, 0), (1, 0), (1, 1), (0, 1)):
            corner_pos.append((n + (2 * us - 1) * s + (2 * ut - 1) * t) * half)
            normals.append(n)
            uvs.append((us, ut))
    positions, corners = np.unique(np.array(corner_pos), axis=0, return_inverse=True)
    return (positions, np.full(6, 4, np.int64), corners.reshape(-1).astype(np.int64),
            np.array(normals), np.array(uvs, dtype=np.float64))


def _ring(radius, n=SEGMENTS):
    """Angles and (x, z) of a ring: seam at -Z, counter-clockwise seen from +Y (the
    standard's texture wrap): x = -r sin θ, z = -r cos θ."""
    theta = 2.0 * np.pi * np.arange(n) / n
    return theta, -radius * np.sin(theta), -radius * np.cos(theta)


def _sphere(radius, n=SEGMENTS, rings=SEGMENTS // 2):
    theta, x, z = _ring(1.0, n)
    phi = np.pi * np.arange(1, rings) / rings                # from the bottom pole
    ring_y, ring_r = -np.cos(phi), np.sin(phi)
    unit = np.concatenate([[[0.0, -1.0, 0.0], [0.0, 1.0, 0.0]],
                           np.stack([np.outer(ring_r, x).ravel(), np.repeat(ring_y, n),
                                     np.outer(ring_r, z).ravel()], axis=1)])

    def vid(i, j):      # position index of segment i (mod n), ring j (0 bottom ... rings top)
        if j == 0:
            return np.zeros_like(i)
        if j == rings:
            return np.ones_like(i)
        return 2 + (j - 1) * n + (i % n)

    i = np.arange(n)
    corners, uv, sizes = [], [], []
    for j in range(rings):
        t0, t1 = j / rings, (j + 1) / rings
        s0, s1 = i / n, (i + 1) / n
        if j == 0:
            quad = [vid(i, 0), vid(i + 1, 1), vid(i, 1)]
            coords = [((s0 + s1) / 2, 0 * s0), (s1, t1 + 0 * s0), (s0, t1 + 0 * s0)]
        elif j == rings - 1:
            quad = [vid(i, j), vid(i + 1, j), vid(i, rings)]
            coords = [(s0, t0 + 0 * s0), (s1, t0 + 0 * s0), ((s0 + s1) / 2, 1 + 0 * s0)]
        else:
            quad = [vid(i, j), vid(i + 1, j), vid(i + 1, j + 1), vid(i, j + 1)]
            coords = [(s0, t0 + 0 * s0), (s1, t0 + 0 * s0), (s1, t1 + 0 * s0),
                      (s0, t1 + 0 * s0)]
        corners.append(np.stack(quad, axis=1))
        uv.append(np.stack([np.stack(c, axis=1) for c in coords], axis=1))
        sizes.append(np.full(n, len(quad), np.int64))
    corner_idx = np.concatenate([c.reshape(-1) for c in corners]).astype(np.int64)
    uvs = np.concatenate([u.reshape(-1, 2) for u in uv])
    normals = unit[corner_idx]
    return unit * radius, np.concatenate(sizes), corner_idx, normals, uvs


def _cylinder(radius, height, top=True, bottom=True, side=True, n=SEGMENTS):
    theta, x, z = _ring(radius, n)
    h = height / 2.0
    positions = np.concatenate([np.stack([x, np.full(n, -h), z], axis=1),
                                np.stack([x, np.full(n, h), z], axis=1)])
    corners, normals, uvs, sizes = [], [], [], []
    i = np.arange(n)
    if side:
        quad = np.stack([i, (i + 1) % n, n + (i + 1) % n, n + i], axis=1)
        corners.append(quad.reshape(-1))
        ang = np.stack([theta, theta + 2 * np.pi / n, theta + 2 * np.pi / n, theta], axis=1)
        normals.append(np.stack([-np.sin(ang), np.zeros_like(ang), -np.cos(ang)],
                                axis=2).reshape(-1, 3))
        s = np.stack([i / n, (i + 1) / n, (i + 1) / n, i / n], axis=1)
        t = np.tile([0.0, 0.0, 1.0, 1.0], (n, 1))
        uvs.append(np.stack([s, t], axis=2).reshape(-1, 2))
        sizes.append(np.full(n, 4, np.int64))
    if top:     # seen from above with -Z up: s = 0.5 + x/2r, t = 0.5 - z/2r
        corners.append(n + i)
        normals.append(np.tile([0.0, 1.0, 0.0], (n, 1)))
        uvs.append(np.stack([0.5 + x / (2 * radius or 1), 0.5 - z / (2 * radius or 1)], axis=1))
        sizes.append(np.array([n], np.int64))
    if bottom:  # seen from below with +Z up: s = 0.5 + x/2r, t = 0.5 + z/2r
        order = i[::-1]
        corners.append(order)
        normals.append(np.tile([0.0, -1.0, 0.0], (n, 1)))
        uvs.append(np.stack([0.5 + x[order] / (2 * radius or 1),
                             0.5 + z[order] / (2 * radius or 1)], axis=1))
        sizes.append(np.array([n], np.int64))
    return _join_parts(positions, corners, normals, uvs, sizes)


def _cone(radius, height, side=True, bottom=True, n=SEGMENTS):
    theta, x, z = _ring(radius, n)
    h = height / 2.0
    positions = np.concatenate([np.stack([x, np.full(n, -h), z], axis=1), [[0.0, h, 0.0]]])
    corners, normals, uvs, sizes = [], [], [], []
    i = np.arange(n)
    if side:
        tri = np.stack([i, (i + 1) % n, np.full(n, n)], axis=1)
        corners.append(tri.reshape(-1))
        ang = np.stack([theta, theta + 2 * np.pi / n, theta + np.pi / n], axis=1)
        slope = radius / height if height else 0.0
        nvec = np.stack([-np.sin(ang), np.full_like(ang, slope), -np.cos(ang)], axis=2)
        normals.append((nvec / np.linalg.norm(nvec, axis=2, keepdims=True)).reshape(-1, 3))
        s = np.stack([i / n, (i + 1) / n, (i + 0.5) / n], axis=1)
        t = np.tile([0.0, 0.0, 1.0], (n, 1))
        uvs.append(np.stack([s, t], axis=2).reshape(-1, 2))
        sizes.append(np.full(n, 3, np.int64))
    if bottom:
        order = i[::-1]
        corners.append(order)
        normals.append(np.tile([0.0, -1.0, 0.0], (n, 1)))
        uvs.append(np.stack([0.5 + x[order] / (2 * radius or 1),
                             0.5 + z[order] / (2 * radius or 1)], axis=1))
        sizes.append(np.array([n], np.int64))
    return _join_parts(positions, corners, normals, uvs, sizes)


def _join_parts(positions, corners, normals, uvs, sizes):
    if not corners:
        return (positions, np.zeros(0, np.int64), np.zeros(0, np.int64), np.zeros((0, 3)),
                np.zeros((0, 2)))
    return (positions, np.concatenate(sizes).astype(np.int64),
            np.concatenate(corners).astype(np.int64), np.concatenate(normals),
            np.concatenate(uvs))


def _default_uvs(mesh) -> np.ndarray:
    """The standard's default texture coordinates of a face set without texCoord: S along the
    bounding box's longest side (0 to 1), T along the second longest (0 to its ratio)."""
    pos = mesh.positions
    if not len(pos):
        return np.zeros((len(mesh.corners), 2))
    low = pos.min(axis=0)
    extent = pos.max(axis=0) - low
    order = np.argsort(-extent, kind="stable")
    size = extent[order[0]] or 1.0
    s = (pos[:, order[0]] - low[order[0]]) / size
    t = (pos[:, order[1]] - low[order[1]]) / size
    return np.stack([s, t], axis=1)[mesh.corners]


# -- Extrusion (ISO/IEC 14772-1 §6.18, 19775-1 §13.3.5) ------------------------------------

def _unit_or_zero(v, reference: float) -> np.ndarray:
    """*v* normalised, or the zero vector where it is zero within rounding of *reference*
    (the size of the vectors it was made from)."""
    norm = float(np.linalg.norm(v))
    if norm <= 1e-12 * max(reference, 1e-300):
        return np.zeros(3)
    return np.asarray(v, dtype=np.float64) / norm


def extrusion_frames(spine) -> np.ndarray:
    """The spine-aligned cross-section plane of each spine point, (n, 3, 3) with columns the
    SCP's X, Y and Z axes, as the standard computes them: Y along the spine (the next point
    minus the previous one; at the ends of an open spine the first or last segment; at the
    ends of a closed spine, whose first and last points are the same, spine[1] − spine[n−2]),
    Z = (next − this) × (previous − this) (the ends of an open spine take their neighbour's;
    a closed spine's ends (spine[1] − spine[0]) × (spine[n−2] − spine[0])), flipped where it
    points against the previous point's Z, X = Y × Z.  Coincident points (no Y) take the
    previous Y, collinear points (no Z) the previous Z; a spine wholly collinear turns the
    Y = 0 plane by the rotation of +Y onto the spine, a spine wholly coincident has Y = +Y."""
    spine = np.asarray(spine, dtype=np.float64).reshape(-1, 3)
    n = len(spine)
    size = float(np.abs(spine).max()) if n else 0.0
    closed = n > 2 and np.array_equal(spine[0], spine[-1])
    ys, zs = np.zeros((n, 3)), np.zeros((n, 3))
    for i in range(n):
        if closed and i in (0, n - 1):
            before, after = spine[n - 2], spine[1]
        else:
            before, after = spine[max(i - 1, 0)], spine[min(i + 1, n - 1)]
        ys[i] = _unit_or_zero(after - before, size)
        if closed and i in (0, n - 1):
            a, b = spine[1] - spine[0], spine[n - 2] - spine[0]
        elif 0 < i < n - 1:
            a, b = spine[i + 1] - spine[i], spine[i - 1] - spine[i]
        else:
            continue            # the ends of an open spine: their neighbour's Z, below
        scale = float(np.linalg.norm(a) * np.linalg.norm(b))
        zs[i] = _unit_or_zero(np.cross(a, b), scale)
    if not closed and n > 2:
        zs[0], zs[-1] = zs[1], zs[-2]
    defined_y = [y for y in ys if y.any()]
    first_y = defined_y[0] if defined_y else np.array([0.0, 1.0, 0.0])
    defined_z = [z for z in zs if z.any()]
    if defined_z:
        first_z = defined_z[0]
    else:               # the whole spine is collinear: +Y turned onto the spine turns +Z
        axis = np.cross([0.0, 1.0, 0.0], first_y)
        cos = float(np.clip(first_y[1], -1.0, 1.0))
        if np.linalg.norm(axis) < 1e-12:
            turn = np.eye(3) if cos > 0 else _rotation3((1.0, 0.0, 0.0), math.pi)
        else:
            turn = _rotation3(axis, math.acos(cos))
        first_z = turn @ np.array([0.0, 0.0, 1.0])
    frames = np.zeros((n, 3, 3))
    y_prev, z_prev = first_y, first_z
    for i in range(n):
        y = ys[i] if ys[i].any() else y_prev
        z = zs[i] if zs[i].any() else z_prev
        if float(np.dot(z, z_prev)) < 0.0:
            z = -z
        x = np.cross(y, z)
        frames[i] = np.stack([x, y, z], axis=1)
        y_prev, z_prev = y, z
    if closed:                      # the first and last points are one: one plane
        frames[-1] = frames[0]
    return frames


def _polygon_area2(points) -> float:
    """Twice the signed area of a 2D polygon (positive counter-clockwise)."""
    x, y = points[:, 0], points[:, 1]
    return float(np.dot(x, np.roll(y, -1)) - np.dot(np.roll(x, -1), y))


def triangulate_polygon(points) -> tuple:
    """Triangles of a simple 2D polygon, convex or not, by ear clipping: ((t, 3) indices into
    *points*, each triangle turning the way the polygon does, whether the polygon was
    simple).  Repeated points are left out; a point on a straight stretch is a corner of
    the triangles like any other (no T-junction with the faces along that edge), unless only
    such points are left (then it is dropped); a polygon that is not simple (its ears run
    out) gets the rest as a fan and False."""
    points = np.asarray(points, dtype=np.float64).reshape(-1, 2)
    keep = [i for i in range(len(points))
            if not np.array_equal(points[i], points[i - 1])] if len(points) else []
    if len(keep) > 1 and np.array_equal(points[keep[0]], points[keep[-1]]):
        keep.pop()
    if len(keep) < 3:
        return np.zeros((0, 3), np.int64), True
    sign = 1.0 if _polygon_area2(points[keep]) >= 0.0 else -1.0
    extent = float(np.abs(points[keep]).max()) or 1.0
    eps = 1e-12 * extent * extent

    def turn(a, b, c):
        pa, pb, pc = points[a], points[b], points[c]
        return sign * ((pb[0] - pa[0]) * (pc[1] - pa[1]) - (pb[1] - pa[1]) * (pc[0] - pa[0]))

    def holds_a_point(a, b, c, ring_points):
        """Whether a point of the ring (other than a, b, c and their copies) lies in or on
        the triangle (a, b, c)."""
        pa, pb, pc = points[a], points[b], points[c]
        x, y = ring_points[:, 0], ring_points[:, 1]
        side_ab = sign * ((pb[0] - pa[0]) * (y - pa[1]) - (pb[1] - pa[1]) * (x - pa[0]))
        side_bc = sign * ((pc[0] - pb[0]) * (y - pb[1]) - (pc[1] - pb[1]) * (x - pb[0]))
        side_ca = sign * ((pa[0] - pc[0]) * (y - pc[1]) - (pa[1] - pc[1]) * (x - pc[0]))
        inside = (side_ab >= 0.0) & (side_bc >= 0.0) & (side_ca >= 0.0)
        for corner in (pa, pb, pc):
            inside &= (x != corner[0]) | (y != corner[1])
        return bool(inside.any())

    ring = list(keep)
    triangles = []
    simple = True
    k = 0
    while len(ring) > 3:
        count = len(ring)
        ring_points = points[ring]
        flat = None
        for step in range(count):
            k = (k + step) % count if step == 0 else (k + 1) % count
            a, b, c = ring[k - 1], ring[k], ring[(k + 1) % count]
            area = turn(a, b, c)
            if abs(area) <= eps:        # on a straight stretch (or a spike): no ear
                flat = k if flat is None else flat
                continue
            if area < 0.0:
                continue                # a reflex corner is no ear
            if not holds_a_point(a, b, c, ring_points):
                triangles.append((a, b, c))
                ring.pop(k)
                k = max(k - 1, 0)
                break
        else:
            if flat is not None:        # only straight stretches left: drop a point
                ring.pop(flat)
                k = 0
                continue
            simple = False              # no ear: not a simple polygon
            triangles.extend((ring[0], ring[m], ring[m + 1]) for m in range(1, len(ring) - 1))
            ring = []
    if len(ring) == 3 and abs(turn(*ring)) > eps:
        triangles.append(tuple(ring))
    return np.array(triangles, dtype=np.int64).reshape(-1, 3), simple


def crease_normals(positions, face_sizes, corners, crease_angle) -> np.ndarray:
    """Per-corner normals by the crease angle, corner by corner as X3D browsers compute them
    (X_ITE's ``refineNormals``): a corner's normal is the sum of the normals of the faces at its
    point that turn less than *crease_angle* from its own face's, each face counted once for
    each triangle of its fan (v0, vk, vk+1) that holds the point (a quad: twice at its first
    and third corner, once at the others), its normal by Newell's formula; so two faces that
    meet at more than the angle keep a lighting discontinuity along their edge (ISO/IEC
    14772-1 §6.23)."""
    positions = np.asarray(positions, dtype=np.float64)
    sizes = np.asarray(face_sizes, dtype=np.int64)
    corners = np.asarray(corners, dtype=np.int64)
    count = len(corners)
    if not count:
        return np.zeros((0, 3))
    starts = np.r_[0, np.cumsum(sizes)[:-1]]
    face_of = np.repeat(np.arange(len(sizes)), sizes)
    following = np.arange(count) + 1
    ends = starts + sizes
    following[ends - 1] = starts
    here, there = positions[corners], positions[corners[following]]
    edges = np.cross(here, there)
    newell = np.stack([np.bincount(face_of, edges[:, k], len(sizes)) for k in range(3)], axis=1)
    length = np.linalg.norm(newell, axis=1, keepdims=True)
    unit = np.where(length > 0, newell / np.where(length > 0, length, 1.0), 0.0)
    local = np.arange(count) - np.repeat(starts, sizes)
    size_c = np.repeat(sizes, sizes)
    fans = np.where(local == 0, size_c - 2, np.where((local == 1) | (local == size_c - 1), 1, 2))
    weighted = unit[face_of] * fans[:, None]
    # every pair of corners at one point: Σ (corners of a point)² pairs
    order = np.argsort(corners, kind="stable")
    point = corners[order]
    first = np.r_[True, point[1:] != point[:-1]]
    group_start = np.flatnonzero(first)
    group_size = np.diff(np.r_[group_start, count])
    group_of = np.cumsum(first) - 1
    size_of = group_size[group_of]
    mine = np.repeat(np.arange(count), size_of)
    within = np.arange(int(size_of.sum())) - np.repeat(np.cumsum(size_of) - size_of, size_of)
    partner = group_start[group_of][mine] + within
    self_face, other_face = face_of[order[mine]], face_of[order[partner]]
    near = np.einsum("ij,ij->i", unit[self_face], unit[other_face]) > \
        math.cos(min(max(float(crease_angle), 0.0), math.pi))
    near |= self_face == other_face
    target, source = order[mine][near], weighted[order[partner][near]]
    normals = np.stack([np.bincount(target, source[:, k], count) for k in range(3)], axis=1)
    norm = np.linalg.norm(normals, axis=1, keepdims=True)
    return np.where(norm > 0, normals / np.where(norm > 0, norm, 1.0), unit[face_of])


def extrude(spine, cross_section, scales=((1.0, 1.0),), orientations=((0.0, 0.0, 1.0, 0.0),),
            begin_cap=True, end_cap=True, convex=True) -> dict:
    """The faces of an Extrusion as the standard builds them.

    Each spine point i carries the cross-section: the point (x, z) of crossSection becomes
    spine[i] + SCP_i · R(orientation_i) · (scale_i.x · x, 0, scale_i.y · z) (SCP_i from
    :func:`extrusion_frames`; the last scale and orientation hold for the spine points after
    them).  Sides: quads (i, j), (i, j+1), (i+1, j+1), (i+1, j) between consecutive spine
    points and cross-section points, or where one is not planar (at a bend of the spine)
    the triangles (i, j), (i, j+1), (i+1, j+1) and (i, j), (i+1, j+1), (i+1, j), as X_ITE
    draws them; caps: the cross-section at the first spine point
    (reversed, facing back along the spine) and at the last, one polygon each (``convex``)
    or its triangulation (:func:`triangulate_polygon`).  These faces are counter-clockwise
    seen from outside for the standard's default square (ccw FALSE reverses them: the
    caller's business).  Points that coincide exactly are one position (a closed
    cross-section's seam, a spine point scaled to 0), faces left with fewer than 3
    different points are dropped.  Texture coordinates: u the cross-section's length from
    its first point (0 to 1), v the spine's (0 to 1); caps (x, z) of the cross-section
    scaled so that its bounding box's larger side is 0 to 1.

    Returns {"positions", "face_sizes", "corners", "uvs", "warnings"}."""
    spine = np.asarray(spine, dtype=np.float64).reshape(-1, 3)
    cross = np.asarray(cross_section, dtype=np.float64).reshape(-1, 2)
    empty = {"positions": np.zeros((0, 3)), "face_sizes": np.zeros(0, np.int64),
             "corners": np.zeros(0, np.int64), "uvs": np.zeros((0, 2)), "warnings": []}
    if len(spine) < 2 or len(cross) < 2:
        empty["warnings"].append("Extrusions with fewer than 2 spine or crossSection points: "
                                 "no faces")
        return empty
    if len(spine) * len(cross) > MAX_EXTRUSION_POINTS:
        empty["warnings"].append(f"Extrusions of more than {MAX_EXTRUSION_POINTS:,} points "
                                 "(spine × crossSection): left out")
        return empty
    ns, nc = len(spine), len(cross)
    scales = np.asarray(scales, dtype=np.float64).reshape(-1, 2)
    orientations = np.asarray(orientations, dtype=np.float64).reshape(-1, 4)
    if not len(scales):
        scales = np.ones((1, 2))
    if not len(orientations):
        orientations = np.array([[0.0, 0.0, 1.0, 0.0]])
    frames = extrusion_frames(spine)
    rings = np.zeros((ns, nc, 3))
    for i in range(ns):
        sx, sz = scales[min(i, len(scales) - 1)]
        axis_angle = orientations[min(i, len(orientations) - 1)]
        local = np.stack([cross[:, 0] * sx, np.zeros(nc), cross[:, 1] * sz], axis=1)
        matrix = frames[i] @ _rotation3(axis_angle[:3], float(axis_angle[3]))
        rings[i] = spine[i] + local @ matrix.T
    # texture coordinates of the sides: lengths along the cross-section and the spine
    u = np.r_[0.0, np.cumsum(np.linalg.norm(np.diff(cross, axis=0), axis=1))]
    u = u / u[-1] if u[-1] > 0 else np.arange(nc) / (nc - 1)
    v = np.r_[0.0, np.cumsum(np.linalg.norm(np.diff(spine, axis=0), axis=1))]
    v = v / v[-1] if v[-1] > 0 else np.arange(ns) / (ns - 1)
    grid = np.arange(ns * nc).reshape(ns, nc)
    i, j = np.meshgrid(np.arange(ns - 1), np.arange(nc - 1), indexing="ij")
    i, j = i.ravel(), j.ravel()
    quads = np.stack([grid[i, j], grid[i, j + 1], grid[i + 1, j + 1], grid[i + 1, j]], axis=1)
    quad_uv = np.stack([np.stack([u[j], v[i]], 1), np.stack([u[j + 1], v[i]], 1),
                        np.stack([u[j + 1], v[i + 1]], 1), np.stack([u[j], v[i + 1]], 1)],
                       axis=1)
    # a quad that is not planar (between spine points whose planes are not parallel: the
    # cross-section is not stretched at a bend) is two triangles, split along (i, j)–(i+1, j+1)
    flat = rings.reshape(-1, 3)
    corner = flat[quads]
    normal = np.cross(corner[:, 1] - corner[:, 0], corner[:, 2] - corner[:, 0])
    length = np.linalg.norm(normal, axis=1)
    off_plane = np.abs(np.einsum("ij,ij->i", corner[:, 3] - corner[:, 0], normal))
    size = float(np.abs(flat).max()) or 1.0
    bent = off_plane > 1e-9 * size * np.where(length > 0, length, np.inf)
    # faces as (sizes, corners, uvs) parts: whole quads and split ones, in spine order
    tri_first, tri_second = quads[:, [0, 1, 2]], quads[:, [0, 2, 3]]
    sides = np.where(bent[:, None], np.concatenate([tri_first, tri_second[:, :1]], axis=1),
                     quads)
    side_sizes = np.where(bent, 3, 4)
    side_corners = np.concatenate([sides, tri_second], axis=1)   # 4 + 3 a quad, some unused
    side_uvs = np.concatenate([np.where(bent[:, None, None], quad_uv[:, [0, 1, 2, 0]], quad_uv),
                               quad_uv[:, [0, 2, 3]]], axis=1)
    used = np.concatenate([np.stack([np.ones_like(bent), np.ones_like(bent), np.ones_like(bent),
                                     ~bent], axis=1), np.repeat(bent[:, None], 3, axis=1)],
                          axis=1)
    face_sizes = [np.stack([side_sizes, np.where(bent, 3, 0)], axis=1).reshape(-1)]
    face_sizes[0] = face_sizes[0][face_sizes[0] > 0]
    face_corners = [side_corners[used]]
    face_uvs = [side_uvs[used]]
    warnings = []
    closed = np.array_equal(cross[0], cross[-1])
    cap_points = cross[:-1] if closed else cross
    low = cross.min(axis=0)
    cap_size = float((cross.max(axis=0) - low).max())
    if len(cap_points) >= 3 and cap_size > 0:
        cap_uv = (cap_points - low) / cap_size
        count = len(cap_points)
        polygons = np.arange(count)[None, :]
        if not convex and count > MAX_CAP_TRIANGULATION:
            warnings.append(f"Extrusion caps of more than {MAX_CAP_TRIANGULATION} points not "
                            "triangulated: one polygon each")
        elif not convex:
            polygons, simple = triangulate_polygon(cap_points)
            if not simple:
                warnings.append("Extrusion crossSections that are not simple polygons: caps "
                                "filled as fans")
        for cap, ring in ((begin_cap, 0), (end_cap, ns - 1)):
            if not cap or not len(polygons):
                continue
            order = polygons[:, ::-1] if ring == 0 else polygons
            face_sizes.append(np.full(len(order), order.shape[1], np.int64))
            face_corners.append(grid[ring][order].reshape(-1))
            face_uvs.append(cap_uv[order].reshape(-1, 2))
    # one position for points that coincide exactly; faces of fewer than 3 points dropped
    _, first, inverse = np.unique(flat, axis=0, return_index=True, return_inverse=True)
    inverse = np.asarray(inverse).reshape(-1)
    order = np.argsort(first, kind="stable")
    rank = np.empty(len(order), np.int64)
    rank[order] = np.arange(len(order))
    positions = flat[np.sort(first)]
    sizes = np.concatenate(face_sizes).astype(np.int64)
    ids = rank[inverse][np.concatenate(face_corners).astype(np.int64)]
    uvs = np.concatenate(face_uvs).reshape(-1, 2)
    starts = np.r_[0, np.cumsum(sizes)[:-1]].astype(np.int64)
    previous = np.arange(len(ids)) - 1
    previous[starts] = starts + sizes - 1
    keep = ids != ids[previous]        # a corner at the point of the one before: left out
    kept = np.add.reduceat(keep.astype(np.int64), starts) if len(sizes) else sizes
    whole = kept >= 3
    keep &= np.repeat(whole, sizes)
    return {"positions": positions, "face_sizes": kept[whole].astype(np.int64),
            "corners": ids[keep], "uvs": uvs[keep], "warnings": warnings}


# -- flattening -----------------------------------------------------------------------------

def _weights(root, count) -> dict:
    """{id(group): how many things *count* finds below it, with DEF/USE multiplicity},
    computed once per shared group (iteratively; capped at 2⁶²)."""
    out, seen = {}, set()
    stack = [(root, False)]
    while stack:
        node, done = stack.pop()
        key = id(node)
        if done:
            total = 0
            for child in node.children:
                total += out.get(id(child), 0) if isinstance(child, Transform) else count(child)
            out[key] = min(total, 1 << 62)
            continue
        if key in seen:         # done, or an ancestor (a cycle, which counts as nothing)
            continue
        seen.add(key)
        stack.append((node, True))
        for child in node.children:
            if isinstance(child, Transform) and id(child) not in seen:
                stack.append((child, False))
    return out


def _local_matrices(root) -> tuple:
    """({id(group): its local matrix as float64, or None for the identity},
    {id(group): how many times groups name it as a child}), once a shared group,
    iteratively."""
    local, refs = {}, {}
    stack = [root]
    while stack:
        node = stack.pop()
        if id(node) in local:
            continue
        m = np.asarray(node.matrix, dtype=np.float64)
        local[id(node)] = None if m.shape == (4, 4) and m.tobytes() == _EYE_BYTES else m
        for child in node.children:
            if isinstance(child, Transform):
                refs[id(child)] = refs.get(id(child), 0) + 1
                if id(child) not in local:
                    stack.append(child)
    return local, refs


_EYE_BYTES = np.eye(4).tobytes()


class _Block:
    """The instances below a shared group, relative to it: shapes, their matrices (k, 4, 4)
    and paths; lights, their matrices (m, 4, 4), scopes ((m, 2) start, stop; -1 for a global
    light) and paths; the bound viewpoint's matrix (or None)."""

    __slots__ = ("shapes", "rel", "paths", "lights", "light_rel", "scopes", "light_paths",
                 "viewpoint")


def _flatten(doc, notes) -> None:
    """Fill ``doc.instances``, ``doc.lights`` and ``doc.viewpoint_matrix`` by walking the
    graph iteratively: groups with nothing to show below them are skipped by their counts
    (computed once per shared group), and a shared group that fits the budget is flattened
    once relative to itself and placed with one batched matrix product a use.  At most
    MAX_INSTANCES shape and light instances, in document order, and MAX_VISITS groups
    visited; paths keep the PATH_LIMIT innermost names."""
    viewpoint = doc.viewpoint

    def counted(child):
        if isinstance(child, Shape):
            return 1 if child.geometry is not None else 0
        if isinstance(child, Light):
            return 1
        return 1 if viewpoint is not None and child is viewpoint else 0

    weights = _weights(doc.root, counted)
    local, refs = _local_matrices(doc.root)
    blocks = {}
    eye = np.eye(4)
    no_matrices = np.zeros((0, 4, 4))
    visits = [0]

    def compose(group, done):
        """_Block of *group* from the blocks of its child groups (in *done* or cached)."""
        counted_children = [c for c in group.children if (weights.get(id(c)) if
                            isinstance(c, Transform) else counted(c))]
        if len(counted_children) == 1 and isinstance(counted_children[0], Transform):
            # a group around one group (common, and DEF/USE chains): its block moved
            child = counted_children[0]
            inner = blocks[id(child)] if id(child) in blocks else done.get(id(child))
            if inner is None:
                return None
            m = local[id(child)]
            out = _Block()
            out.shapes, out.lights = inner.shapes, inner.lights
            prefix = (child.name,) if child.name else ()
            out.paths = inner.paths if not prefix else [(prefix + p)[-PATH_LIMIT:]
                                                        for p in inner.paths]
            out.light_paths = inner.light_paths if not prefix else [
                (prefix + p)[-PATH_LIMIT:] for p in inner.light_paths]
            out.scopes = inner.scopes
            if m is None:
                out.rel, out.light_rel, out.viewpoint = (inner.rel, inner.light_rel,
                                                         inner.viewpoint)
                return out
            out.rel = np.matmul(m, inner.rel)
            out.light_rel = np.matmul(m, inner.light_rel) if inner.lights else no_matrices
            out.viewpoint = None if inner.viewpoint is None else np.dot(m, inner.viewpoint)
            if not (np.isfinite(out.rel).all() and np.isfinite(out.light_rel).all()):
                return None
            return out
        shapes, rels, paths = [], [], []
        lights, light_rels, scopes, light_paths = [], [], [], []
        seen_viewpoint = None
        own_scoped = []
        for child in group.children:
            if isinstance(child, Transform):
                if not weights.get(id(child)):
                    continue
                inner = blocks[id(child)] if id(child) in blocks else done.get(id(child))
                if inner is None:
                    return None
                m = local[id(child)]
                offset = len(shapes)
                prefix = (child.name,) if child.name else ()
                shapes.extend(inner.shapes)
                rels.append(inner.rel if m is None else np.matmul(m, inner.rel))
                paths.extend(inner.paths if not prefix else
                             [(prefix + p)[-PATH_LIMIT:] for p in inner.paths])
                if inner.lights:
                    lights.extend(inner.lights)
                    light_rels.append(inner.light_rel if m is None
                                      else np.matmul(m, inner.light_rel))
                    scopes.append(np.where(inner.scopes >= 0, inner.scopes + offset, -1))
                    light_paths.extend(inner.light_paths if not prefix else
                                       [(prefix + p)[-PATH_LIMIT:] for p in inner.light_paths])
                if seen_viewpoint is None and inner.viewpoint is not None:
                    seen_viewpoint = inner.viewpoint if m is None else np.dot(m, inner.viewpoint)
            elif isinstance(child, Shape):
                if child.geometry is not None:
                    shapes.append(child)
                    rels.append(eye[None])
                    paths.append(())
            elif isinstance(child, Light):
                if not child.is_global:
                    own_scoped.append(sum(len(x) for x in scopes))
                lights.append(child)
                light_rels.append(eye[None])
                scopes.append(np.array([[-1, -1]]))
                light_paths.append(())
            elif isinstance(child, Viewpoint) and child is viewpoint and seen_viewpoint is None:
                seen_viewpoint = eye
        out = _Block()
        out.shapes, out.paths, out.lights, out.light_paths = shapes, paths, lights, light_paths
        out.rel = np.concatenate(rels) if rels else no_matrices
        out.light_rel = np.concatenate(light_rels) if light_rels else no_matrices
        out.scopes = np.concatenate(scopes) if scopes else np.zeros((0, 2), np.int64)
        out.scopes[own_scoped] = (0, len(shapes))
        out.viewpoint = seen_viewpoint
        if not (np.isfinite(out.rel).all() and np.isfinite(out.light_rel).all()):
            return None
        return out

    def block(group):
        """_Block of a shared group, computed iteratively (children first) and cached for
        every shared group met; None when a matrix is not finite."""
        if id(group) in blocks:
            return blocks[id(group)]
        done, busy = {}, set()
        stack = [(group, False)]
        while stack:
            node, finished = stack.pop()
            key = id(node)
            if finished:
                busy.discard(key)
                visits[0] += 1
                result = compose(node, done)
                if refs.get(key, 0) > 1:
                    blocks[key] = result
                else:
                    done[key] = result
                for child in node.children:     # a child used once is needed no more
                    if isinstance(child, Transform) and refs.get(id(child), 0) <= 1:
                        done.pop(id(child), None)
                continue
            if key in blocks or key in done or key in busy:
                continue
            busy.add(key)
            stack.append((node, True))
            stack.extend((c, False) for c in node.children if isinstance(c, Transform)
                         and weights.get(id(c)) and id(c) not in blocks and id(c) not in done)
        return blocks[id(group)] if id(group) in blocks else done.get(id(group))

    instances, lights = [], []
    doc.instances, doc.lights = instances, lights
    doc.viewpoint_matrix = np.eye(4)
    found_viewpoint = False
    truncated = stopped = broken = cycles = 0
    on_stack = {id(doc.root)}
    # a bound on |world entries|: |(A·B)ij| ≤ 4·max|A|·max|B|
    scale = {key: 4.0 * float(np.abs(m).max()) + 1.0 for key, m in local.items() if m is not None}
    root_matrix = local[id(doc.root)]
    start = eye if root_matrix is None else root_matrix
    stack = [[doc.root, start, 0, 0, [], (), float(np.abs(start).max()) + 1.0]]
    budget = MAX_INSTANCES
    with np.errstate(over="ignore", invalid="ignore"):
        while stack:
            frame = stack[-1]
            group, matrix, i = frame[0], frame[1], frame[2]
            children = group.children
            if i >= len(children):
                for light in frame[4]:
                    light.scope = range(frame[3], len(instances))
                on_stack.discard(id(group))
                stack.pop()
                continue
            frame[2] = i + 1
            child = children[i]
            if isinstance(child, Transform):
                weight = weights.get(id(child))
                if not weight:
                    continue
                if id(child) in on_stack:       # a graph built by hand may hold a cycle
                    cycles += 1
                    continue
                visits[0] += 1
                if visits[0] > MAX_VISITS:
                    stopped = 1
                    break
                m = local[id(child)]
                bound = frame[6]
                if m is None:
                    world = matrix
                else:
                    world = np.dot(matrix, m)   # np.dot: a third of ``@``'s overhead on 4×4
                    bound *= scale[id(child)]
                    if bound > 1e300:           # only then can a product overflow
                        if not math.isfinite(world.sum()):
                            broken += 1
                            continue
                        bound = float(np.abs(world).max()) * 4.0 + 1.0
                path = (frame[5] + (child.name,))[-PATH_LIMIT:] if child.name else frame[5]
                if refs.get(id(child), 0) > 1 \
                        and weight <= budget - len(instances) - len(lights):
                    shared = block(child)
                    if shared is not None:
                        mats = np.matmul(world, shared.rel)
                        if np.isfinite(mats).all():
                            base = len(instances)
                            instances.extend(
                                ShapeInstance(base + k, s, mats[k],
                                              (path + p)[-PATH_LIMIT:] if p else path)
                                for k, (s, p) in enumerate(zip(shared.shapes, shared.paths)))
                            if shared.lights:
                                lmats = np.matmul(world, shared.light_rel)
                                ranges = (shared.scopes + base).tolist()
                                lights.extend(
                                    LightInstance(light, lmats[k], None if scope[0] < base
                                                  else range(*scope),
                                                  (path + lpath)[-PATH_LIMIT:])
                                    for k, (light, scope, lpath) in enumerate(
                                        zip(shared.lights, ranges, shared.light_paths)))
                            if shared.viewpoint is not None and not found_viewpoint:
                                doc.viewpoint_matrix = np.dot(world, shared.viewpoint)
                                found_viewpoint = True
                            continue
                stack.append([child, world, 0, len(instances), [], path, bound])
                on_stack.add(id(child))
            elif isinstance(child, Shape):
                if child.geometry is None:
                    continue
                if len(instances) + len(lights) >= budget:
                    truncated = 1
                    break
                instances.append(ShapeInstance(len(instances), child, matrix, frame[5]))
            elif isinstance(child, Light):
                if len(instances) + len(lights) >= budget:
                    truncated = 1
                    break
                light = LightInstance(child, matrix, None, frame[5])
                lights.append(light)
                if not child.is_global:
                    frame[4].append(light)
            elif isinstance(child, Viewpoint):
                if child is viewpoint and not found_viewpoint:
                    doc.viewpoint_matrix = matrix
                    found_viewpoint = True
    if truncated or stopped:
        for frame in stack:
            for light in frame[4]:
                light.scope = range(frame[3], len(instances))
    if truncated:
        total = _weights(doc.root, lambda c: 1 if isinstance(c, (Shape, Light))
                         and (not isinstance(c, Shape) or c.geometry is not None) else 0)
        notes.add(f"the scene holds {total.get(id(doc.root), 0):,} shape and light instances "
                  f"(DEF/USE multiplies them): the first {MAX_INSTANCES:,} are kept")
    if stopped:
        notes.add(f"flattening stopped after {MAX_VISITS:,} groups (DEF/USE nests them "
                  f"deeply): the {len(instances):,} shape instances before are kept")
    if broken:
        notes.add("groups whose world matrix is not finite left out", n=broken)
    if cycles:
        notes.add("groups inside themselves (a cycle in the graph) left out", n=cycles)


# -- the public reading functions -----------------------------------------------------------

def loads(data, path: str = "<string>", resolver=None) -> Document:
    """Read VRML97 / X3D from *data* (bytes or str; gzip or not); *path* names it and is the
    base of relative URLs; *resolver* (url, base folder) → local path or None resolves
    Inline, EXTERNPROTO and texture URLs (default :func:`resolve_local`).  Raises
    X3DError for what is not VRML97 / X3D at all; everything else is a warning."""
    reader = _Reader(resolver)
    src = reader.parse(data, path, 0)
    reader.main = src
    x3d = src.encoding != "vrml97"
    doc = Document(path=path, encoding=src.encoding, version=src.version, profile=src.profile,
                   meter=src.meter, unit_name=src.unit_name, meta=dict(src.meta),
                   navigation_types=["EXAMINE", "ANY"] if x3d else ["WALK", "ANY"])
    reader.doc = doc
    for node in src.nodes:
        child = reader.build(node, 1, "", "child")
        if child is not None:
            doc.root.children.append(child)
    exact = {}
    kept = []
    for line in doc.info:
        if line.startswith(NAME_PREFIX) and "=" in line:
            key, _, name = line[len(NAME_PREFIX):].partition("=")
            exact[key] = name
        else:
            kept.append(line)
    if exact:
        doc.info = kept
        for _node, obj in reader.memo.values():
            if obj is not None and getattr(obj, "name", None) in exact:
                obj.name = exact[obj.name]
    _flatten(doc, reader.notes)
    reader.finish(doc)
    return doc


def load(path: str, resolver=None) -> Document:
    """Read the VRML97 / X3D file *path* (``.wrl``, ``.x3dv``, ``.x3d``, gzipped or not);
    raises X3DError for a missing file or one that is not VRML97 / X3D at all."""
    return loads(_read_file(path), path, resolver)


# -- mappings to the Phong model and to Blender's axes ----------------------------------------

def to_blender_matrix(doc: Document) -> np.ndarray:
    """4×4 matrix from the file's axes and units to Blender's (Z up, metres): a rotation of
    +90° about X (X3D's +Y becomes +Z, its +Z, towards the viewer, becomes -Y) times
    ``doc.meter``.  The Blender side puts it in front of every world matrix (or of the
    root); the parsed data is never converted."""
    return Y_UP_TO_Z_UP @ np.diag([doc.meter, doc.meter, doc.meter, 1.0])


def phong_values(material: Material | None, texture_components: int | None = None,
                 colors: bool = False) -> dict:
    """The project's Phong parameters of a VRML97 / X3D material (ISO/IEC 14772-1 §4.14 and
    19775-1 §17.2.2 "lighting model"):

    ============================  ==========================================================
    VRML97 / X3D                  Phong
    ============================  ==========================================================
    diffuseColor                  Kd (Object Color)
    ambientIntensity × diffuse    Ka (Ambient Object Color)
    specularColor                 Ks (Specular Color)
    emissiveColor                 Ke (Irradiant Color)
    128 × shininess               exponent
    (the standard's N·H)          blinn = 1: the half-vector highlight
    1 − transparency              opacity
    Material NULL (None)          unlit: Ke white, Kd = Ka = Ks = 0 ("lit" False)
    UnlitMaterial                 unlit: Ke = its colour
    an RGB(A) texture             replaces Kd (unlit: Ke) — VRML97 and X3D 3
    a 1- or 2-channel texture     multiplies Kd (unlit: Ke), or the colours when given
    a Color / ColorRGBA node      replaces Kd (unlit: Ke), unless an RGB texture is given
    ============================  ==========================================================

    *texture_components* is the number of channels of the shape's texture (None: no
    texture), *colors* whether its geometry has colours.  Returns Kd, Ka, Ks, Ke (RGB),
    exponent, blinn, opacity, lit, and "source": what colours the term the texture and
    colours act on ("material", "colors", "texture", "texture*material",
    "texture*colors")."""
    if texture_components is None:
        source = "colors" if colors else "material"
    elif texture_components >= 3:
        source = "texture"
    else:
        source = "texture*colors" if colors else "texture*material"
    if material is None or material.kind == "unlit":
        emissive = (1.0, 1.0, 1.0) if material is None else tuple(material.emissive)
        opacity = 1.0 if material is None else 1.0 - material.transparency
        return {"Kd": (0.0, 0.0, 0.0), "Ka": (0.0, 0.0, 0.0), "Ks": (0.0, 0.0, 0.0),
                "Ke": emissive, "exponent": 0.0, "blinn": 1.0, "opacity": opacity,
                "lit": False, "source": source}
    kd = tuple(float(c) for c in material.diffuse)
    return {"Kd": kd, "Ka": tuple(material.ambient_intensity * c for c in kd),
            "Ks": tuple(float(c) for c in material.specular),
            "Ke": tuple(float(c) for c in material.emissive),
            "exponent": 128.0 * material.shininess, "blinn": 1.0,
            "opacity": 1.0 - material.transparency, "lit": True, "source": source}


def light_values(doc: Document, light: Light) -> dict:
    """A light's values for the Phong lights, distances in metres: the standard's
    attenuation 1/max(a0 + a1·d + a2·d², 1) with d in the file's units equals
    1/max(a0 + a1'·d' + a2'·d'², 1) with d' = d·meter: a1' = a1/m, a2' = a2/m²; radius × m;
    beamWidth and cutOffAngle in radians (the half-angles of the cone: full intensity inside
    beamWidth, none beyond cutOffAngle, a linear ramp between as X3D says); ambient intensity
    and ``global`` as read; ``shadows`` (default false: X3D's lights cast none unless a file
    says so)."""
    m = doc.meter
    a0, a1, a2 = light.attenuation
    return {"kind": light.kind, "on": light.on, "intensity": light.intensity,
            "ambient_intensity": light.ambient_intensity, "color": tuple(light.color),
            "attenuation": (a0, a1 / m, a2 / (m * m)), "radius": light.radius * m,
            "beam_width": light.beam_width, "cut_off_angle": light.cut_off_angle,
            "global": light.is_global, "shadows": bool(light.shadows)}


def counter_clockwise(mesh: Mesh) -> Mesh:
    """A copy of *mesh* whose faces are counter-clockwise (``ccw`` True): each face of a
    ``ccw`` FALSE mesh reversed, keeping its first corner, with its per-corner values."""
    out = Mesh(**{k: getattr(mesh, k) for k in mesh.__dataclass_fields__})
    if mesh.ccw or not len(mesh.corners):
        return out
    sizes = np.asarray(mesh.face_sizes, dtype=np.int64)
    starts = np.repeat(np.r_[0, np.cumsum(sizes)[:-1]], sizes)
    local = np.arange(len(mesh.corners)) - starts
    order = starts + (np.repeat(sizes, sizes) - local) % np.repeat(sizes, sizes)
    out.corners = mesh.corners[order]
    for name in ("normals", "colors", "uvs"):
        values = getattr(mesh, name)
        if values is not None:
            setattr(out, name, values[order])
    out.ccw = True
    return out


def apply_texture_transform(uvs: np.ndarray, transform: TextureTransform | None) -> np.ndarray:
    """*uvs* (c, 2) transformed by a TextureTransform (the standard's Tc' = -C·S·R·C·T·Tc)."""
    if transform is None or uvs is None:
        return uvs
    m = transform.matrix()
    uvs = np.asarray(uvs, dtype=np.float64)
    return uvs @ m[:2, :2].T + m[:2, 2]


# -- writing --------------------------------------------------------------------------------

_POINT_ZERO = re.compile(r"\.0(?![0-9])")


def _num(value) -> str:
    """The shortest decimal that reads back as the same float64 ("1" for 1.0)."""
    text = repr(float(value))
    if text.endswith(".0"):
        text = text[:-2]
    return "0" if text == "-0" else text


def _nums(values) -> str:
    """Numbers as :func:`_num` writes them, for a whole array at once."""
    flat = np.asarray(values, dtype=np.float64).reshape(-1).tolist()
    return _POINT_ZERO.sub("", " ".join(map(repr, flat)))


def _tuples(values) -> str:
    """Rows of numbers, a comma between rows (commas are whitespace in both encodings)."""
    rows = np.asarray(values, dtype=np.float64)
    if rows.ndim < 2 or rows.shape[1] == 0:
        return _nums(rows)
    width = rows.shape[1]
    words = _POINT_ZERO.sub("", " ".join(map(repr, rows.reshape(-1).tolist()))).split(" ")
    for k in range(width - 1, len(words) - 1, width):
        words[k] += ","
    return " ".join(words)


def _ints(values) -> str:
    return " ".join(map(str, np.asarray(values, dtype=np.int64).reshape(-1).tolist()))


def _separated(values, sizes) -> np.ndarray:
    """Per-corner integers with -1 after each face (coordIndex and its kin)."""
    values = np.asarray(values, dtype=np.int64)
    sizes = np.asarray(sizes, dtype=np.int64)
    out = np.full(len(values) + len(sizes), -1, np.int64)
    out[np.arange(len(values)) + np.repeat(np.arange(len(sizes)), sizes)] = values
    return out


_IDENT = re.compile(r"[^A-Za-z0-9_\-]")


class _W:
    """A node to write: type, DEF or USE, fields [(name, kind, value)], node fields
    [(name, [_W], single)]; written as classic or XML from the same tree."""

    __slots__ = ("type", "name", "use", "fields", "nodes")

    def __init__(self, type_, name=None, use=None):
        self.type = type_
        self.name = name
        self.use = use
        self.fields = []
        self.nodes = []

    def add(self, name, kind, value):
        self.fields.append((name, kind, value))
        return self

    def node(self, name, child, single=True):
        if child is not None:
            self.nodes.append((name, [child] if single else list(child), single))
        return self


class _Emit:
    """The model (a Document's graph) as _W trees for one target encoding: objects used more
    than once are DEF'd once and USE'd after; every DEF is a valid, unique identifier in both
    encodings, and a name that had to change is kept exactly in WorldInfo (NAME_PREFIX)."""

    def __init__(self, doc: Document, target: str):
        self.doc = doc
        self.target = target
        self.x3d = target != "vrml97"
        self.written = {}       # id(object) → DEF name (or "" when written without DEF)
        self.used = set()
        self.exact = {}
        self.serial = 0
        self.uses = self.count_uses()

    def count_uses(self) -> dict:
        uses = {}
        stack = [self.doc.root]
        seen = set()
        while stack:
            obj = stack.pop()
            uses[id(obj)] = uses.get(id(obj), 0) + 1
            if id(obj) in seen:
                continue
            seen.add(id(obj))
            if isinstance(obj, Transform):
                stack.extend(obj.children)
            elif isinstance(obj, Shape):
                stack.extend(x for x in (obj.geometry, obj.appearance) if x is not None)
            elif isinstance(obj, Appearance):
                stack.extend(x for x in (obj.material, obj.texture, obj.texture_transform)
                             if x is not None)
        return uses

    def reachable(self, target) -> bool:
        stack, seen = [self.doc.root], set()
        while stack:
            obj = stack.pop()
            if obj is target:
                return True
            if id(obj) in seen or not isinstance(obj, Transform):
                continue
            seen.add(id(obj))
            stack.extend(obj.children)
        return False

    def define(self, obj, kind, always=False):
        """(_W with DEF or None, USE name or None) for *obj*: a USE when it was written."""
        key = id(obj)
        if key in self.written:
            name = self.written[key]
            if name:
                return None, name
        name = getattr(obj, "name", "") or ""
        if not name and (always or self.uses.get(key, 0) > 1):
            self.serial += 1
            name = f"{kind}_{self.serial}" if not always else kind
        if not name:
            self.written[key] = ""
            return _W(kind), None
        ident = _IDENT.sub("_", name)
        if not re.match(r"[A-Za-z_]", ident):
            ident = "_" + ident
        base, n = ident, 1
        while ident in self.used:
            n += 1
            ident = f"{base}_{n}"
        self.used.add(ident)
        if ident != name:
            self.exact[ident] = name
        self.written[key] = ident
        return _W(kind, ident), None

    def use(self, kind, name):
        return _W(kind, use=name)

    # scene ---------------------------------------------------------------------------------
    def scene(self) -> list:
        doc = self.doc
        out = []
        if doc.viewpoint is not None and not self.reachable(doc.viewpoint):
            holder = self.group(Transform(kind="Transform",
                                          matrix=np.asarray(doc.viewpoint_matrix, float),
                                          children=[doc.viewpoint]))
            out.append(holder)
        body = [w for w in (self.child(c) for c in doc.root.children) if w is not None]
        if not self.x3d and doc.meter != 1.0:
            holder = _W("Transform").add("scale", "vec", (doc.meter,) * 3)
            holder.node("children", body, single=False)
            body = [holder]
        out.extend(body)
        front = []
        info = list(doc.info) + [f"{NAME_PREFIX}{k}={v}" for k, v in self.exact.items()]
        if doc.title or info:
            world = _W("WorldInfo")
            if doc.title:
                world.add("title", "string", doc.title)
            if info:
                world.add("info", "strings", info)
            front.append(world)
        nav = _W("NavigationInfo").add("headlight", "bool", bool(doc.headlight))
        if doc.navigation_types:
            nav.add("type", "strings", list(doc.navigation_types))
        front.append(nav)
        if doc.background is not None:
            front.append(_W("Background").add("skyColor", "floats", tuple(doc.background[:3])))
        return front + out

    def child(self, obj):
        if isinstance(obj, Transform):
            return self.group(obj)
        if isinstance(obj, Shape):
            return self.shape(obj)
        if isinstance(obj, Light):
            return self.light(obj)
        if isinstance(obj, Viewpoint):
            return self.viewpoint(obj)
        return None

    def group(self, t: Transform):
        m = np.asarray(t.matrix, dtype=np.float64)
        kind = "Group" if np.array_equal(m, np.eye(4)) else "Transform"
        w, use = self.define(t, kind)
        if use:
            return self.use(kind, use)
        if kind == "Transform":
            parts = decompose(m)
            if any(parts["translation"]):
                w.add("translation", "vec", parts["translation"])
            if parts["rotation"][3] != 0.0:
                w.add("rotation", "vec", parts["rotation"])
            if not np.allclose(parts["scale"], 1.0, rtol=0.0, atol=0.0):
                w.add("scale", "vec", parts["scale"])
                if parts["scale_orientation"][3] != 0.0:
                    w.add("scaleOrientation", "vec", parts["scale_orientation"])
        kids = [k for k in (self.child(c) for c in t.children) if k is not None]
        w.node("children", kids, single=False)
        return w

    def shape(self, s: Shape):
        w, use = self.define(s, "Shape")
        if use:
            return self.use("Shape", use)
        if s.appearance is not None:
            w.node("appearance", self.appearance(s.appearance))
        if s.geometry is not None:
            w.node("geometry", self.geometry(s.geometry))
        return w

    def appearance(self, a: Appearance):
        w, use = self.define(a, "Appearance")
        if use:
            return self.use("Appearance", use)
        if a.material is not None:
            w.node("material", self.material(a.material))
        if a.texture is not None:
            w.node("texture", self.texture(a.texture))
        if a.texture_transform is not None:
            w.node("textureTransform", self.texture_transform(a.texture_transform))
        return w

    def material(self, m: Material):
        two = self.x3d and m.kind == "two_sided"
        kind = "TwoSidedMaterial" if two else "Material"
        w, use = self.define(m, kind, always=True)
        if use:
            return self.use(kind, use)
        w.add("diffuseColor", "vec", m.diffuse).add("ambientIntensity", "float",
                                                     m.ambient_intensity)
        w.add("specularColor", "vec", m.specular).add("emissiveColor", "vec", m.emissive)
        w.add("shininess", "float", m.shininess).add("transparency", "float", m.transparency)
        if two and m.back is not None:
            b = m.back
            w.add("separateBackColor", "bool", True)
            w.add("backDiffuseColor", "vec", b.diffuse)
            w.add("backAmbientIntensity", "float", b.ambient_intensity)
            w.add("backSpecularColor", "vec", b.specular)
            w.add("backEmissiveColor", "vec", b.emissive)
            w.add("backShininess", "float", b.shininess)
            w.add("backTransparency", "float", b.transparency)
        return w

    def texture(self, t: Texture):
        kind = "PixelTexture" if t.image is not None else "ImageTexture"
        w, use = self.define(t, kind)
        if use:
            return self.use(kind, use)
        if t.image is not None:
            img = np.asarray(t.image, dtype=np.uint64)
            height, width, comps = img.shape
            shifts = np.arange(comps - 1, -1, -1, dtype=np.uint64) * np.uint64(8)
            packed = (img.reshape(-1, comps) << shifts[None, :]).sum(axis=1)
            w.add("image", "raw", f"{width} {height} {comps} " + _ints(packed.astype(np.int64)))
        else:
            w.add("url", "strings", list(t.urls))
        if not t.repeat_s:
            w.add("repeatS", "bool", False)
        if not t.repeat_t:
            w.add("repeatT", "bool", False)
        return w

    def texture_transform(self, t: TextureTransform):
        w, use = self.define(t, "TextureTransform")
        if use:
            return self.use("TextureTransform", use)
        return (w.add("center", "vec", t.center).add("rotation", "float", t.rotation)
                .add("scale", "vec", t.scale).add("translation", "vec", t.translation))

    def text(self, mesh: Mesh):
        """A Text read from a file written back as Text with its FontStyle."""
        w, use = self.define(mesh, "Text")
        if use:
            return self.use("Text", use)
        t = mesh.text
        w.add("string", "strings", [str(s) for s in t["strings"]])
        if any(t["length"]):
            w.add("length", "floats", t["length"])
        if t["max_extent"]:
            w.add("maxExtent", "float", t["max_extent"])
        if self.x3d and t["solid"]:
            w.add("solid", "bool", True)
        style = (_W("FontStyle").add("family", "strings", [str(f) for f in t["family"]])
                 .add("style", "string", t["style"]).add("size", "float", t["size"])
                 .add("spacing", "float", t["spacing"])
                 .add("justify", "strings", list(t["justify"])))
        for key, field_ in (("horizontal", "horizontal"), ("left_to_right", "leftToRight"),
                            ("top_to_bottom", "topToBottom")):
            if not t[key]:
                style.add(field_, "bool", False)
        if t["language"]:
            style.add("language", "string", t["language"])
        return w.node("fontStyle", style)

    def geometry(self, mesh: Mesh):
        if mesh.text is not None:
            return self.text(mesh)
        # VRML97's primitives are always solid: a two-sided one is written as its faces
        primitive = mesh.kind in _PRIMITIVES and mesh.primitive and (self.x3d or mesh.solid)
        kind = mesh.kind if primitive else \
            ("PointSet" if mesh.kind == "PointSet" else
             "IndexedLineSet" if mesh.edges is not None else "IndexedFaceSet")
        w, use = self.define(mesh, kind)
        if use:
            return self.use(kind, use)
        if kind in _PRIMITIVES:
            for key, value in mesh.primitive.items():
                if isinstance(value, bool):
                    w.add(key, "bool", value)
                elif isinstance(value, (tuple, list)):
                    w.add(key, "vec", value)
                else:
                    w.add(key, "float", value)
            if self.x3d and not mesh.solid:
                w.add("solid", "bool", False)
            return w
        coord = _W("Coordinate").add("point", "tuples", mesh.positions)
        if kind == "PointSet":
            w.node("coord", coord)
            if mesh.point_colors is not None:
                w.node("color", self.colors(mesh.point_colors))
            return w
        if kind == "IndexedLineSet":
            w.node("coord", coord)
            edges = np.asarray(mesh.edges, dtype=np.int64).reshape(-1, 2)
            w.add("coordIndex", "ints", _separated(edges.reshape(-1), np.full(len(edges), 2)))
            if mesh.point_colors is not None:
                w.node("color", self.colors(mesh.point_colors))
            return w
        if not mesh.solid:
            w.add("solid", "bool", False)
        if not mesh.ccw:
            w.add("ccw", "bool", False)
        if not mesh.convex:
            w.add("convex", "bool", False)
        if mesh.crease_angle:
            w.add("creaseAngle", "float", mesh.crease_angle)
        w.node("coord", coord)
        w.add("coordIndex", "ints", _separated(mesh.corners, mesh.face_sizes))
        for attr, node, field_, index_field, width in (
                ("normals", "Normal", "vector", "normalIndex", 3),
                ("colors", None, "color", "colorIndex", 4),
                ("uvs", "TextureCoordinate", "point", "texCoordIndex", 2)):
            values = getattr(mesh, attr)
            if values is None:
                continue
            values = np.asarray(values, dtype=np.float64).reshape(-1, width)
            unique, inverse = np.unique(values, axis=0, return_inverse=True)
            if attr == "colors":
                holder = self.colors(unique)
            else:
                holder = _W(node).add(field_, "tuples", unique)
            w.node({"normals": "normal", "colors": "color", "uvs": "texCoord"}[attr], holder)
            w.add(index_field, "ints", _separated(inverse.reshape(-1), mesh.face_sizes))
        return w

    def colors(self, rgba):
        rgba = np.asarray(rgba, dtype=np.float64)
        if rgba.shape[1] == 4 and self.x3d and not np.all(rgba[:, 3] == 1.0):
            return _W("ColorRGBA").add("color", "tuples", rgba)
        return _W("Color").add("color", "tuples", rgba[:, :3])

    def light(self, light: Light):
        kind = {"directional": "DirectionalLight", "point": "PointLight",
                "spot": "SpotLight"}[light.kind]
        w, use = self.define(light, kind)
        if use:
            return self.use(kind, use)
        w.add("on", "bool", bool(light.on)).add("intensity", "float", light.intensity)
        w.add("ambientIntensity", "float", light.ambient_intensity)
        w.add("color", "vec", light.color)
        if light.kind != "directional":
            w.add("location", "vec", light.location).add("attenuation", "vec", light.attenuation)
            w.add("radius", "float", light.radius)
        if light.kind != "point":
            w.add("direction", "vec", light.direction)
        if light.kind == "spot":
            w.add("beamWidth", "float", light.beam_width)
            w.add("cutOffAngle", "float", light.cut_off_angle)
        if self.x3d:
            w.add("global", "bool", bool(light.is_global))
            if light.shadows:  # X3D 3.2+; FALSE, the default, is not written
                w.add("shadows", "bool", True)
        return w

    def viewpoint(self, vp: Viewpoint):
        kind = "OrthoViewpoint" if vp.kind == "OrthoViewpoint" and self.x3d else "Viewpoint"
        w, use = self.define(vp, kind)
        if use:
            return self.use(kind, use)
        w.add("position", "vec", vp.position).add("orientation", "vec", vp.orientation)
        if kind == "OrthoViewpoint":
            w.add("fieldOfView", "vec", vp.ortho_field or (-1.0, -1.0, 1.0, 1.0))
        else:
            w.add("fieldOfView", "float", vp.field_of_view)
        if self.x3d:
            w.add("centerOfRotation", "vec", vp.center_of_rotation)
        if vp.description:
            w.add("description", "string", vp.description)
        return w


def _classic_quote(text: str) -> str:
    return '"' + text.replace("\\", "\\\\").replace('"', '\\"') + '"'


def _classic_value(kind, value, x3d) -> str:
    if kind == "bool":
        return "TRUE" if value else "FALSE"
    if kind == "float":
        return _num(value)
    if kind == "vec":
        return _nums(value)
    if kind == "floats":
        return "[ " + _nums(value) + " ]"
    if kind == "tuples":
        return "[ " + _tuples(value) + " ]"
    if kind == "ints":
        return "[ " + _ints(value) + " ]"
    if kind == "string":
        return _classic_quote(value)
    if kind == "strings":
        return "[ " + " ".join(_classic_quote(s) for s in value) + " ]"
    return str(value)


def _write_classic(w: _W, out: list, pad: str, x3d: bool) -> None:
    if w.use:
        out.append(f"USE {w.use}")
        return
    out.append((f"DEF {w.name} " if w.name else "") + w.type + " {\n")
    inner = pad + "  "
    for name, kind, value in w.fields:
        out.append(f"{inner}{name} {_classic_value(kind, value, x3d)}\n")
    for name, nodes, single in w.nodes:
        if single:
            out.append(f"{inner}{name} ")
            _write_classic(nodes[0], out, inner, x3d)
            out.append("\n")
        else:
            out.append(f"{inner}{name} [\n")
            for node in nodes:
                out.append(inner + "  ")
                _write_classic(node, out, inner + "  ", x3d)
                out.append("\n")
            out.append(f"{inner}]\n")
    out.append(pad + "}")


def _xml_value(kind, value) -> str:
    if kind == "bool":
        return "true" if value else "false"
    if kind == "float":
        return _num(value)
    if kind in ("vec", "floats"):
        return _nums(value)
    if kind == "tuples":
        return _tuples(value)
    if kind == "ints":
        return _ints(value)
    if kind == "string":
        return value
    if kind == "strings":
        return " ".join(_classic_quote(s) for s in value)
    return str(value)


def _write_xml(w: _W, parent, container: str) -> None:
    element = ET.SubElement(parent, w.type)
    if w.use:
        element.set("USE", w.use)
    elif w.name:
        element.set("DEF", w.name)
    if container != _CONTAINER.get(w.type, "children"):
        element.set("containerField", container)
    if w.use:
        return
    for name, kind, value in w.fields:
        element.set(name, _xml_value(kind, value))
    for name, nodes, _single in w.nodes:
        for node in nodes:
            _write_xml(node, element, name)


def dumps_x3d(doc: Document) -> str:
    """X3D 3.3 XML text of *doc* (profile Immersive): units as ``<unit>``, the scene graph
    with DEF/USE where objects are shared, every light field written."""
    emit = _Emit(doc, "x3d-xml")
    nodes = emit.scene()
    root = ET.Element("X3D", {"profile": "Immersive", "version": "3.3"})
    head = ET.SubElement(root, "head")
    ET.SubElement(head, "meta", {"name": "generator", "content": "Phong Nodes"})
    for key, value in doc.meta.items():
        if key != "generator":
            ET.SubElement(head, "meta", {"name": key, "content": value})
    if doc.meter != 1.0:
        ET.SubElement(head, "unit", {"category": "length", "name": doc.unit_name or "length",
                                     "conversionFactor": _num(doc.meter)})
    scene = ET.SubElement(root, "Scene")
    for node in nodes:
        _write_xml(node, scene, "children")
    ET.indent(root, space=" ")
    return ('<?xml version="1.0" encoding="UTF-8"?>\n'
            '<!DOCTYPE X3D PUBLIC "ISO//Web3D//DTD X3D 3.3//EN" '
            '"http://www.web3d.org/specifications/x3d-3.3.dtd">\n'
            + ET.tostring(root, encoding="unicode") + "\n")


def _dumps_classic(doc: Document, target: str) -> str:
    emit = _Emit(doc, target)
    nodes = emit.scene()
    x3d = target != "vrml97"
    if x3d:
        out = ["#X3D V3.3 utf8\nPROFILE Immersive\n"]
        if doc.meter != 1.0:
            name = _IDENT.sub("_", doc.unit_name or "length") or "length"
            out.append(f"UNIT length {name} {_num(doc.meter)}\n")
        out.append(f"META {_classic_quote('generator')} {_classic_quote('Phong Nodes')}\n")
        for key, value in doc.meta.items():
            if key != "generator":
                out.append(f"META {_classic_quote(key)} {_classic_quote(value)}\n")
    else:
        out = ["#VRML V2.0 utf8\n# written by Phong Nodes\n"]
    for node in nodes:
        out.append("\n")
        _write_classic(node, out, "", x3d)
        out.append("\n")
    return "".join(out)


def dumps_vrml(doc: Document) -> str:
    """VRML97 text of *doc* (what KiCad and every VRML97 browser read).  VRML97 has no
    units (a scene in other units is wrapped in a Transform scaling it to metres), no
    ``global`` light field, no ColorRGBA (alpha is dropped), no OrthoViewpoint (written as a
    Viewpoint), no TwoSidedMaterial, PhysicalMaterial or UnlitMaterial (written as the
    Material of their values)."""
    return _dumps_classic(doc, "vrml97")


def dumps_x3dv(doc: Document) -> str:
    """X3D 3.3 ClassicVRML text of *doc* (``.x3dv``)."""
    return _dumps_classic(doc, "x3d-classic")


def save(doc: Document, path: str) -> str:
    """Write *doc* to *path* atomically (``core.outputs.write_file``), the encoding chosen by
    the extension: ``.x3d`` XML, ``.x3dv`` ClassicVRML, ``.wrl`` VRML97; gzipped when the name
    ends in ``z`` (``.x3dz``, ``.x3dvz``, ``.wrz``) or ``.gz``."""
    lower = path.lower()
    gz = lower.endswith(".gz")
    stem = lower[:-3] if gz else lower
    for packed, plain in ((".x3dz", ".x3d"), (".x3dvz", ".x3dv"), (".wrz", ".wrl")):
        if stem.endswith(packed):
            gz, stem = True, stem[:-len(packed)] + plain
    if stem.endswith(".x3d"):
        text = dumps_x3d(doc)
    elif stem.endswith(".x3dv"):
        text = dumps_x3dv(doc)
    elif stem.endswith((".wrl", ".vrml")):
        text = dumps_vrml(doc)
    else:
        raise ValueError(f"{path}: not an X3D or VRML file name (.x3d, .x3dv, .wrl, gzipped: "
                         ".x3dz, .x3dvz, .wrz, .gz)")
    data = text.encode("utf-8")
    if gz:
        data = gzip.compress(data, mtime=0)
    return outputs.write_file(path, data)
