# SPDX-License-Identifier: GPL-3.0-or-later
"""The generic node graph that both encodings parse into (nodes as written, USE, IS, PROTOs,
scopes, a file read, its UNIT statements), and the table of node types the reader knows.
PROTO expansion is ``protos``.
"""

from __future__ import annotations

import math
import os

from .numeric import _word_number


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


_CASE = "node and field names read regardless of case"


def unit(notes, src, category, name, factor):
    """A UNIT statement (X3D 3.3) into *src*: its length (metres per unit) or angle (radians
    per unit); a factor that is not a positive number is a warning."""
    value = _word_number(factor) if isinstance(factor, str) else float(factor)
    if not (isinstance(value, (int, float)) and math.isfinite(value) and value > 0):
        notes.add("UNIT statements that could not be read", f"{category} {factor}")
        return
    category = category.lower()
    if category == "length":
        src.meter, src.unit_name = float(value), name
    elif category == "angle":
        src.angle = float(value)
