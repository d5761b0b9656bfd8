# SPDX-License-Identifier: GPL-3.0-or-later
"""Geometry: the tessellation of the primitives (:data:`SEGMENTS` around), the Extrusion of
the standards (:func:`extrude`, :func:`triangulate_polygon`, :func:`crease_normals`), and
the geometry nodes (:func:`geometry_node`: face sets, triangle sets, ElevationGrid, line and
point sets, primitives, Extrusion and Text) into :class:`~.model.Mesh`, each function handed
the reading context (:class:`~.context._Reading`: its notes, its caches of arrays and
tessellations).
"""

from __future__ import annotations

import math

import numpy as np

from .numeric import _rotation3
from .model import Mesh
from .graph import _N, _PRIMITIVES
from .fields import (
    angle, flag, ints, node_value, node_values, num, numbers, string, strings, type_of, vec,
    where)
from .protos import lookup


#: Segments around a tessellated Sphere, Cylinder or Cone (a Sphere has half as many rings).
SEGMENTS = 32
#: An Extrusion of more spine × crossSection points is left out (a warning); a convex FALSE
#: cap of more points is one polygon (Blender fills it) rather than triangulated.
MAX_EXTRUSION_POINTS = 2_000_000
MAX_CAP_TRIANGULATION = 20_000


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


# the geometry nodes -------------------------------------------------------------------

def data_node(ctx, n, name, types):
    found = lookup(ctx, node_value(ctx, n, name))
    if found is None:
        return None
    t = type_of(ctx, found)
    if t not in types:
        ctx.notes.add("nodes where the standard allows none of their type: left out",
                      f"{t or found.type} as {name}")
        return None
    return found


def array(ctx, n, name, types, field_name, width):
    """The (k, width) values of a data node (Coordinate, Color, Normal ...), cached per
    node so that a USE'd Coordinate is read once."""
    node = data_node(ctx, n, name, types)
    if node is None:
        return None, None
    key = (id(node), field_name)
    if key in ctx.arrays:
        return ctx.arrays[key][1], node
    t = type_of(ctx, node)
    if t == "ColorRGBA":
        width = 4
    values = numbers(ctx, node, field_name)
    if values is None:
        values = np.zeros(0)
    if len(values) % width:
        ctx.notes.add("lists whose length is not a multiple of their tuple size: the "
                      "rest left out", where(node, field_name))
        values = values[:len(values) - len(values) % width]
    values = values.reshape(-1, width)
    if t == "Color":
        values = np.concatenate([values, np.ones((len(values), 1))], axis=1)
    ctx.arrays[key] = (node, values)
    return values, node


def coords_of(ctx, n):
    points, node = array(ctx, n, "coord", ("Coordinate", "CoordinateDouble"), "point", 3)
    if points is None:
        found = lookup(ctx, node_value(ctx, n, "coord"))
        if found is not None and type_of(ctx, found) == "GeoCoordinate":
            ctx.notes.add("GeoCoordinate not read", found.name or None)
        return np.zeros((0, 3))
    return points


def colors_of(ctx, n):
    return array(ctx, n, "color", ("Color", "ColorRGBA"), "color", 3)[0]


def normals_of(ctx, n):
    return array(ctx, n, "normal", ("Normal",), "vector", 3)[0]


def texcoords_of(ctx, n):
    found = lookup(ctx, node_value(ctx, n, "texCoord"))
    if found is not None and type_of(ctx, found) == "MultiTextureCoordinate":
        ctx.notes.add("MultiTextureCoordinate read as its first set", found.name or None)
        first = next(iter(node_values(ctx, found, "texCoord")), None)
        holder = _N("Shape", src=found.src)
        holder.fields["texCoord"] = first
        return array(ctx, holder, "texCoord", ("TextureCoordinate",), "point", 2)[0]
    if found is not None and type_of(ctx, found) == "TextureCoordinateGenerator":
        ctx.notes.add("TextureCoordinateGenerator not read: no texture coordinates",
                      found.name or None)
        return None
    return array(ctx, n, "texCoord", ("TextureCoordinate",), "point", 2)[0]


def geometry_node(ctx, n, t, hint):
    mesh = Mesh(name=n.name or hint or t, kind=t)
    if t in _PRIMITIVES:
        primitive(ctx, n, t, mesh)
        return mesh
    mesh.solid = flag(ctx, n, "solid", True)
    mesh.ccw = flag(ctx, n, "ccw", True)
    if t == "IndexedFaceSet":
        face_set(ctx, n, mesh)
    elif t == "ElevationGrid":
        elevation_grid(ctx, n, mesh)
    elif t == "Extrusion":
        extrusion(ctx, n, mesh)
    elif t == "Text":
        text(ctx, n, mesh)
    elif t in ("IndexedLineSet", "LineSet"):
        line_set(ctx, n, t, mesh)
    elif t == "PointSet":
        mesh.positions = coords_of(ctx, n)
        colors = colors_of(ctx, n)
        if colors is not None and len(colors) >= len(mesh.positions):
            mesh.point_colors = colors[:len(mesh.positions)]
        elif colors is not None:
            ctx.notes.add("colours fewer than their points: left out", mesh.name)
    else:
        triangle_set(ctx, n, t, mesh)
    return mesh


def attribute(ctx, values, index, per_vertex, faces, what, mesh):
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
                ctx.notes.add(f"{what} left out: their index is shorter than coordIndex",
                              mesh.name)
                return None
            idx = index[at]
        else:
            idx = corners
    else:
        if len(index):
            if len(index) <= face_no.max():
                ctx.notes.add(f"{what} left out: their index has fewer entries than faces",
                              mesh.name)
                return None
            idx = np.repeat(index[face_no], sizes)
        else:
            idx = np.repeat(face_no, sizes)
    if idx.min() < 0 or idx.max() >= len(values):
        ctx.notes.add(f"{what} left out: an index is out of range", mesh.name)
        return None
    return values[idx]


def face_set(ctx, n, mesh):
    positions = coords_of(ctx, n)
    mesh.positions = positions
    mesh.convex = flag(ctx, n, "convex", True)
    mesh.crease_angle = angle(ctx, n, "creaseAngle", 0.0)
    mesh.color_per_vertex = flag(ctx, n, "colorPerVertex", True)
    mesh.normal_per_vertex = flag(ctx, n, "normalPerVertex", True)
    index = ints(ctx, n, "coordIndex")
    faces = polygons(ctx, index, len(positions), mesh)
    mesh.face_sizes, mesh.corners = faces[0], faces[1]
    mesh.normals = attribute(ctx, normals_of(ctx, n), ints(ctx, n, "normalIndex"),
                                  mesh.normal_per_vertex, faces, "normals", mesh)
    mesh.colors = attribute(ctx, colors_of(ctx, n), ints(ctx, n, "colorIndex"),
                                 mesh.color_per_vertex, faces, "colours", mesh)
    mesh.uvs = attribute(ctx, texcoords_of(ctx, n), ints(ctx, n, "texCoordIndex"), True, faces,
                              "texture coordinates", mesh)


def polygons(ctx, index, count, mesh, smallest=3):
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
        ctx.notes.add(f"faces or lines with fewer than {smallest} indices: left out",
                      mesh.name, int(small.sum()))
    if (outside & ~small).any():
        ctx.notes.add("faces or lines with a coordinate index out of range: left out",
                      mesh.name, int((outside & ~small).sum()))
    keep = ~(small | outside)
    if keep.all():
        return sizes, corners, valid, np.arange(len(sizes))
    corner_keep = np.repeat(keep, sizes)
    return sizes[keep], corners[corner_keep], valid[corner_keep], np.flatnonzero(keep)


def triangle_set(ctx, n, t, mesh):
    """IndexedTriangleSet, TriangleSet, the fan and strip sets, IndexedQuadSet, QuadSet:
    faces of one index into coord, color, normal and texCoord alike; per-face values are
    one a triangle (or quad)."""
    positions = coords_of(ctx, n)
    mesh.positions = positions
    mesh.color_per_vertex = flag(ctx, n, "colorPerVertex", True)
    mesh.normal_per_vertex = flag(ctx, n, "normalPerVertex", True)
    indexed = t.startswith("Indexed")
    index = ints(ctx, n, "index") if indexed else np.arange(len(positions), dtype=np.int64)
    width = 4 if "Quad" in t else 3
    if t in ("IndexedTriangleSet", "TriangleSet", "IndexedQuadSet", "QuadSet"):
        usable = len(index) - len(index) % width
        if usable != len(index):
            ctx.notes.add("index lists whose length is not a multiple of their face size: "
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
            counts = ints(ctx, n, "fanCount" if fan else "stripCount")
            sequence = index
            if counts.sum() > len(sequence) or (counts < 0).any():
                ctx.notes.add("fan or strip counts beyond their coordinates: the rest "
                              "left out", mesh.name)
                counts = np.clip(counts, 0, None)
                ends = np.cumsum(counts)
                counts = counts[ends <= len(sequence)]
            starts = np.r_[0, np.cumsum(counts)[:-1]].astype(np.int64) if len(counts) \
                else np.zeros(0, np.int64)
        if (counts < 3).any():
            ctx.notes.add("fans or strips of fewer than 3 vertices: left out", mesh.name)
            keep = counts >= 3
            starts, counts = starts[keep], counts[keep]
        faces = _fans(sequence, starts, counts) if fan else _strips(sequence, starts, counts)
    face_no = np.arange(len(faces))
    if len(faces):
        bad = (faces >= len(positions)).any(axis=1) | (faces < 0).any(axis=1)
        if bad.any():
            ctx.notes.add("faces or lines with a coordinate index out of range: left out",
                          mesh.name, int(bad.sum()))
            faces, face_no = faces[~bad], face_no[~bad]
    mesh.face_sizes = np.full(len(faces), faces.shape[1] if faces.ndim == 2 else 3, np.int64)
    mesh.corners = faces.reshape(-1).astype(np.int64)
    info = (mesh.face_sizes, mesh.corners, np.zeros(0, np.int64), face_no)
    empty = np.zeros(0, np.int64)
    mesh.normals = attribute(ctx, normals_of(ctx, n), empty, mesh.normal_per_vertex, info,
                                  "normals", mesh)
    mesh.colors = attribute(ctx, colors_of(ctx, n), empty, mesh.color_per_vertex, info,
                                 "colours", mesh)
    mesh.uvs = attribute(ctx, texcoords_of(ctx, n), empty, True, info, "texture coordinates",
                              mesh)


def elevation_grid(ctx, n, mesh):
    nx, nz = int(num(ctx, n, "xDimension", 0)), int(num(ctx, n, "zDimension", 0))
    dx, dz = num(ctx, n, "xSpacing", 1.0), num(ctx, n, "zSpacing", 1.0)
    heights = numbers(ctx, n, "height")
    mesh.crease_angle = angle(ctx, n, "creaseAngle", 0.0)
    mesh.color_per_vertex = flag(ctx, n, "colorPerVertex", True)
    mesh.normal_per_vertex = flag(ctx, n, "normalPerVertex", True)
    mesh.primitive = {"xDimension": nx, "zDimension": nz, "xSpacing": dx, "zSpacing": dz}
    if nx < 2 or nz < 2 or nx * nz > 50_000_000 or heights is None \
            or len(heights) < nx * nz:
        if nx * nz:
            ctx.notes.add("ElevationGrids whose heights do not fill the grid: left out",
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
    mesh.normals = attribute(ctx, normals_of(ctx, n), empty, mesh.normal_per_vertex, info,
                                  "normals", mesh)
    mesh.colors = attribute(ctx, colors_of(ctx, n), empty, mesh.color_per_vertex, info,
                                 "colours", mesh)
    uvs = texcoords_of(ctx, n)
    if uvs is None:     # the standard's default: s along x, t along z, 0 to 1
        uvs = np.stack([i.ravel() / (nx - 1), j.ravel() / (nz - 1)], axis=1)
    mesh.uvs = attribute(ctx, uvs, empty, True, info, "texture coordinates", mesh)


def line_set(ctx, n, t, mesh):
    positions = coords_of(ctx, n)
    mesh.positions = positions
    mesh.color_per_vertex = flag(ctx, n, "colorPerVertex", True)
    if t == "IndexedLineSet":
        index = ints(ctx, n, "coordIndex")
    else:
        counts = ints(ctx, n, "vertexCount")
        counts = counts[(counts >= 0) & (np.cumsum(np.clip(counts, 0, None)) <= len(positions))]
        index = np.full(int(counts.sum()) + len(counts), -1, np.int64)
        starts = np.r_[0, np.cumsum(counts + 1)[:-1]].astype(np.int64) if len(counts) else \
            np.zeros(0, np.int64)
        offsets = np.r_[0, np.cumsum(counts)[:-1]].astype(np.int64) if len(counts) else \
            np.zeros(0, np.int64)
        within = np.arange(int(counts.sum())) - np.repeat(offsets, counts)
        index[np.repeat(starts, counts) + within] = np.repeat(offsets, counts) + within
    sizes, corners, _at, _face_no = polygons(ctx, index, len(positions), mesh, smallest=2)
    if len(sizes):
        ends = np.cumsum(sizes)
        first = np.arange(len(corners) - 1)
        keep = np.ones(len(first), bool)
        keep[ends[:-1] - 1] = False
        mesh.edges = np.stack([corners[first[keep]], corners[first[keep] + 1]], axis=1)
    else:
        mesh.edges = np.zeros((0, 2), np.int64)
    colors = colors_of(ctx, n)
    if colors is not None:
        if mesh.color_per_vertex and not len(ints(ctx, n, "colorIndex")) \
                and len(colors) >= len(positions):
            mesh.point_colors = colors[:len(positions)]
        else:
            ctx.notes.add("line colours given per line or by colorIndex: left out",
                          mesh.name)


def primitive(ctx, n, t, mesh):
    if t == "Box":
        p = {"size": vec(ctx, n, "size", (2.0, 2.0, 2.0))}
    elif t == "Sphere":
        p = {"radius": num(ctx, n, "radius", 1.0)}
    elif t == "Cylinder":
        p = {"radius": num(ctx, n, "radius", 1.0), "height": num(ctx, n, "height", 2.0),
             "top": flag(ctx, n, "top", True), "bottom": flag(ctx, n, "bottom", True),
             "side": flag(ctx, n, "side", True)}
    else:
        p = {"bottomRadius": num(ctx, n, "bottomRadius", 1.0),
             "height": num(ctx, n, "height", 2.0), "side": flag(ctx, n, "side", True),
             "bottom": flag(ctx, n, "bottom", True)}
    mesh.primitive = p
    key = (t,) + tuple(p.values())
    parts = ctx.tessellated.get(key)
    if parts is None:       # equal primitives share their (read-only) arrays
        maker = {"Box": _box, "Sphere": _sphere, "Cylinder": _cylinder, "Cone": _cone}[t]
        parts = maker(*p.values())
        ctx.tessellated[key] = parts
    mesh.positions, mesh.face_sizes, mesh.corners, mesh.normals, mesh.uvs = parts
    mesh.solid = flag(ctx, n, "solid", True)
    mesh.crease_angle = 0.5     # smooth sides, sharp edges (the normals are given anyway)


def extrusion(ctx, n, mesh):
    """Extrusion: its faces by :func:`extrude` (ISO/IEC 14772-1 §6.18), smoothed by
    creaseAngle, with the standard's texture coordinates."""
    def pairs(name, width, default):
        values = numbers(ctx, n, name)
        if values is None:
            return np.asarray(default, dtype=np.float64).reshape(-1, width)
        if len(values) % width:
            ctx.notes.add("lists whose length is not a multiple of their tuple size: the "
                          "rest left out", where(n, name))
        return values[:len(values) - len(values) % width].reshape(-1, width)

    spine = pairs("spine", 3, [(0.0, 0.0, 0.0), (0.0, 1.0, 0.0)])
    cross = pairs("crossSection", 2, [(1, 1), (1, -1), (-1, -1), (-1, 1), (1, 1)])
    scales = pairs("scale", 2, [(1.0, 1.0)])
    orientations = pairs("orientation", 4, [(0.0, 0.0, 1.0, 0.0)]).copy()
    orientations[:, 3] *= n.src.angle if n.src is not None else 1.0
    mesh.convex = flag(ctx, n, "convex", True)
    mesh.crease_angle = angle(ctx, n, "creaseAngle", 0.0)
    made = extrude(spine, cross, scales, orientations, flag(ctx, n, "beginCap", True),
                   flag(ctx, n, "endCap", True), mesh.convex)
    for line in made["warnings"]:
        ctx.notes.add(line, mesh.name)
    mesh.positions, mesh.face_sizes = made["positions"], made["face_sizes"]
    mesh.corners, mesh.uvs = made["corners"], made["uvs"]
    if mesh.crease_angle > 0 and len(mesh.corners):   # flat without: Blender's faces
        normals = crease_normals(mesh.positions, mesh.face_sizes, mesh.corners,
                                 mesh.crease_angle)
        mesh.normals = normals if mesh.ccw else -normals


def text(ctx, n, mesh):
    """Text: its strings and FontStyle as plain data in ``mesh.text`` (no faces here: the
    Blender side sets the text in its font).  Keys: strings, length (per string, 0: its
    natural length), max_extent, solid, and the FontStyle's family (list), style, size,
    spacing, justify (major, minor), horizontal, left_to_right, top_to_bottom,
    language."""
    style = lookup(ctx, node_value(ctx, n, "fontStyle"))
    if style is not None and type_of(ctx, style) != "FontStyle":
        ctx.notes.add("Text fontStyle that is not a FontStyle: defaults used",
                      style.name or style.type)
        style = None
    lengths = numbers(ctx, n, "length")
    font = {"family": ["SERIF"], "style": "PLAIN", "size": 1.0, "spacing": 1.0,
            "justify": ["BEGIN", "FIRST"], "horizontal": True, "left_to_right": True,
            "top_to_bottom": True, "language": ""}
    if style is not None:
        font.update(
            family=strings(ctx, style, "family") or ["SERIF"],
            style=string(ctx, style, "style", "PLAIN") or "PLAIN",
            size=num(ctx, style, "size", 1.0), spacing=num(ctx, style, "spacing", 1.0),
            justify=strings(ctx, style, "justify") or ["BEGIN"],
            horizontal=flag(ctx, style, "horizontal", True),
            left_to_right=flag(ctx, style, "leftToRight", True),
            top_to_bottom=flag(ctx, style, "topToBottom", True),
            language=string(ctx, style, "language", ""))
    words = [str(word).strip().upper() for word in font["justify"][:2]]
    font["justify"] = (words[0] if words and words[0] else "BEGIN",
                       words[1] if len(words) > 1 and words[1] else "FIRST")
    mesh.text = dict(font, strings=strings(ctx, n, "string"),
                     length=[float(v) for v in lengths] if lengths is not None else [],
                     max_extent=num(ctx, n, "maxExtent", 0.0),
                     solid=flag(ctx, n, "solid", False))
