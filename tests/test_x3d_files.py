# SPDX-License-Identifier: GPL-3.0-or-later
"""VRML97 / X3D: pure tests of ``core/x3d/`` (no bpy) on real files of Choreonoid, three.js,
x3dom and KiCad (tests/data/x3d, origins in tests/data/README.md), with the values read by eye
from each file, and more of the two encodings (XML PROTOs, classic header statements, URLs,
Latin-1, bulk arrays, a cycle built by hand).  Helpers: ``x3d_text.py``.
"""

from __future__ import annotations

import os

import numpy as np
from x3d_text import DATA, VRML, faces, kinds, move, read, rot, timed, warned, write, xml

from phong_nodes.core import x3d


# -- real files (tests/data/x3d; origins and licences in tests/data/README.md) ---------------

def real(name):
    return x3d.load(os.path.join(DATA, name))


def test_kicad_model_materials_defined_in_shapes_without_geometry():
    doc = real("kicad_R_0805_2012Metric_excerpt.wrl")
    assert doc.encoding == "vrml97" and not doc.warnings
    assert [s.geometry for s in doc.roots[:3]] == [None, None, None]
    pin, res, plastic = (s.material for s in doc.roots[:3])
    assert (pin.name, pin.ambient_intensity, pin.diffuse, pin.specular, pin.emissive,
            pin.transparency, pin.shininess) == ("PIN-01", 0.271, (0.824, 0.82, 0.781),
                                                 (0.328, 0.258, 0.172), (0, 0, 0), 0, 0.7)
    assert (res.name, res.ambient_intensity, res.diffuse, res.specular, res.shininess) == \
        ("RES-SMD-01", 0.638, (0.082, 0.086, 0.094), (0.066, 0.063, 0.063), 0.3)
    assert (plastic.name, plastic.ambient_intensity, plastic.diffuse, plastic.shininess) == \
        ("PLASTIC-WHITE-01", 0.494, (0.895, 0.891, 0.813), 0.25)
    assert [i.shape.material for i in doc.instances] == [pin, plastic, res, res]
    assert doc.materials() == [pin, plastic, res]
    meshes = [i.shape.geometry for i in doc.instances]
    assert [len(m.face_sizes) for m in meshes] == [2, 6, 2, 2]
    assert [len(m.positions) for m in meshes] == [4, 8, 4, 4]
    assert meshes[0].positions[1].tolist() == [-0.394, -0.236, 0.159]
    assert meshes[0].corners.tolist() == [0, 1, 2, 2, 1, 3]
    assert all(m.crease_angle == 0.5 and m.solid for m in meshes)
    assert all(np.array_equal(i.matrix, np.eye(4)) for i in doc.instances)


def test_choreonoid_openhrp_protos():
    doc = real("choreonoid_box1.wrl")
    (inst,) = doc.instances
    assert inst.shape.geometry.primitive == {"size": (0.2, 0.8, 0.2)}
    mat = inst.shape.material
    assert mat.diffuse == (1, 1, 0) and mat.ambient_intensity == 0.2 and mat.name == "BODY"
    assert inst.path == ("box1", "WAIST", "BODY") and np.allclose(inst.matrix, np.eye(4))
    assert doc.headlight is True and doc.navigation_types == ["EXAMINE", "ANY"]
    assert doc.background == (0.4, 0.6, 0.4)
    assert doc.viewpoint.position == (3, 0, 0.835)
    assert doc.viewpoint.orientation == (0.577, 0.5775, 0.5775, 2.0935)
    # three ROUTEs in the bodies of the (unused) CylinderSensor PROTOs
    assert doc.warnings == ["not imported (animation, interaction, scripts, sound, shaders, "
                            "fog): ROUTE ×3"]


def test_choreonoid_table_nested_transforms_scale_orientation_and_texture_transform():
    doc = real("choreonoid_table.wrl")
    box, leg1, leg2 = doc.instances
    assert (box.shape.geometry.kind, leg1.shape.geometry.kind, leg2.shape.geometry.kind) == \
        ("Box", "Cylinder", "Cylinder")
    assert box.shape.material is None, "a shape without Material is unlit"
    tex = box.shape.texture
    assert tex.urls == ["textures/wood.4.png"] and tex.path is None
    assert os.path.join(DATA, "textures", "wood.4.png") in tex.paths
    tt = box.shape.texture_transform
    assert (tt.scale, tt.center, tt.rotation, tt.translation) == ((1.0139, 1.90015), (0.5, 0.5),
                                                                 0, (0, 0))
    assert (leg1.shape.material.ambient_intensity, leg1.shape.material.diffuse,
            leg1.shape.material.shininess) == (0.574468, (1, 0.769946, 0.418716), 0.414894)
    assert leg2.shape.material.diffuse == (1, 0.75361, 0.353117)
    outer = (move((0, 2.5, 0)) @ rot((1, 0, 0), 1.57)
             @ move((0.81736, -0.000393301, 3.09967)) @ rot((0, 1, 0), 1.57295)
             @ move((3.12287, 0, -0.934591)) @ rot((0, 1, 0), 4.7022)
             @ np.diag([0.999999, 0.999998, 0.999999, 1]))
    axis = (1.84775e-06, 1, -1.84775e-06)
    so = rot((2.97959e-08, 1, -1.87755e-06), 1.5708)
    assert np.allclose(box.matrix, outer @ move((2.02399, 0.815218, 1.0783)) @ rot(axis, 4.71239)
                       @ np.diag([1, 0.02, 0.6, 1]), atol=1e-12)
    assert np.allclose(leg1.matrix, outer @ move((2, 0.3952, 1.7)) @ rot(axis, 4.71239) @ so
                       @ np.diag([0.15, 0.4, 0.15, 1]) @ so.T, atol=1e-12)
    assert np.allclose(leg2.matrix, outer @ move((2, 0.3952, 0.5))
                       @ np.diag([0.15, 0.4, 0.15, 1]), atol=1e-12)
    assert doc.warnings == ["texture files not found: textures/wood.4.png"]


def test_choreonoid_file_without_header_and_with_trailing_commas():
    doc = real("choreonoid_HAND_L.wrl")
    (inst,) = doc.instances
    mesh = inst.shape.geometry
    assert len(mesh.positions) == 8 and mesh.face_sizes.tolist() == [3] * 12
    assert mesh.positions[7].tolist() == [-0.015, 0.09, 0.01]
    assert faces(mesh)[:2] == [[7, 2, 3], [4, 7, 3]]
    mat = inst.shape.material
    assert (mat.name, mat.diffuse, mat.ambient_intensity) == ("FL", (0.85, 0.85, 0.85), 1.0)
    assert np.allclose(inst.matrix @ [0, 1, 0, 0], [0, 0, 1, 0], atol=1e-12)
    assert doc.warnings == ["files without a '#VRML V2.0 utf8' header, read as vrml97: "
                            "choreonoid_HAND_L.wrl"]


def test_choreonoid_fog_and_tunnel_light():
    doc = real("choreonoid_fog.wrl")
    assert doc.instances[0].shape.geometry.primitive == {"radius": 90}
    assert doc.instances[0].shape.material.diffuse == (1, 1, 1)
    assert doc.warnings == ["not imported (animation, interaction, scripts, sound, shaders, "
                            "fog): Fog"]
    doc = real("choreonoid_TunnelLight.wrl")
    (light,) = doc.lights
    assert (light.light.kind, light.light.ambient_intensity, light.light.color,
            light.light.direction, light.light.intensity, light.light.on) == \
        ("directional", 0.2, (1, 1, 1), (0, 0, -1), 0.7, True)
    assert light.matrix[:3, 3].tolist() == [0, 0, 5] and light.scope == range(0, 0)


def test_threejs_camera_file_with_vrml1_cameras_and_an_anchor():
    doc = real("threejs_camera.wrl")
    sphere, box = doc.instances
    assert sphere.shape.geometry.primitive == {"radius": 2.3}
    assert sphere.shape.material.diffuse == (0, 0, 1)
    assert sphere.matrix[:3, 3].tolist() == [3, 0, 1]
    assert box.shape.geometry.primitive == {"size": (2, 2, 2)}
    assert box.shape.material.emissive == (1, 1, 0) and box.shape.material.diffuse == \
        (0.8, 0.8, 0.8)
    assert box.matrix[:3, 3].tolist() == [2, 2.5, 1.25]
    (light,) = doc.lights
    assert light.light.direction == (1, 0, -1) and list(light.scope) == [0, 1]
    assert doc.viewpoint is None
    assert doc.warnings == ["unknown node types skipped (their children read where they have "
                            "them): OrthographicCamera, PerspectiveCamera"]


def test_threejs_3ds_max_export_with_texture_indices():
    doc = real("threejs_meshWithTexture.wrl")
    (inst,) = doc.instances
    mesh = inst.shape.geometry
    assert mesh.name == "Plane001FACES" and inst.shape.material.name == "Plane001"
    assert (inst.shape.material.diffuse, inst.shape.material.ambient_intensity,
            inst.shape.material.shininess) == ((0.5882, 0.5882, 0.5882), 1.0, 0.145)
    assert len(mesh.positions) == 25 and mesh.face_sizes.tolist() == [3] * 32
    assert np.array_equal(mesh.normals, np.tile([0, 1, 0], (96, 1)))
    # first face: coordIndex 5 0 6, texCoordIndex 15 10 16
    assert mesh.corners[:3].tolist() == [5, 0, 6]
    assert mesh.uvs[:3].tolist() == [[0, 0.25], [0, 0], [0.25, 0.25]]
    # scale 0.1 then 1.571 about +X (written as -1.571 about -X): (-20.27, 0, 21.37) → about
    # (-2.027, -2.137, 0)
    corner = inst.matrix @ np.append(mesh.positions[0], 1)
    assert np.allclose(corner[:3], [-2.027, -2.137, 0], atol=2e-3)
    assert doc.warnings == ["texture files not found: map.gif"]


def test_threejs_catia_export_with_shared_coordinates_lines_and_viewpoints():
    doc = real("threejs_meshWithLines.wrl")
    assert len(doc.instances) == 18 and not doc.warnings
    faces_ = [i.shape.geometry for i in doc.instances[:6]]
    lines = [i.shape.geometry for i in doc.instances[6:]]
    assert all(m.positions is faces_[0].positions for m in faces_), "one Coordinate USE'd"
    assert [faces(m) for m in faces_[:2]] == [[[7, 5, 6], [5, 4, 6]], [[6, 2, 7], [2, 3, 7]]]
    assert all(not m.solid for m in faces_)
    assert all(m.edges.tolist() == [[0, 1]] and len(m.positions) == 2 for m in lines)
    assert lines[0].positions.tolist() == [[-12, -13.5, -1.8], [-12, -13.5, 0]]
    first, line = doc.instances[0].shape.material, doc.instances[6].shape.material
    assert (first.name, first.diffuse) == ("_material0", (0.866667, 0.666667, 0.266667))
    assert (line.name, line.emissive, line.diffuse) == ("_material1", (0, 0, 0), (0.8, 0.8, 0.8))
    assert all(np.allclose(i.matrix, np.diag([0.1, 0.1, 0.1, 1])) for i in doc.instances)
    assert doc.instances[0].path == ("_000000002D59E720",)
    vp = doc.viewpoint
    assert (vp.position, vp.field_of_view, vp.description) == \
        ((0.411502, 0.183945, 0.216403), 0.471225, "Main Viewpoint")
    assert doc.navigation_types == ["EXAMINE", "WALK", "FLY"] and doc.headlight is True
    assert doc.background == (0, 0, 0) and doc.info == ["File created using CATIA"]


def test_x3dom_savage_drum_cylinders_and_shared_shapes():
    doc = real("x3dom_Drum55Gallon.x3d")
    assert (doc.encoding, doc.version, doc.profile) == ("x3d-xml", "3.2", "Interchange")
    assert doc.meta["title"] == "Drum55Gallon.x3d" and not doc.warnings
    shapes = [i.shape for i in doc.instances]
    assert [s.name for s in shapes] == ["", "Bunghole", "Rim", "MidProtrusions",
                                        "MidProtrusions", "BottomRim"]
    assert shapes[3] is shapes[4]
    assert [i.matrix[1, 3] for i in doc.instances] == [0, 0.42775, 0.433, 0.13, -0.13, -0.42]
    blue = shapes[0].material
    assert blue.name == "Blue" and blue.diffuse == (0.062745, 0, 0.8)
    assert all(s.material is blue for s in shapes if s.name != "Bunghole")
    assert shapes[1].material.name == "Bunghole" and shapes[1].material.diffuse == (0.8,) * 3
    drum, rim = shapes[0].geometry, shapes[2].geometry
    assert drum.name == "Drum" and drum.primitive == {"radius": 0.28575, "height": 0.8509,
                                                      "top": True, "bottom": True, "side": True}
    assert np.allclose(sorted(set(np.round(drum.positions[:, 1], 12))), [-0.42545, 0.42545])
    assert rim.primitive["top"] is False and rim.solid is False
    assert len(rim.face_sizes) == x3d.SEGMENTS + 1


# -- more of the encodings --------------------------------------------------------------------

def test_xml_proto_declare_instance_and_extern_proto(tmp_path):
    write(tmp_path, "lib.x3d", xml("""
      <ProtoDeclare name='Ball'><ProtoInterface>
        <field name='r' type='SFFloat' accessType='initializeOnly' value='1'/></ProtoInterface>
        <ProtoBody><Shape><Sphere><IS><connect nodeField='radius' protoField='r'/></IS></Sphere>
        </Shape></ProtoBody></ProtoDeclare>"""))
    doc = read(xml("""
      <ExternProtoDeclare name='Ball' url='"lib.x3d#Ball"'>
        <field name='r' type='SFFloat' accessType='initializeOnly'/></ExternProtoDeclare>
      <ProtoDeclare name='Post'>
        <ProtoInterface>
          <field name='where' type='SFVec3f' accessType='inputOutput' value='0 0 0'/>
          <field name='tint' type='SFColor' accessType='inputOutput' value='1 0 0'/>
          <field name='extra' type='MFNode' accessType='inputOutput'/>
        </ProtoInterface>
        <ProtoBody>
          <Transform><IS><connect nodeField='translation' protoField='where'/></IS>
            <Shape><Appearance><Material><IS><connect nodeField='diffuseColor' protoField='tint'/>
            </IS></Material></Appearance><Box/></Shape>
            <Group><IS><connect nodeField='children' protoField='extra'/></IS></Group></Transform>
          <Script DEF='S'><field name='n' type='SFNode' accessType='initializeOnly'><Group/></field>
            <![CDATA[ecmascript: function initialize() {}]]></Script>
        </ProtoBody>
      </ProtoDeclare>
      <ProtoInstance name='Post' DEF='P1'>
        <fieldValue name='where' value='1 2 3'/>
        <fieldValue name='extra'><Shape><Cone/></Shape></fieldValue>
      </ProtoInstance>
      <ProtoInstance name='Post'><fieldValue name='tint' value='0 0 1'/></ProtoInstance>
      <ProtoInstance name='Ball'><fieldValue name='r' value='4'/></ProtoInstance>
      <Transform translation='0 9 0'><ProtoInstance USE='P1'/></Transform>"""), "main.x3d",
               folder=tmp_path)
    assert kinds(doc) == ["Box", "Cone", "Box", "Sphere", "Box", "Cone"]
    box, cone = doc.instances[:2]
    assert box.matrix[:3, 3].tolist() == [1, 2, 3] and box.shape.material.diffuse == (1, 0, 0)
    assert doc.instances[2].shape.material.diffuse == (0, 0, 1)
    assert doc.instances[3].shape.geometry.primitive == {"radius": 4}
    assert doc.instances[4].shape is box.shape and doc.instances[4].matrix[1, 3] == 11
    assert cone.path == ("P1",)


def test_classic_header_statements_are_read_or_skipped_cleanly():
    doc = read("""#X3D V4.0 utf8
    PROFILE Interchange
    COMPONENT Geometry3D:2
    COMPONENT CADGeometry : 1
    META "creator" "someone"
    UNIT length centimetre 0.01
    IMPORT Inlined.Exported AS Local
    EXPORT Shown AS Seen
    DEF Shown Shape { geometry Box {} }
    EXPORT Shown
    """, "header.x3dv")
    assert (doc.encoding, doc.version, doc.profile, doc.meter) == ("x3d-classic", "4.0",
                                                                  "Interchange", 0.01)
    assert doc.meta == {"creator": "someone"} and kinds(doc) == ["Box"] and not doc.warnings


def test_urls_resolve_relative_to_the_file_and_other_schemes_are_not_fetched(tmp_path):
    base = str(tmp_path)
    assert x3d.resolve_local("maps/a b.png", base) == os.path.join(base, "maps", "a b.png")
    assert x3d.resolve_local("maps/a%20b.png", base) == os.path.join(base, "maps", "a b.png")
    assert x3d.resolve_local("part.wrl#Viewpoint1", base) == os.path.join(base, "part.wrl")
    assert x3d.resolve_local("file:///data/x.png", base) == "/data/x.png"
    assert x3d.resolve_local("maps\\wood.png", base) == os.path.join(base, "maps", "wood.png")
    for url in ("http://example.com/a.wrl", "https://x/y.png", "urn:web3d:media:a", ""):
        assert x3d.resolve_local(url, base) is None
    seen = []

    def resolver(url, folder):
        seen.append((url, folder))
        return None

    doc = x3d.loads(VRML + 'Inline { url "part.wrl" }', os.path.join(base, "main.wrl"),
                    resolver=resolver)
    assert seen == [("part.wrl", base)]
    warned(doc, "Inline files not found")


def test_a_file_that_is_not_utf8_is_read_as_latin1():
    doc = read(VRML.encode() + 'WorldInfo { title "Caf\xe9" } Shape { geometry Box {} }'
               .encode("latin-1"))
    assert doc.title == "Café" and kinds(doc) == ["Box"]
    warned(doc, "Latin-1")


def test_large_numeric_arrays_are_read_in_bulk(tmp_path):
    """About 10 MB: 200,000 positions and 200,000 triangles, read within a few seconds (a 50 MB
    file took about 1 s on the development machine)."""
    rng = np.random.default_rng(5)
    points = np.round(rng.random((200_000, 3)) * 100, 4)
    tris = rng.integers(0, len(points), (200_000, 3))
    text = (VRML + "Shape { geometry IndexedFaceSet { coord Coordinate { point [\n"
            + ",\n".join(" ".join(map(repr, p)) for p in points.tolist())
            + "] }\ncoordIndex [\n"
            + "\n".join(f"{a} {b} {c} -1" for a, b, c in tris.tolist()) + "] } }")
    path = write(tmp_path, "big.wrl", text)
    doc = timed(x3d.load, path, limit=8.0)
    mesh = doc.instances[0].shape.geometry
    assert np.array_equal(mesh.positions, points)
    assert np.array_equal(mesh.corners, tris.reshape(-1)) and len(mesh.face_sizes) == 200_000


def test_a_cycle_in_a_graph_built_by_hand_is_cut():
    inner = x3d.Transform(name="a")
    outer = x3d.Transform(name="b", children=[inner, x3d.Shape(geometry=x3d.Mesh())])
    inner.children.append(outer)
    doc = x3d.Document(root=x3d.Transform(kind="Scene", children=[inner]))
    timed(doc.flatten)
    assert [i.path for i in doc.instances] == [("a", "b")]
    warned(doc, "cycle")
