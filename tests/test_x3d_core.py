# SPDX-License-Identifier: GPL-3.0-or-later
"""VRML97 / X3D (issue 36): pure tests of ``core/x3d/`` (no bpy).

Each rule of ISO/IEC 14772-1 (VRML97) and 19775-1 (X3D) that the reader implements is checked
on a small file written here, with the expected values worked out by hand in the test: the
defaults of both standards (the SpotLight's differ), DEF/USE as object identity, PROTO with IS
and defaults, EXTERNPROTO, Inline, Switch, LOD, the Transform order, IndexedFaceSet's index
rules, the triangle and quad sets, the primitives, scoped lights, UNIT, gzip, the XML and
classic encodings giving the same data, liberal reading, and hostile files (entities, a 2⁴⁰
DEF/USE bomb, recursive PROTOs and Inlines, absurd indices, NaN, deep nesting, truncation)
each ending within a second or two, and round trips through the three writers.  Real files of
other programs and more of the encodings: ``test_x3d_files.py``.
"""

from __future__ import annotations

import gzip
import math
import os
import random
import time

import numpy as np
import pytest
from x3d_text import DATA, VRML, X3DV, faces, kinds, move, read, timed, warned, write, xml

from phong_nodes.core import x3d


# -- the defaults of both standards ------------------------------------------------------------

DEFAULTS_CLASSIC = """
Shape { appearance Appearance { material Material {} } geometry Box {} }
DirectionalLight {}
PointLight {}
SpotLight {}
"""
DEFAULTS_XML = """<Shape><Appearance><Material/></Appearance><Box/></Shape>
<DirectionalLight/><PointLight/><SpotLight/>"""


@pytest.mark.parametrize("encoding", ["vrml97", "x3d-classic", "x3d-xml"])
def test_defaults_of_materials_and_lights_follow_the_files_standard(encoding):
    text = {"vrml97": VRML + DEFAULTS_CLASSIC, "x3d-classic": X3DV + DEFAULTS_CLASSIC,
            "x3d-xml": xml(DEFAULTS_XML)}[encoding]
    doc = read(text)
    assert doc.encoding == encoding
    mat = doc.instances[0].shape.material
    assert (mat.diffuse, mat.ambient_intensity, mat.specular, mat.emissive, mat.shininess,
            mat.transparency) == ((0.8, 0.8, 0.8), 0.2, (0, 0, 0), (0, 0, 0), 0.2, 0)
    directional, point, spot = (inst.light for inst in doc.lights)
    for light in (directional, point, spot):
        assert (light.on, light.intensity, light.ambient_intensity, light.color) == \
            (True, 1.0, 0.0, (1, 1, 1))
    assert directional.direction == spot.direction == (0, 0, -1)
    assert point.location == spot.location == (0, 0, 0)
    assert point.attenuation == spot.attenuation == (1, 0, 0)
    assert point.radius == spot.radius == 100
    if encoding == "vrml97":       # ISO/IEC 14772-1 §6.45
        assert (spot.beam_width, spot.cut_off_angle) == (1.570796, 0.785398)
    else:                          # ISO/IEC 19775-1 §17.4.5
        assert (spot.beam_width, spot.cut_off_angle) == (0.7854, 1.570796)
    # DirectionalLight lights its group only; point and spot lights are global
    assert (directional.is_global, point.is_global, spot.is_global) == (False, True, True)
    assert doc.lights[0].scope == range(0, 1) and doc.lights[1].scope is None
    assert doc.headlight is True
    assert doc.navigation_types == (["WALK", "ANY"] if encoding == "vrml97"
                                    else ["EXAMINE", "ANY"])


def test_every_light_field_is_read():
    doc = read(X3DV + """
    SpotLight { on FALSE intensity 0.5 ambientIntensity 0.25 color 1 0.5 0
                location 1 2 3 direction 0 -1 0 attenuation 0.5 0.25 0.125 radius 7
                beamWidth 0.3 cutOffAngle 0.6 global FALSE }
    PointLight { location -1 -2 -3 attenuation 0 1 0 radius 3 global TRUE }
    DirectionalLight { direction 1 0 0 intensity 0.75 global TRUE }
    """)
    spot, point, directional = (inst.light for inst in doc.lights)
    assert (spot.on, spot.intensity, spot.ambient_intensity, spot.color, spot.location,
            spot.direction, spot.attenuation, spot.radius, spot.beam_width, spot.cut_off_angle,
            spot.is_global) == (False, 0.5, 0.25, (1, 0.5, 0), (1, 2, 3), (0, -1, 0),
                                (0.5, 0.25, 0.125), 7, 0.3, 0.6, False)
    assert (point.location, point.attenuation, point.radius, point.is_global) == \
        ((-1, -2, -3), (0, 1, 0), 3, True)
    assert (directional.direction, directional.intensity, directional.is_global) == \
        ((1, 0, 0), 0.75, True)
    assert doc.lights[0].scope == range(0, 0) and doc.lights[2].scope is None


# -- DEF/USE ----------------------------------------------------------------------------------

def test_def_use_gives_the_same_objects_and_separate_instances():
    doc = read(VRML + """
    DEF T Transform { translation 1 0 0 children [
      DEF S Shape {
        appearance DEF A Appearance { material DEF M Material { diffuseColor 0.1 0.2 0.3 } }
        geometry DEF G IndexedFaceSet { coord DEF C Coordinate { point [0 0 0, 1 0 0, 0 1 0] }
                                        coordIndex [0 1 2] } } ] }
    Transform { translation 0 5 0 children [ USE T ] }
    Shape { appearance USE A geometry USE G }
    Shape { appearance Appearance { material USE M }
            geometry IndexedFaceSet { coord USE C coordIndex [2 1 0] } }
    """)
    a, b, c, d = doc.instances
    assert a.shape is b.shape, "a USE'd group's shape is the same object"
    assert doc.roots[1].children[0] is doc.roots[0], "USE T is the group T itself"
    assert c.shape is not a.shape and c.shape.geometry is a.shape.geometry
    assert c.shape.appearance is a.shape.appearance
    assert d.shape.material is a.shape.material and d.shape.material.name == "M"
    assert d.shape.geometry is not a.shape.geometry
    assert d.shape.geometry.positions is a.shape.geometry.positions, "USE'd Coordinate read once"
    assert [inst.id for inst in doc.instances] == [0, 1, 2, 3]
    assert a.matrix[:3, 3].tolist() == [1, 0, 0] and b.matrix[:3, 3].tolist() == [1, 5, 0]
    assert a.path == ("T",) and b.path == ("T",)
    assert doc.materials() == [a.shape.material]


# -- PROTO, EXTERNPROTO, Inline -------------------------------------------------------------

LAMP = """
PROTO Lamp [
  field        SFColor col   1 0 0
  exposedField SFVec3f where 0 0 0
  exposedField MFNode  extra []
  eventIn      SFBool  set_on
] {
  Transform { translation IS where children [
    Shape { appearance Appearance { material Material { diffuseColor IS col } }
            geometry Box { size 1 1 1 } }
    Group { children IS extra }
  ] }
  DEF Unused Shape { geometry Sphere {} }
}
"""


def test_proto_instances_take_their_fields_through_is_and_defaults_otherwise():
    doc = read(VRML + LAMP + """
    DEF L1 Lamp { where 1 2 3 }
    Lamp { col 0 0 1 extra [ Shape { geometry Sphere { radius 2 } } ] }
    PROTO Outer [ field SFColor c 0 1 0 ] { Lamp { col IS c where 9 0 0 } }
    Outer {}
    """)
    first, second, sphere, third = doc.instances
    assert first.matrix[:3, 3].tolist() == [1, 2, 3] and first.path == ("L1",)
    assert first.shape.material.diffuse == (1, 0, 0), "the interface's default"
    assert second.matrix[:3, 3].tolist() == [0, 0, 0]
    assert second.shape.material.diffuse == (0, 0, 1), "the instance's value"
    assert sphere.shape.geometry.kind == "Sphere" and sphere.shape.geometry.primitive == \
        {"radius": 2.0}
    assert third.shape.material.diffuse == (0, 1, 0) and third.matrix[:3, 3].tolist() == [9, 0, 0]
    assert first.shape is not second.shape, "a shape that depends on IS is one an instance"
    assert first.shape.geometry is second.shape.geometry is third.shape.geometry, \
        "what no IS reaches is shared between instances"
    assert kinds(doc) == ["Box", "Box", "Sphere", "Box"], "only a PROTO's first node is shown"


def test_choreonoid_style_proto_with_single_node_children(tmp_path):
    doc = read(VRML + """
    PROTO Joint [ exposedField SFVec3f translation 0 0 0 exposedField SFRotation rotation 0 0 1 0
                  exposedField MFNode children [] exposedField SFString jointType "" ]
    { Transform { translation IS translation rotation IS rotation children IS children } }
    DEF J Joint { jointType "rotate" translation 0 1 0 rotation 0 0 1 1.5707963267948966
      children Joint { translation 2 0 0 children Shape { geometry Cone {} } } }
    """)
    (inst,) = doc.instances
    # T(0,1,0)·Rz(90°)·T(2,0,0): the origin goes to (0, 1, 0) + Rz·(2, 0, 0) = (0, 3, 0)
    assert np.allclose(inst.matrix[:3, 3], [0, 3, 0])
    assert inst.path == ("J",)


def test_externproto_reads_the_proto_from_a_local_file(tmp_path):
    write(tmp_path, "lib.wrl", VRML + "PROTO Widget [ field SFFloat r 1 ] "
                                       "{ Shape { geometry Sphere { radius IS r } } }")
    doc = read(VRML + """
    EXTERNPROTO Widget [ field SFFloat r ] [ "missing.wrl#Widget" "lib.wrl#Widget" ]
    EXTERNPROTO Gone [ field SFFloat r ] "nowhere.wrl#Gone"
    Widget { r 3 }
    Widget {}
    Gone {}
    """, folder=tmp_path)
    assert [i.shape.geometry.primitive["radius"] for i in doc.instances] == [3, 1]
    warned(doc, "EXTERNPROTO", "Gone")


def test_inline_shares_the_inlined_files_objects_and_warns_once_for_a_missing_file(tmp_path):
    write(tmp_path, "part.wrl", VRML + "DEF P Shape { appearance Appearance { material DEF PM "
                                       "Material { diffuseColor 0 1 0 } } "
                                       "geometry Box { size 1 2 3 } }")
    doc = read(VRML + """
    Transform { translation 10 0 0 children Inline { url "part.wrl" } }
    Inline { url [ "missing.wrl" "part.wrl" ] }
    Inline { url "nothere.wrl" }
    """, folder=tmp_path)
    a, b = doc.instances
    assert a.shape is b.shape and a.shape.material.name == "PM"
    assert a.matrix[:3, 3].tolist() == [10, 0, 0] and b.matrix[:3, 3].tolist() == [0, 0, 0]
    warned(doc, "Inline files not found", "nothere.wrl")


def test_inline_of_a_file_in_other_units_is_scaled_to_the_including_file(tmp_path):
    write(tmp_path, "mm.x3dv", X3DV + "UNIT length millimetre 0.001\n"
                                      "Shape { geometry Box { size 10 10 10 } }")
    doc = read(X3DV + 'Inline { url "mm.x3dv" }', folder=tmp_path)
    assert doc.meter == 1.0
    assert np.allclose(doc.instances[0].matrix, np.diag([0.001, 0.001, 0.001, 1]))


def test_inline_that_includes_itself_ends_quickly_with_a_warning(tmp_path):
    path = write(tmp_path, "self.wrl", VRML + 'Inline { url "self.wrl" } Shape { geometry Box {} }')
    doc = timed(x3d.load, path)
    assert kinds(doc) == ["Box"]
    warned(doc, "include themselves")
    write(tmp_path, "a.wrl", VRML + 'Inline { url "b.wrl" } Shape { geometry Sphere {} }')
    write(tmp_path, "b.wrl", VRML + 'Inline { url "a.wrl" } Shape { geometry Cone {} }')
    doc = timed(x3d.load, os.path.join(tmp_path, "a.wrl"))
    assert kinds(doc) == ["Cone", "Sphere"]
    warned(doc, "include themselves")


def test_switch_shows_its_chosen_child_and_lod_its_first_level():
    for header, field_ in ((VRML, "choice"), (X3DV, "children")):
        doc = read(header + f"""
        Switch {{ whichChoice 1 {field_} [ Shape {{ geometry Box {{}} }}
                                          Shape {{ geometry Sphere {{}} }} ] }}
        Switch {{ {field_} [ Shape {{ geometry Box {{}} }} ] }}
        Switch {{ whichChoice 5 {field_} [ Shape {{ geometry Box {{}} }} ] }}
        LOD {{ {"level" if header == VRML else "children"} [ Shape {{ geometry Cone {{}} }}
                                                       Shape {{ geometry Box {{}} }} ] }}
        """)
        assert kinds(doc) == ["Sphere", "Cone"], "whichChoice -1 (default) or out of range: none"


# -- transforms ---------------------------------------------------------------------------------

def test_transform_composes_center_scale_orientation_rotation_scale_translation_in_order():
    """P' = T·C·R·SR·S·SR⁻¹·C⁻¹·P, worked by hand for T (1, 2, 3), C (1, 0, 0), R and SR 90°
    about Z, S (2, 1, 1): P (2, 0, 0) → -C (1, 0, 0) → SR⁻¹ (0, -1, 0) → S (0, -1, 0) → SR
    (1, 0, 0) → R (0, 1, 0) → C (1, 1, 0) → T (2, 3, 3); P (1, 1, 0) → (0, 1, 0) → (1, 0, 0)
    → (2, 0, 0) → (0, 2, 0) → (-2, 0, 0) → (-1, 0, 0) → (0, 2, 3)."""
    half_pi = math.pi / 2
    for text in (VRML + f"Transform {{ translation 1 2 3 center 1 0 0 rotation 0 0 1 {half_pi} "
                        f"scale 2 1 1 scaleOrientation 0 0 1 {half_pi} "
                        "children Shape { geometry Box {} } }",
                 xml(f"<Transform translation='1 2 3' center='1 0 0' rotation='0 0 1 {half_pi}' "
                     f"scale='2 1 1' scaleOrientation='0 0 1 {half_pi}'><Shape><Box/></Shape>"
                     "</Transform>")):
        m = read(text).instances[0].matrix
        assert np.allclose(m @ [2, 0, 0, 1], [2, 3, 3, 1], atol=1e-12)
        assert np.allclose(m @ [1, 1, 0, 1], [0, 2, 3, 1], atol=1e-12)


def test_matrix_transform_reads_the_translation_from_the_last_row():
    doc = read(VRML + "MatrixTransform { matrix 0 1 0 0  -1 0 0 0  0 0 1 0  4 5 6 1 "
                      "children Shape { geometry Box {} } }")
    m = doc.instances[0].matrix
    # rows as written are the images of the axes: x → (0, 1, 0), y → (-1, 0, 0)
    assert np.allclose(m @ [1, 0, 0, 1], [4, 6, 6, 1]) and np.allclose(m @ [0, 1, 0, 1],
                                                                        [3, 5, 6, 1])


def test_decompose_gives_transform_fields_that_compose_the_matrix_again():
    rng = np.random.default_rng(7)
    for mirror in (1, -1):
        m = np.eye(4)
        m[:3, :3] = rng.normal(size=(3, 3))
        m[:3, :3] *= np.sign(np.linalg.det(m[:3, :3])) * mirror
        m[:3, 3] = rng.normal(size=3)
        parts = x3d.decompose(m)
        assert np.allclose(x3d.transform_matrix(**parts), m, atol=1e-12)
        assert (np.prod(parts["scale"]) < 0) == (mirror < 0)


# -- IndexedFaceSet: the standard's index rules ---------------------------------------------

SQUARE = "coord Coordinate { point [0 0 0, 1 0 0, 1 1 0, 0 1 0] } coordIndex [0 1 2 -1 0 2 3]"
R, G, B, W = [1, 0, 0, 1], [0, 1, 0, 1], [0, 0, 1, 1], [1, 1, 1, 1]


def face_set(body: str):
    doc = read(VRML + f"Shape {{ geometry IndexedFaceSet {{ {SQUARE} {body} }} }}")
    return doc, doc.instances[0].shape.geometry


def test_face_set_faces_and_the_last_polygon_without_separator():
    _doc, mesh = face_set("")
    assert mesh.face_sizes.tolist() == [3, 3] and mesh.corners.tolist() == [0, 1, 2, 0, 2, 3]
    assert mesh.normals is None and mesh.colors is None and mesh.uvs is None
    assert (mesh.solid, mesh.ccw, mesh.convex, mesh.crease_angle) == (True, True, True, 0)


def test_face_colours_per_face_without_and_with_colorIndex():
    _doc, mesh = face_set("colorPerVertex FALSE color Color { color [1 0 0, 0 1 0] }")
    assert mesh.colors.tolist() == [R, R, R, G, G, G], "in face order"
    _doc, mesh = face_set("colorPerVertex FALSE color Color { color [1 0 0, 0 1 0] } "
                          "colorIndex [1 0]")
    assert mesh.colors.tolist() == [G, G, G, R, R, R], "colorIndex[face]"


def test_vertex_colours_without_colorIndex_follow_coordIndex_and_with_it_their_own():
    colors = "color Color { color [1 0 0, 0 1 0, 0 0 1, 1 1 1] }"
    _doc, mesh = face_set(colors)
    assert mesh.colors.tolist() == [R, G, B, R, B, W]
    _doc, mesh = face_set(colors + " colorIndex [3 2 1 -1 0 0 0 -1]")
    assert mesh.colors.tolist() == [W, B, G, R, R, R]
    _doc, mesh = face_set("color ColorRGBA { color [1 0 0 0.5, 0 1 0 0.25] } "
                          "colorPerVertex FALSE")
    assert mesh.colors[:, 3].tolist() == [0.5, 0.5, 0.5, 0.25, 0.25, 0.25]


def test_normals_fall_back_to_coordIndex_and_may_be_per_face():
    normals = "normal Normal { vector [1 0 0, 0 1 0, 0 0 1, 0 0 -1] }"
    _doc, mesh = face_set(normals)
    assert mesh.normals.tolist() == [[1, 0, 0], [0, 1, 0], [0, 0, 1], [1, 0, 0], [0, 0, 1],
                                     [0, 0, -1]]
    _doc, mesh = face_set(normals + " normalPerVertex FALSE normalIndex [3 2]")
    assert mesh.normals.tolist() == [[0, 0, -1]] * 3 + [[0, 0, 1]] * 3
    assert mesh.normal_per_vertex is False


def test_texture_coordinates_by_texCoordIndex_or_else_coordIndex():
    coords = "texCoord TextureCoordinate { point [0 0, 1 0, 1 1, 0 1, 0.5 0.5] }"
    _doc, mesh = face_set(coords + " texCoordIndex [4 3 2 -1 1 0 4]")
    assert mesh.uvs.tolist() == [[0.5, 0.5], [0, 1], [1, 1], [1, 0], [0, 0], [0.5, 0.5]]
    _doc, mesh = face_set(coords)
    assert mesh.uvs.tolist() == [[0, 0], [1, 0], [1, 1], [0, 0], [1, 1], [0, 1]]


def test_faces_with_indices_out_of_range_or_too_few_are_dropped_keeping_face_numbers():
    doc = read(VRML + """Shape { geometry IndexedFaceSet {
        coord Coordinate { point [0 0 0, 1 0 0, 1 1 0, 0 1 0] }
        coordIndex [0 1 9 -1 0 2 3 -1 1 2 -1 -1 3 2 1]
        colorPerVertex FALSE color Color { color [1 0 0, 0 1 0, 0 0 1, 1 1 1] } } }""")
    mesh = doc.instances[0].shape.geometry
    assert mesh.corners.tolist() == [0, 2, 3, 3, 2, 1] and mesh.face_sizes.tolist() == [3, 3]
    assert mesh.colors.tolist() == [G, G, G, W, W, W], "faces keep their numbers in the file"
    warned(doc, "out of range", "left out")
    warned(doc, "fewer than 3")


def test_an_attribute_whose_index_is_out_of_range_is_left_out_with_a_warning():
    doc, mesh = face_set("color Color { color [1 0 0] } colorIndex [0 0 5 -1 0 0 0]")
    assert mesh.colors is None and mesh.face_sizes.tolist() == [3, 3]
    warned(doc, "colours left out", "out of range")


def test_default_texture_coordinates_of_a_textured_face_set_follow_its_bounding_box():
    doc = read(VRML + """Shape { appearance Appearance { texture ImageTexture { url "t.png" } }
      geometry IndexedFaceSet { coord Coordinate { point [0 0 0, 4 0 0, 4 0 2, 0 0 2] }
                                coordIndex [0 1 2 3] } }""")
    # longest side x (4): S = x / 4; next z (2): T = z / 4
    assert doc.instances[0].shape.geometry.uvs.tolist() == [[0, 0], [1, 0], [1, 0.5], [0, 0.5]]


def test_counter_clockwise_reverses_the_faces_of_a_clockwise_mesh():
    _doc, mesh = face_set("ccw FALSE color Color { color [1 0 0, 0 1 0, 0 0 1, 1 1 1] }")
    out = x3d.counter_clockwise(mesh)
    assert out.ccw and out.corners.tolist() == [0, 2, 1, 0, 3, 2]
    assert out.colors.tolist() == [R, B, G, R, W, B]
    assert mesh.corners.tolist() == [0, 1, 2, 0, 2, 3], "the original is left as it was"


# -- the other face sets, lines and points ---------------------------------------------------

def geometry(text):
    return read(X3DV + f"Shape {{ geometry {text} }}").instances[0].shape.geometry


SIX = "coord Coordinate { point [0 0 0, 1 0 0, 1 1 0, 0 1 0, 2 0 0, 2 1 0, 3 0 0, 3 1 0] }"


def test_triangle_and_quad_sets():
    assert faces(geometry(f"IndexedTriangleSet {{ index [0 1 2 2 1 3] {SIX} }}")) == \
        [[0, 1, 2], [2, 1, 3]]
    assert faces(geometry(f"TriangleSet {{ {SIX} }}")) == [[0, 1, 2], [3, 4, 5]]
    assert faces(geometry(f"TriangleFanSet {{ fanCount [4] {SIX} }}")) == [[0, 1, 2], [0, 2, 3]]
    assert faces(geometry(f"IndexedTriangleFanSet {{ index [0 1 2 3 -1 4 5 6] {SIX} }}")) == \
        [[0, 1, 2], [0, 2, 3], [4, 5, 6]]
    # strips: every other triangle turned, so all keep the strip's winding
    assert faces(geometry(f"TriangleStripSet {{ stripCount [5] {SIX} }}")) == \
        [[0, 1, 2], [2, 1, 3], [2, 3, 4]]
    assert faces(geometry(f"IndexedTriangleStripSet {{ index [3 2 1 0] {SIX} }}")) == \
        [[3, 2, 1], [1, 2, 0]]
    assert faces(geometry(f"QuadSet {{ {SIX} }}")) == [[0, 1, 2, 3], [4, 5, 6, 7]]
    assert faces(geometry(f"IndexedQuadSet {{ index [0 1 2 3 4 5 6 7 1] {SIX} }}")) == \
        [[0, 1, 2, 3], [4, 5, 6, 7]]
    mesh = geometry(f"IndexedTriangleSet {{ index [0 1 2 2 1 3] colorPerVertex FALSE "
                    f"color Color {{ color [1 0 0, 0 1 0] }} {SIX} }}")
    assert mesh.colors.tolist() == [R, R, R, G, G, G], "per face: one colour a triangle"


def test_elevation_grid_quads_heights_and_default_texture_coordinates():
    mesh = geometry("ElevationGrid { xDimension 3 zDimension 2 xSpacing 2 zSpacing 5 "
                    "height [0 1 2 3 4 5] }")
    assert mesh.positions.tolist() == [[0, 0, 0], [2, 1, 0], [4, 2, 0], [0, 3, 5], [2, 4, 5],
                                       [4, 5, 5]]
    assert faces(mesh) == [[0, 3, 4, 1], [1, 4, 5, 2]]
    assert mesh.uvs[:4].tolist() == [[0, 0], [0, 1], [0.5, 1], [0.5, 0]]


def test_line_sets_give_edges_and_point_sets_points():
    mesh = geometry(f"IndexedLineSet {{ {SIX} coordIndex [0 1 2 -1 3 4 -1 5] }}")
    assert mesh.edges.tolist() == [[0, 1], [1, 2], [3, 4]] and len(mesh.corners) == 0
    mesh = geometry(f"LineSet {{ {SIX} vertexCount [3 2] }}")
    assert mesh.edges.tolist() == [[0, 1], [1, 2], [3, 4]]
    mesh = geometry("PointSet { coord Coordinate { point [0 0 0, 1 1 1] } "
                    "color Color { color [1 0 0, 0 1 0] } }")
    assert mesh.positions.tolist() == [[0, 0, 0], [1, 1, 1]]
    assert mesh.point_colors.tolist() == [R, G] and mesh.edges is None


# -- primitives --------------------------------------------------------------------------------

def face_normals(mesh) -> np.ndarray:
    """Newell's normal of each face (written here)."""
    out = []
    for corners in faces(mesh):
        p = mesh.positions[corners]
        q = np.roll(p, -1, axis=0)
        out.append([np.sum((p[:, 1] - q[:, 1]) * (p[:, 2] + q[:, 2])),
                    np.sum((p[:, 2] - q[:, 2]) * (p[:, 0] + q[:, 0])),
                    np.sum((p[:, 0] - q[:, 0]) * (p[:, 1] + q[:, 1]))])
    return np.array(out)


def centroids(mesh) -> np.ndarray:
    return np.array([mesh.positions[c].mean(axis=0) for c in faces(mesh)])


def assert_outward(mesh):
    assert (np.einsum("ij,ij->i", face_normals(mesh), centroids(mesh)) > 0).all()


def corner_at(mesh, point, uv=None, normal=None):
    """Indices of the corners at *point* (with *uv*, on a face of *normal*)."""
    at = np.all(np.isclose(mesh.positions[mesh.corners], point, atol=1e-9), axis=1)
    if uv is not None:
        at &= np.all(np.isclose(mesh.uvs, uv, atol=1e-9), axis=1)
    if normal is not None:
        at &= np.all(np.isclose(mesh.normals, normal, atol=1e-9), axis=1)
    return np.flatnonzero(at)


def test_box_size_normals_and_texture_orientation():
    mesh = geometry("Box { size 2 3 4 }")
    assert sorted(map(tuple, mesh.positions.tolist())) == sorted(
        (x, y, z) for x in (-1, 1) for y in (-1.5, 1.5) for z in (-2, 2))
    assert mesh.face_sizes.tolist() == [4] * 6
    assert_outward(mesh)
    # every corner's normal is its face's outward axis
    per_corner = np.repeat(face_normals(mesh), 4, axis=0)
    assert np.allclose(mesh.normals, per_corner / np.linalg.norm(per_corner, axis=1)[:, None])
    # each face shows the image upright seen from outside with Y up: (0, 0) at its bottom left
    # (front +Z: -X; back -Z: +X; right +X: +Z; left -X: -Z), (1, 1) at its top right
    for normal, bottom_left, top_right in (((0, 0, 1), (-1, -1.5, 2), (1, 1.5, 2)),
                                           ((0, 0, -1), (1, -1.5, -2), (-1, 1.5, -2)),
                                           ((1, 0, 0), (1, -1.5, 2), (1, 1.5, -2)),
                                           ((-1, 0, 0), (-1, -1.5, -2), (-1, 1.5, 2)),
                                           # top seen from above with -Z up
                                           ((0, 1, 0), (-1, 1.5, 2), (1, 1.5, -2)),
                                           # bottom seen from below with +Z up
                                           ((0, -1, 0), (-1, -1.5, -2), (1, -1.5, 2))):
        assert len(corner_at(mesh, bottom_left, (0, 0), normal)) == 1, normal
        assert len(corner_at(mesh, top_right, (1, 1), normal)) == 1, normal


def test_sphere_radius_normals_and_seam_at_the_back():
    mesh = geometry("Sphere { radius 2 }")
    assert np.allclose(np.linalg.norm(mesh.positions, axis=1), 2)
    assert np.allclose(mesh.normals, mesh.positions[mesh.corners] / 2)
    assert_outward(mesh)
    # s = 0 at the back (-Z), counter-clockwise seen from above: -X at 1/4, +Z at 1/2;
    # t from 0 at the bottom to 1 at the top
    assert len(corner_at(mesh, (0, 0, -2), (0, 0.5))) and len(corner_at(mesh, (0, 0, -2), (1, 0.5)))
    assert len(corner_at(mesh, (-2, 0, 0), (0.25, 0.5)))
    assert len(corner_at(mesh, (0, 0, 2), (0.5, 0.5)))
    assert np.allclose(mesh.uvs[corner_at(mesh, (0, 2, 0)), 1], 1)


def test_cylinder_and_cone_sizes_caps_and_texture():
    mesh = geometry("Cylinder { radius 1 height 4 }")
    assert set(np.round(mesh.positions[:, 1], 12).tolist()) == {-2, 2}
    assert np.allclose(np.hypot(mesh.positions[:, 0], mesh.positions[:, 2]), 1)
    assert len(mesh.face_sizes) == x3d.SEGMENTS + 2
    assert_outward(mesh)
    # the top cap seen from above with -Z up: the point at -Z is the image's top middle
    assert len(corner_at(mesh, (0, 2, -1), (0.5, 1)))
    # the side wraps from the back: s = 0 at -Z, t = 1 at the top
    assert len(corner_at(mesh, (0, 2, -1), (0, 1)))
    assert len(geometry("Cylinder { top FALSE bottom FALSE }").face_sizes) == x3d.SEGMENTS
    assert len(geometry("Cylinder { side FALSE }").face_sizes) == 2
    cone = geometry("Cone { bottomRadius 2 height 3 }")
    assert np.allclose(cone.positions.max(axis=0), [2, 1.5, 2])
    assert np.allclose(cone.positions[:, 1].min(), -1.5)
    assert_outward(cone)
    # the slanted side's normal: (outward, r/h) normalised, at the side's corners on the rim
    rim = corner_at(cone, (0, -1.5, -2))
    side = [c for c in rim if abs(cone.normals[c, 1]) < 0.99]
    assert np.allclose(cone.normals[side[0]], np.array([0, 2 / 3, -1]) / math.hypot(2 / 3, 1))
    assert len(geometry("Cone { bottom FALSE }").face_sizes) == x3d.SEGMENTS


# -- scoped lights -------------------------------------------------------------------------

def test_vrml97_directional_light_lights_its_group_and_point_lights_everything():
    doc = read(VRML + """
    DEF A Group { children [
      DirectionalLight { direction 0 -1 0 }
      DEF S1 Shape { geometry Box {} }
      Group { children [ DEF S2 Shape { geometry Sphere {} } ] }
    ] }
    DEF S3 Shape { geometry Cone {} }
    DEF B Transform { translation 5 0 0 children [ USE A ] }
    PointLight { location 0 1 0 }
    """)
    assert kinds(doc) == ["Box", "Sphere", "Cone", "Box", "Sphere"]
    first, second, point = doc.lights
    assert first.light is second.light
    assert list(first.scope) == [0, 1] and list(second.scope) == [3, 4]
    assert second.matrix[:3, 3].tolist() == [5, 0, 0] and second.path == ("B", "A")
    assert point.scope is None
    assert np.allclose(second.world_direction(), [0, -1, 0])


def test_x3d_global_field_decides_the_scope():
    for text in (X3DV + """
        Group { children [ DirectionalLight { global TRUE } PointLight { global FALSE }
                           Shape { geometry Box {} } ] }
        Shape { geometry Sphere {} }""",
                 xml("<Group><DirectionalLight global='true'/><PointLight global='false'/>"
                     "<Shape><Box/></Shape></Group><Shape><Sphere/></Shape>")):
        directional, point = read(text).lights
        assert directional.scope is None and list(point.scope) == [0]


def test_a_light_at_the_root_lights_the_whole_file_and_world_location_follows_the_matrix():
    doc = read(VRML + """DirectionalLight {} Shape { geometry Box {} }
    Transform { translation 1 2 3 rotation 0 1 0 3.141592653589793 children [
      PointLight { location 1 0 0 } Shape { geometry Box {} } ] }""")
    assert list(doc.lights[0].scope) == [0, 1]
    assert np.allclose(doc.lights[1].world_location(), [0, 2, 3])


# -- units, axes, the Phong mapping ----------------------------------------------------------

UNITS_CLASSIC = X3DV + """UNIT length millimetres 0.001
UNIT angle degrees 0.017453292519943295
Transform { rotation 0 0 1 90 children [
  PointLight { attenuation 1 2 3 radius 500 }
  SpotLight { beamWidth 30 cutOffAngle 60 }
  Shape { geometry IndexedFaceSet { creaseAngle 45 coord Coordinate { point [0 0 0, 1 0 0, 0 1 0] }
                                    coordIndex [0 1 2] } } ] }
Viewpoint { fieldOfView 40 orientation 0 1 0 180 }
"""


def test_unit_statements_scale_lengths_and_convert_angles():
    doc = read(UNITS_CLASSIC)
    assert doc.meter == 0.001 and doc.unit_name == "millimetres"
    assert np.allclose(doc.instances[0].matrix[:3, :3], [[0, -1, 0], [1, 0, 0], [0, 0, 1]])
    spot = doc.lights[1].light
    assert math.isclose(spot.beam_width, math.pi / 6) and math.isclose(spot.cut_off_angle,
                                                                       math.pi / 3)
    assert math.isclose(doc.instances[0].shape.geometry.crease_angle, math.pi / 4)
    assert math.isclose(doc.viewpoint.field_of_view, 40 * math.pi / 180)
    assert math.isclose(doc.viewpoint.orientation[3], math.pi)
    values = x3d.light_values(doc, doc.lights[0].light)
    # 1/(a0 + a1·d + a2·d²) with d in mm equals 1/(a0 + a1'·d' + a2'·d'²) with d' = d/1000 m
    assert np.allclose(values["attenuation"], (1, 2000, 3e6)) and math.isclose(values["radius"],
                                                                                 0.5)
    m = 0.001
    assert np.allclose(x3d.to_blender_matrix(doc), [[m, 0, 0, 0], [0, 0, -m, 0], [0, m, 0, 0],
                                                    [0, 0, 0, 1]])
    head = "<unit category='length' name='millimetres' conversionFactor='0.001'/>"
    assert read(xml("<Shape><Box/></Shape>", head)).meter == 0.001


def test_to_blender_matrix_turns_y_up_into_z_up():
    doc = read(VRML + "Shape { geometry Box {} }")
    turn = x3d.to_blender_matrix(doc)
    assert np.allclose(turn @ [0, 1, 0, 0], [0, 0, 1, 0]), "X3D's up is Blender's up"
    assert np.allclose(turn @ [0, 0, 1, 0], [0, -1, 0, 0]), "towards the viewer: Blender's -Y"
    assert np.allclose(doc.instances[0].matrix, np.eye(4)), "the parsed data is not converted"


def test_phong_values_of_materials_textures_and_colours():
    mat = x3d.Material(diffuse=(0.5, 0.4, 0.2), ambient_intensity=0.5, specular=(0.1, 0.2, 0.3),
                       emissive=(0.05, 0, 0), shininess=0.25, transparency=0.25)
    values = x3d.phong_values(mat)
    assert values["Kd"] == (0.5, 0.4, 0.2) and values["Ka"] == (0.25, 0.2, 0.1)
    assert values["Ks"] == (0.1, 0.2, 0.3) and values["Ke"] == (0.05, 0, 0)
    assert values["exponent"] == 32 and values["blinn"] == 1 and values["opacity"] == 0.75
    assert values["lit"] and values["source"] == "material"
    assert x3d.phong_values(mat, texture_components=3)["source"] == "texture"
    assert x3d.phong_values(mat, texture_components=1)["source"] == "texture*material"
    assert x3d.phong_values(mat, texture_components=1, colors=True)["source"] == "texture*colors"
    assert x3d.phong_values(mat, colors=True)["source"] == "colors"
    unlit = x3d.phong_values(None)
    assert not unlit["lit"] and unlit["Ke"] == (1, 1, 1) and unlit["Kd"] == (0, 0, 0)


def test_x3d4_materials_and_two_sided_material():
    doc = read(xml("""
      <Shape><Appearance><TwoSidedMaterial DEF='T' diffuseColor='1 0 0' separateBackColor='true'
              backDiffuseColor='0 0 1' backShininess='0.5'/></Appearance><Box/></Shape>
      <Shape><Appearance><UnlitMaterial emissiveColor='0 1 0' transparency='0.5'/></Appearance>
             <Box/></Shape>
      <Shape><Appearance><PhysicalMaterial baseColor='0.2 0.3 0.4' metallic='0.5'/></Appearance>
             <Box/></Shape>""", version="4.0"))
    two, unlit, physical = (i.shape.material for i in doc.instances)
    assert two.kind == "two_sided" and two.diffuse == (1, 0, 0)
    assert two.back.diffuse == (0, 0, 1) and two.back.shininess == 0.5
    assert unlit.kind == "unlit" and unlit.emissive == (0, 1, 0) and unlit.diffuse == (0, 0, 0)
    assert x3d.phong_values(unlit)["Ke"] == (0, 1, 0) and not x3d.phong_values(unlit)["lit"]
    assert physical.kind == "physical" and physical.diffuse == (0.2, 0.3, 0.4)
    assert physical.metallic == 0.5
    warned(doc, "PhysicalMaterial")


def test_material_names_come_from_def_else_appearance_shape_or_group():
    doc = read(VRML + """
    DEF Grp Group { children [
      Shape { appearance DEF App Appearance { material Material {} } geometry Box {} }
      DEF Shp Shape { appearance Appearance { material Material {} } geometry Box {} }
      Shape { appearance Appearance { material Material {} } geometry Box {} }
      Shape { appearance Appearance { material DEF Own Material {} } geometry Box {} } ] }
    Shape { appearance Appearance { material Material {} } geometry Box {} }
    Shape { geometry Box {} }""")
    assert [i.shape.material.name if i.shape.material else None for i in doc.instances] == \
        ["App", "Shp", "Grp", "Own", "Material", None]


def test_textures_keep_every_url_candidate_and_find_the_file(tmp_path):
    os.makedirs(os.path.join(tmp_path, "maps"))
    write(tmp_path, os.path.join("maps", "wood.png"), b"\x89PNG")
    doc = read(VRML + """Shape { appearance Appearance {
        texture DEF Wood ImageTexture { url [ "http://example.com/wood.png" "maps/nothere.png"
                                              "maps/wood.png" ] repeatS FALSE }
        textureTransform TextureTransform { translation 0.5 0 rotation 1.5707963267948966
                                            scale 2 2 center 0.5 0.5 } }
      geometry Box {} }""", folder=tmp_path)
    tex = doc.instances[0].shape.texture
    assert tex.name == "Wood" and tex.urls[0] == "http://example.com/wood.png"
    assert tex.path == os.path.join(tmp_path, "maps", "wood.png")
    assert os.path.join(tmp_path, "maps", "nothere.png") in tex.paths
    assert (tex.repeat_s, tex.repeat_t) == (False, True)
    tt = doc.instances[0].shape.texture_transform
    # Tc' = -C·S·R·C·T·Tc for Tc (0, 0): T → (0.5, 0), C → (1, 0.5), R 90° → (-0.5, 1),
    # S → (-1, 2), -C → (-1.5, 1.5)
    assert np.allclose(x3d.apply_texture_transform(np.array([[0.0, 0.0]]), tt), [[-1.5, 1.5]])
    assert not doc.warnings


def test_pixel_texture_image_is_decoded():
    doc = read(VRML + "Shape { appearance Appearance { texture PixelTexture { "
                      "image 2 1 3 0xFF0000 0x00FF80 } } geometry Box {} }")
    tex = doc.instances[0].shape.texture
    assert tex.components == 3 and tex.image.tolist() == [[[255, 0, 0], [0, 255, 128]]]


def test_bindable_nodes_first_of_the_main_file(tmp_path):
    write(tmp_path, "part.wrl", VRML + "NavigationInfo { headlight TRUE } "
                                       "Viewpoint { position 9 9 9 }")
    doc = read(VRML + """
    WorldInfo { title "A title" info [ "one" "two" ] }
    Inline { url "part.wrl" }
    Background { skyColor [ 0.1 0.2 0.3, 0.4 0.5 0.6 ] }
    NavigationInfo { headlight FALSE type [ "FLY" ] }
    NavigationInfo { headlight TRUE }
    Transform { translation 0 0 5 children DEF VP Viewpoint { position 1 2 3
                fieldOfView 0.5 description "front" } }
    Viewpoint { position 7 7 7 }
    """, folder=tmp_path)
    assert doc.title == "A title" and doc.info == ["one", "two"]
    assert doc.background == (0.1, 0.2, 0.3)
    assert doc.headlight is False and doc.navigation_types == ["FLY"]
    vp = doc.viewpoint
    assert (vp.name, vp.position, vp.field_of_view, vp.description) == ("VP", (1, 2, 3), 0.5,
                                                                         "front")
    assert doc.viewpoint_matrix[:3, 3].tolist() == [0, 0, 5]
    assert np.allclose((doc.viewpoint_matrix @ vp.matrix())[:3, 3], [1, 2, 8])


def test_ortho_viewpoint_and_grouping_nodes_of_cad_and_hanim():
    doc = read(xml("""
      <OrthoViewpoint fieldOfView='-2 -1 2 1' position='0 0 4'/>
      <CADAssembly><CADLayer><CADPart translation='1 0 0'><CADFace><Shape><Box/></Shape></CADFace>
      </CADPart></CADLayer></CADAssembly>
      <HAnimHumanoid translation='0 1 0'><HAnimJoint containerField='skeleton' translation='0 0 2'>
        <HAnimSegment><Shape><Sphere/></Shape></HAnimSegment></HAnimJoint></HAnimHumanoid>
      <StaticGroup><Collision><Billboard><Shape><Cone/></Shape></Billboard></Collision>
      </StaticGroup>"""))
    assert doc.viewpoint.kind == "OrthoViewpoint" and doc.viewpoint.ortho_field == (-2, -1, 2, 1)
    assert kinds(doc) == ["Box", "Sphere", "Cone"]
    assert [i.matrix[:3, 3].tolist() for i in doc.instances] == [[1, 0, 0], [0, 1, 2], [0, 0, 0]]
    warned(doc, "Billboard")


# -- encodings ------------------------------------------------------------------------------------

def test_gzip_is_found_by_its_magic_bytes_whatever_the_name(tmp_path):
    text = VRML + "Shape { geometry Box { size 1 2 3 } }"
    for name in ("plain.wrl", "packed.wrz", "packed.gz"):
        path = write(tmp_path, name, gzip.compress(text.encode()))
        assert x3d.load(path).instances[0].shape.geometry.primitive == {"size": (1, 2, 3)}
    path = write(tmp_path, "scene.x3dz", gzip.compress(xml("<Shape><Sphere/></Shape>").encode()))
    assert kinds(x3d.load(path)) == ["Sphere"]
    cones = "".join(f" Transform {{ translation {k} {k * 7 % 13} 0 children Shape "
                    "{ geometry Cone {} } }" for k in range(3000))
    packed = gzip.compress((text + cones).encode())
    doc = x3d.load(write(tmp_path, "cut.wrz", packed[:len(packed) // 2]))
    assert kinds(doc)[0] == "Box" and 100 < len(doc.instances) < 3001
    warned(doc, "gzip", "break off")
    with pytest.raises(x3d.X3DError, match="gzip"):
        x3d.load(write(tmp_path, "header.wrz", packed[:12]))


SAME_CLASSIC = """
NavigationInfo { headlight FALSE }
DEF Top Transform { translation 1 2 3 rotation 0 1 0 0.5 scale 2 2 2 children [
  DEF L SpotLight { location 0 1 0 direction 0 -1 0 beamWidth 0.2 cutOffAngle 0.4 }
  DEF S Shape {
    appearance Appearance { material DEF M Material { diffuseColor 0.1 0.2 0.3
        specularColor 0.4 0.5 0.6 shininess 0.7 transparency 0.1 } }
    geometry IndexedFaceSet { solid FALSE creaseAngle 1
      coord Coordinate { point [0 0 0, 1 0 0, 1 1 0, 0 1 0] } coordIndex [0 1 2 -1 0 2 3 -1]
      color Color { color [1 0 0, 0 1 0] } colorPerVertex FALSE
      normal Normal { vector [0 0 1] } normalIndex [0 0 0 -1 0 0 0 -1] } } ] }
Transform { translation -1 0 0 children [ USE S ] }
Viewpoint { position 0 0 7 }
"""
SAME_XML = """<NavigationInfo headlight='false'/>
<Transform DEF='Top' translation='1 2 3' rotation='0 1 0 0.5' scale='2 2 2'>
 <SpotLight DEF='L' location='0 1 0' direction='0 -1 0' beamWidth='0.2' cutOffAngle='0.4'/>
 <Shape DEF='S'><Appearance><Material DEF='M' diffuseColor='0.1 0.2 0.3'
   specularColor='0.4 0.5 0.6' shininess='0.7' transparency='0.1'/></Appearance>
  <IndexedFaceSet solid='false' creaseAngle='1' coordIndex='0 1 2 -1 0 2 3 -1'
    colorPerVertex='false' normalIndex='0 0 0 -1 0 0 0 -1'>
   <Coordinate point='0 0 0, 1 0 0, 1 1 0, 0 1 0'/><Color color='1 0 0, 0 1 0'/>
   <Normal vector='0 0 1'/></IndexedFaceSet></Shape></Transform>
<Transform translation='-1 0 0'><Shape USE='S'/></Transform>
<Viewpoint position='0 0 7'/>"""


def summary(doc) -> dict:
    """The plain values of a document, to compare two readings."""
    vp = doc.viewpoint
    out = {"headlight": doc.headlight,
           "viewpoint": vp and (vp.position, vp.orientation, vp.field_of_view)}
    out["instances"] = []
    for inst in doc.instances:
        shape, mesh = inst.shape, inst.shape.geometry
        mat = shape.material
        out["instances"].append((
            np.round(inst.matrix, 12).tolist(), inst.path, shape.name,
            None if mat is None else (mat.name, mat.diffuse, mat.ambient_intensity, mat.specular,
                                      mat.emissive, mat.shininess, mat.transparency),
            mesh.kind, mesh.positions.tolist(), mesh.face_sizes.tolist(), mesh.corners.tolist(),
            None if mesh.normals is None else np.round(mesh.normals, 12).tolist(),
            None if mesh.colors is None else mesh.colors.tolist(),
            None if mesh.uvs is None else np.round(mesh.uvs, 12).tolist(),
            mesh.solid, mesh.ccw, mesh.crease_angle))
    out["lights"] = [(np.round(li.matrix, 12).tolist(), li.light.name, li.light.kind,
                      li.light.on, li.light.intensity, li.light.ambient_intensity,
                      li.light.color, li.light.location, li.light.direction,
                      li.light.attenuation, li.light.radius, li.light.beam_width,
                      li.light.cut_off_angle, li.light.is_global,
                      None if li.scope is None else tuple(li.scope)) for li in doc.lights]
    return out


def test_the_xml_and_classic_encodings_of_one_scene_give_the_same_data():
    classic, other = read(X3DV + SAME_CLASSIC), read(xml(SAME_XML))
    assert summary(classic) == summary(other)
    assert classic.instances[0].shape is classic.instances[1].shape
    assert other.instances[0].shape is other.instances[1].shape
    assert not classic.warnings and not other.warnings


# -- liberal reading ---------------------------------------------------------------------------

def test_slips_other_browsers_accept_are_read_with_one_warning_each():
    doc = read(VRML + """
    Transform { translation 1,2,3 children [
      Shape { appearance Appearance { material Material { diffusecolor 0.5 0.25 0.125 } }
              geometry IndexedFaceset { coord DEF C { point [0 0 0, 1 0 0, 0 1 0] }
                                        coordIndex [0,1,2,-1,] } }
      Shape { geometry IndexedFaceSet { coord USE Later coordIndex [0 1 2] } }
      Frobnicator { children [ Shape { geometry Box {} } ] }
      Frobnicator { size 3 }
    ] }
    Group { children [ DEF Later Coordinate { point [0 0 0, 0 0 1, 1 0 0] } ] }
    """)
    first, second, third = doc.instances
    assert first.matrix[:3, 3].tolist() == [1, 2, 3]
    assert first.shape.material.diffuse == (0.5, 0.25, 0.125)
    assert first.shape.geometry.kind == "IndexedFaceSet"
    assert first.shape.geometry.positions.tolist() == [[0, 0, 0], [1, 0, 0], [0, 1, 0]]
    assert second.shape.geometry.positions.tolist() == [[0, 0, 0], [0, 0, 1], [1, 0, 0]], \
        "USE before DEF, resolved at the end"
    assert third.shape.geometry.kind == "Box", "an unknown node's children are read"
    warned(doc, "regardless of case", "diffusecolor", "IndexedFaceset")
    warned(doc, "DEF without a node type")
    warned(doc, "unknown node types", "Frobnicator ×2")


def test_xml_booleans_and_mfstrings_with_or_without_quotes():
    doc = read(xml("""
      <Shape><Appearance><ImageTexture url='plain.png' repeatS='FALSE'/></Appearance>
        <IndexedFaceSet solid='FALSE' ccw='False' coordIndex='0 1 2'>
          <Coordinate point='0 0 0 1 0 0 0 1 0'/></IndexedFaceSet></Shape>
      <Shape><Appearance><ImageTexture url='"a.png" "b b.png"' repeatT='false'/></Appearance>
        <Box solid='true'/></Shape>
      <NavigationInfo type='"EXAMINE" "ANY"' headlight='TRUE'/>"""))
    first, second = (i.shape for i in doc.instances)
    assert first.texture.urls == ["plain.png"] and first.texture.repeat_s is False
    assert (first.geometry.solid, first.geometry.ccw) == (False, False)
    assert second.texture.urls == ["a.png", "b b.png"] and second.texture.repeat_t is False
    assert doc.navigation_types == ["EXAMINE", "ANY"] and doc.headlight is True


def test_behaviour_nodes_are_named_once_and_the_rest_is_read():
    doc = read(X3DV + """
    DEF T TimeSensor { loop TRUE cycleInterval 5 }
    DEF I PositionInterpolator { key [0 1] keyValue [0 0 0, 1 1 1] }
    DEF SC Script {
      inputOnly SFFloat set_fraction
      outputOnly SFVec3f value_changed
      initializeOnly SFNode target USE T
      initializeOnly MFFloat values [ 1 2 3 ]
      url "javascript: function set_fraction(f) { value_changed = new SFVec3f(f, f, f); }"
    }
    ROUTE T.fraction_changed TO I.set_fraction
    ROUTE I . value_changed TO Moved . set_translation
    Fog { color 1 1 1 }
    DEF Moved Transform { children Shape { geometry Box {} } }
    Shape { appearance Appearance { shaders ComposedShader { language "GLSL" } }
            geometry Sphere {} }
    """)
    assert kinds(doc) == ["Box", "Sphere"]
    line = warned(doc, "not imported")
    for word in ("Script", "ROUTE ×2", "TimeSensor", "PositionInterpolator", "Fog",
                 "ComposedShader"):
        assert word in line
    assert len(doc.warnings) == 1


def test_a_file_without_header_is_read_with_a_warning_but_vrml1_and_other_files_are_refused():
    doc = read("Shape { geometry Box {} }")
    assert kinds(doc) == ["Box"]
    warned(doc, "without a '#VRML V2.0 utf8' header")
    with pytest.raises(x3d.X3DError, match="VRML 1.0"):
        read("#VRML V1.0 ascii\nSeparator { Cube {} }")
    for text in ("hello world", "", "<COLLADA/>", "<X3D"):
        with pytest.raises(x3d.X3DError):
            read(text)
    with pytest.raises(x3d.X3DError, match="No such file"):
        x3d.load("/nonexistent-folder/missing.wrl")


# -- hostile files: bounded time and memory, one error or warnings -------------------------------

def test_xml_declaring_entities_is_refused_before_parsing():
    laughs = ('<?xml version="1.0"?><!DOCTYPE X3D [<!ENTITY a "aaaaaaaaaa">'
              + "".join(f'<!ENTITY {chr(98 + k)} "{("&" + chr(97 + k) + ";") * 10}">'
                        for k in range(9))
              + ']><X3D><Scene><WorldInfo title="&j;"/></Scene></X3D>')
    with pytest.raises(x3d.X3DError, match="entities"):
        timed(read, laughs, "laughs.x3d", limit=1.0)
    external = ('<?xml version="1.0"?><!DOCTYPE X3D [<!ENTITY e SYSTEM "file:///etc/passwd">]>'
                '<X3D><Scene><WorldInfo title="&e;"/></Scene></X3D>')
    with pytest.raises(x3d.X3DError, match="entities"):
        read(external, "external.x3d")


def bomb(levels=40, leaf="Shape { geometry Box {} }"):
    lines = [VRML, "DEF G0 Group { children [ %s ] }" % leaf]
    lines += [f"DEF G{i} Transform {{ translation 1 0 0 children [ USE G{i - 1} USE G{i - 1} ] }}"
              for i in range(1, levels + 1)]
    return "\n".join(lines)


def test_a_def_use_bomb_keeps_the_first_instances_quickly_and_says_how_many_there_are():
    doc = timed(read, bomb(), limit=1.5)
    assert len(doc.instances) == x3d.MAX_INSTANCES
    # the file's top level holds G0 ... G40: G_k holds 2^k boxes, 2^41 - 1 in all
    warned(doc, f"{2 ** 41 - 1:,} shape and light instances", f"first {x3d.MAX_INSTANCES:,}")
    # G_k at the top level (k = 0 ... 15) adds 2^k instances: G16 starts at 2^16 - 1, below
    # G16, G15 ... G0, 16 translations of 1 along x
    assert doc.instances[2 ** 16 - 1].path == tuple(f"G{k}" for k in range(16, -1, -1))
    assert doc.instances[2 ** 16 - 1].matrix[0, 3] == 16
    assert all(i.shape is doc.instances[0].shape for i in doc.instances)
    doc = timed(read, bomb(leaf="DirectionalLight {} Shape { geometry Box {} }"), limit=1.5)
    assert len(doc.instances) + len(doc.lights) == x3d.MAX_INSTANCES
    assert all(list(light.scope) == [light_index] for light_index, light in enumerate(doc.lights))


def test_a_proto_inside_itself_and_proto_fan_out_end_quickly():
    doc = timed(read, VRML + "PROTO A [] { Group { children [ A {} Shape { geometry Box {} } ] } }"
                             "\nA {}")
    assert kinds(doc) == ["Box"]
    warned(doc, "inside themselves")
    doc = timed(read, VRML + "PROTO A [ field SFFloat r 1 ] { Group { children [ A { r IS r } "
                             "Shape { geometry Sphere { radius IS r } } ] } }\nA { r 2 }")
    assert kinds(doc) == ["Sphere"]
    warned(doc, "PROTO instances inside their own PROTO")
    lines = [VRML, "PROTO P0 [ field SFColor c 1 0 0 ] { Shape { appearance Appearance { "
                   "material Material { diffuseColor IS c } } geometry Box {} } }"]
    lines += [f"PROTO P{i} [ field SFColor c 1 0 0 ] {{ Group {{ children [ "
              + f"P{i - 1} {{ c IS c }} " * 10 + "] } }" for i in range(1, 10)]
    doc = timed(read, "\n".join(lines) + "\nP9 { c 0 1 0 }", limit=3.0)
    assert doc.instances[0].shape.material.diffuse == (0, 1, 0)
    warned(doc, "PROTO expansion beyond")


def test_indices_out_of_range_absurd_counts_and_nan_never_reach_the_data():
    doc = read(VRML + """
    Transform { translation nan 1 inf scale 1e35 1 1 children [
      Shape { geometry IndexedFaceSet {
        coord Coordinate { point [0 0 0, 1 NaN 0, 0 1 0, 1 1 1] }
        coordIndex [0 1 2 -1 0 1 4611686018427387904 -1 3 2 1.5 -1 -7 0 1 2]
        normal Normal { vector [0 0 1] } normalIndex [0 0 0 -1 0 0 0 -1 0 0 0 -1 -1 0 99 0] } }
      Shape { geometry ElevationGrid { xDimension 1000000000 zDimension 1000000000 height [1 2] } }
      Shape { geometry IndexedTriangleFanSet { index [0 1 999]
                                               coord Coordinate { point [0 0 0] } } }
      Shape { geometry TriangleFanSet { fanCount [1000000000] coord Coordinate { point [0 0 0] } } }
      Shape { appearance Appearance { texture PixelTexture { image 100000 100000 3 1 2 3 } }
              geometry Box { size 1 -inf 1 } } ] }
    """)
    mesh = doc.instances[0].shape.geometry
    assert mesh.corners.tolist() == [0, 1, 2, 0, 1, 2], "the faces naming 2^62, 1.5 are dropped"
    assert mesh.normals is None, "normalIndex 99 is out of range"
    for inst in doc.instances:
        assert np.isfinite(inst.matrix).all()
        geo = inst.shape.geometry
        for values in (geo.positions, geo.normals, geo.uvs, geo.colors):
            assert values is None or np.isfinite(values).all()
    assert doc.instances[0].matrix[:3, 3].tolist() == [0, 1, 0]
    assert doc.instances[-1].shape.texture.image is None
    for words in (("not finite",), ("larger than",), ("coordinate index out of range",),
                  ("normals left out", "out of range"),
                  ("ElevationGrid",), ("PixelTexture",), ("fan or strip counts",),
                  ("not integers",)):
        warned(doc, *words)


def test_deep_nesting_is_cut_without_recursion_errors():
    deep = 100_000
    doc = timed(read, VRML + "Group { children [ " * deep + "Shape { geometry Box {} }"
                + " ] }" * deep)
    assert doc.instances == []
    warned(doc, f"deeper than {x3d.MAX_DEPTH}")
    doc = timed(read, xml("<Group>" * deep + "<Shape><Box/></Shape>" + "</Group>" * deep),
                "deep.x3d")
    warned(doc, f"deeper than {x3d.MAX_DEPTH}")
    doc = timed(read, VRML + "Group { children " + "[" * deep + "]" * deep + " }"
                + " Shape { geometry Box {} }")
    assert kinds(doc) == ["Box"]
    doc = timed(read, VRML + "Group { children [ " * deep)
    warned(doc, "truncated")
    # DEF/USE nests C_k k deep: 5,000 groups each shown at the top level and inside the next
    chain = [VRML, "DEF C0 Shape { geometry Box {} }"]
    chain += [f"DEF C{k} Transform {{ translation 1 0 0 children USE C{k - 1} }}"
              for k in range(1, 5000)]
    doc = timed(read, "\n".join(chain))
    assert len(doc.instances) == 5000 and not doc.warnings
    last = doc.instances[-1]
    assert last.matrix[0, 3] == 4999 and len(last.path) == x3d.PATH_LIMIT
    # the innermost names: C32 ... C1 above the shape C0
    assert last.path == tuple(f"C{k}" for k in range(x3d.PATH_LIMIT, 0, -1))


def test_a_node_used_inside_itself_is_left_out():
    doc = timed(read, VRML + "DEF A Group { children [ Shape { geometry Box {} } USE A ] }")
    assert kinds(doc) == ["Box"]
    warned(doc, "used inside themselves")


def test_truncated_files_keep_what_came_before():
    doc = read(VRML + "Shape { geometry Box {} } Shape { geometry IndexedFaceSet { coord "
                      "Coordinate { point [0 0 0, 1 0 0, 0 1 0] } coordIndex [0 1 2")
    assert kinds(doc) == ["Box", "IndexedFaceSet"]
    warned(doc, "truncated")
    doc = read(VRML + 'WorldInfo { title "never ends')
    warned(doc, "truncated")
    doc = read(xml("<Shape><Box/></Shape><Shape><Sphere/></Shape>")[:-20], "cut.x3d")
    assert kinds(doc) == ["Box", "Sphere"]
    warned(doc, "not well-formed")


def test_files_beyond_the_size_limit_are_refused(tmp_path, monkeypatch):
    monkeypatch.setattr(x3d.files, "MAX_BYTES", 1000)   # the module that applies it
    path = write(tmp_path, "big.wrl", VRML + "Shape { geometry Box {} }" + " " * 2000)
    with pytest.raises(x3d.X3DError, match="larger than"):
        x3d.load(path)
    path = write(tmp_path, "bomb.wrz", gzip.compress((VRML + " " * 100_000).encode()))
    with pytest.raises(x3d.X3DError, match="decompresses to more than"):
        timed(x3d.load, path)


# -- flattening against a reference walk -----------------------------------------------------

def reference_flatten(doc, limit):
    """Shape and light instances by a plain recursive walk (written here): (shape, matrix,
    path) and (light, matrix, scope), the first *limit* shapes and lights in document order."""
    shapes, lights, count = [], [], [0]

    def walk(group, matrix, path):
        start, scoped = len(shapes), []
        for child in group.children:
            if count[0] >= limit:
                break
            if isinstance(child, x3d.Transform):
                walk(child, matrix @ child.matrix, path + ((child.name,) if child.name else ()))
            elif isinstance(child, x3d.Shape):
                shapes.append((child, matrix, path))
                count[0] += 1
            elif isinstance(child, x3d.Light):
                entry = [child, matrix, None]
                lights.append(entry)
                count[0] += 1
                if not child.is_global:
                    scoped.append(entry)
        for entry in scoped:
            entry[2] = (start, len(shapes))

    walk(doc.root, np.eye(4), ())
    return shapes, lights


def random_graph(seed):
    rng = random.Random(seed)
    shapes = [x3d.Shape(name=f"S{k}", geometry=x3d.Mesh()) for k in range(3)]
    groups = []
    for k in range(12):
        children = [rng.choice(shapes) for _ in range(rng.randint(0, 2))]
        children += [rng.choice(groups) for _ in range(rng.randint(0, 3)) if groups]
        if rng.random() < 0.4:
            children.insert(rng.randint(0, len(children)),
                            x3d.Light(kind=rng.choice(["directional", "point"]),
                                      is_global=rng.random() < 0.5))
        rng.shuffle(children)
        matrix = x3d.transform_matrix([rng.uniform(-1, 1) for _ in range(3)],
                                      (0, 1, 0, rng.uniform(0, 3)), (1, rng.uniform(0.5, 2), 1))
        groups.append(x3d.Transform(name=rng.choice(["", f"G{k}"]), matrix=matrix,
                                    children=children))
    return x3d.Document(root=x3d.Transform(kind="Scene", children=groups[-3:]))


@pytest.mark.parametrize("seed", range(8))
def test_flattening_equals_a_plain_walk_also_when_the_budget_cuts_it(seed, monkeypatch):
    for limit in (x3d.MAX_INSTANCES, 37):
        monkeypatch.setattr(x3d.flatten, "MAX_INSTANCES", limit)
        doc = random_graph(seed)
        doc.flatten()
        shapes, lights = reference_flatten(doc, limit)
        assert [i.id for i in doc.instances] == list(range(len(shapes)))
        assert [i.shape for i in doc.instances] == [s for s, _m, _p in shapes]
        assert all(np.allclose(i.matrix, m, atol=1e-9) for i, (_s, m, _p) in
                   zip(doc.instances, shapes))
        assert [i.path for i in doc.instances] == [p for _s, _m, p in shapes]
        assert [li.light for li in doc.lights] == [entry[0] for entry in lights]
        assert all(np.allclose(li.matrix, entry[1], atol=1e-9)
                   for li, entry in zip(doc.lights, lights))
        assert [None if li.scope is None else (li.scope.start, li.scope.stop)
                for li in doc.lights] == [entry[2] for entry in lights]


# -- writing ---------------------------------------------------------------------------------

def built_document():
    """A scene as the Blender side would build one: names that are not identifiers, a shared
    shape, a transform with non-uniform scale and a mirror, colours with alpha, every light."""
    mesh = x3d.Mesh(name="Roof mesh", positions=np.array(
        [[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0], [0.5, 1.5, 0.25]], float),
        face_sizes=np.array([4, 3]), corners=np.array([0, 1, 2, 3, 3, 2, 4]),
        normals=np.array([[0, 0, 1]] * 4 + [[0, 0.6, 0.8]] * 3, float),
        colors=np.array([[1, 0, 0, 1], [0, 1, 0, 0.5], [0, 0, 1, 1], [1, 1, 1, 1],
                         [0.5, 0.5, 0.5, 0.25], [0.1, 0.2, 0.3, 1], [0, 0, 0, 1]]),
        uvs=np.array([[0, 0], [1, 0], [1, 1], [0, 1], [0, 1], [1, 1], [0.5, 1.5]]),
        solid=False, crease_angle=0.5)
    material = x3d.Material(name="Red Paint.001", diffuse=(0.8, 0.1, 0.1), ambient_intensity=0.3,
                            specular=(0.5, 0.5, 0.5), emissive=(0.01, 0.02, 0.03),
                            shininess=0.25, transparency=0.125)
    appearance = x3d.Appearance(material=material, texture=x3d.Texture(
        urls=["maps/brick wall.png"], repeat_t=False), texture_transform=x3d.TextureTransform(
        center=(0.5, 0.5), rotation=0.25, scale=(2, 3), translation=(0.1, 0.2)))
    house = x3d.Shape(name="House #1", geometry=mesh, appearance=appearance)
    ball = x3d.Shape(name="Ball", geometry=geometry("Sphere { radius 2 }"),
                     appearance=x3d.Appearance(material=x3d.Material(name="Plain")))
    spot = x3d.Light(kind="spot", name="Key Light", intensity=0.75, ambient_intensity=0.1,
                     color=(1, 0.9, 0.8), location=(1, 2, 3), direction=(0, -1, 0),
                     attenuation=(1, 0.5, 0.25), radius=50, beam_width=0.4, cut_off_angle=0.8)
    sun = x3d.Light(kind="directional", name="Sun", intensity=0.5, direction=(0, -1, -1),
                    is_global=False)
    bulb = x3d.Light(kind="point", name="Bulb", on=False, location=(0, 3, 0),
                     attenuation=(0, 0, 1), radius=10)
    camera = x3d.Viewpoint(name="Cam", position=(0, 1, 10), orientation=(1, 0, 0, -0.2),
                           field_of_view=0.6, description="Main view")
    sheared = x3d.transform_matrix((1, 2, 3), (0, 1, 0, 0.3), (1, 2, -3), (1, 0, 0, 0.4))
    root = x3d.Transform(kind="Scene", children=[
        x3d.Transform(name="Obj 1", matrix=sheared, children=[house]),
        x3d.Transform(name="Obj 1", matrix=move((5, 0, 0)), children=[house]),
        x3d.Transform(name="Lamps", matrix=move((0, 5, 0)), children=[
            spot, sun, bulb, x3d.Transform(children=[ball])]),
        x3d.Transform(name="Rig", matrix=move((0, 0, 2)), children=[camera])])
    doc = x3d.Document(root=root, headlight=False, navigation_types=["EXAMINE", "ANY"],
                       viewpoint=camera, title="Round trip", background=(0.1, 0.2, 0.3))
    doc.flatten()
    return doc


def assert_same_scene(a, b, alpha=True):
    assert (a.headlight, a.navigation_types, a.title, a.background) == \
        (b.headlight, b.navigation_types, b.title, b.background)
    va, vb = a.viewpoint, b.viewpoint
    assert (va.name, va.position, va.orientation, va.field_of_view, va.description) == \
        (vb.name, vb.position, vb.orientation, vb.field_of_view, vb.description)
    assert np.allclose(a.viewpoint_matrix, b.viewpoint_matrix, atol=1e-12)
    assert len(a.instances) == len(b.instances)
    for x, y in zip(a.instances, b.instances):
        assert x.path == y.path and x.shape.name == y.shape.name
        assert np.allclose(x.matrix, y.matrix, atol=1e-12)
        mx, my = x.shape.material, y.shape.material
        assert (mx.name, mx.diffuse, mx.ambient_intensity, mx.specular, mx.emissive,
                mx.shininess, mx.transparency) == (my.name, my.diffuse, my.ambient_intensity,
                                                   my.specular, my.emissive, my.shininess,
                                                   my.transparency)
        gx, gy = x.shape.geometry, y.shape.geometry
        assert (gx.name, gx.kind, gx.solid, gx.ccw, gx.crease_angle, gx.primitive) == \
            (gy.name, gy.kind, gy.solid, gy.ccw, gy.crease_angle, gy.primitive)
        assert np.array_equal(gx.positions, gy.positions)
        assert np.array_equal(gx.face_sizes, gy.face_sizes)
        assert np.array_equal(gx.corners, gy.corners)
        assert np.array_equal(gx.normals, gy.normals) and np.array_equal(gx.uvs, gy.uvs)
        if gx.colors is not None:
            width = 4 if alpha else 3
            assert np.array_equal(gx.colors[:, :width], gy.colors[:, :width])
        tx, ty = x.shape.texture, y.shape.texture
        assert (tx is None) == (ty is None)
        if tx is not None:
            assert (tx.urls, tx.repeat_s, tx.repeat_t) == (ty.urls, ty.repeat_s, ty.repeat_t)
            fx, fy = x.shape.texture_transform, y.shape.texture_transform
            assert (fx.center, fx.rotation, fx.scale, fx.translation) == \
                (fy.center, fy.rotation, fy.scale, fy.translation)
    assert len(a.lights) == len(b.lights)
    for x, y in zip(a.lights, b.lights):
        lx, ly = x.light, y.light
        assert (lx.kind, lx.name, lx.on, lx.intensity, lx.ambient_intensity, lx.color,
                lx.location, lx.direction, lx.attenuation, lx.radius, lx.is_global) == \
            (ly.kind, ly.name, ly.on, ly.intensity, ly.ambient_intensity, ly.color,
             ly.location, ly.direction, ly.attenuation, ly.radius, ly.is_global)
        if lx.kind == "spot":
            assert (lx.beam_width, lx.cut_off_angle) == (ly.beam_width, ly.cut_off_angle)
        assert np.allclose(x.matrix, y.matrix, atol=1e-12) and x.scope == y.scope


@pytest.mark.parametrize("writer, name, alpha", [(x3d.dumps_x3d, "back.x3d", True),
                                                 (x3d.dumps_x3dv, "back.x3dv", True),
                                                 (x3d.dumps_vrml, "back.wrl", False)])
def test_written_scenes_read_back_with_the_same_values_names_and_sharing(writer, name, alpha):
    doc = built_document()
    text = writer(doc)
    back = read(text, name)
    assert back.warnings == ["texture files not found: maps/brick wall.png"]
    assert_same_scene(doc, back, alpha=alpha)
    assert back.instances[0].shape is back.instances[1].shape, "a shared shape stays shared"
    assert back.instances[0].shape.material.name == "Red Paint.001"
    assert back.instances[0].path == ("Obj 1",) and back.instances[1].path == ("Obj 1",)
    defs = [m.split("=")[1].strip("'\"") if "=" in m else m.split()[1]
            for m in __import__("re").findall(r"DEF=\"[^\"]*\"|DEF \S+", text)]
    assert len(defs) == len(set(defs)), "DEF names are unique"
    assert all(__import__("re").fullmatch(r"[A-Za-z_][A-Za-z0-9_\-]*", d) for d in defs)
    assert_same_scene(back, read(writer(back), name), alpha=alpha)


def test_vrml97_writes_other_units_as_a_scale_and_x3d_as_unit_statements():
    doc = read(UNITS_CLASSIC)
    for writer, name in ((x3d.dumps_x3d, "u.x3d"), (x3d.dumps_x3dv, "u.x3dv")):
        back = read(writer(doc), name)
        assert back.meter == 0.001 and np.allclose(back.instances[0].matrix,
                                                   doc.instances[0].matrix)
        assert np.allclose(back.lights[1].light.beam_width, math.pi / 6)
    back = read(x3d.dumps_vrml(doc), "u.wrl")
    assert back.meter == 1.0
    assert np.allclose(back.instances[0].matrix, np.diag([0.001] * 3 + [1])
                       @ doc.instances[0].matrix)


def test_real_files_write_back_to_the_same_data(tmp_path):
    for name in ("x3dom_Drum55Gallon.x3d", "threejs_meshWithLines.wrl",
                 "kicad_R_0805_2012Metric_excerpt.wrl", "choreonoid_box1.wrl"):
        doc = x3d.load(os.path.join(DATA, name))
        for writer, out in ((x3d.dumps_x3d, "o.x3d"), (x3d.dumps_vrml, "o.wrl")):
            back = read(writer(doc), out, folder=tmp_path)
            expected = summary(doc)["instances"]
            if out == "o.wrl":      # VRML97's primitives are solid: a two-sided one is faces
                expected = [e[:4] + ("IndexedFaceSet",) + e[5:] if e[4] in x3d._PRIMITIVES
                            and not e[11] else e for e in expected]
            assert summary(back)["instances"] == expected, (name, out)


def test_save_picks_the_encoding_by_extension_gzips_and_leaves_no_temporary_file(tmp_path):
    doc = built_document()
    for name, start in (("a.x3d", b"<?xml"), ("a.x3dv", b"#X3D V3.3"), ("a.wrl", b"#VRML V2.0"),
                        ("a.x3dz", b"\x1f\x8b"), ("a.wrz", b"\x1f\x8b"), ("a.x3dvz", b"\x1f\x8b"),
                        ("a.wrl.gz", b"\x1f\x8b")):
        path = x3d.save(doc, os.path.join(tmp_path, name))
        with open(path, "rb") as handle:
            assert handle.read().startswith(start), name
        assert_same_scene(doc, x3d.load(path), alpha=not name.startswith("a.wrl")
                          and not name.startswith("a.wrz"))
    assert sorted(os.listdir(tmp_path)) == sorted(["a.x3d", "a.x3dv", "a.wrl", "a.x3dz",
                                                   "a.wrz", "a.x3dvz", "a.wrl.gz"])
    with pytest.raises(ValueError):
        x3d.save(doc, os.path.join(tmp_path, "a.obj"))
