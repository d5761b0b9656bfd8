# SPDX-License-Identifier: GPL-3.0-or-later
"""COLLADA read: :func:`load` and :func:`parse_bytes` into a :class:`~.model.Document`.

Hardening: a document type declaring entities is refused before parsing (``core.xmlsafe``),
counts are never trusted for allocation (arrays are as long as their text), and every index
is checked against its source.  Reading is liberal: namespaces (1.4, 1.5 or none) are
ignored, decimal commas are repaired, an unbound material symbol is looked up by id and
name, a texture may name a sampler, a surface, an image or a file.
"""

from __future__ import annotations

import math
import os
import warnings
import xml.etree.ElementTree as ET

import numpy as np

from .. import xmlsafe
from ..xmlsafe import local as _local
from .model import (
    LIGHT_KINDS, MAX_BYTES, MAX_INDICES, OPAQUE_MODES, PROFILE, TECHNIQUES, UP_AXES, Camera,
    ColladaError, Document, Instance, Light, Material, Mesh, Node, Texture, _uri_path)


# -- parsing helpers -----------------------------------------------------------------------

def _strip_namespaces(root) -> None:
    for element in root.iter():
        element.tag = _local(element.tag)
        if element.attrib and any("}" in k for k in element.attrib):
            element.attrib = {_local(k): v for k, v in element.attrib.items()}


def _name(element, default=""):
    """An element's exact name (our ``<extra>``), else its ``name``, else *default*."""
    exact = element.find(f"extra/technique[@profile='{PROFILE}']/name")
    if exact is not None and exact.text:
        return exact.text
    return element.get("name") or default


def _ref(url) -> str:
    """The id a URL (``#id``) or an IDREF names."""
    url = (url or "").strip()
    return url[1:] if url.startswith("#") else url


#: Texts shorter than this are read by the plain path (``str.split``); longer ones by numpy's
#: C parsers first (:func:`_bulk_floats`, :func:`_bulk_ints`), with the plain path behind.
BULK = 2048


def _bulk_floats(text: str):
    """The numbers of a long *text* of plain whitespace-separated decimals, read by numpy's C
    parser (``loadtxt``, correctly rounded as ``float()``), or None where it cannot read the
    text: the caller's liberal path reads it then (decimal commas, ...)."""
    flat = text.replace("\n", " ").replace("\r", " ").replace("\t", " ")
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("error")
            return np.loadtxt([flat], dtype=np.float64, comments=None, ndmin=1)
    except (ValueError, TypeError, UserWarning, DeprecationWarning):
        return None


def _bulk_ints(text: str):
    """The integers of a long *text* read by numpy's C parser (``fromstring``), or None
    where it cannot read the text (the caller's path reads it then)."""
    if not text.strip():
        return np.zeros(0, np.int64)   # (fromstring reads blank text as [-1])
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("error")
            return np.fromstring(text, dtype=np.int64, sep=" ")
    except (ValueError, TypeError, DeprecationWarning):
        return None


class _Reader:
    def __init__(self, doc: Document, root):
        self.doc = doc
        self.root = root
        self.ids = {}
        for element in root.iter():
            ident = element.get("id")
            if ident is not None:
                self.ids.setdefault(ident, element)
        self.commas = []   # where decimal commas were read (one warning at the end)

    # numbers ------------------------------------------------------------------------
    def floats(self, element, where, expected=None):
        """The numbers of *element*'s text (decimal commas repaired with one warning)."""
        text = (element.text or "") if element is not None else ""
        values = _bulk_floats(text) if len(text) >= BULK else None
        if values is None:
            words = text.split()
            try:
                values = np.array(words, dtype=np.float64) if words else np.zeros(0)
            except ValueError:
                values = None
        if values is None and "," in text:
            dotted = text.replace(",", ".").split()
            spaced = text.replace(",", " ").split()
            for candidate, what in ((dotted, "decimal commas"), (spaced, "commas between numbers")):
                if expected is not None and len(candidate) != expected and candidate is dotted \
                        and len(spaced) == expected:
                    continue
                try:
                    values = np.array(candidate, dtype=np.float64)
                except ValueError:
                    continue
                if what == "decimal commas":
                    self.commas.append(where)
                else:
                    self.doc.warn(f"{where}: {what} read as numbers")
                break
        if values is None:
            self.doc.warn(f"{where}: numbers that cannot be read; left out")
            return None
        if not np.all(np.isfinite(values)):
            self.doc.warn(f"{where}: NaN or infinite numbers read as 0")
            values = np.nan_to_num(values, nan=0.0, posinf=0.0, neginf=0.0)
        return values

    def ints(self, element, where):
        text = (element.text or "") if element is not None else ""
        values = _bulk_ints(text) if len(text) >= BULK else None
        if values is not None:
            return values
        try:
            return np.array(text.split(), dtype=np.int64)
        except (ValueError, OverflowError):
            values = self.floats(element, where)
            if values is None or np.any(values != np.round(values)):
                self.doc.warn(f"{where}: indices that are not integers; left out")
                return None
            return values.astype(np.int64)

    def number(self, element, where, default=None):
        values = self.floats(element, where) if element is not None else None
        if values is None or not len(values):
            return default
        return float(values[0])

    # asset ----------------------------------------------------------------------------
    def asset(self):
        asset = self.root.find("asset")
        if asset is None:
            return
        unit = asset.find("unit")
        if unit is not None and unit.get("meter") is not None:
            text = unit.get("meter").strip()
            if "," in text and "." not in text:
                self.commas.append("<unit meter>")
                text = text.replace(",", ".")
            try:
                meter = float(text)
            except ValueError:
                meter = float("nan")
            if not math.isfinite(meter) or meter <= 0.0:
                self.doc.warn(f"<unit meter=\"{unit.get('meter')}\"> is not a length; read as 1")
            else:
                self.doc.meter = meter
        up = asset.find("up_axis")
        if up is not None and up.text:
            axis = up.text.strip().upper()
            if axis in UP_AXES:
                self.doc.up_axis = axis
            else:
                self.doc.warn(f"<up_axis>{up.text.strip()}</up_axis> unknown; read as Y_UP")

    # sources ---------------------------------------------------------------------------
    def source(self, ident, where):
        """(values (count, stride) of the source *ident*, stride) or None."""
        element = self.ids.get(_ref(ident))
        if element is None or element.tag != "source":
            self.doc.warn(f"{where}: source {ident} not found; left out")
            return None
        array = element.find("float_array")
        accessor = element.find("technique_common/accessor")
        values = self.floats(array, f"{where}: source {element.get('id')}",
                             _int_attr(array, "count")) if array is not None else None
        if values is None:
            if array is None:
                self.doc.warn(f"{where}: source {element.get('id')} has no float_array; left out")
            return None
        stride = _int_attr(accessor, "stride") or 1
        offset = _int_attr(accessor, "offset") or 0
        if accessor is not None and accessor.get("source") and \
                _ref(accessor.get("source")) not in (array.get("id"), None) and \
                self.ids.get(_ref(accessor.get("source"))) is not None:
            other = self.ids[_ref(accessor.get("source"))]
            if other.tag == "float_array":
                values = self.floats(other, f"{where}: {other.get('id')}")
                if values is None:
                    return None
        stride = max(stride, 1)
        usable = (len(values) - offset) // stride
        count = _int_attr(accessor, "count")
        if count is not None and 0 <= count < usable:
            usable = count
        if usable <= 0:
            return np.zeros((0, stride)), stride
        block = values[offset:offset + usable * stride].reshape(usable, stride)
        return block, stride

    # geometry ----------------------------------------------------------------------------
    def mesh(self, geometry):
        ident = geometry.get("id", "")
        name = _name(geometry, ident)
        where = f"geometry {name}"
        mesh = geometry.find("mesh")
        if mesh is None:
            kinds = [_local(c.tag) for c in geometry if _local(c.tag) not in ("asset", "extra")]
            self.doc.warn(f"{where}: {', '.join(kinds) or 'nothing'} (not a <mesh>); left out")
            return None
        vertices = mesh.find("vertices")
        positions, vertex_extra = None, {}
        if vertices is not None:
            for inp in vertices.findall("input"):
                semantic = (inp.get("semantic") or "").upper()
                got = self.source(inp.get("source"), where)
                if got is None:
                    continue
                if semantic == "POSITION":
                    positions = got[0]
                else:
                    vertex_extra[semantic] = got[0]
        if positions is not None and len(positions) == 0:
            positions = np.zeros((0, 3))
        if positions is not None and positions.shape[1] == 2:
            self.doc.warn(f"{where}: 2D positions read with z = 0")
            positions = np.hstack([positions, np.zeros((len(positions), 1))])
        if positions is None or positions.shape[1] < 3:
            self.doc.warn(f"{where}: no positions; left out")
            return None
        positions = positions[:, :3].copy()
        acc = {"sizes": [], "face_symbols": [], "symbols": [], "corners": [], "normals": [],
               "uvs": {}, "colors": {}, "n_corners": 0, "has_normals": False, "edges": []}
        for prim in mesh:
            kind = prim.tag
            if kind in ("lines", "linestrips"):
                self.lines(prim, kind, positions, acc, where)
                continue
            if kind not in ("triangles", "polylist", "polygons", "tristrips", "trifans"):
                continue
            self.primitive(prim, kind, positions, vertex_extra, acc, where)
        edges = np.concatenate(acc["edges"]) if acc["edges"] else None
        if not acc["sizes"]:
            empty = np.zeros(0, np.int64)
            return Mesh(ident, name, positions, empty, np.zeros(0, np.int32), acc["symbols"],
                        empty.copy(), edges=edges)
        total = acc["n_corners"]
        out = Mesh(ident, name, positions, np.concatenate(acc["sizes"]),
                   np.concatenate(acc["face_symbols"]), acc["symbols"],
                   np.concatenate(acc["corners"]))
        out.from_strips = acc.get("strips", False)
        out.edges = edges
        if acc["has_normals"]:
            out.normals = np.concatenate(acc["normals"])
        for key, target in (("uvs", out.uvs), ("colors", out.colors)):
            width = 2 if key == "uvs" else 4
            for channel, parts in acc[key].items():
                full = np.zeros((total, width)) if key == "uvs" else np.ones((total, width))
                for start, block in parts:
                    full[start:start + len(block)] = block
                target[channel] = full
        return out

    def lines(self, prim, kind, positions, acc, where):
        """``<lines>`` (a pair of vertices per line) and ``<linestrips>`` (one ``<p>`` per
        strip) as edges between positions (loose edges in Blender, as Blender's own OBJ and
        4.2's COLLADA importers keep lines); their material symbol becomes a slot of the
        mesh.  A line with an index out of range, or from a vertex to itself, is left out."""
        symbol = prim.get("material", "")
        label = f"{where}: <{kind} material=\"{symbol}\">"
        offsets = []
        for inp in prim.findall("input"):
            try:
                offsets.append(((inp.get("semantic") or "").upper(), int(inp.get("offset", "0"))))
            except ValueError:
                self.doc.warn(f"{label}: an input's offset is not a number; left out")
                return
        vertex = [offset for semantic, offset in offsets if semantic == "VERTEX"]
        if not vertex:
            self.doc.warn(f"{label}: no VERTEX input; left out")
            return
        stride = max(offset for _semantic, offset in offsets) + 1
        if stride > 64:
            self.doc.warn(f"{label}: {stride} index offsets; left out")
            return
        strips = []
        for p in prim.findall("p"):
            values = self.ints(p, label)
            if values is None:
                return
            strips.append(values[:len(values) - len(values) % stride].reshape(-1, stride)
                          [:, vertex[0]])
        if sum(len(v) for v in strips) > MAX_INDICES:
            self.doc.warn(f"{label}: more than {MAX_INDICES} indices; left out")
            return
        if kind == "lines":
            points = np.concatenate(strips) if strips else np.zeros(0, np.int64)
            pairs = points[:len(points) - len(points) % 2].reshape(-1, 2)
        else:
            pairs = np.concatenate([np.stack([v[:-1], v[1:]], axis=1) for v in strips
                                    if len(v) >= 2] or [np.zeros((0, 2), np.int64)])
        outside = np.any((pairs < 0) | (pairs >= len(positions)), axis=1)
        if np.any(outside):
            self.doc.warn(f"{label}: {int(outside.sum())} line(s) with position indices out "
                          "of range left out")
        pairs = pairs[~outside & (pairs[:, 0] != pairs[:, 1])]
        if not len(pairs):
            return
        acc["edges"].append(pairs)
        if symbol and symbol not in acc["symbols"]:
            acc["symbols"].append(symbol)

    def primitive(self, prim, kind, positions, vertex_extra, acc, where):
        symbol = prim.get("material", "")
        label = f"{where}: <{kind} material=\"{symbol}\">"
        inputs = []
        for inp in prim.findall("input"):
            try:
                offset = int(inp.get("offset", "0"))
                channel = int(inp.get("set", "0") or 0)
            except ValueError:
                self.doc.warn(f"{label}: an input's offset or set is not a number; left out")
                continue
            inputs.append(((inp.get("semantic") or "").upper(), inp.get("source"), offset, channel))
        vertex = [i for i in inputs if i[0] == "VERTEX"]
        if not vertex:
            self.doc.warn(f"{label}: no VERTEX input; left out")
            return
        stride = max(i[2] for i in inputs) + 1
        if stride > 64:
            self.doc.warn(f"{label}: {stride} index offsets; left out")
            return
        # index lists: one per polygon (polygons), strip/fan, or the whole <p>
        lists = []
        for p in prim.findall("p"):
            values = self.ints(p, label)
            if values is None:
                return
            lists.append(values)
        if prim.findall("ph"):
            self.doc.warn(f"{label}: polygons with holes (<ph>) imported without their holes")
            for ph in prim.findall("ph"):
                values = self.ints(ph.find("p"), label)
                if values is not None:
                    lists.append(values)
        if sum(len(v) for v in lists) > MAX_INDICES:
            self.doc.warn(f"{label}: more than {MAX_INDICES} indices; left out")
            return
        if not lists:
            return
        lists = [v[:len(v) - len(v) % stride].reshape(-1, stride) for v in lists]
        if kind == "triangles":
            rows = np.concatenate(lists)
            rows = rows[:len(rows) - len(rows) % 3]
            sizes = np.full(len(rows) // 3, 3, np.int64)
        elif kind == "polylist":
            vcount = self.ints(prim.find("vcount"), label) if prim.find("vcount") is not None \
                else None
            rows = np.concatenate(lists)
            if vcount is None or np.any(vcount < 0) or vcount.sum() > len(rows):
                self.doc.warn(f"{label}: <vcount> does not match <p>; left out")
                return
            sizes = vcount.astype(np.int64)
            rows = rows[:int(sizes.sum())]
        elif kind == "polygons":
            rows = np.concatenate(lists)
            sizes = np.array([len(v) for v in lists], np.int64)
        else:
            parts, size_parts = [], []
            for strip in lists:
                n = len(strip) - 2
                if n <= 0:
                    continue
                k = np.arange(n)
                if kind == "trifans":
                    tri = np.stack([np.zeros(n, np.int64), k + 1, k + 2], axis=1)
                else:   # strip: every other triangle turned to keep its winding
                    even = (k % 2) == 0
                    tri = np.stack([k, np.where(even, k + 1, k + 2),
                                    np.where(even, k + 2, k + 1)], axis=1)
                parts.append(strip[tri.reshape(-1)])
                size_parts.append(np.full(n, 3, np.int64))
            if not parts:
                return
            acc["strips"] = True
            rows = np.concatenate(parts)
            sizes = np.concatenate(size_parts)
        keep = sizes >= 3
        if not np.all(keep):
            self.doc.warn(f"{label}: {int((~keep).sum())} face(s) with fewer than 3 corners "
                          "left out")
            mask = np.repeat(keep, sizes)
            rows, sizes = rows[mask], sizes[keep]
        if not len(sizes):
            return
        # check every index against its source
        vertex_offset = vertex[0][2]
        position_index = rows[:, vertex_offset]
        sources = {}
        for semantic, source, offset, channel in inputs:
            if semantic not in ("NORMAL", "TEXCOORD", "COLOR"):
                continue    # VERTEX above; TANGENT, CUSTOM ... the model does not read
            got = self.source(source, label)
            if got is None:
                continue
            sources[(semantic, channel, offset)] = got[0]
        bad = (position_index < 0) | (position_index >= len(positions))
        if np.any(bad):
            face_of = np.repeat(np.arange(len(sizes)), sizes)
            bad_faces = np.unique(face_of[bad])
            self.doc.warn(f"{label}: {len(bad_faces)} face(s) with position indices out of "
                          "range left out")
            keep = np.ones(len(sizes), bool)
            keep[bad_faces] = False
            mask = np.repeat(keep, sizes)
            rows, sizes = rows[mask], sizes[keep]
            position_index = rows[:, vertex_offset]
            if not len(sizes):
                return
        start = acc["n_corners"]
        if symbol not in acc["symbols"]:
            acc["symbols"].append(symbol)
        acc["sizes"].append(sizes)
        acc["face_symbols"].append(np.full(len(sizes), acc["symbols"].index(symbol), np.int32))
        acc["corners"].append(position_index)
        normals = None
        missing = []
        for (semantic, channel, offset), data in sources.items():
            index = rows[:, offset]
            outside = (index < 0) | (index >= len(data))
            if np.any(outside):   # the corner keeps its position; this value is left out
                missing.append(f"{int(outside.sum())} {semantic}")
                data = np.vstack([data, np.full((1, data.shape[1]),
                                                1.0 if semantic == "COLOR" else 0.0)])
                index = np.where(outside, len(data) - 1, index)
            if semantic == "NORMAL" and normals is None and data.shape[1] >= 3:
                normals = data[index, :3]
            elif semantic == "TEXCOORD" and data.shape[1] >= 2:
                acc["uvs"].setdefault(channel, []).append((start, data[index, :2]))
            elif semantic == "COLOR" and data.shape[1] >= 3:
                block = np.ones((len(index), 4))
                block[:, :min(4, data.shape[1])] = data[index, :4]
                acc["colors"].setdefault(channel, []).append((start, block))
        if normals is None and "NORMAL" in vertex_extra and \
                len(vertex_extra["NORMAL"]) >= len(positions):
            normals = vertex_extra["NORMAL"][position_index, :3]
        if normals is not None:
            if not acc["has_normals"] and start:
                acc["normals"].insert(0, np.zeros((start, 3)))
            acc["has_normals"] = True
            acc["normals"].append(normals)
        elif acc["has_normals"]:
            acc["normals"].append(np.zeros((len(rows), 3)))
        acc["n_corners"] += len(rows)
        if missing:
            self.doc.warn(f"{label}: indices out of range for {', '.join(missing)} corner "
                          "value(s); those values left out (zero normal, UV (0, 0), white)")

    # effects and materials -------------------------------------------------------------
    def params(self, *scopes):
        """{sid: newparam element} of *scopes* (later scopes win)."""
        out = {}
        for scope in scopes:
            if scope is None:
                continue
            for param in scope.findall("newparam"):
                if param.get("sid"):
                    out[param.get("sid")] = param
        return out

    def material(self, element):
        ident = element.get("id", "")
        name = _name(element, ident)
        where = f"material {name}"
        out = Material(ident, name)
        inst = element.find("instance_effect")
        effect = self.ids.get(_ref(inst.get("url"))) if inst is not None else None
        if effect is None or effect.tag != "effect":
            self.doc.warn(f"{where}: effect {inst.get('url') if inst is not None else '(none)'} "
                          "not found; imported black")
            out.technique = "lambert"
            return out
        out.effect_id = effect.get("id", "")
        profile = effect.find("profile_COMMON")
        if profile is None:
            profiles = [c.tag for c in effect if c.tag.startswith("profile_")]
            self.doc.warn(f"{where}: no profile_COMMON ({', '.join(profiles) or 'no profile'}); "
                          "imported black")
            out.technique = "lambert"
            return out
        technique_element = profile.find("technique")
        shading = None
        if technique_element is not None:
            shading = next((c for c in technique_element if c.tag in TECHNIQUES), None)
        if shading is None:
            self.doc.warn(f"{where}: no constant, lambert, phong or blinn technique; "
                          "imported black")
            out.technique = "lambert"
            return out
        out.technique = shading.tag
        params = self.params(effect, profile, technique_element)
        setparams = {}
        if inst is not None:
            for setparam in inst.findall("setparam"):
                if setparam.get("ref"):
                    setparams[setparam.get("ref")] = setparam
        context = (params, setparams, where)
        for child in shading:
            tag = child.tag
            if tag in ("emission", "ambient", "diffuse", "specular", "transparent"):
                color, texture = self.color_or_texture(child, context)
                if tag == "transparent":
                    mode = (child.get("opaque") or "A_ONE").strip().upper()
                    if mode not in OPAQUE_MODES:
                        self.doc.warn(f"{where}: <transparent opaque=\"{mode}\"> unknown; "
                                      "read as A_ONE")
                        mode = "A_ONE"
                    out.opaque = mode
                    if texture is not None:
                        out.transparent_texture = texture
                    elif color is not None:
                        out.transparent = color
                    continue
                if color is not None:
                    out.colors[tag] = color
                if texture is not None:
                    out.textures[tag] = texture
                    out.colors.setdefault(tag, (1.0, 1.0, 1.0, 1.0))
            elif tag in ("shininess", "transparency"):
                value = self.float_value(child, context)
                if value is not None:
                    setattr(out, tag, value)
        return out

    def _param_value(self, ref, context, kinds):
        params, setparams, where = context
        source = setparams.get(ref) if ref in setparams else params.get(ref)
        if source is None:
            return None
        for kind in kinds:
            value = source.find(kind)
            if value is not None:
                return self.floats(value, f"{where}: <{kind}> of {ref}")
        return None

    def color_or_texture(self, element, context):
        where = context[2]
        color = element.find("color")
        if color is not None:
            values = self.floats(color, f"{where}: <{element.tag}>")
            if values is not None and len(values) >= 3:
                a = float(values[3]) if len(values) >= 4 else 1.0
                return (float(values[0]), float(values[1]), float(values[2]), a), None
            self.doc.warn(f"{where}: <{element.tag}> colour that cannot be read; left out")
            return None, None
        param = element.find("param")
        if param is not None:
            values = self._param_value(param.get("ref", ""), context,
                                       ("float4", "float3", "color", "float"))
            if values is not None and len(values) >= 3:
                a = float(values[3]) if len(values) >= 4 else 1.0
                return (float(values[0]), float(values[1]), float(values[2]), a), None
            if values is not None and len(values) == 1:
                v = float(values[0])
                return (v, v, v, 1.0), None
            self.doc.warn(f"{where}: <{element.tag}> parameter {param.get('ref')} not found; "
                          "left out")
            return None, None
        texture = element.find("texture")
        if texture is not None:
            found = self.texture(texture.get("texture", ""), texture.get("texcoord", ""),
                                 context)
            if found is None:
                self.doc.warn(f"{where}: <{element.tag}> texture {texture.get('texture')} not "
                              "resolved to an image; left out")
            return None, found
        return None, None

    def float_value(self, element, context):
        where = context[2]
        value = element.find("float")
        if value is not None:
            return self.number(value, f"{where}: <{element.tag}>")
        param = element.find("param")
        if param is not None:
            values = self._param_value(param.get("ref", ""), context, ("float",))
            if values is not None and len(values):
                return float(values[0])
            self.doc.warn(f"{where}: <{element.tag}> parameter {param.get('ref')} not found; "
                          "left out")
        return None

    def texture(self, name, texcoord, context, depth=0):
        """The Texture a ``<texture texture=...>`` names: the spec's sampler → surface →
        image chain (setparam first), 1.5's instance_image, or (as other readers accept)
        an image id, image name or a file name."""
        params, setparams, where = context
        if depth > 8:
            return None
        param = setparams.get(name) if name in setparams else params.get(name)
        if param is not None:
            sampler = next((c for c in param if c.tag.startswith("sampler")), None)
            surface = param.find("surface")
            if sampler is not None:
                inst = sampler.find("instance_image")
                if inst is not None:
                    return self.image(_ref(inst.get("url")), texcoord, where)
                src = sampler.find("source")
                if src is not None and src.text:
                    return self.texture(src.text.strip(), texcoord, context, depth + 1)
            if surface is not None:
                init = surface.find("init_from")
                if init is not None and init.text and init.text.strip():
                    return self.image(init.text.strip(), texcoord, where)
                inst = surface.find("init_from/ref")
                if inst is not None and inst.text:
                    return self.image(inst.text.strip(), texcoord, where)
                # init_planar / init_volume / init_cube: <all ref="image"/> (or the first face)
                ref = next((e.get("ref") for e in surface.iter() if e.get("ref")), None)
                if ref:
                    return self.image(ref, texcoord, where)
        return self.image(name, texcoord, where, liberal=True)

    def image(self, ident, texcoord, where, liberal=False):
        element = self.ids.get(ident)
        if element is None or element.tag != "image":
            element = next((i for i in self.root.iter("image") if i.get("name") == ident), None)
        if element is None:
            if liberal and os.path.splitext(ident)[1]:
                return self.texture_file(ident, texcoord, ident)
            return None
        init = element.find("init_from")
        text = None
        if init is not None:
            ref = init.find("ref")
            text = ref.text if ref is not None else init.text
        if not text or not text.strip():
            self.doc.warn(f"{where}: image {ident} has no file; left out")
            return None
        return self.texture_file(text.strip(), texcoord, element.get("id", ident))

    def texture_file(self, written, texcoord, image_id):
        folder = os.path.dirname(os.path.abspath(self.doc.path))
        path = _uri_path(written)
        candidates = []
        if os.path.isabs(path):
            candidates.append(path)
        candidates.append(os.path.normpath(os.path.join(folder, path.replace("\\", "/"))))
        candidates.append(os.path.join(folder, os.path.basename(path.replace("\\", "/"))))
        resolved = next((c for c in candidates if os.path.isfile(c)), candidates[0])
        return Texture(written, resolved, texcoord, image_id)

    # lights and cameras --------------------------------------------------------------------
    def light(self, element):
        ident = element.get("id", "")
        name = _name(element, ident)
        common = element.find("technique_common")
        kind_element = next((c for c in common if c.tag in LIGHT_KINDS), None) \
            if common is not None else None
        if kind_element is None:
            self.doc.warn(f"light {name}: no ambient, directional, point or spot; left out")
            return None
        where = f"light {name}"
        out = Light(ident, name, kind_element.tag)
        color = kind_element.find("color")
        values = self.floats(color, f"{where}: <color>") if color is not None else None
        if values is not None and len(values) >= 3:
            out.color = tuple(float(v) for v in values[:3])
        for attr, tag in (("constant", "constant_attenuation"),
                          ("linear", "linear_attenuation"),
                          ("quadratic", "quadratic_attenuation"),
                          ("falloff_angle", "falloff_angle"),
                          ("falloff_exponent", "falloff_exponent")):
            child = kind_element.find(tag)
            if child is not None:
                value = self.number(child, f"{where}: <{tag}>")
                if value is not None:
                    setattr(out, attr, value)
        if out.kind in ("point", "spot"):
            if min(out.constant, out.linear, out.quadratic) < 0.0:
                self.doc.warn(f"{where}: negative attenuation read as 0")
                out.constant, out.linear, out.quadratic = (max(v, 0.0) for v in (
                    out.constant, out.linear, out.quadratic))
        return out

    def camera(self, element):
        ident = element.get("id", "")
        name = _name(element, ident)
        common = element.find("optics/technique_common")
        kind = next((c for c in common if c.tag in ("perspective", "orthographic")), None) \
            if common is not None else None
        if kind is None:
            self.doc.warn(f"camera {name}: no perspective or orthographic optics; left out")
            return None
        out = Camera(ident, name, kind.tag)
        for attr in ("xfov", "yfov", "xmag", "ymag", "aspect_ratio", "znear", "zfar"):
            child = kind.find(attr)
            if child is not None:
                value = self.number(child, f"camera {name}: <{attr}>")
                if value is not None:
                    setattr(out, attr, value)
        return out

    # scene -----------------------------------------------------------------------------------
    def node(self, element, depth=0):
        ident = element.get("id", "")
        name = _name(element, ident) or element.get("sid") or "node"
        matrix = np.eye(4)
        for child in element:
            local = transform(child, self, f"node {name}")
            if local is not None:
                matrix = matrix @ local
        out = Node(ident, name, matrix)
        if depth > 256:
            self.doc.warn(f"node {name}: nested more than 256 deep; the rest left out")
            return out
        for child in element:
            tag = child.tag
            if tag == "node":
                out.children.append(self.node(child, depth + 1))
            elif tag in ("instance_geometry", "instance_light", "instance_camera",
                         "instance_node", "instance_controller"):
                kind = tag.removeprefix("instance_")
                inst = Instance(kind, _ref(child.get("url")))
                if kind == "controller":
                    self.doc.warn(f"node {name}: <instance_controller> (skinning) imported as "
                                  "its skin's mesh at rest")
                    controller = self.ids.get(inst.url)
                    skin = controller.find("skin") if controller is not None else None
                    if skin is None:
                        continue
                    inst = Instance("geometry", _ref(skin.get("source")))
                for im in child.iter("instance_material"):
                    symbol = im.get("symbol", "")
                    inst.bindings[symbol] = _ref(im.get("target"))
                    uv = {}
                    for bvi in im.findall("bind_vertex_input"):
                        try:
                            uv[bvi.get("semantic", "")] = int(bvi.get("input_set", "0") or 0)
                        except ValueError:
                            pass
                    inst.uv_bindings[symbol] = uv
                out.instances.append(inst)
        return out


TRANSFORMS = ("matrix", "translate", "rotate", "scale", "lookat", "skew")


def transform(element, reader, where):
    """The 4x4 matrix of one transform element (None for other elements)."""
    tag = element.tag
    if tag not in TRANSFORMS:
        return None
    sizes = {"matrix": 16, "translate": 3, "rotate": 4, "scale": 3, "lookat": 9, "skew": 7}
    values = reader.floats(element, f"{where}: <{tag}>")
    if values is None or len(values) < sizes[tag]:
        reader.doc.warn(f"{where}: <{tag}> with fewer than {sizes[tag]} numbers; left out")
        return None
    v = values[:sizes[tag]]
    out = np.eye(4)
    if tag == "matrix":
        out = v.reshape(4, 4).copy()
    elif tag == "translate":
        out[:3, 3] = v
    elif tag == "scale":
        out[:3, :3] = np.diag(v)
    elif tag == "rotate":
        out[:3, :3] = rotation(v[:3], math.radians(v[3]))
    elif tag == "lookat":
        out = lookat(v[0:3], v[3:6], v[6:9])
    else:
        out[:3, :3] = skew(math.radians(v[0]), v[1:4], v[4:7])
    return out


def rotation(axis, angle) -> np.ndarray:
    axis = np.asarray(axis, dtype=np.float64)
    length = np.linalg.norm(axis)
    if length == 0.0:
        return np.eye(3)
    x, y, z = axis / length
    c, s = math.cos(angle), math.sin(angle)
    t = 1.0 - c
    return np.array([[t * x * x + c, t * x * y - s * z, t * x * z + s * y],
                     [t * x * y + s * z, t * y * y + c, t * y * z - s * x],
                     [t * x * z - s * y, t * y * z + s * x, t * z * z + c]])


def lookat(eye, interest, up) -> np.ndarray:
    """The spec's ``<lookat>``: the node at *eye*, its −Z towards *interest*, +Y towards
    *up* (as gluLookAt's inverse: a camera or light there looks at the interest point)."""
    eye, interest, up = (np.asarray(a, dtype=np.float64) for a in (eye, interest, up))
    z = eye - interest
    out = np.eye(4)
    out[:3, 3] = eye
    if np.linalg.norm(z) == 0.0:
        return out
    z = z / np.linalg.norm(z)
    x = np.cross(up, z)
    if np.linalg.norm(x) < 1e-12:    # up along the view: any perpendicular
        x = np.cross((1.0, 0.0, 0.0) if abs(z[0]) < 0.9 else (0.0, 1.0, 0.0), z)
    x = x / np.linalg.norm(x)
    y = np.cross(z, x)
    out[:3, 0], out[:3, 1], out[:3, 2] = x, y, z
    return out


def skew(angle, rotate_axis, translate_axis) -> np.ndarray:
    """RenderMan's skew (the spec's ``<skew>``): points move parallel to *translate_axis*
    by an amount proportional to their distance along the component of *rotate_axis*
    perpendicular to it, so that *rotate_axis* turns by *angle*."""
    a = np.asarray(rotate_axis, dtype=np.float64)
    b = np.asarray(translate_axis, dtype=np.float64)
    if np.linalg.norm(a) == 0.0 or np.linalg.norm(b) == 0.0:
        return np.eye(3)
    b = b / np.linalg.norm(b)
    a = a / np.linalg.norm(a)
    a1 = a - np.dot(a, b) * b       # the part of a perpendicular to b
    if np.linalg.norm(a1) < 1e-12:
        return np.eye(3)
    a1 = a1 / np.linalg.norm(a1)
    an1, an2 = np.dot(a, a1), np.dot(a, b)
    rx = an1 * math.cos(angle) - an2 * math.sin(angle)
    ry = an1 * math.sin(angle) + an2 * math.cos(angle)
    if rx <= 1e-12:
        return np.eye(3)
    alpha = 0.0 if an1 == 0.0 else (ry / rx - an2 / an1)
    return np.eye(3) + alpha * np.outer(b, a1)


def _int_attr(element, name):
    if element is None or element.get(name) is None:
        return None
    try:
        return int(element.get(name).strip())
    except ValueError:
        return None


# -- reading ------------------------------------------------------------------------------


def parse_bytes(data: bytes, path: str = "<bytes>") -> Document:
    """Read COLLADA from *data*; raises ColladaError for what is not COLLADA XML."""
    xmlsafe.refuse_entities(data, path, ColladaError)
    try:
        parser = ET.XMLParser()
        parser.feed(data)
        root = parser.close()
    except ET.ParseError as error:
        raise ColladaError(path, f"not well-formed XML ({error})") from None
    _strip_namespaces(root)
    if root.tag != "COLLADA":
        raise ColladaError(path, f"not a COLLADA file (its root element is <{root.tag}>)")
    doc = Document(path, version=root.get("version", "1.4.1"))
    reader = _Reader(doc, root)
    reader.asset()
    for element in root.iter("material"):
        if element.get("id") is None and element.get("name") is None:
            continue
        material = reader.material(element)
        doc.materials.setdefault(material.id or material.name, material)
    lights = list(root.iter("light"))
    defined = {e.get("id") for e in lights if e.find("technique_common") is not None}
    for element in lights:
        if element.find("technique_common") is None and element.get("id") in defined:
            continue    # an empty twin of a light defined elsewhere (Maya's exporter)
        light = reader.light(element)
        if light is not None:
            doc.lights.setdefault(light.id or light.name, light)
    for element in root.iter("camera"):
        camera = reader.camera(element)
        if camera is not None:
            doc.cameras.setdefault(camera.id or camera.name, camera)
    for element in root.iter("geometry"):
        mesh = reader.mesh(element)
        if mesh is not None:
            doc.meshes.setdefault(mesh.id or mesh.name, mesh)
    for lib in root.findall("library_nodes"):
        for element in lib.findall("node"):
            node = reader.node(element)
            doc.library_nodes.setdefault(node.id, node)
    scenes = {s.get("id"): s for s in root.iter("visual_scene")}
    chosen = None
    inst = root.find("scene/instance_visual_scene")
    if inst is not None:
        chosen = scenes.get(_ref(inst.get("url")))
        if chosen is None:
            doc.warn(f"<instance_visual_scene url=\"{inst.get('url')}\"> not found; "
                     "the first visual scene read")
    if chosen is None and scenes:
        chosen = next(iter(scenes.values()))
    if chosen is not None:
        doc.scene_name = chosen.get("name") or chosen.get("id") or ""
        doc.nodes = [reader.node(n) for n in chosen.findall("node")]
    if reader.commas:
        places = list(dict.fromkeys(reader.commas))
        more = f" and {len(places) - 3} more" if len(places) > 3 else ""
        doc.warn(f"decimal commas read as decimal points ({', '.join(places[:3])}{more})")
    return doc


def load(path: str) -> Document:
    """Read the COLLADA file *path*; raises ColladaError for a missing file or one that is
    not COLLADA XML (everything else: ``Document.warnings``)."""
    try:
        size = os.path.getsize(path)
        if size > MAX_BYTES:
            raise ColladaError(path, f"{size} bytes: larger than {MAX_BYTES} bytes; refused")
        with open(path, "rb") as handle:
            data = handle.read()
    except OSError as error:
        raise ColladaError(path, error.strerror or str(error)) from None
    return parse_bytes(data, path)
