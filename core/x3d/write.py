# SPDX-License-Identifier: GPL-3.0-or-later
"""Writing: the data model as X3D XML, X3D ClassicVRML or VRML97.

:func:`dumps_x3d` (X3D 3.3 XML, profile Immersive), :func:`dumps_x3dv` (X3D 3.3 ClassicVRML)
and :func:`dumps_vrml` (VRML97, what KiCad reads) write the same graph: an object used more
than once is DEF'd once and USE'd after (so ``load(dumps(doc))`` shares what ``doc`` shares);
every Material is DEF'd (its name, taken before any other node's: a material keeps the file's
name for every reader, and a group or shape whose name collides with it yields); a
Transform's matrix is written as translation, rotation, scale and scaleOrientation
(:func:`decompose`: exact for any affine matrix, mirrors included);
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
import re
import xml.etree.ElementTree as ET

import numpy as np

from .. import outputs
from .numeric import decompose
from .model import (
    NAME_PREFIX, Appearance, Light, Material, Mesh, Shape, Texture, TextureTransform, Transform,
    Viewpoint)
from .graph import _CONTAINER, _PRIMITIVES
from .document import Document


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
        self.reserved = self.reserve_materials()

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

    def reserve_materials(self) -> dict:
        """{id(Material): its DEF}, given before any other node's: the materials keep the
        file's names for every reader (KiCad's library names them on purpose: ``PIN-01``),
        and a group or shape whose name collides with one yields (``_2`` ...).  In the order
        of the document, so that equal identifiers number alike in every run."""
        out = {}
        stack, seen = [self.doc.root], set()
        while stack:
            obj = stack.pop()
            if id(obj) in seen:
                continue
            seen.add(id(obj))
            if isinstance(obj, Material):
                out[id(obj)] = self.identifier(getattr(obj, "name", "") or "Material")
            elif isinstance(obj, Transform):
                stack.extend(reversed(obj.children))
            elif isinstance(obj, Shape) and obj.appearance is not None:
                stack.append(obj.appearance)
            elif isinstance(obj, Appearance) and obj.material is not None:
                stack.append(obj.material)
        return out

    def identifier(self, name) -> str:
        """A valid identifier for *name* not used before (``_2`` ... when it was), taken;
        the exact name is kept (WorldInfo) where it differs."""
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
        return ident

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
        if key in self.reserved:   # a material: its DEF given first (reserve_materials)
            ident = self.written[key] = self.reserved[key]
            return _W(kind, ident), None
        name = getattr(obj, "name", "") or ""
        if not name and (always or self.uses.get(key, 0) > 1):
            self.serial += 1
            name = f"{kind}_{self.serial}" if not always else kind
        if not name:
            self.written[key] = ""
            return _W(kind), None
        ident = self.written[key] = self.identifier(name)
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
        if doc.avatar_size:
            nav.add("avatarSize", "floats", tuple(doc.avatar_size))
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
