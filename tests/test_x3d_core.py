# SPDX-License-Identifier: GPL-3.0-or-later
"""VRML97 / X3D (issue 36): pure tests of ``core/x3d.py`` (no bpy).

Each rule of ISO/IEC 14772-1 (VRML97) and 19775-1 (X3D) that the reader implements is checked
on a small file written here, with the expected values worked out by hand in the test: the
defaults of both standards (the SpotLight's differ), DEF/USE as object identity, PROTO with IS
and defaults, EXTERNPROTO, Inline, Switch, LOD, the Transform order, IndexedFaceSet's index
rules, the triangle and quad sets, the primitives, scoped lights, UNIT, gzip, the XML and
classic encodings giving the same data, liberal reading, and hostile files (entities, a 2⁴⁰
DEF/USE bomb, recursive PROTOs and Inlines, absurd indices, NaN, deep nesting, truncation)
each ending within a second or two.  Round trips through the three writers, and real files
of Choreonoid, three.js, x3dom and KiCad (tests/data/x3d, origins in tests/data/README.md)
with the values read by eye from each file.
"""

from __future__ import annotations

import gzip
import math
import os
import random
import time

import numpy as np
import pytest

from phong_nodes.core import x3d

DATA = os.path.join(os.path.dirname(os.path.abspath(__file__)), "data", "x3d")
VRML = "#VRML V2.0 utf8\n"
X3DV = "#X3D V3.3 utf8\nPROFILE Immersive\n"


def xml(scene: str, head: str = "", version: str = "3.3") -> str:
    return (f'<?xml version="1.0" encoding="UTF-8"?>\n<X3D profile="Immersive" '
            f'version="{version}"><head>{head}</head><Scene>{scene}</Scene></X3D>')


def read(text, name="scene.wrl", folder="/nonexistent-folder"):
    return x3d.loads(text, os.path.join(str(folder), name))


def write(folder, name, text) -> str:
    path = os.path.join(str(folder), name)
    with open(path, "wb" if isinstance(text, bytes) else "w") as handle:
        handle.write(text)
    return path


def timed(function, *args, limit=2.0):
    """function(*args), asserting that it returns within *limit* seconds."""
    start = time.perf_counter()
    result = function(*args)
    elapsed = time.perf_counter() - start
    assert elapsed < limit, f"took {elapsed:.2f} s (limit {limit} s)"
    return result


def warned(doc, *words) -> str:
    """The one warning that holds all *words* (asserting there is one)."""
    hits = [w for w in doc.warnings if all(word in w for word in words)]
    assert len(hits) == 1, f"{words} in {doc.warnings}"
    return hits[0]


def kinds(doc) -> list:
    return [inst.shape.geometry.kind for inst in doc.instances]


def rot(axis, angle) -> np.ndarray:
    """Rodrigues' rotation (written here, independently of the module), 4×4."""
    x, y, z = np.asarray(axis, float) / np.linalg.norm(axis)
    k = np.array([[0, -z, y], [z, 0, -x], [-y, x, 0]])
    out = np.eye(4)
    out[:3, :3] = np.eye(3) + math.sin(angle) * k + (1 - math.cos(angle)) * (k @ k)
    return out


def move(v) -> np.ndarray:
    out = np.eye(4)
    out[:3, 3] = v
    return out


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


# -- PROTO, EXTERNPROTO, Inline ----------------------------------------------------------------------------

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
                                       "Material { diffuseColor 0 1 0 } } geometry Box { size 1 2 3 } }")
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
        Switch {{ whichChoice 1 {field_} [ Shape {{ geometry Box {{}} }} Shape {{ geometry Sphere {{}} }} ] }}
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


def faces(mesh) -> list:
    out, start = [], 0
    for size in mesh.face_sizes.tolist():
        out.append(mesh.corners[start:start + size].tolist())
        start += size
    return out


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
