# SPDX-License-Identifier: GPL-3.0-or-later
"""The scene graph: a ``<node>`` into a :class:`~.model.Node` (its transform elements
multiplied in order, its child nodes, its instances of geometry, controllers, lights, cameras
and nodes with their material bindings), and the matrices of the transform elements
(:func:`transform`: matrix, translate, rotate, scale, lookat, skew).  Each function is
handed the reading context (``context._Reading``).
"""

from __future__ import annotations

import math

import numpy as np

from .model import Instance, Node
from .context import _name, _ref
from .numbers import floats


TRANSFORMS = ("matrix", "translate", "rotate", "scale", "lookat", "skew")


def transform(ctx, element, where):
    """The 4x4 matrix of one transform element (None for other elements)."""
    tag = element.tag
    if tag not in TRANSFORMS:
        return None
    sizes = {"matrix": 16, "translate": 3, "rotate": 4, "scale": 3, "lookat": 9, "skew": 7}
    values = floats(ctx, element, f"{where}: <{tag}>")
    if values is None or len(values) < sizes[tag]:
        ctx.doc.warn(f"{where}: <{tag}> with fewer than {sizes[tag]} numbers; left out")
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


def read_node(ctx, element, depth=0):
    ident = element.get("id", "")
    name = _name(element, ident) or element.get("sid") or "node"
    matrix = np.eye(4)
    for child in element:
        local = transform(ctx, child, f"node {name}")
        if local is not None:
            matrix = matrix @ local
    out = Node(ident, name, matrix)
    if depth > 256:
        ctx.doc.warn(f"node {name}: nested more than 256 deep; the rest left out")
        return out
    for child in element:
        tag = child.tag
        if tag == "node":
            out.children.append(read_node(ctx, child, depth + 1))
        elif tag in ("instance_geometry", "instance_light", "instance_camera",
                     "instance_node", "instance_controller"):
            kind = tag.removeprefix("instance_")
            inst = Instance(kind, _ref(child.get("url")))
            if kind == "controller":
                ctx.doc.warn(f"node {name}: <instance_controller> (skinning) imported as "
                             "its skin's mesh at rest")
                controller = ctx.ids.get(inst.url)
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
