# SPDX-License-Identifier: GPL-3.0-or-later
"""Geometry: a ``<geometry>``'s ``<mesh>`` into a :class:`~.model.Mesh` (its sources, every
kind of primitive, lines as edges), every index checked against its source.  Each function is
handed the reading context (``context._Reading``).
"""

from __future__ import annotations

import numpy as np

from ..xmlsafe import local as _local
from .model import MAX_INDICES, Mesh
from .context import _int_attr, _name, _ref
from .numbers import floats, ints


def read_source(ctx, ident, where):
    """(values (count, stride) of the source *ident*, stride) or None."""
    element = ctx.ids.get(_ref(ident))
    if element is None or element.tag != "source":
        ctx.doc.warn(f"{where}: source {ident} not found; left out")
        return None
    array = element.find("float_array")
    accessor = element.find("technique_common/accessor")
    values = floats(ctx, array, f"{where}: source {element.get('id')}",
                         _int_attr(array, "count")) if array is not None else None
    if values is None:
        if array is None:
            ctx.doc.warn(f"{where}: source {element.get('id')} has no float_array; left out")
        return None
    stride = _int_attr(accessor, "stride") or 1
    offset = _int_attr(accessor, "offset") or 0
    if accessor is not None and accessor.get("source") and \
            _ref(accessor.get("source")) not in (array.get("id"), None) and \
            ctx.ids.get(_ref(accessor.get("source"))) is not None:
        other = ctx.ids[_ref(accessor.get("source"))]
        if other.tag == "float_array":
            values = floats(ctx, other, f"{where}: {other.get('id')}")
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


def read_mesh(ctx, geometry):
    ident = geometry.get("id", "")
    name = _name(geometry, ident)
    where = f"geometry {name}"
    mesh = geometry.find("mesh")
    if mesh is None:
        kinds = [_local(c.tag) for c in geometry if _local(c.tag) not in ("asset", "extra")]
        ctx.doc.warn(f"{where}: {', '.join(kinds) or 'nothing'} (not a <mesh>); left out")
        return None
    vertices = mesh.find("vertices")
    positions, vertex_extra = None, {}
    if vertices is not None:
        for inp in vertices.findall("input"):
            semantic = (inp.get("semantic") or "").upper()
            got = read_source(ctx, inp.get("source"), where)
            if got is None:
                continue
            if semantic == "POSITION":
                positions = got[0]
            else:
                vertex_extra[semantic] = got[0]
    if positions is not None and len(positions) == 0:
        positions = np.zeros((0, 3))
    if positions is not None and positions.shape[1] == 2:
        ctx.doc.warn(f"{where}: 2D positions read with z = 0")
        positions = np.hstack([positions, np.zeros((len(positions), 1))])
    if positions is None or positions.shape[1] < 3:
        ctx.doc.warn(f"{where}: no positions; left out")
        return None
    positions = positions[:, :3].copy()
    acc = {"sizes": [], "face_symbols": [], "symbols": [], "corners": [], "normals": [],
           "uvs": {}, "colors": {}, "n_corners": 0, "has_normals": False, "edges": []}
    for prim in mesh:
        kind = prim.tag
        if kind in ("lines", "linestrips"):
            lines(ctx, prim, kind, positions, acc, where)
            continue
        if kind not in ("triangles", "polylist", "polygons", "tristrips", "trifans"):
            continue
        primitive(ctx, prim, kind, positions, vertex_extra, acc, where)
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


def lines(ctx, prim, kind, positions, acc, where):
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
            ctx.doc.warn(f"{label}: an input's offset is not a number; left out")
            return
    vertex = [offset for semantic, offset in offsets if semantic == "VERTEX"]
    if not vertex:
        ctx.doc.warn(f"{label}: no VERTEX input; left out")
        return
    stride = max(offset for _semantic, offset in offsets) + 1
    if stride > 64:
        ctx.doc.warn(f"{label}: {stride} index offsets; left out")
        return
    strips = []
    for p in prim.findall("p"):
        values = ints(ctx, p, label)
        if values is None:
            return
        strips.append(values[:len(values) - len(values) % stride].reshape(-1, stride)
                      [:, vertex[0]])
    if sum(len(v) for v in strips) > MAX_INDICES:
        ctx.doc.warn(f"{label}: more than {MAX_INDICES} indices; left out")
        return
    if kind == "lines":
        points = np.concatenate(strips) if strips else np.zeros(0, np.int64)
        pairs = points[:len(points) - len(points) % 2].reshape(-1, 2)
    else:
        pairs = np.concatenate([np.stack([v[:-1], v[1:]], axis=1) for v in strips
                                if len(v) >= 2] or [np.zeros((0, 2), np.int64)])
    outside = np.any((pairs < 0) | (pairs >= len(positions)), axis=1)
    if np.any(outside):
        ctx.doc.warn(f"{label}: {int(outside.sum())} line(s) with position indices out "
                     "of range left out")
    pairs = pairs[~outside & (pairs[:, 0] != pairs[:, 1])]
    if not len(pairs):
        return
    acc["edges"].append(pairs)
    if symbol and symbol not in acc["symbols"]:
        acc["symbols"].append(symbol)


def primitive(ctx, prim, kind, positions, vertex_extra, acc, where):
    symbol = prim.get("material", "")
    label = f"{where}: <{kind} material=\"{symbol}\">"
    inputs = []
    for inp in prim.findall("input"):
        try:
            offset = int(inp.get("offset", "0"))
            channel = int(inp.get("set", "0") or 0)
        except ValueError:
            ctx.doc.warn(f"{label}: an input's offset or set is not a number; left out")
            continue
        inputs.append(((inp.get("semantic") or "").upper(), inp.get("source"), offset, channel))
    vertex = [i for i in inputs if i[0] == "VERTEX"]
    if not vertex:
        ctx.doc.warn(f"{label}: no VERTEX input; left out")
        return
    stride = max(i[2] for i in inputs) + 1
    if stride > 64:
        ctx.doc.warn(f"{label}: {stride} index offsets; left out")
        return
    # index lists: one per polygon (polygons), strip/fan, or the whole <p>
    lists = []
    for p in prim.findall("p"):
        values = ints(ctx, p, label)
        if values is None:
            return
        lists.append(values)
    if prim.findall("ph"):
        ctx.doc.warn(f"{label}: polygons with holes (<ph>) imported without their holes")
        for ph in prim.findall("ph"):
            values = ints(ctx, ph.find("p"), label)
            if values is not None:
                lists.append(values)
    if sum(len(v) for v in lists) > MAX_INDICES:
        ctx.doc.warn(f"{label}: more than {MAX_INDICES} indices; left out")
        return
    if not lists:
        return
    lists = [v[:len(v) - len(v) % stride].reshape(-1, stride) for v in lists]
    if kind == "triangles":
        rows = np.concatenate(lists)
        rows = rows[:len(rows) - len(rows) % 3]
        sizes = np.full(len(rows) // 3, 3, np.int64)
    elif kind == "polylist":
        vcount = ints(ctx, prim.find("vcount"), label) if prim.find("vcount") is not None \
            else None
        rows = np.concatenate(lists)
        if vcount is None or np.any(vcount < 0) or vcount.sum() > len(rows):
            ctx.doc.warn(f"{label}: <vcount> does not match <p>; left out")
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
        ctx.doc.warn(f"{label}: {int((~keep).sum())} face(s) with fewer than 3 corners "
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
        got = read_source(ctx, source, label)
        if got is None:
            continue
        sources[(semantic, channel, offset)] = got[0]
    bad = (position_index < 0) | (position_index >= len(positions))
    if np.any(bad):
        face_of = np.repeat(np.arange(len(sizes)), sizes)
        bad_faces = np.unique(face_of[bad])
        ctx.doc.warn(f"{label}: {len(bad_faces)} face(s) with position indices out of "
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
        ctx.doc.warn(f"{label}: indices out of range for {', '.join(missing)} corner "
                     "value(s); those values left out (zero normal, UV (0, 0), white)")
