# SPDX-License-Identifier: GPL-3.0-or-later
"""VRML97 and X3D files read and written without ``bpy``.

VRML97 (ISO/IEC 14772-1) and X3D (ISO/IEC 19775-1) shade with a Phong model: ``Material {
diffuseColor ambientIntensity specularColor emissiveColor shininess transparency }`` lit by
DirectionalLight, PointLight and SpotLight (attenuation 1/max(a0 + a1·d + a2·d², 1), a radius, a
cone of ``beamWidth`` / ``cutOffAngle``) and a headlight.  This package reads a file into plain
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

The package, one job a module, each importing only the modules before it in this list
(``tests/test_layout.py`` holds the order):

* ``numeric`` — numbers tokenised in bulk, non-finite values made safe; Transform matrices and
  their decomposition.
* ``model`` — the data model (Transform, Shape, Mesh, Material, Light, Viewpoint, the
  flattened instances), the nesting limit, :class:`X3DError`, the warnings collected.
* ``context`` — one reading's context (its option, notes, memo and caches, budgets), the one
  object that every function of the reading below is handed: no reader object whose parts
  share ``self``, so each module's dependencies are its imports.
* ``graph`` — the generic node graph both encodings parse into, the table of node types, UNIT
  statements.
* ``parse_classic`` — ClassicVRML (VRML97 and X3D classic) into the graph.
* ``parse_xml`` — X3D's XML encoding into the graph (entities refused: ``core/xmlsafe.py``,
  shared with COLLADA).
* ``fields`` — typed field access (numbers, vectors, angles, booleans, strings, nodes, a
  node's canonical type).
* ``files`` — reading a file (gzip, size limit), resolving URLs, sniffing the encoding.
* ``protos`` — PROTO and EXTERNPROTO expansion; a field's node looked up (USE, PROTO).
* ``geometry`` — tessellation, Extrusion, Text, and every geometry node into a Mesh.
* ``build`` — the reader: DEF/USE dispatch, the scene-graph nodes, the warnings.
* ``flatten`` — the shared graph into shape and light instances with world matrices.
* ``document`` — :class:`Document` and :func:`load` / :func:`loads`.
* ``phong`` — the mappings to the project's Phong model and to Blender's axes.
* ``write`` — :func:`dumps_x3d`, :func:`dumps_x3dv`, :func:`dumps_vrml`, :func:`save`.

Every name callers use is imported here: ``from phong_nodes.core import x3d``;
``x3d.load(path)``.  A limit lives in the module that applies it (``x3d.files.MAX_BYTES``,
``x3d.flatten.MAX_INSTANCES`` ...): the name here is a copy, to read; set it there.

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
"""

from .numeric import MAX_ABS, decompose, rotation_matrix, transform_matrix
from .model import (
    ENCODINGS, LIGHT_KINDS, MAX_DEPTH, NAME_PREFIX, SPOT_DEFAULTS, Y_UP_TO_Z_UP, Appearance,
    Light, LightInstance, Material, Mesh, Shape, ShapeInstance, Texture, TextureTransform,
    Transform, Viewpoint, X3DError)
from .graph import _PRIMITIVES
from .files import MAX_BYTES, MAX_INLINE_DEPTH, resolve_local
from .protos import MAX_NODES, MAX_PROTO_DEPTH
from .geometry import (
    MAX_CAP_TRIANGULATION, MAX_EXTRUSION_POINTS, SEGMENTS, crease_normals, extrude,
    extrusion_frames, triangulate_polygon)
from .flatten import MAX_INSTANCES, MAX_VISITS, PATH_LIMIT
from .document import Document, load, loads
from .phong import (
    NO_RADIUS, WORLD_AMBIENT, ambient_intensity_of, apply_texture_transform, colour32,
    counter_clockwise, f32, highlight_note, is_world_ambient, light_fields, light_settings,
    light_values, material_fields, model_note, phong_values, shininess_of, to_blender_matrix,
    world_ambient, world_ambient_light)
from .write import dumps_vrml, dumps_x3d, dumps_x3dv, save

__all__ = [
    "MAX_ABS", "decompose", "rotation_matrix", "transform_matrix",
    "ENCODINGS", "LIGHT_KINDS", "MAX_DEPTH", "NAME_PREFIX", "SPOT_DEFAULTS", "Y_UP_TO_Z_UP",
    "Appearance", "Light", "LightInstance", "Material", "Mesh", "Shape", "ShapeInstance",
    "Texture", "TextureTransform", "Transform", "Viewpoint", "X3DError",
    "MAX_NODES", "MAX_PROTO_DEPTH", "MAX_BYTES", "MAX_INLINE_DEPTH", "resolve_local",
    "MAX_CAP_TRIANGULATION", "MAX_EXTRUSION_POINTS", "SEGMENTS", "crease_normals", "extrude",
    "extrusion_frames", "triangulate_polygon", "MAX_INSTANCES", "MAX_VISITS", "PATH_LIMIT",
    "Document", "load", "loads", "apply_texture_transform", "counter_clockwise", "light_values",
    "phong_values", "to_blender_matrix", "NO_RADIUS", "ambient_intensity_of", "colour32", "f32",
    "highlight_note", "light_fields", "light_settings", "material_fields", "model_note",
    "shininess_of", "WORLD_AMBIENT", "is_world_ambient", "world_ambient",
    "world_ambient_light", "dumps_vrml", "dumps_x3d", "dumps_x3dv", "save",
]
