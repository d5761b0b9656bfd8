# SPDX-License-Identifier: GPL-3.0-or-later
"""Extrusion and Text read by ``core/x3d.py`` (issue 42; no bpy).

Extrusion (ISO/IEC 14772-1 §6.18, 19775-1 §13.3.5): positions of small files worked out by
hand in each test (the spine-aligned cross-section plane of a straight, a bent, a zig-zag, a
closed and a collinear spine; scale and orientation; caps present or absent; a concave cap;
texture coordinates), and the Web3D archive's ExtrusionHeart.x3d (tests/data/x3d, origin in
tests/data/README.md) with counts read from the file.  Text: the strings and FontStyle as read.
"""

from __future__ import annotations

import math
import os
import re
import time

import numpy as np
import pytest

from phong_nodes.core import x3d

DATA = os.path.join(os.path.dirname(os.path.abspath(__file__)), "data", "x3d")
X3DV = "#X3D V3.3 utf8\nPROFILE Immersive\n"
R = 1.0 / math.sqrt(2.0)
SQUARE = "crossSection [1 1, 1 -1, -1 -1, -1 1, 1 1]"


def only_mesh(text):
    doc = x3d.loads(text, "/nonexistent-folder/scene.x3dv")
    assert len(doc.instances) == 1, doc.warnings
    return doc, doc.instances[0].shape.geometry


def ring(mesh, index, count):
    """The positions of spine point *index* (no coincident points: positions are in order)."""
    return mesh.positions[index * count:(index + 1) * count]


def faces(mesh):
    ends = np.cumsum(mesh.face_sizes)
    return [mesh.corners[e - s:e].tolist() for s, e in zip(mesh.face_sizes, ends)]


def test_straight_spine_with_scale_and_one_orientation():
    """Spine along +Y: the SCP is the file's axes.  orientation 0 1 0 90° (one value: every
    spine point) turns (x, 0, z) into (z, 0, −x) after the scale; the second spine point's
    scale (0.5, 2) comes first."""
    _, mesh = only_mesh(X3DV + f"""Shape {{ geometry Extrusion {{
        spine [0 0 0, 0 2 0] {SQUARE} scale [1 1, 0.5 2] orientation 0 1 0 1.5707963267948966
    }} }}""")
    assert mesh.kind == "Extrusion" and mesh.ccw and mesh.solid and mesh.convex
    expected_0 = [(1, 0, -1), (-1, 0, -1), (-1, 0, 1), (1, 0, 1)]
    # (0.5·x, 2·z) turned: (2z, 0, −0.5x), + (0, 2, 0)
    expected_1 = [(2, 2, -0.5), (-2, 2, -0.5), (-2, 2, 0.5), (2, 2, 0.5)]
    assert len(mesh.positions) == 8     # the closed cross-section's last point is its first
    np.testing.assert_allclose(ring(mesh, 0, 4), expected_0, atol=1e-12)
    np.testing.assert_allclose(ring(mesh, 1, 4), expected_1, atol=1e-12)
    # 4 sides, a begin cap (reversed: facing −Y) and an end cap
    assert faces(mesh) == [[0, 1, 5, 4], [1, 2, 6, 5], [2, 3, 7, 6], [3, 0, 4, 7],
                           [3, 2, 1, 0], [4, 5, 6, 7]]
    # texture coordinates: u along the cross-section (4 sides of length 2), v along the spine;
    # caps: (x, z) of the cross-section over its 2 × 2 bounding box
    uvs = mesh.uvs.reshape(-1, 2)
    np.testing.assert_allclose(uvs[:4], [(0, 0), (0.25, 0), (0.25, 1), (0, 1)])
    np.testing.assert_allclose(uvs[12:16], [(0.75, 0), (1, 0), (1, 1), (0.75, 1)])
    cap_end = uvs[20:24]      # cross-section points (1,1), (1,-1), (-1,-1), (-1,1)
    np.testing.assert_allclose(cap_end, [(1, 1), (1, 0), (0, 0), (0, 1)])
    cap_begin = uvs[16:20]    # reversed: (-1,1), (-1,-1), (1,-1), (1,1)
    np.testing.assert_allclose(cap_begin, [(0, 1), (0, 0), (1, 0), (1, 1)])


def test_the_outward_faces_of_the_default_box_and_ccw_false_flips_them():
    """The standard's default Extrusion is a 2 × 1 × 2 box from y = 0 to 1: each face's
    normal (Newell's) points away from its centre; ccw FALSE turns every one inward."""
    for ccw, sign in (("TRUE", 1.0), ("FALSE", -1.0)):
        _, mesh = only_mesh(X3DV + f"Shape {{ geometry Extrusion {{ ccw {ccw} }} }}")
        mesh = x3d.counter_clockwise(mesh)
        centre = np.array([0.0, 0.5, 0.0])
        assert len(mesh.face_sizes) == 6
        for face in faces(mesh):
            p = mesh.positions[face]
            normal = np.cross(p[1] - p[0], p[2] - p[0])
            outward = p.mean(axis=0) - centre
            assert sign * np.dot(normal, outward) > 0, (ccw, face)


def test_crease_angle_gives_corner_normals_of_the_faces_within_it():
    """The default box with creaseAngle 3.14: at its point (1 1 1) (spine point 1, cross-
    section point 0) meet the side x = 1 (quad 0 1 5 4: the point is its 4th corner, in one
    triangle of its fan), the side z = 1 (quad 3 0 4 7: 3rd corner, two triangles) and the end
    cap (4 5 6 7: 1st corner, two triangles): (1 0 0) + 2 (0 0 1) + 2 (0 1 0) = (1 2 2), /3.
    creaseAngle 1 (under the box's 90°): each corner its own face's normal.  ccw FALSE: the
    same normals turned round (the faces are reversed too)."""
    for ccw, sign in (("TRUE", 1.0), ("FALSE", -1.0)):
        _, mesh = only_mesh(X3DV + f"Shape {{ geometry Extrusion {{ creaseAngle 3.14 ccw {ccw} "
                            "} }")
        at_point = mesh.normals[mesh.corners == 4]
        assert len(at_point) == 3
        np.testing.assert_allclose(at_point, [np.multiply(sign / 3, (1, 2, 2))] * 3,
                                   atol=1e-12)
    _, mesh = only_mesh(X3DV + "Shape { geometry Extrusion { creaseAngle 1 } }")
    per_face = np.repeat([(1, 0, 0), (0, 0, -1), (-1, 0, 0), (0, 0, 1), (0, -1, 0), (0, 1, 0)],
                         4, axis=0)
    np.testing.assert_allclose(mesh.normals, per_face, atol=1e-12)
    # creaseAngle 0 (the default): no normals, flat faces
    _, mesh = only_mesh(X3DV + "Shape { geometry Extrusion { } }")
    assert mesh.normals is None and mesh.crease_angle == 0


def test_caps_present_or_absent():
    counts = {}
    for begin in ("TRUE", "FALSE"):
        for end in ("TRUE", "FALSE"):
            _, mesh = only_mesh(X3DV + f"""Shape {{ geometry Extrusion {{
                spine [0 0 0, 0 1 0, 0 2 0] beginCap {begin} endCap {end} }} }}""")
            counts[begin, end] = (len(mesh.face_sizes), len(mesh.positions))
    # 2 segments × 4 sides = 8, + one face a cap; 3 rings of 4 points
    assert counts == {("TRUE", "TRUE"): (10, 12), ("TRUE", "FALSE"): (9, 12),
                      ("FALSE", "TRUE"): (9, 12), ("FALSE", "FALSE"): (8, 12)}


def test_bent_spine_follows_the_scp_rule():
    """Spine (0 0 0), (0 1 0), (1 1 0): at the corner Y = normalize((1 1 0) − (0 0 0)),
    Z = ((1 1 0) − (0 1 0)) × ((0 0 0) − (0 1 0)) = (1 0 0) × (0 −1 0) = (0 0 −1),
    X = Y × Z = (−1 1 0)/√2; the first point has Y = (0 1 0) and its neighbour's Z, X = (−1 0 0);
    the last Y = (1 0 0), X = (0 1 0).  A point (x, z) goes to spine + x·X + z·Z."""
    _, mesh = only_mesh(X3DV + """Shape { geometry Extrusion {
        spine [0 0 0, 0 1 0, 1 1 0] crossSection [0.5 0.5, 0.5 -0.5, -0.5 -0.5, -0.5 0.5, 0.5 0.5]
        beginCap FALSE endCap FALSE } }""")
    axes = [((0, 0, 0), (-1, 0, 0), (0, 0, -1)),
            ((0, 1, 0), (-R, R, 0), (0, 0, -1)),
            ((1, 1, 0), (0, 1, 0), (0, 0, -1))]
    section = [(0.5, 0.5), (0.5, -0.5), (-0.5, -0.5), (-0.5, 0.5)]
    for index, (spine, x_axis, z_axis) in enumerate(axes):
        expected = [np.add(spine, np.multiply(x, x_axis) + np.multiply(z, z_axis))
                    for x, z in section]
        np.testing.assert_allclose(ring(mesh, index, 4), expected, atol=1e-12)
    assert len(mesh.face_sizes) == 8
    # v runs along the spine's length: 0, 1/2 (the corner), 1
    assert sorted(set(np.round(mesh.uvs[:, 1], 12))) == [0.0, 0.5, 1.0]


def test_a_quad_that_is_not_planar_at_a_bend_is_two_triangles():
    """The bent spine above with a diamond [1 0, 0 −1, −1 0, 0 1]: the first side quad runs
    from (−1 0 0), (0 0 1) (spine point 0, X = (−1 0 0), Z = (0 0 −1)) to (0 1 1),
    (−R 1+R 0) (the corner: X = (−1 1 0)/√2); the plane of its first three points has the
    normal (1 0 1) × (1 1 1) = (−1 0 1), and the fourth point lies (1−R 1+R 0)·(−1 0 1) = R − 1
    off it: split along its first diagonal, as every side quad of this spine (16 triangles)."""
    _, mesh = only_mesh(X3DV + """Shape { geometry Extrusion {
        spine [0 0 0, 0 1 0, 1 1 0] crossSection [1 0, 0 -1, -1 0, 0 1, 1 0] } }""")
    assert mesh.face_sizes.tolist() == [3] * 16 + [4, 4]
    np.testing.assert_allclose(mesh.positions[[0, 1, 5, 4]],
                               [(-1, 0, 0), (0, 0, 1), (0, 1, 1), (-R, 1 + R, 0)], atol=1e-12)
    assert faces(mesh)[:2] == [[0, 1, 5], [0, 5, 4]]


def test_z_flips_where_it_would_point_against_the_previous_one():
    """Spine (0 0 0), (0 1 0), (1 2 0), (1 3 0): Z at point 1 = (1 1 0) × (0 −1 0) = (0 0 −1);
    at point 2 (0 1 0) × (−1 −1 0) = (0 0 1), against the previous one: flipped to (0 0 −1).
    A ribbon crossSection [0 1, 0 −1] lies along Z: its first point at spine + Z."""
    _, mesh = only_mesh(X3DV + """Shape { geometry Extrusion {
        spine [0 0 0, 0 1 0, 1 2 0, 1 3 0] crossSection [0 1, 0 -1] } }""")
    for index, spine in enumerate([(0, 0, 0), (0, 1, 0), (1, 2, 0), (1, 3, 0)]):
        np.testing.assert_allclose(ring(mesh, index, 2),
                                   [np.add(spine, (0, 0, -1)), np.add(spine, (0, 0, 1))],
                                   atol=1e-12)
    assert len(mesh.face_sizes) == 3      # an open cross-section of 2 points has no caps


@pytest.mark.parametrize("spine, x_axis, z_axis", [
    # +Y turned onto +X: a quarter turn about −Z leaves Z; X = (1 0 0) × (0 0 1) = (0 −1 0)
    ("0 0 0, 2 0 0", (0, -1, 0), (0, 0, 1)),
    # +Y turned onto +Z: a quarter turn about +X takes Z to (0 −1 0); X = (0 0 1) × Z = (1 0 0)
    ("0 0 0, 0 0 2", (1, 0, 0), (0, -1, 0)),
    # several collinear points along +Y: the file's axes
    ("0 0 0, 0 1 0, 0 3 0", (1, 0, 0), (0, 0, 1)),
])
def test_a_collinear_spine_turns_the_y0_plane_by_the_rotation_of_y_onto_it(spine, x_axis,
                                                                           z_axis):
    _, mesh = only_mesh(X3DV + f"""Shape {{ geometry Extrusion {{
        spine [{spine}] crossSection [1 0, 0 1, -1 0] }} }}""")
    np.testing.assert_allclose(ring(mesh, 0, 3), [x_axis, z_axis, np.negative(x_axis)],
                               atol=1e-12)


def test_coincident_spine_points_share_their_plane_and_a_wholly_coincident_spine_is_flat():
    """Spine (0 0 0), (0 1 0), (0 1 0), (0 2 0): the two middle points are one ring (their Y
    from their neighbours, (0 1 0)); the sides between them have no area and are left out:
    3 rings of 4 points, 2 × 4 sides and 2 caps.  A spine of one point twice: Y falls back to
    +Y, Z to +Z: the cross-section lies in the Y = 0 plane, its two caps back to back."""
    _, mesh = only_mesh(X3DV + f"""Shape {{ geometry Extrusion {{
        spine [0 0 0, 0 1 0, 0 1 0, 0 2 0] {SQUARE} }} }}""")
    assert (len(mesh.positions), len(mesh.face_sizes)) == (12, 10)
    np.testing.assert_allclose(ring(mesh, 1, 4), [(1, 1, 1), (1, 1, -1), (-1, 1, -1),
                                                  (-1, 1, 1)], atol=1e-12)
    _, mesh = only_mesh(X3DV + f"""Shape {{ geometry Extrusion {{
        spine [0 0 0, 0 0 0] {SQUARE} }} }}""")
    np.testing.assert_allclose(mesh.positions, [(1, 0, 1), (1, 0, -1), (-1, 0, -1),
                                                (-1, 0, 1)], atol=1e-12)
    assert faces(mesh) == [[3, 2, 1, 0], [0, 1, 2, 3]]


def test_a_closed_spine_has_one_plane_at_its_ends_and_shares_their_points():
    """Spine (0 0 0), (2 0 0), (2 0 2), (0 0 2), (0 0 0): closed.  At its ends
    Y = spine[1] − spine[3] = (2 0 −2)/√8, Z = (spine[1] − spine[0]) × (spine[3] − spine[0])
    = (2 0 0) × (0 0 2) = (0 −4 0) → (0 −1 0), X = Y × Z = (−1 0 −1)/√2.  The last ring is the
    first: 4 rings of 4 points, 4 × 4 sides."""
    _, mesh = only_mesh(X3DV + """Shape { geometry Extrusion {
        spine [0 0 0, 2 0 0, 2 0 2, 0 0 2, 0 0 0]
        crossSection [0.1 0.1, 0.1 -0.1, -0.1 -0.1, -0.1 0.1, 0.1 0.1]
        beginCap FALSE endCap FALSE } }""")
    x_axis, z_axis = np.array([-R, 0, -R]), np.array([0.0, -1.0, 0.0])
    expected = [x * x_axis + z * z_axis for x, z in [(0.1, 0.1), (0.1, -0.1), (-0.1, -0.1),
                                                     (-0.1, 0.1)]]
    np.testing.assert_allclose(ring(mesh, 0, 4), expected, atol=1e-12)
    assert len(mesh.positions) == 16 and len(mesh.face_sizes) == 16
    assert mesh.corners.max() == 15        # the last side quads close onto the first ring
    last_sides = faces(mesh)[-4:]
    assert all(set(face) & set(range(4)) for face in last_sides)


def test_a_concave_cross_section_with_convex_false_gets_a_triangulated_cap():
    """An L of area 3: (0 0) (0 2) (1 2) (1 1) (2 1) (2 0), turning as the default square
    does: each cap 4 triangles facing out (−Y, +Y), of total area 3 (no overlap, no gap),
    none over the square (1..2, 1..2) outside the reflex corner."""
    section = [(0, 0), (0, 2), (1, 2), (1, 1), (2, 1), (2, 0), (0, 0)]
    text = " ".join(f"{x} {z}," for x, z in section)
    _, mesh = only_mesh(X3DV + f"""Shape {{ geometry Extrusion {{
        spine [0 0 0, 0 1 0] crossSection [{text}] convex FALSE }} }}""")
    assert not mesh.convex
    sides = 6
    assert len(mesh.face_sizes) == sides + 8 and (mesh.face_sizes[sides:] == 3).all()
    for cap, y, sign in ((faces(mesh)[sides:sides + 4], 0.0, -1.0),
                         (faces(mesh)[sides + 4:], 1.0, 1.0)):
        total = 0.0
        for tri in cap:
            p = mesh.positions[tri]
            assert np.allclose(p[:, 1], y)
            normal = np.cross(p[1] - p[0], p[2] - p[0])     # the cap faces along ∓Y
            assert sign * normal[1] > 0
            total += abs(normal[1]) / 2
            centre = p.mean(axis=0)
            assert not (1 < centre[0] < 2 and 1 < centre[2] < 2)
        assert total == pytest.approx(3.0)
    # the same with convex TRUE: one polygon a cap (Blender fills a concave n-gon)
    _, mesh = only_mesh(X3DV + f"""Shape {{ geometry Extrusion {{
        spine [0 0 0, 0 1 0] crossSection [{text}] }} }}""")
    assert mesh.face_sizes.tolist() == [4] * 6 + [6, 6]


def test_triangulate_polygon_of_a_clockwise_u():
    # a clockwise U: 6 corners, area 3·2 − 1·1 = 5 → 6 triangles of 8 points
    u_shape = [(0, 0), (0, 2), (1, 2), (1, 1), (2, 1), (2, 2), (3, 2), (3, 0)]
    tris, simple = x3d.triangulate_polygon(u_shape)
    points = np.array(u_shape, dtype=float)
    assert simple and len(tris) == 6
    def area(a, b, c):
        (x1, y1), (x2, y2) = points[b] - points[a], points[c] - points[a]
        return (x1 * y2 - y1 * x2) / 2

    areas = [area(*t) for t in tris]
    assert all(a < 0 for a in areas) and sum(areas) == pytest.approx(-5.0)
    # a repeated point is left out, a point on an edge is a corner (no T-junction there):
    # a 2 × 2 square of 6 points gives 3 triangles of area 4
    points = np.array([(0, 0), (1, 0), (2, 0), (2, 0), (2, 2), (0, 2)], dtype=float)
    tris, simple = x3d.triangulate_polygon(points)
    assert simple and len(tris) == 3 and 3 not in tris and 1 in tris
    areas = [area(*t) for t in tris]
    assert all(a > 0 for a in areas) and sum(areas) == pytest.approx(4.0)


def test_degenerate_extrusions_warn_or_drop_faces_without_area():
    doc, mesh = only_mesh(X3DV + "Shape { geometry Extrusion { spine [0 0 0] } }")
    assert len(mesh.face_sizes) == 0
    assert any("fewer than 2 spine" in w for w in doc.warnings)
    # a spine point scaled to 0: its ring is one point, the sides there triangles (a pyramid)
    _, mesh = only_mesh(X3DV + "Shape { geometry Extrusion { scale [1 1, 0 0] } }")
    assert len(mesh.positions) == 5
    assert mesh.face_sizes.tolist() == [3, 3, 3, 3, 4]   # the end cap has no area: dropped


def test_unit_angle_applies_to_orientation():
    _, mesh = only_mesh(X3DV + "UNIT angle degree 0.017453292519943295\n"
                        "Shape { geometry Extrusion { crossSection [1 0, 0 1, -1 0] "
                        "orientation 0 1 0 90 } }")
    np.testing.assert_allclose(ring(mesh, 0, 3), [(0, 0, -1), (1, 0, 0), (0, 0, 1)], atol=1e-9)


def test_web3d_extrusion_heart_counts_read_from_the_file():
    path = os.path.join(DATA, "web3d_ExtrusionHeart.x3d")
    with open(path) as handle:
        text = handle.read()

    def numbers(field):
        return [float(v) for v in re.search(field + r"='([^']*)'", text).group(1).split()]

    spine, cross = numbers("spine"), numbers("crossSection")
    spine_points, cross_points = len(spine) // 3, len(cross) // 2
    closed = cross[:2] == cross[-2:]
    assert (spine_points, cross_points, closed) == (5, 13, True)
    doc = x3d.load(path)
    mesh = doc.instances[0].shape.geometry
    assert mesh.kind == "Extrusion" and not mesh.solid
    assert mesh.crease_angle == pytest.approx(3.14)
    assert doc.instances[0].shape.material.diffuse == (0.8, 0.3, 0.3)
    ring_points = cross_points - 1
    assert len(mesh.positions) == spine_points * ring_points
    # sides between consecutive spine points, and a cap at each end (convex TRUE: a polygon)
    assert mesh.face_sizes.tolist() == [4] * ((spine_points - 1) * ring_points) + \
        [ring_points] * 2
    # the middle spine point (0 0.5 0) has scale 1: the file's cross-section there, in its
    # SCP (a straight spine along +Y: the file's axes)
    middle = ring(mesh, 2, ring_points)
    expected = np.array([(x, 0.5, z) for x, z in zip(cross[0:-2:2], cross[1:-2:2])])
    np.testing.assert_allclose(middle, expected, atol=1e-12)


def test_text_strings_and_font_style_are_read():
    doc, mesh = only_mesh(X3DV + """Shape { geometry Text {
        string ["Hello", "second line"] length [2, 0] maxExtent 5
        fontStyle FontStyle { size 0.5 spacing 1.5 justify ["MIDDLE" "BEGIN"]
                              family ["TYPEWRITER", "SANS"] style "BOLDITALIC" }
    } }""")
    assert mesh.kind == "Text" and len(mesh.face_sizes) == 0
    t = mesh.text
    assert (t["strings"], t["length"], t["max_extent"]) == (["Hello", "second line"],
                                                             [2.0, 0.0], 5.0)
    assert (t["size"], t["spacing"], t["justify"], t["family"], t["style"]) == (
        0.5, 1.5, ("MIDDLE", "BEGIN"), ["TYPEWRITER", "SANS"], "BOLDITALIC")
    # the defaults: SERIF, PLAIN, BEGIN FIRST; one justify word: minor FIRST
    _, mesh = only_mesh(X3DV + 'Shape { geometry Text { string "a" } }')
    t = mesh.text
    assert (t["family"], t["style"], t["size"], t["spacing"], t["justify"], t["solid"]) == (
        ["SERIF"], "PLAIN", 1.0, 1.0, ("BEGIN", "FIRST"), False)
    _, mesh = only_mesh(X3DV + 'Shape { geometry Text { string "a" fontStyle FontStyle { '
                        'justify "END" } } }')
    assert mesh.text["justify"] == ("END", "FIRST")


@pytest.mark.parametrize("writer, name", [(x3d.dumps_x3d, "o.x3d"), (x3d.dumps_x3dv, "o.x3dv"),
                                          (x3d.dumps_vrml, "o.wrl")])
def test_the_writers_write_text_back_as_text_and_an_extrusion_as_its_faces(writer, name):
    doc, _ = only_mesh(X3DV + """Shape { geometry Text {
        string ["Hello", "there"] length [2, 0] maxExtent 5
        fontStyle FontStyle { size 0.5 spacing 1.5 justify ["END" "MIDDLE"] family "SANS"
                              style "ITALIC" topToBottom FALSE } } }""")
    back = x3d.loads(writer(doc), f"/nonexistent-folder/{name}")
    assert back.instances[0].shape.geometry.text == doc.instances[0].shape.geometry.text
    doc, mesh = only_mesh(X3DV + "Shape { geometry Extrusion { spine [0 0 0, 0 1 0, 1 1 0] } }")
    back = x3d.loads(writer(doc), f"/nonexistent-folder/{name}").instances[0].shape.geometry
    assert back.kind == "IndexedFaceSet"
    np.testing.assert_allclose(back.positions, mesh.positions, atol=1e-12)
    assert back.face_sizes.tolist() == mesh.face_sizes.tolist()
    assert back.corners.tolist() == mesh.corners.tolist()


@pytest.mark.slow
def test_large_extrusions_are_quick_and_absurd_ones_left_out():
    """A helix of 1,000 spine points × a 101-point circle (100,000 points, 200,000 faces once
    its quads split) builds with its crease normals within seconds; 100,000 × 200 points are
    left out with a warning; a concave 2,000-point cap triangulates into 1,998 triangles."""
    t = np.linspace(0, 20 * np.pi, 1000)
    spine = " ".join(f"{math.cos(a)} {a / 10} {math.sin(a)}," for a in t)
    circle = [f"{0.1 * math.cos(a)} {0.1 * math.sin(a)}," for a in np.arange(100) * np.pi / 50]
    circle = " ".join(circle + circle[:1])
    start = time.perf_counter()
    _, mesh = only_mesh(X3DV + f"Shape {{ geometry Extrusion {{ spine [{spine}] "
                        f"crossSection [{circle}] creaseAngle 1 }} }}")
    assert time.perf_counter() - start < 10.0
    assert len(mesh.positions) == 1000 * 100 and mesh.normals is not None
    spine = " ".join(f"0 {k} 0," for k in range(100_000))
    section = " ".join(f"{math.cos(a)} {math.sin(a)}," for a in np.linspace(0, 6, 200))
    start = time.perf_counter()
    doc, mesh = only_mesh(X3DV + f"Shape {{ geometry Extrusion {{ spine [{spine}] "
                          f"crossSection [{section}] }} }}")
    assert time.perf_counter() - start < 5.0
    assert len(mesh.face_sizes) == 0 and any("left out" in w and "Extrusion" in w
                                             for w in doc.warnings)
    a = np.linspace(0, 2 * np.pi, 2001)[:-1]
    star = np.stack([(1 + 0.3 * np.sin(7 * a)) * np.cos(a),
                     (1 + 0.3 * np.sin(7 * a)) * np.sin(a)], axis=1)
    start = time.perf_counter()
    tris, simple = x3d.triangulate_polygon(star)
    assert time.perf_counter() - start < 5.0 and simple and len(tris) == 1998
