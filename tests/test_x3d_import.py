# SPDX-License-Identifier: GPL-3.0-or-later
"""VRML97 / X3D imported into Blender (issue 36; addon/interchange/x3d_import.py).

Hand-written files for each rule of the standards (written here into a temporary folder, and
the two scenes of the comparisons in tests/data/x3d: ``hand_rules.x3dv``, ``hand_scope.wrl``):
every light type with non-default fields after UNIT and the axis turn (values worked out by
hand below), VRML97's and X3D's spot defaults, scoped lights as Light Linking, ``on FALSE``,
DEF/USE sharing, PROTO, Inline, gzip, textures (RGB replaces the diffuse colour, grey
multiplies it), colours, unlit shapes, TextureTransform, the headlight; the data blocks an
import adds; a failed import leaves the file as it was; the drop handler; the real files of
tests/data/x3d with the counts read from them; and the rendered pixels: Cycles and Eevee
against the standard's equation (the comparison engine's reference, ``node_groups/reference.py``)
and against values worked out by hand.
"""

from __future__ import annotations

import gzip
import math
import os
import struct
import zlib

import numpy as np
import pytest

import blender_env as be

DATA = os.path.join(os.path.dirname(os.path.abspath(__file__)), "data", "x3d")
F32 = np.float32


def _f32(values):
    return pytest.approx(tuple(float(v) for v in F32(values)), abs=0)


def write(tmp_path, name, text):
    path = tmp_path / name
    path.write_text(text)
    return str(path)


def png(path, pixels, bits=8) -> str:
    """A PNG file of *pixels* ((h, w) grey or (h, w, 3) RGB, integers; first row the top),
    written with the standard library: no image library decides the channels."""
    pixels = np.asarray(pixels)
    h, w = pixels.shape[:2]
    comps = 1 if pixels.ndim == 2 else pixels.shape[2]
    kind = {1: 0, 2: 4, 3: 2, 4: 6}[comps]
    dtype = ">u2" if bits == 16 else "u1"
    rows = pixels.astype(dtype).reshape(h, -1)
    raw = b"".join(b"\0" + rows[y].tobytes() for y in range(h))

    def chunk(tag, data):
        return (struct.pack(">I", len(data)) + tag + data
                + struct.pack(">I", zlib.crc32(tag + data) & 0xFFFFFFFF))

    data = (b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", w, h, bits, kind,
                                                             0, 0, 0))
            + chunk(b"IDAT", zlib.compress(raw)) + chunk(b"IEND", b""))
    with open(path, "wb") as handle:
        handle.write(data)
    return str(path)


def _import(bpy, path):
    assert bpy.ops.phong.import_x3d(filepath=str(path)) == {"FINISHED"}


def _controls(material):
    """The colours the lights group reads (from its control nodes) and the scalar controls."""
    nodes = material.node_tree.nodes
    lights = nodes["phong_lights"]

    def colour(name):
        return tuple(lights.inputs[name].links[0].from_node.outputs[0].default_value)[:3]

    return {"Kd": colour("Object Color"), "Ka": colour("Ambient Object Color"),
            "Ks": colour("Specular Color"), "Ke": colour("Irradiant Color"),
            "exponent": nodes["phong_exponent"].outputs[0].default_value,
            "opacity": nodes["phong_opacity"].outputs[0].default_value}


def _ids(bpy):
    return {kind: {b.name for b in getattr(bpy.data, kind)} for kind in
            ("objects", "meshes", "materials", "lights", "cameras", "images", "worlds",
             "node_groups", "collections")}


# -- values ---------------------------------------------------------------------------------

LIGHTS = """#X3D V3.3 utf8
PROFILE Immersive
UNIT length half 0.5
NavigationInfo { headlight FALSE }
Transform { translation 0 4 0 scale 2 2 2 children [
  DEF Bulb PointLight { location 1 2 3 intensity 0.75 ambientIntensity 0.125 color 1 0.5 0.25
                        attenuation 0.5 0.2 0.1 radius 5 }
  DEF Beam SpotLight { location 0 1 0 direction 1 -1 0 beamWidth 0.2 cutOffAngle 0.5
                       intensity 0.5 ambientIntensity 0.25 attenuation 1 0.4 0 radius 7
                       color 0.5 1 0.5 }
  DEF Sky DirectionalLight { direction 0 -1 0 intensity 0.25 ambientIntensity 0.5
                             color 0.1 0.2 0.3 global TRUE }
  DEF Dark PointLight { on FALSE }
  DEF Crate Shape {
    appearance Appearance { material DEF Paint Material {
      diffuseColor 0.8 0.4 0.2 ambientIntensity 0.25 specularColor 0.5 0.5 0.5
      emissiveColor 0.1 0 0 shininess 0.5 transparency 0.25 } }
    geometry Box { size 2 2 2 }
  }
] }
"""


def test_every_light_type_with_its_fields_after_unit_scale_and_axes(bpy_clean, tmp_path):
    """By hand: a file unit of half a metre, Y up (Blender (x, y, z) = (fx, −fz, fy)), the
    lights under translation (0 4 0) and scale 2.  Bulb at 2·(1, 2, 3) + (0, 4, 0) = (2, 8, 6)
    half-units = (1, 4, 3) m → Blender (1, −3, 4); its radius 5 × 2 (the group's scale) × 0.5
    = 5 m; the attenuation's distance is the light's own (half-units of the scaled group: 1 m
    is 1 / (0.5 · 2) = 1 of them), a1 = 0.2 / 1 = 0.2 per metre, a2 = 0.1 / 1² = 0.1 per m²."""
    bpy = bpy_clean
    _import(bpy, write(tmp_path, "lights.x3dv", LIGHTS))
    objects = bpy.data.objects
    bulb, beam, sky = objects["Bulb"], objects["Beam"], objects["Sky"]
    assert (bulb.data.type, beam.data.type, sky.data.type) == ("POINT", "SPOT", "SUN")
    assert tuple(bulb.matrix_world.translation) == pytest.approx((1, -3, 4), abs=1e-6)
    assert tuple(bulb.data.color) == _f32((1, 0.5, 0.25))
    assert bulb.data["phong_intensity"] == 0.75 and bulb.data["phong_light_ambient"] == 0.125
    assert bulb.data["phong_constant"] == 0.5
    assert bulb.data["phong_linear"] == pytest.approx(0.2, rel=1e-15)
    assert bulb.data["phong_quadratic"] == pytest.approx(0.1, rel=1e-15)
    assert bulb.data["phong_radius"] == pytest.approx(5.0, rel=1e-12)
    # Beam at 2·(0, 1, 0) + (0, 4, 0) = (0, 6, 0) half-units = (0, 3, 0) m → Blender (0, 0, 3);
    # its direction (1, −1, 0)/√2 → Blender (1, 0, −1)/√2, the light's −Z axis
    assert tuple(beam.matrix_world.translation) == pytest.approx((0, 0, 3), abs=1e-6)
    axis = -np.array(beam.matrix_world.col[2][:3])
    assert axis == pytest.approx((2 ** -0.5, 0, -2 ** -0.5), abs=1e-6)
    assert beam.data.spot_size == pytest.approx(1.0, abs=1e-7), "2 × cutOffAngle"
    assert beam.data["phong_beam_width"] == 0.2
    assert beam.data["phong_radius"] == pytest.approx(7.0) and beam.data["phong_linear"] == \
        pytest.approx(0.4)
    assert (beam.data["phong_intensity"], beam.data["phong_light_ambient"]) == (0.5, 0.25)
    assert -np.array(sky.matrix_world.col[2][:3]) == pytest.approx((0, 0, -1), abs=1e-7)
    assert (sky.data["phong_intensity"], sky.data["phong_light_ambient"]) == (0.25, 0.5)
    assert tuple(sky.data.color) == _f32((0.1, 0.2, 0.3))
    assert sky.light_linking.receiver_collection is None, "global TRUE: no linking"
    dark = objects["Dark (off)"]
    assert dark.hide_render and not bulb.hide_render, "on FALSE: hidden from render"
    assert "Headlight" not in objects, "headlight FALSE"
    # the shape: scale 2 at (0, 2, 0) m, its box ±1 half-unit = ±0.5 m: Blender x, y ∈ ±1,
    # z ∈ [1, 3]
    crate = objects["Crate"]
    corners = np.array([tuple(crate.matrix_world @ v.co) for v in crate.data.vertices])
    assert corners.min(axis=0) == pytest.approx((-1, -1, 1), abs=1e-6)
    assert corners.max(axis=0) == pytest.approx((1, 1, 3), abs=1e-6)
    got = _controls(bpy.data.materials["Paint"])
    assert got["Kd"] == _f32((0.8, 0.4, 0.2))
    assert got["Ka"] == _f32((0.2, 0.1, 0.05)), "ambientIntensity × diffuseColor"
    assert got["Ks"] == _f32((0.5, 0.5, 0.5)) and got["Ke"] == _f32((0.1, 0, 0))
    assert got["exponent"] == 64.0 and got["opacity"] == 0.75
    scene = bpy.context.scene
    assert scene["phong_model"] == "x3d" and scene.phong.model == "x3d"
    assert scene.world.phong.ambient_intensity == 0.0, "no global ambient light in X3D"
    material = bpy.data.materials["Paint"]
    tree = material.node_tree.nodes["phong_lights"].node_tree
    assert tree.name == "X3D Lights Scene", "the scene's X3D lights group"


@pytest.mark.parametrize("header, beam, cut", [
    ("#VRML V2.0 utf8", 1.570796, 0.785398),
    ("#X3D V3.3 utf8\nPROFILE Immersive", 0.7854, 1.570796),
], ids=["vrml97", "x3d"])
def test_spot_defaults_of_each_standard(bpy_clean, tmp_path, header, beam, cut):
    bpy = bpy_clean
    _import(bpy, write(tmp_path, "spot.wrl", f"{header}\nDEF S SpotLight {{ }}\n"))
    spot = bpy.data.objects["S"].data
    assert spot.spot_size == pytest.approx(2 * cut, abs=1e-6)
    assert spot["phong_beam_width"] == beam


SCOPED = """#VRML V2.0 utf8
NavigationInfo { headlight FALSE }
DEF G Group { children [
  DirectionalLight { direction 0 -1 0 }
  DEF A Shape { appearance Appearance { material DEF M Material { } } geometry Box { } }
  Transform { translation 3 0 0 children DEF B Shape {
    appearance Appearance { material USE M } geometry Sphere { } } }
] }
Transform { translation 0 0 -6 children USE G }
DEF C Shape { appearance Appearance { material USE M } geometry Cone { } }
PointLight { location 0 5 0 }
"""


def test_scoped_directional_light_reaches_exactly_its_group(bpy_clean, tmp_path):
    """VRML97's DirectionalLight lights its siblings and their descendants: A and B and their
    copies through USE G (the same light at the same direction: one Blender light reaching
    both), never C; the PointLight is global."""
    bpy = bpy_clean
    _import(bpy, write(tmp_path, "scoped.wrl", SCOPED))
    objects = bpy.data.objects
    suns = [o for o in objects if o.type == "LIGHT" and o.data.type == "SUN"]
    assert len(suns) == 1, "the USE'd group's light at the same direction is one light"
    receivers = suns[0].light_linking.receiver_collection
    assert sorted(o.name for o in receivers.objects) == ["A", "A.001", "B", "B.001"]
    point = next(o for o in objects if o.type == "LIGHT" and o.data.type == "POINT")
    assert point.light_linking.receiver_collection is None
    from phong_nodes.addon.lighting import recipe  # noqa: PLC0415

    def lights_of(name):
        material = objects[name].material_slots[0].material
        group = material.node_tree.nodes[recipe.LIGHTS_NODE].node_tree
        return sorted(group["phong_lights"])

    assert lights_of("A") == lights_of("B.001") == sorted([suns[0].name, point.name])
    assert lights_of("C") == [point.name]
    # one core Material, two light sets: the file's name, and the variant for C's set
    assert objects["A"].material_slots[0].material.name == "M"
    assert objects["C"].material_slots[0].material.name == f"M [{point.name}]"
    assert objects["A"].data is objects["A.001"].data, "DEF/USE: one mesh"


def test_x3d_global_field_and_a_scope_without_shapes(bpy_clean, tmp_path):
    bpy = bpy_clean
    _import(bpy, write(tmp_path, "global.x3dv", """#X3D V3.3 utf8
PROFILE Immersive
NavigationInfo { headlight FALSE }
Group { children [
  DEF Local PointLight { global FALSE }
  DEF Everywhere DirectionalLight { global TRUE }
  DEF Inside Shape { geometry Box { } }
] }
Group { children [ DEF Nowhere DirectionalLight { } ] }
DEF Outside Shape { geometry Box { } }
"""))
    objects = bpy.data.objects
    assert [o.name for o in objects["Local"].light_linking.receiver_collection.objects] == \
        ["Inside"]
    assert objects["Everywhere"].light_linking.receiver_collection is None
    nowhere = objects["Nowhere"]   # its group holds no shape: it lights nothing
    assert nowhere.hide_render and nowhere.light_linking.receiver_collection is None


def test_def_use_shares_meshes_and_materials_proto_and_inline(bpy_clean, tmp_path):
    bpy = bpy_clean
    write(tmp_path, "part.wrl", """#VRML V2.0 utf8
DEF Part Shape { appearance Appearance { material DEF Steel Material {
  diffuseColor 0.5 0.5 0.6 } } geometry Box { size 1 2 3 } }
""")
    _import(bpy, write(tmp_path, "main.wrl", """#VRML V2.0 utf8
NavigationInfo { headlight FALSE }
PROTO Tinted [ field SFColor tint 1 1 1 ] {
  Shape { appearance Appearance { material DEF Tint Material { diffuseColor IS tint } }
          geometry Sphere { radius 0.5 } }
}
DEF Peg Shape { appearance Appearance { material DEF Wood Material { diffuseColor 0.6 0.4 0.2 } }
                geometry DEF Stick Cylinder { radius 0.1 height 2 } }
Transform { translation 2 0 0 children USE Peg }
Transform { translation 4 0 0 children Shape {
  appearance Appearance { material USE Wood } geometry USE Stick } }
Transform { translation 6 0 0 children Shape {
  appearance Appearance { material DEF Iron Material { diffuseColor 0.3 0.3 0.3 } }
  geometry USE Stick } }
Transform { translation 0 3 0 children Tinted { tint 1 0 0 } }
Transform { translation 2 3 0 children Tinted { tint 0 0 1 } }
Transform { translation 0 6 0 children Inline { url "part.wrl" } }
Transform { translation 3 6 0 children Inline { url "part.wrl" } }
"""))
    objects = bpy.data.objects
    pegs = [o for o in objects if o.type == "MESH" and o.data.name == "Stick"]
    assert len(pegs) == 4 and len({o.data.name for o in pegs}) == 1, "one mesh, four objects"
    assert sorted(o.material_slots[0].material.name for o in pegs) == \
        ["Iron", "Wood", "Wood", "Wood"]
    iron = next(o for o in pegs if o.material_slots[0].material.name == "Iron")
    assert iron.material_slots[0].link == "OBJECT", "the shared mesh keeps Wood in its slot"
    balls = [o for o in objects if o.type == "MESH" and o.data.polygons
             and len(o.data.polygons) == 512]   # the PROTO's Sphere (32 × 16)
    assert len(balls) == 2 and balls[0].data is balls[1].data, "no IS reaches it: shared"
    tints = sorted((o.material_slots[0].material for o in balls), key=lambda m: m.name)
    assert [m.name for m in tints] == ["Tint", "Tint.001"], "each PROTO instance its own"
    assert {_controls(m)["Kd"] for m in tints} == {_f32((1, 0, 0)).expected,
                                                   _f32((0, 0, 1)).expected}
    parts = [o for o in objects if o.name.startswith("Part")]
    assert len(parts) == 2 and parts[0].data is parts[1].data, "a file inlined twice: shared"
    assert sorted(tuple(round(c, 6) for c in o.matrix_world.translation) for o in parts) == \
        [(0.0, 0.0, 6.0), (3.0, 0.0, 6.0)]
    assert [m.name for m in bpy.data.materials if m.name.startswith("Steel")] == ["Steel"]


def test_a_sheared_transform_is_exact_through_the_parent_inverse(bpy_clean, tmp_path):
    """scale 2 1 1 with scaleOrientation 0.5 rad about Z: the matrix R(0.5)·diag(2, 1, 1)·
    R(−0.5) shears the box, which location, rotation and scale cannot hold."""
    bpy = bpy_clean
    _import(bpy, write(tmp_path, "shear.wrl", """#VRML V2.0 utf8
Transform { translation 1 2 3 scale 2 1 1 scaleOrientation 0 0 1 0.5
  children DEF Skew Shape { geometry Box { } } }
"""))
    skew = bpy.data.objects["Skew"]
    assert skew.parent is not None and skew.parent.type == "EMPTY"
    c, s = math.cos(0.5), math.sin(0.5)
    r = np.array([[c, -s, 0], [s, c, 0], [0, 0, 1]])
    m = r @ np.diag([2.0, 1.0, 1.0]) @ r.T
    y_up = np.array([[1, 0, 0], [0, 0, -1], [0, 1, 0]])   # (x, y, z) → (x, −z, y)
    for vertex in skew.data.vertices:
        want = y_up @ (m @ np.array(vertex.co) + (1, 2, 3))
        assert tuple(skew.matrix_world @ vertex.co) == pytest.approx(tuple(want), abs=1e-6)


def test_gzipped_files_by_their_bytes(bpy_clean, tmp_path):
    bpy = bpy_clean
    path = tmp_path / "crate.wrz"
    path.write_bytes(gzip.compress(b"#VRML V2.0 utf8\nDEF Crate Shape { geometry Box { } }\n"))
    _import(bpy, path)
    assert len(bpy.data.objects["Crate"].data.polygons) == 6


def test_crease_angle_normals_lines_and_points(bpy_clean, tmp_path):
    bpy = bpy_clean
    _import(bpy, write(tmp_path, "shading.wrl", """#VRML V2.0 utf8
DEF Flat Shape { geometry IndexedFaceSet {
  coord DEF Roof Coordinate { point [ 0 0 0, 1 0 0, 1 0.2 1, 0 0.2 1, 1 0 2, 0 0 2 ] }
  coordIndex [ 0 3 2 1 -1, 3 5 4 2 -1 ] } }
DEF Smooth Shape { geometry IndexedFaceSet { creaseAngle 0.5
  coord USE Roof coordIndex [ 0 3 2 1 -1, 3 5 4 2 -1 ] } }
DEF Sharp Shape { geometry IndexedFaceSet { creaseAngle 0.3
  coord USE Roof coordIndex [ 0 3 2 1 -1, 3 5 4 2 -1 ] } }
DEF Given Shape { geometry IndexedFaceSet {
  coord USE Roof coordIndex [ 0 3 2 1 -1 ]
  normal Normal { vector [ 0 1 0, 0 0 1 ] } normalIndex [ 0 0 1 1 -1 ] } }
DEF Wire Shape { geometry IndexedLineSet { coord USE Roof coordIndex [ 0 1 2 -1, 4 5 -1 ] } }
DEF Dots Shape { geometry PointSet { coord USE Roof
  color Color { color [ 1 0 0, 0 1 0, 0 0 1, 1 1 0, 0 1 1, 1 0 1 ] } } }
"""))
    objects = bpy.data.objects
    # the two faces meet at 2·atan(0.2) = 0.395 rad: smooth under 0.5, sharp under 0.3
    flat, smooth, sharp = (objects[n].data for n in ("Flat", "Smooth", "Sharp"))
    assert not any(p.use_smooth for p in flat.polygons)
    middle = [e for e in smooth.edges if sorted(e.vertices) == [2, 3]]
    assert all(p.use_smooth for p in smooth.polygons) and not middle[0].use_edge_sharp
    assert [e.use_edge_sharp for e in sharp.edges if sorted(e.vertices) == [2, 3]] == [True]
    given = objects["Given"].data
    normals = np.zeros(len(given.loops) * 3, dtype=np.float32)
    given.corner_normals.foreach_get("vector", normals)
    # file (0, 1, 0) and (0, 0, 1) in the object's own (file) axes
    assert normals.reshape(-1, 3) == pytest.approx(np.array([[0, 1, 0]] * 2 + [[0, 0, 1]] * 2),
                                                   abs=1e-3)
    wire = objects["Wire"].data
    assert (len(wire.polygons), sorted(sorted(e.vertices) for e in wire.edges)) == \
        (0, [[0, 1], [1, 2], [4, 5]])
    dots = objects["Dots"].data
    assert (len(dots.vertices), len(dots.edges), len(dots.polygons)) == (6, 0, 0)
    colours = dots.color_attributes["Col"]
    assert colours.domain == "POINT" and tuple(colours.data[2].color) == (0, 0, 1, 1)


# -- what an import adds -------------------------------------------------------------------

def test_an_import_adds_exactly_the_files_materials_as_phong(bpy_clean, tmp_path):
    bpy = bpy_clean
    # the user's own material named like one of the file's, and its object
    mine = bpy.data.materials.new("Stone")
    before = _ids(bpy)
    _import(bpy, os.path.join(DATA, "hand_rules.x3dv"))
    after = _ids(bpy)
    from phong_nodes.addon.lighting import recipe  # noqa: PLC0415

    added = after["materials"] - before["materials"]
    # Stone, Clay, and Clay for the second ball's light set (not the Blue light's scope)
    assert added == {"Stone.001", "Clay", "Clay [Cone, Headlight, Lamp]"}
    assert all(recipe.is_phong_material(bpy.data.materials[n]) for n in added)
    assert all(bpy.data.materials[n].users >= 1 for n in added), "nothing unused"
    assert not recipe.is_phong_material(mine) and mine.name == "Stone", "the user's untouched"
    assert after["images"] == before["images"]
    assert after["objects"] - before["objects"] == {"Ground", "Ball", "Ball.001", "Lamp",
                                                    "Cone", "Blue", "Headlight", "Front"}
    assert after["collections"] - before["collections"] == {"hand_rules", "Blue scope"}
    assert after["meshes"] - before["meshes"] == {"Ground", "Ball"}, "named by their shapes"
    from phong_nodes.node_groups import library  # noqa: PLC0415

    assert all(n in library.GROUPS or n in library.RIG_GROUPS or n.startswith("X3D Lights ")
               for n in after["node_groups"] - before["node_groups"])


def test_a_failed_import_leaves_the_file_as_it_was(bpy_clean, tmp_path, monkeypatch):
    bpy = bpy_clean
    scene = bpy.context.scene
    scene.world = bpy.data.worlds.new("Mine")
    scene.world["phong_ambient_intensity"] = 0.3
    before = _ids(bpy)
    for name, text, message in (
            ("vrml1.wrl", "#VRML V1.0 ascii\nSeparator { }\n", "VRML 1.0"),
            ("drawing.x3d", '<svg xmlns="http://www.w3.org/2000/svg"/>', "not an X3D file"),
            ("notes.wrl", "hello, this is not a scene\n", "not a VRML97 or X3D file"),
            ("ents.x3d", '<?xml version="1.0"?><!DOCTYPE X3D [<!ENTITY a "b">]><X3D/>',
             "entit")):
        with pytest.raises(RuntimeError, match=message):
            bpy.ops.phong.import_x3d(filepath=write(tmp_path, name, text))
    with pytest.raises(RuntimeError, match="gone.wrl"):
        bpy.ops.phong.import_x3d(filepath=str(tmp_path / "gone.wrl"))
    from phong_nodes.addon.interchange import x3d_import  # noqa: PLC0415

    # an error in the middle of building (after the lights and the model switch)
    def boom(*_args):
        raise ValueError("boom")

    monkeypatch.setattr(x3d_import._Builder, "material", boom)   # its lights group made
    with pytest.raises(x3d_import.X3DImportError, match="boom"):
        x3d_import.import_file(bpy.context, os.path.join(DATA, "hand_rules.x3dv"))
    assert _ids(bpy) == before
    assert "phong_model" not in scene.keys() and scene.camera is None
    assert scene.world["phong_ambient_intensity"] == 0.3
    assert sorted(scene.world.keys()) == ["phong_ambient_intensity"], "no light's World key"
    assert scene.world.animation_data is None or not scene.world.animation_data.drivers
    assert sorted(os.listdir(tmp_path)) == ["drawing.x3d", "ents.x3d", "notes.wrl", "vrml1.wrl"]


def test_menus_and_file_handler_exist(bpy_clean):
    bpy = bpy_clean
    for name in ("PHONG_OT_import_x3d", "PHONG_OT_export_x3d", "PHONG_OT_add_headlight"):
        assert hasattr(bpy.types, name)
    if hasattr(bpy.types, "FileHandler"):
        handler = bpy.types.PHONG_FH_x3d
        assert handler.bl_import_operator == "phong.import_x3d"
        assert handler.bl_file_extensions.split(";") == [
            ".wrl", ".wrz", ".x3d", ".x3dz", ".x3dv", ".x3dvz", ".gz"]

        class Area:
            type = "VIEW_3D"

        assert handler.poll_drop(type("C", (), {"area": Area()})())
        assert not handler.poll_drop(type("C", (), {"area": None})())
    prop = bpy.ops.phong.import_x3d.get_rna_type().properties["filepath"]
    assert prop.is_skip_save, "a dropped file's path is set before invoke"
    labels = []

    class Layout:
        def operator(self, idname, text="", icon=""):
            labels.append((idname, text))

        def separator(self):
            pass

    for menu in (bpy.types.TOPBAR_MT_file_import, bpy.types.TOPBAR_MT_file_export,
                 bpy.types.VIEW3D_MT_light_add):
        for draw in menu._dyn_ui_initialize():
            if getattr(draw, "__module__", "").endswith("x3d_ui"):
                draw(type("Menu", (), {"layout": Layout()})(), bpy.context)
    assert ("phong.import_x3d", "X3D / VRML97 (Phong)") in labels
    assert ("phong.export_x3d", "X3D / VRML97 (Phong)") in labels
    assert any(idname == "phong.add_headlight" for idname, _text in labels)


# -- the camera and the headlight ----------------------------------------------------------

def test_viewpoint_fov_is_the_smaller_side_and_ortho(bpy_clean, tmp_path):
    bpy = bpy_clean
    scene = bpy.context.scene
    scene.render.resolution_x, scene.render.resolution_y = 200, 100
    _import(bpy, write(tmp_path, "vp.x3dv", """#X3D V3.3 utf8
PROFILE Immersive
DEF Eye Viewpoint { position 1 2 3 orientation 0 1 0 1.5707963267948966 fieldOfView 0.6 }
"""))
    camera = bpy.data.objects["Eye"]
    assert scene.camera is camera
    assert camera.data.sensor_fit == "VERTICAL" and camera.data.angle == pytest.approx(0.6)
    # file (1, 2, 3) → Blender (1, −3, 2); turned 90° about file +Y (Blender +Z): it looks
    # along file −X (Blender −X)
    assert tuple(camera.matrix_world.translation) == pytest.approx((1, -3, 2), abs=1e-6)
    look = -np.array(camera.matrix_world.col[2][:3])
    assert look == pytest.approx((-1, 0, 0), abs=1e-6)
    head = bpy.data.objects["Headlight"]
    constraint = head.constraints[0]
    assert (head.data.type, constraint.type, constraint.target) == \
        ("SUN", "COPY_TRANSFORMS", camera)
    assert (head.data["phong_intensity"], head.data["phong_light_ambient"]) == (1.0, 0.0)
    assert tuple(head.data.color) == (1.0, 1.0, 1.0)
    be.reset_empty_file()
    scene = bpy.context.scene
    scene.render.resolution_x, scene.render.resolution_y = 100, 200   # portrait
    _import(bpy, write(tmp_path, "ortho.x3dv", """#X3D V3.3 utf8
PROFILE Immersive
NavigationInfo { headlight FALSE }
DEF Plan OrthoViewpoint { position 0 0 5 fieldOfView -2 -1 4 3 }
"""))
    plan = bpy.data.objects["Plan"]
    # 6 wide and 4 high, centred at (1, 1): in a portrait view the width limits it
    assert plan.data.type == "ORTHO" and plan.data.sensor_fit == "HORIZONTAL"
    assert plan.data.ortho_scale == pytest.approx(6.0)
    assert tuple(plan.matrix_world.translation) == pytest.approx((1, -5, 1), abs=1e-6)
    assert "Headlight" not in bpy.data.objects and scene["phong_x3d_no_headlight"]
    be.reset_empty_file()
    _import(bpy, write(tmp_path, "none.wrl", "#VRML V2.0 utf8\nShape { geometry Box { } }\n"))
    camera = bpy.context.scene.camera   # X3D's default viewpoint
    assert tuple(camera.matrix_world.translation) == pytest.approx((0, -10, 0), abs=1e-6)
    assert camera.data.angle == pytest.approx(0.785398, abs=1e-6)


@pytest.mark.slow
def test_a_second_import_keeps_one_headlight_and_a_model_switch_is_said(bpy_clean, tmp_path,
                                                                         capfd, monkeypatch):
    bpy = bpy_clean
    scene = bpy.context.scene
    # the user's own Phong material in the seeds' model
    mesh = bpy.data.meshes.new("Mine")
    mesh.from_pydata([(0, 0, 0), (1, 0, 0), (0, 1, 0)], [], [(0, 1, 2)])
    mine = bpy.data.objects.new("Mine", mesh)
    scene.collection.objects.link(mine)
    mine.select_set(True)
    bpy.context.view_layer.objects.active = mine
    assert bpy.ops.phong.apply_material() == {"FINISHED"}
    capfd.readouterr()
    _import(bpy, os.path.join(DATA, "hand_rules.x3dv"))
    assert "switched from the seeds lighting model to X3D / VRML97" in capfd.readouterr().out
    _import(bpy, os.path.join(DATA, "hand_rules.x3dv"))
    heads = [o for o in bpy.data.objects if o.name.startswith("Headlight")]
    assert len(heads) == 1, "the viewer has one headlight"
    assert heads[0].constraints[0].target is scene.camera and scene.camera.name == "Front.001"
    assert {"Clay", "Clay.001", "Stone", "Stone.001"} <= {m.name for m in bpy.data.materials}
    from phong_nodes.addon.interchange import x3d_import  # noqa: PLC0415

    monkeypatch.setattr(x3d_import._Builder, "material", lambda *a: 1 / 0)
    with pytest.raises(x3d_import.X3DImportError):
        x3d_import.import_file(bpy.context, os.path.join(DATA, "hand_rules.x3dv"))
    assert heads[0].constraints[0].target is scene.camera, "a failed import puts it back"
    assert scene.camera.name == "Front.001"


def test_add_headlight_operator(bpy_clean):
    bpy = bpy_clean
    scene = bpy.context.scene
    with pytest.raises(RuntimeError):   # no camera: the operator's poll refuses
        bpy.ops.phong.add_headlight()
    first = bpy.data.objects.new("Cam", bpy.data.cameras.new("Cam"))
    scene.collection.objects.link(first)
    scene.camera = first
    assert bpy.ops.phong.add_headlight() == {"FINISHED"}
    (head,) = [o for o in bpy.data.objects if o.type == "LIGHT"]
    assert head.constraints[0].target is first
    second = bpy.data.objects.new("Cam2", bpy.data.cameras.new("Cam2"))
    scene.collection.objects.link(second)
    scene.camera = second
    assert bpy.ops.phong.add_headlight() == {"FINISHED"}
    assert [o for o in bpy.data.objects if o.type == "LIGHT"] == [head], "pointed, not added"
    assert head.constraints[0].target is second


# -- the real files ------------------------------------------------------------------------

#: Read from each file by eye: its shapes with geometry (objects), distinct geometries
#: (meshes), Materials by name (the file's DEF names; unnamed ones "Material"; a shape without
#: Material "Unlit"), its lights (+ the headlight of a file that does not turn it off) and
#: its bound Viewpoint's DEF ("Viewpoint" where there is none: X3D's default viewpoint).
REAL = {
    "choreonoid_HAND_L.wrl": (1, 1, ["FL"], ["Headlight"], "Viewpoint"),
    "choreonoid_TunnelLight.wrl": (0, 0, [], ["DirectionalLight", "Headlight"], "Viewpoint"),
    "choreonoid_box1.wrl": (1, 1, ["BODY"], ["Headlight"], "Viewpoint"),
    "choreonoid_fog.wrl": (1, 1, ["Material"], ["Headlight"], "Viewpoint"),
    "choreonoid_table.wrl": (3, 3, ["Material", "Material.001", "Unlit"], ["Headlight"],
                             "Viewpoint"),
    "kicad_R_0805_2012Metric_excerpt.wrl": (4, 4, ["PIN-01", "PLASTIC-WHITE-01",
                                                   "RES-SMD-01"], ["Headlight"], "Viewpoint"),
    "threejs_camera.wrl": (2, 2, ["Material", "Material.001"], ["DirectionalLight",
                                                                "Headlight"], "Viewpoint"),
    "threejs_meshWithLines.wrl": (18, 18, ["_material0", "_material1"], ["Headlight"],
                                  "Main Viewpoint"),
    "threejs_meshWithTexture.wrl": (1, 1, ["Plane001"], ["Headlight"], "Viewpoint"),
    # Blue's lids are solid='false', its barrel solid: two variants
    "x3dom_Drum55Gallon.x3d": (6, 5, ["Blue", "Blue [two-sided]", "Bunghole"], ["Headlight"],
                               "Viewpoint"),
}


@pytest.mark.parametrize("name", sorted(REAL))
def test_real_files_import_with_their_counts(bpy_clean, name):
    bpy = bpy_clean
    objects, meshes, materials, lights, camera = REAL[name]
    _import(bpy, os.path.join(DATA, name))
    data = bpy.data
    assert sum(o.type == "MESH" for o in data.objects) == objects
    assert len(data.meshes) == meshes
    assert sorted(m.name for m in data.materials) == materials
    assert sorted(o.name for o in data.objects if o.type == "LIGHT") == lights
    assert bpy.context.scene.camera.name == camera
    if name == "threejs_meshWithLines.wrl":   # 6 face sets of 2 triangles, 12 lines
        faces = [m for m in data.meshes if len(m.polygons)]
        lines = [m for m in data.meshes if not len(m.polygons)]
        assert (len(faces), len(lines)) == (6, 12)
        assert all(len(m.polygons) == 2 for m in faces)
        assert all((len(m.edges), len(m.vertices)) == (1, 2) for m in lines)
    if name == "kicad_R_0805_2012Metric_excerpt.wrl":   # named after their materials
        assert sorted(o.name for o in data.objects if o.type == "MESH") == [
            "PIN-01", "PLASTIC-WHITE-01", "RES-SMD-01", "RES-SMD-01.001"]
        assert _controls(data.materials["PIN-01"])["Ka"] == _f32(
            [0.271 * c for c in (0.824, 0.82, 0.781)])
        assert _controls(data.materials["PIN-01"])["exponent"] == F32(128 * 0.7)


# -- rendered pixels ---------------------------------------------------------------------------

def _compare(bpy, path, tmp_path, engines, size=(120, 90), prepare=None):
    from phong_nodes.addon.comparison import engine  # noqa: PLC0415

    scene = bpy.context.scene
    scene.render.resolution_x, scene.render.resolution_y = size
    _import(bpy, path)
    if prepare is not None:
        prepare(scene)
    metrics = engine.run(scene, str(tmp_path / "compare"), engines=engines)
    cycles = metrics["pairs"]["cycles-reference"]["max_abs"]
    worst = max([cycles] + [t["max_abs"] for t in metrics["terms"].values()])
    line = f"[x3d {os.path.basename(str(path))}] Cycles max |Δ| {worst:.2e}"
    if "eevee" in engines:
        line += f", Eevee {1 - metrics['pairs']['eevee-reference']['share_over_1_255']:.3%} " \
                "within 1/255"
    be.report(line + f", {metrics['pixels']['compared']} pixels")
    return metrics, worst


@pytest.mark.slow
@pytest.mark.cycles
@pytest.mark.eevee
def test_every_rule_renders_the_standards_equation(bpy_clean, tmp_path):
    """hand_rules.x3dv: the headlight, a point light whose radius (3.5 m) cuts the floor and
    whose attenuation 1/max(0.3 + 0.2·d + 0.05·d², 1) is clamped within 2.2 m of it, a spot's
    linear ramp (0.25 to 0.6 rad) with its own ambient light, a DirectionalLight scoped to
    one of two balls: Cycles within 1e-4 and Eevee within 1/255 of the standard's equation."""
    bpy = bpy_clean
    metrics, worst = _compare(bpy, os.path.join(DATA, "hand_rules.x3dv"), tmp_path,
                              ("cycles", "eevee"))
    assert metrics["ok"], metrics["verdict"]
    assert worst <= 1e-4 and metrics["pixels"]["compared"] > 6000
    lights = {light["name"]: light for light in metrics["parameters"]["lights"]}
    assert lights["Lamp"]["radius"] == 3.5 and lights["Lamp"]["constant"] == 0.3
    assert lights["Cone"]["beam_width"] == 0.25 and lights["Cone"]["ambient"] == 0.3
    assert lights["Cone"]["half_angle"] == pytest.approx(math.degrees(0.6), abs=1e-5)
    assert lights["Headlight"]["intensity"] == 1.0
    objects = {o["name"]: o for o in metrics["parameters"]["objects"]}
    names = metrics["parameters"]["light_names"]
    assert "Blue" in [names[k] for k in objects["Ball"]["lights"]]
    assert "Blue" not in [names[k] for k in objects["Ball.001"]["lights"]]
    assert "Blue" not in [names[k] for k in objects["Ground"]["lights"]]


@pytest.mark.slow
@pytest.mark.cycles
@pytest.mark.eevee
def test_vrml97_scope_hard_spot_and_face_colours_render_the_equation(bpy_clean, tmp_path):
    bpy = bpy_clean
    metrics, worst = _compare(bpy, os.path.join(DATA, "hand_scope.wrl"), tmp_path,
                              ("cycles", "eevee"))
    assert metrics["ok"], metrics["verdict"]
    assert worst <= 1e-4 and metrics["pixels"]["compared"] > 6000
    (spot,) = [light for light in metrics["parameters"]["lights"] if light["type"] == "spot"]
    assert spot["half_angle"] == pytest.approx(45.0, abs=1e-4), "VRML97's cutOffAngle"
    assert spot["beam_width"] == 1.570796, "VRML97's beamWidth: a hard cone"


@pytest.mark.slow
@pytest.mark.cycles
def test_the_headlight_follows_a_moved_camera(bpy_clean, tmp_path):
    """The headlight takes the camera's transform through its constraint: after the camera
    moves and turns, the lights groups (World properties the drivers write from the evaluated
    matrix) and the comparison's reference (the evaluated light) agree again."""
    bpy = bpy_clean
    from mathutils import Matrix, Vector  # noqa: PLC0415

    def move(scene):
        camera = scene.camera
        eye = Vector((4.0, -5.0, 3.5))
        rotation = (Vector((0.0, 0.5, 0.5)) - eye).to_track_quat("-Z", "Y")
        camera.matrix_world = Matrix.LocRotScale(eye, rotation, None)

    metrics, worst = _compare(bpy, os.path.join(DATA, "hand_rules.x3dv"), tmp_path,
                              ("cycles",), size=(96, 72), prepare=move)
    assert metrics["ok"] and worst <= 1e-4
    head = next(light for light in metrics["parameters"]["lights"]
                if light["name"] == "Headlight")
    want = (Vector((0.0, 0.5, 0.5)) - Vector((4.0, -5.0, 3.5))).normalized()
    assert head["direction"] == pytest.approx(tuple(want), abs=1e-6), "the camera's view"


TEXTURED = """#X3D V3.3 utf8
PROFILE Immersive
# 8 quads side by side, seen from the front by an orthographic view 8 × 1 wide
NavigationInfo { headlight FALSE }
OrthoViewpoint { position 0 0 5 fieldOfView -4 -0.5 4 0.5 }
DirectionalLight { direction 0 0 -1 intensity 0.8 ambientIntensity 0.25 }
PROTO Quad [ field SFVec3f at 0 0 0 field SFNode look NULL field SFNode colors NULL ] {
  Transform { translation IS at children Shape { appearance IS look geometry IndexedFaceSet {
    coord Coordinate { point [ -0.4 -0.4 0, 0.4 -0.4 0, 0.4 0.4 0, -0.4 0.4 0 ] }
    coordIndex [ 0 1 2 3 -1 ]
    texCoord TextureCoordinate { point [ 0 0, 1 0, 1 1, 0 1 ] }
    color IS colors } } }
}
Quad { at -3.5 0 0 look Appearance { texture ImageTexture { url "rgb.png" }
  material Material { diffuseColor 0.9 0.9 0.9 ambientIntensity 0.5 } } }
Quad { at -2.5 0 0 look Appearance { texture ImageTexture { url "grey.png" }
  material Material { diffuseColor 0.8 0.4 0.2 ambientIntensity 0.5 } } }
Quad { at -1.5 0 0 look Appearance { material Material { diffuseColor 0.5 0.5 0.5
  ambientIntensity 0.4 } } colors Color { color [ 0.3 0.6 0.9, 0.3 0.6 0.9, 0.3 0.6 0.9,
  0.3 0.6 0.9 ] } }
Quad { at -0.5 0 0 look Appearance { texture ImageTexture { url "grey.png" }
  material Material { diffuseColor 0.1 0.1 0.1 ambientIntensity 0.4 } }
  colors Color { color [ 0.3 0.6 0.9, 0.3 0.6 0.9, 0.3 0.6 0.9, 0.3 0.6 0.9 ] } }
Quad { at 0.5 0 0 look Appearance { texture ImageTexture { url "rgb.png" } } }
Quad { at 1.5 0 0 look Appearance { texture ImageTexture { url "grey.png" } } }
Quad { at 2.5 0 0 look Appearance { } colors Color { color [ 0.3 0.6 0.9, 0.3 0.6 0.9,
  0.3 0.6 0.9, 0.3 0.6 0.9 ] } }
Quad { at 3.5 0 0 }
"""
RGB = np.array([51, 102, 153]) / 255.0      # = (0.2, 0.4, 0.6)
GREY = 128 / 255.0
COLOUR = np.array([0.3, 0.6, 0.9])
#: By hand, per quad: the light gives Ia·O_a + I·O_d·(N·L = 1) = 0.25·O_a + 0.8·O_d with
#: O_d the diffuse colour as the texture or colours leave it and O_a = ambientIntensity·O_d;
#: an unlit quad shows its texture / colours / white.
EXPECTED = [
    0.25 * 0.5 * RGB + 0.8 * RGB,                                   # an RGB texture replaces Kd
    (0.25 * 0.5 + 0.8) * GREY * np.array([0.8, 0.4, 0.2]),          # a grey one multiplies it
    (0.25 * 0.4 + 0.8) * COLOUR,                                    # Color replaces Kd
    (0.25 * 0.4 + 0.8) * GREY * COLOUR,                             # grey texture × Color
    RGB, np.full(3, GREY), COLOUR, np.ones(3),                      # unlit
]


@pytest.mark.cycles
def test_textures_colours_and_unlit_shapes_render_the_standards_colours(bpy_clean, tmp_path):
    bpy = bpy_clean
    from phong_scene import render  # noqa: PLC0415

    png(tmp_path / "rgb.png", np.tile([51, 102, 153], (4, 4, 1)))
    png(tmp_path / "grey.png", np.full((4, 4), 128))
    scene = be.new_scene("textured", 128, 16, "cycles")
    bpy.context.window.scene = scene
    _import(bpy, write(tmp_path, "textured.x3dv", TEXTURED))
    images = sorted(i.name for i in bpy.data.images)
    assert images == ["grey.png", "rgb.png"]
    assert all(bpy.data.images[n].colorspace_settings.name == "Non-Color" for n in images)
    unlit = [m for m in bpy.data.materials if m.get("phong_x3d_unlit")]
    assert len(unlit) == 4 and all(m.name.startswith("Unlit") for m in unlit)
    passes, _seconds = render(bpy, scene, str(tmp_path / "textured.exr"))
    picture = passes["Combined"][..., :3].astype(np.float64)
    for index, want in enumerate(EXPECTED):   # 16 pixels a quad: its middle 6 × 6
        centre = 8 + 16 * index
        got = picture[5:11, centre - 3:centre + 3].reshape(-1, 3)
        assert np.abs(got - want).max() <= 1e-5, (index, got[0], want)


@pytest.mark.cycles
def test_texture_transform_gives_the_standards_texture_coordinates(bpy_clean, tmp_path):
    """A 16-bit ramp texture (red = s, green = t at the texel centres) on a quad that fills an
    orthographic view, through TextureTransform { center 0.1 0.2 rotation 0.5 scale 2 0.5
    translation 0.3 0.05 }: each pixel shows the texture at Tc' = −C + S·R·(C + T + Tc)
    (ISO/IEC 19775-1 §18.4.9, −C × S × R × C × T × Tc), computed here by hand."""
    bpy = bpy_clean
    from phong_scene import render  # noqa: PLC0415

    size = 256
    ramp = (np.arange(size) + 0.5) / size * 65535.0
    pixels = np.zeros((size, size, 3))
    pixels[..., 0] = ramp[None, :]
    pixels[..., 1] = ramp[::-1, None]   # first row the top: t = 1 there
    png(tmp_path / "ramp.png", np.rint(pixels), bits=16)
    scene = be.new_scene("ramp", 24, 24, "cycles")
    bpy.context.window.scene = scene
    _import(bpy, write(tmp_path, "ramp.x3dv", """#X3D V3.3 utf8
PROFILE Immersive
NavigationInfo { headlight FALSE }
OrthoViewpoint { position 0.5 0.5 5 fieldOfView -0.5 -0.5 0.5 0.5 }
Shape { appearance Appearance { texture ImageTexture { url "ramp.png" }
  textureTransform TextureTransform { center 0.1 0.2 rotation 0.5 scale 2 0.5
                                      translation 0.3 0.05 } }
  geometry IndexedFaceSet { coord Coordinate { point [ 0 0 0, 1 0 0, 1 1 0, 0 1 0 ] }
    coordIndex [ 0 1 2 3 -1 ] texCoord TextureCoordinate { point [ 0 0, 1 0, 1 1, 0 1 ] } } }
"""))
    passes, _seconds = render(bpy, scene, str(tmp_path / "ramp.exr"))
    picture = passes["Combined"][..., :2].astype(np.float64)   # row 0 = bottom
    c, s = math.cos(0.5), math.sin(0.5)
    checked = 0
    for j in range(24):
        for i in range(24):
            u, v = (i + 0.5) / 24, (j + 0.5) / 24
            x, y = u + 0.3 + 0.1, v + 0.05 + 0.2          # C + T + Tc
            x, y = c * x - s * y, s * x + c * y           # R
            x, y = 2 * x - 0.1, 0.5 * y - 0.2             # S, then −C
            x, y = x % 1.0, y % 1.0
            if min(x, 1 - x, y, 1 - y) < 1.5 / size:      # the ramp wraps there
                continue
            assert picture[j, i] == pytest.approx((x, y), abs=2e-4), (i, j)
            checked += 1
    assert checked > 400


def test_image_components_are_read_from_the_file(tmp_path):
    from phong_nodes.addon.interchange import x3d_import  # noqa: PLC0415

    for comps in (1, 2, 3, 4):
        shape = (2, 2) if comps == 1 else (2, 2, comps)
        assert x3d_import.image_components(png(tmp_path / f"{comps}.png",
                                               np.zeros(shape))) == comps
    jpeg = bytes.fromhex("ffd8ffe000104a46494600010100000100010000"
                         "ffc0000b080002000201011100ffd9")
    (tmp_path / "g.jpg").write_bytes(jpeg)
    assert x3d_import.image_components(str(tmp_path / "g.jpg")) == 1
    assert x3d_import.image_components(str(tmp_path / "missing.png")) is None


def test_degenerate_faces_are_found_without_a_loop():
    from phong_nodes.addon.interchange import x3d_import  # noqa: PLC0415

    sizes = np.array([3, 3, 4, 4])
    corners = np.array([0, 1, 2, 3, 3, 4, 0, 1, 2, 3, 5, 6, 5, 7])
    assert x3d_import.degenerate_faces(sizes, corners).tolist() == [False, True, False, True]
    tris = np.array([0, 1, 2, 2, 2, 3, 4, 5, 4])
    assert x3d_import.degenerate_faces(np.array([3, 3, 3]), tris).tolist() == \
        [False, True, True]


@pytest.mark.slow
def test_a_large_mesh_imports_through_arrays(bpy_clean, tmp_path):
    """200,000 triangles of one face set: built through arrays, in seconds."""
    import time  # noqa: PLC0415

    bpy = bpy_clean
    n = 316
    grid = np.stack(np.meshgrid(np.arange(n + 1.0), np.arange(n + 1.0)), -1).reshape(-1, 2)
    points = np.column_stack([grid[:, 0], np.zeros(len(grid)), grid[:, 1]])
    i = (np.arange(n)[:, None] * (n + 1) + np.arange(n)[None, :]).ravel()
    faces = np.column_stack([i, i + n + 1, i + n + 2, -np.ones_like(i),
                             i, i + n + 2, i + 1, -np.ones_like(i)])
    path = tmp_path / "big.wrl"
    with open(path, "w") as handle:
        handle.write("#VRML V2.0 utf8\nDEF Big Shape { geometry IndexedFaceSet { "
                     "coord Coordinate { point [\n")
        np.savetxt(handle, points, fmt="%g")
        handle.write("] } coordIndex [\n")
        np.savetxt(handle, faces, fmt="%d")
        handle.write("] } }\n")
    t0 = time.perf_counter()
    _import(bpy, path)
    seconds = time.perf_counter() - t0
    mesh = bpy.data.objects["Big"].data
    assert (len(mesh.polygons), len(mesh.vertices)) == (2 * n * n, (n + 1) ** 2)
    be.report(f"[x3d import] {2 * n * n:,} triangles in {seconds:.2f} s")
    assert seconds < 60


@pytest.mark.slow
@pytest.mark.cycles
def test_phong_compare_reads_a_wrl_file(tmp_path):
    """``phong compare FILE.wrl``: the extension's importer in an empty scene, the file's
    own camera and lights (no sun added: the file turns its headlight off)."""
    import json  # noqa: PLC0415
    import subprocess  # noqa: PLC0415
    import sys  # noqa: PLC0415

    out = tmp_path / "out"
    env = dict(os.environ, BLENDER_USER_RESOURCES=str(tmp_path / "user"))
    result = subprocess.run([sys.executable, "-m", "phong_nodes.cli", "compare",
                             os.path.join(DATA, "hand_scope.wrl"), "--engines", "cycles",
                             "--resolution", "32", "--out", str(out)],
                            capture_output=True, text=True, env=env, timeout=600)
    assert result.returncode == 0, result.stdout[-2000:] + result.stderr[-2000:]
    assert "has no light" not in result.stderr and "has no camera" not in result.stderr
    (folder,) = [p for p in out.iterdir() if p.is_dir()]
    metrics = json.loads((folder / "metrics.json").read_text())
    assert metrics["ok"] and metrics["pairs"]["cycles-reference"]["max_abs"] <= 1e-4
    assert metrics["parameters"]["model"] == "x3d"
    assert sorted(light["name"] for light in metrics["parameters"]["lights"]) == \
        ["DirectionalLight", "Hard"]
