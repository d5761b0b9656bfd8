# SPDX-License-Identifier: GPL-3.0-or-later
"""The generic node graph that both encodings parse into (nodes as written, USE, IS, PROTOs,
scopes, a file read), the table of node types the reader knows, and PROTO expansion
(:class:`_Protos`, a part of the reader: an instance stands for its PROTO's first body
node; what depends on its fields through IS is copied, the rest shared, at most
:data:`MAX_NODES` nodes, nested at most :data:`MAX_PROTO_DEPTH` deep).
"""

from __future__ import annotations

import os


#: Most nodes that PROTO expansion copies in one file (only the nodes of a PROTO body that
#: depend on the instance's fields through IS are copied; the rest is shared).
MAX_NODES = 50_000
#: Deepest nesting of PROTO instances inside PROTO bodies.
MAX_PROTO_DEPTH = 32


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


class _Budget(Exception):
    pass


_CASE = "node and field names read regardless of case"


class _Protos:
    """The reader's PROTO expansion (a mixin of ``build._Reader``)."""

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
