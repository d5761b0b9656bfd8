# SPDX-License-Identifier: GPL-3.0-or-later
"""COLLADA (.dae) import and export (issue 26).

Pure tests of ``core/collada.py`` (no bpy): the spec's values read exactly (setparam,
effect-level params, transparency formulas of all four modes, the ``<lookat>`` that pycollada
builds wrongly, tristrips/trifans of pycollada's own test files counted from their ``<p>``),
liberal reading (decimal commas, swapped names) and hostile input (entity expansion,
external entities, indices out of range, absurd counts) in bounded time.  Blender tests:
values of lights and materials after the unit and axis conversion, a failed import leaves the
file as it was, import → export → import keeps names and values, the export validates against
the COLLADA 1.4.1 schema (pycollada's copy, lxml).  Cycles pixels against the Phong formula and
the real files of other programs: ``test_collada_files.py``; helpers: ``collada_text.py``.
"""

from __future__ import annotations

import math
import os
import re
import sys
import time
import xml.etree.ElementTree as ET

import numpy as np
import pytest

import blender_env as be
from collada_text import DATA, F32, LIT, _doc, _f32, _ids, _valid, be_reset
from phong_scene import linked_controls

from phong_nodes.core import collada


def _effect(inner, effect_params="", setparams="", name="M"):
    return _doc(f"""<library_effects><effect id="fx">{effect_params}<profile_COMMON>
      <newparam sid="pcol"><float4>0.25 0.5 0.75 1</float4></newparam>
      <technique sid="t">{inner}</technique></profile_COMMON></effect></library_effects>
      <library_materials><material id="mat" name="{name}"><instance_effect url="#fx">{setparams}
      </instance_effect></material></library_materials>""")


def _material(data):
    return next(iter(collada.parse_bytes(data).materials.values()))


# -- pure: values -------------------------------------------------------------------------

def test_phong_values_setparam_and_effect_params_are_read_exactly():
    doc = collada.parse_bytes(open(LIT, "rb").read(), LIT)
    mat = doc.materials["red-id"]
    assert mat.name == "Red Paint", "the material's name, not its id"
    assert mat.technique == "phong"
    assert mat.color("emission") == (0.01, 0.02, 0.03)
    assert mat.color("ambient") == (0.1, 0.2, 0.3)
    assert mat.color("diffuse") == (0.8, 0.1, 0.1), "decimal commas repaired"
    assert mat.color("specular") == (0.5, 0.4, 0.3), "<setparam> of the instance_effect"
    assert mat.shininess == 25.0, "a <newparam> of the profile"
    assert [w for w in doc.warnings if "decimal commas" in w] == [
        "decimal commas read as decimal points (material Red Paint: <diffuse>)"]
    # effect-level newparam and a param the setparam overrides
    m = _material(_effect("<phong><diffuse><param ref='e'/></diffuse>"
                          "<specular><param ref='pcol'/></specular></phong>",
                          effect_params="<newparam sid='e'><float3>0.1 0.2 0.4</float3></newparam>",
                          setparams="<setparam ref='pcol'><float4>1 0 0.5 1</float4></setparam>"))
    assert m.color("diffuse") == (0.1, 0.2, 0.4)
    assert m.color("specular") == (1.0, 0.0, 0.5)


def test_terms_left_out_are_black_and_techniques_keep_only_their_terms():
    lam = _material(_effect("<lambert><diffuse><color>0.5 0.5 0.5 1</color></diffuse>"
                            "<specular><color>1 1 1 1</color></specular></lambert>"))
    assert lam.technique == "lambert"
    assert lam.color("ambient") == (0.0, 0.0, 0.0), "no <ambient>: contributes nothing"
    assert lam.color("specular") == (0.0, 0.0, 0.0), "lambert has no specular term"
    const = _material(_effect("<constant><emission><color>0.3 0.2 0.1 1</color></emission>"
                              "</constant>"))
    assert [const.color(e) for e in ("emission", "ambient", "diffuse", "specular")] == [
        (0.3, 0.2, 0.1), (0.0, 0.0, 0.0), (0.0, 0.0, 0.0), (0.0, 0.0, 0.0)]
    blinn = _material(_effect("<blinn><shininess><float>7</float></shininess></blinn>"))
    assert (blinn.technique, blinn.shininess) == ("blinn", 7.0)


@pytest.mark.parametrize("mode, transparent, transparency, expected", [
    ("A_ONE", "1 1 1 0.5", "0.8", 0.5 * 0.8),
    ("A_ONE", "1 1 1 1", None, 1.0),                 # missing transparency: 1
    ("RGB_ZERO", "0.2 0.2 0.2 1", "0.5", 1 - 0.2 * 0.5),
    ("RGB_ZERO", "0.4 0.4 0.4 1", None, 1 - 0.4),     # pycollada reads the missing value as 0
    ("A_ZERO", "0 0 0 0.25", "1", 0.75),             # COLLADA 1.5
    ("RGB_ONE", "0.6 0.6 0.6 1", "0.5", 0.3),        # COLLADA 1.5
    (None, None, "0", 1.0),                          # no <transparent>: opaque
])
def test_opacity_follows_the_spec_formulas(mode, transparent, transparency, expected):
    inner = ""
    if transparent is not None:
        inner += f"<transparent opaque='{mode}'><color>{transparent}</color></transparent>"
    if transparency is not None:
        inner += f"<transparency><float>{transparency}</float></transparency>"
    m = _material(_effect(f"<phong>{inner}</phong>"))
    assert m.opacity() == pytest.approx(expected, abs=1e-12)


def test_texture_chains_of_14_15_and_plain_image_references():
    images = ("<library_images><image id='img' name='wood'><init_from>tex/wood.png</init_from>"
              "</image></library_images>")
    chain14 = ("<newparam sid='surf'><surface type='2D'><init_from>img</init_from></surface>"
               "</newparam><newparam sid='samp'><sampler2D><source>surf</source></sampler2D>"
               "</newparam>")
    data = _doc(images + f"""<library_effects><effect id="fx"><profile_COMMON>{chain14}
      <technique sid="t"><phong><diffuse><texture texture="samp" texcoord="UV0"/></diffuse>
      <ambient><texture texture="img" texcoord="UV0"/></ambient></phong></technique>
      </profile_COMMON></effect></library_effects><library_materials><material id="m">
      <instance_effect url="#fx"/></material></library_materials>""")
    m = _material(data)
    assert m.textures["diffuse"].path == "tex/wood.png"
    assert m.textures["diffuse"].texcoord == "UV0"
    assert m.textures["ambient"].path == "tex/wood.png", "an image id named directly"
    data15 = _doc("""<library_images><image id="i15"><init_from><ref>a%20b.png</ref></init_from>
      </image></library_images><library_effects><effect id="fx"><profile_COMMON>
      <newparam sid="s"><sampler2D><instance_image url="#i15"/></sampler2D></newparam>
      <technique sid="t"><blinn><diffuse><texture texture="s" texcoord="CHANNEL1"/></diffuse>
      </blinn></technique></profile_COMMON></effect></library_effects><library_materials>
      <material id="m"><instance_effect url="#fx"/></material></library_materials>""",
                  version="1.5")
    m15 = _material(data15)
    assert m15.textures["diffuse"].path == "a%20b.png"
    assert os.path.basename(m15.textures["diffuse"].resolved) == "a b.png"


def _scene(nodes, asset=""):
    return collada.parse_bytes(_doc(f"""<library_visual_scenes><visual_scene id="vs">{nodes}
      </visual_scene></library_visual_scenes><scene><instance_visual_scene url="#vs"/></scene>""",
                                    asset))


def test_lookat_places_the_node_at_eye_looking_at_interest():
    """pycollada puts this spot at the origin pointing away; the spec: at eye, −Z towards
    the interest point, +Y towards up (worked out here by hand)."""
    doc = _scene("<node id='s' name='s'><lookat>10 0 0  0 0 0  0 1 0</lookat></node>")
    m = doc.nodes[0].matrix
    np.testing.assert_allclose(m[:3, 3], (10, 0, 0))
    np.testing.assert_allclose(m[:3, :3] @ (0, 0, -1), (-1, 0, 0), atol=1e-12)
    np.testing.assert_allclose(m[:3, :3] @ (0, 1, 0), (0, 1, 0), atol=1e-12)


def test_transform_elements_compose_in_order():
    doc = _scene("<node id='n'><translate>1 2 3</translate><rotate>0 0 1 90</rotate>"
                 "<scale>2 2 2</scale><matrix>1 0 0 5 0 1 0 0 0 0 1 0 0 0 0 1</matrix></node>")
    m = doc.nodes[0].matrix
    # the point (0,0,0): matrix moves it to (5,0,0), scale to (10,0,0), rotate 90° about z to
    # (0,10,0), translate to (1,12,3)
    np.testing.assert_allclose(m @ (0, 0, 0, 1), (1, 12, 3, 1), atol=1e-12)
    sk = _scene("<node id='k'><skew>45 0 1 0 1 0 0</skew></node>").nodes[0].matrix
    # RenderMan skew of 45° turning the y axis towards x: (0, 1, 0) -> (1, 1, 0)
    np.testing.assert_allclose(sk @ (0, 1, 0, 1), (1, 1, 0, 1), atol=1e-12)


def test_units_and_up_axis_convert_to_blender():
    doc = collada.load(LIT)
    assert (doc.meter, doc.up_axis) == (0.0254, "Y_UP")
    bulb = doc.lights["pt"]
    c, lin, q = collada.attenuation(doc, bulb)
    for d_file in (1.0, 7.5, 100.0):
        d_m = d_file * 0.0254
        assert 1 / (c + lin * d_m + q * d_m ** 2) == pytest.approx(
            1 / (0.5 + 0.1 * d_file + 0.01 * d_file ** 2), rel=1e-12)
    node = next(n for n in doc.nodes if n.name == "Bulb node")
    m = collada.to_blender(doc, node.matrix, root=True)
    np.testing.assert_allclose(m[:3, 3], (0, 0, 100 * 0.0254), atol=1e-12), "Y up -> Z up"


def _p_counts(path, tag):
    """(strips, vertices per strip) of a file's <tag>, read with ElementTree here."""
    root = ET.parse(path).getroot()
    ns = {"c": collada.NS14}
    out = []
    for prim in root.iterfind(f".//c:{tag}", ns):
        stride = max(int(i.get("offset")) for i in prim.iterfind("c:input", ns)) + 1
        out += [len(p.text.split()) // stride for p in prim.iterfind("c:p", ns)]
    return out


@pytest.mark.parametrize("name, tag", [("pycollada_trifans.dae", "trifans"),
                                       ("pycollada_tristrips.dae", "tristrips"),
                                       ("pycollada_cube_tristrips.dae", "tristrips")])
def test_strips_and_fans_of_pycollada_files_triangulate(name, tag):
    path = os.path.join(DATA, name)
    doc = collada.load(path)
    mesh = next(iter(doc.meshes.values()))
    expected = sum(n - 2 for n in _p_counts(path, tag))
    assert len(mesh.face_sizes) == expected and set(mesh.face_sizes.tolist()) == {3}
    assert doc.warnings == []


def test_fan_winding_and_first_corner():
    doc = collada.load(os.path.join(DATA, "pycollada_trifans.dae"))
    mesh = next(iter(doc.meshes.values()))
    # the fan 0 1 2 3 4 5 6 1: triangles (0,1,2), (0,2,3) ... (0,6,1)
    tris = mesh.corners.reshape(-1, 3).tolist()
    assert tris == [[0, 1, 2], [0, 2, 3], [0, 3, 4], [0, 4, 5], [0, 5, 6], [0, 6, 1]]


# -- pure: hostile input --------------------------------------------------------------------

def test_entity_expansion_and_external_entities_are_refused_fast():
    laughs = ('<?xml version="1.0"?><!DOCTYPE lolz [<!ENTITY lol "lol">'
              + "".join(f'<!ENTITY lol{i} "{("&lol" + (str(i - 1) if i > 1 else "") + ";") * 10}">'
                        for i in range(1, 10))
              + f']><COLLADA xmlns="{collada.NS14}"><asset/>&lol9;</COLLADA>').encode()
    start = time.process_time()
    with pytest.raises(collada.ColladaError, match="entities"):
        collada.parse_bytes(laughs, "laughs.dae")
    external = (f'<?xml version="1.0"?><!DOCTYPE c [<!ENTITY x SYSTEM "file:///etc/passwd">]>'
                f'<COLLADA xmlns="{collada.NS14}"><asset><title>&x;</title></asset></COLLADA>').encode()
    with pytest.raises(collada.ColladaError, match="entities"):
        collada.parse_bytes(external, "external.dae")
    # the same in UTF-16 (no byte pattern to look for: expat itself finds the declaration)
    with pytest.raises(collada.ColladaError, match="entities"):
        collada.parse_bytes(laughs.decode().replace('version="1.0"?>', 'version="1.0" '
                                                    'encoding="UTF-16"?>').encode("utf-16"),
                            "laughs16.dae")
    assert time.process_time() - start < 1.0
    with pytest.raises(collada.ColladaError, match="not well-formed"):
        collada.parse_bytes(b"<COLLADA><asset>", "cut.dae")
    with pytest.raises(collada.ColladaError, match="not a COLLADA file"):
        collada.parse_bytes(b"<html/>", "page.dae")


def _tri_mesh(p, count="1", accessor_count="3"):
    return _doc(f"""<library_geometries><geometry id="g"><mesh>
      <source id="pos"><float_array id="pa" count="9">0 0 0 1 0 0 0 1 0</float_array>
      <technique_common><accessor source="#pa" count="{accessor_count}" stride="3"/></technique_common>
      </source><vertices id="v"><input semantic="POSITION" source="#pos"/></vertices>
      <triangles count="{count}"><input semantic="VERTEX" source="#v" offset="0"/><p>{p}</p>
      </triangles></mesh></geometry></library_geometries>""")


def test_indices_out_of_range_and_absurd_counts_are_left_out_with_a_warning():
    doc = collada.parse_bytes(_tri_mesh("0 1 2 0 1 7 -1 1 2"))
    mesh = doc.meshes["g"]
    assert mesh.corners.tolist() == [0, 1, 2], "only the face whose indices exist"
    assert any("2 face(s) with position indices out of range" in w for w in doc.warnings)
    # a texture coordinate index out of range (Maya wrote such files, Khronos's suite has
    # them): the face stays, that corner's UV is left out
    data = _tri_mesh("0 0 1 1 2 9").replace(
        b'<input semantic="VERTEX" source="#v" offset="0"/>',
        b'<input semantic="VERTEX" source="#v" offset="0"/>'
        b'<input semantic="TEXCOORD" source="#uv" offset="1" set="0"/>').replace(
        b'<vertices', b'<source id="uv"><float_array id="ua" count="4">0.5 0.5 1 1</float_array>'
        b'<technique_common><accessor source="#ua" count="2" stride="2"/></technique_common>'
        b'</source><vertices')
    doc = collada.parse_bytes(data)
    mesh = doc.meshes["g"]
    assert mesh.corners.tolist() == [0, 1, 2]
    assert mesh.uvs[0].tolist() == [[0.5, 0.5], [1.0, 1.0], [0.0, 0.0]]
    assert any("indices out of range for 1 TEXCOORD corner value(s)" in w for w in doc.warnings)
    start = time.process_time()
    doc = collada.parse_bytes(_tri_mesh("0 1 2", count="999999999999", accessor_count="4000000000"))
    assert len(doc.meshes["g"].face_sizes) == 1, "counts are not trusted for allocation"
    assert time.process_time() - start < 1.0


def test_lines_are_edges_with_their_material_and_unknown_profiles_import_black():
    """<lines> (pairs) and <linestrips> (one <p> per strip) become edges between positions
    (issue 35: loose edges, as Blender's OBJ importer and 4.2's COLLADA importer keep lines);
    a line's material symbol is a slot of the mesh; a line out of range or from a vertex to
    itself is left out, with one warning for the first."""
    data = _doc("""<library_geometries><geometry id="g" name="wire"><mesh>
      <source id="pos"><float_array id="pa" count="12">0 0 0 1 0 0 1 1 0 0 1 0</float_array>
      <technique_common><accessor source="#pa" count="4" stride="3"/></technique_common></source>
      <vertices id="v"><input semantic="POSITION" source="#pos"/></vertices>
      <lines count="3" material="ink"><input semantic="VERTEX" source="#v" offset="0"/>
      <input semantic="NORMAL" source="#pos" offset="1"/><p>0 9 1 9 2 9 2 9 3 9 7 9</p></lines>
      <linestrips count="1"><input semantic="VERTEX" source="#v" offset="0"/><p>3 0 1</p>
      </linestrips></mesh></geometry></library_geometries><library_effects><effect id="fx">
      <profile_GLSL/></effect></library_effects><library_materials><material id="m"
      name="Shader"><instance_effect url="#fx"/></material></library_materials>""")
    doc = collada.parse_bytes(data)
    mesh = doc.meshes["g"]
    # pairs (0, 1), (2, 2): a vertex to itself, (3, 7): out of range; strip 3-0-1
    assert mesh.edges.tolist() == [[0, 1], [3, 0], [0, 1]]
    assert mesh.symbols == ["ink"] and len(mesh.face_sizes) == 0
    assert "geometry wire: <lines material=\"ink\">: 1 line(s) with position indices out of " \
        "range left out" in doc.warnings
    assert not [w for w in doc.warnings if "skipped" in w]
    assert any(w.startswith("material Shader: no profile_COMMON (profile_GLSL)")
               for w in doc.warnings)


# -- pure: writing ---------------------------------------------------------------------------

#: Validates the COLLADA document on stdin against pycollada's copy of the 1.4.1 schema (lxml);
#: prints the error log and exits 1 when it is not valid.


#: pycollada's strict load of the file argv[1]: its one effect and its spot light, as JSON.
_PYCOLLADA_READS = """
import json, sys
import collada
other = collada.Collada(sys.argv[1])
(effect,) = other.effects
spot = next(l for l in other.lights if type(l).__name__ == "SpotLight")
print(json.dumps([{"shadingtype": effect.shadingtype, "diffuse": list(effect.diffuse),
                   "specular": list(effect.specular), "shininess": effect.shininess},
                  {"falloff_ang": spot.falloff_ang, "falloff_exp": spot.falloff_exp}]))
"""


def test_written_file_validates_and_reads_back_the_same_values():
    doc = collada.load(LIT)
    text = collada.dumps(doc)
    _valid(text)
    again = collada.parse_bytes(text.encode(), "again.dae")
    assert again.warnings == []
    (mat,) = again.materials.values()
    src = doc.materials["red-id"]
    assert mat.name == "Red Paint", "a name with a space, written as an NCName, reads back"
    for element in ("emission", "ambient", "diffuse", "specular"):
        assert F32(mat.color(element)).tobytes() == F32(src.color(element)).tobytes()
    assert (mat.shininess, mat.opaque, mat.transparency) == (25.0, "RGB_ZERO", 0.0)
    for key, light in doc.lights.items():
        other = next(v for v in again.lights.values() if v.name == light.name)
        for attr in ("kind", "constant", "linear", "quadratic", "falloff_angle",
                     "falloff_exponent"):
            assert F32(getattr(other, attr)) == F32(getattr(light, attr)) \
                if attr != "kind" else other.kind == light.kind, (key, attr)
    assert "6e+01" not in text and "<falloff_angle>60</falloff_angle>" in text


def test_pycollada_reads_what_is_written(tmp_path):
    """Another reader: pycollada's strict load of a written file, with its values."""
    import json  # noqa: PLC0415
    import subprocess  # noqa: PLC0415

    be.need_module("collada")
    doc = collada.load(LIT)
    path = tmp_path / "written.dae"
    path.write_text(collada.dumps(doc), encoding="utf-8")
    # pycollada parses with lxml: in a Python of its own, as _valid (libxml2 and bpy's clash)
    done = subprocess.run([sys.executable, "-c", _PYCOLLADA_READS, str(path)],
                          capture_output=True, text=True, timeout=120)
    assert done.returncode == 0, done.stderr[-3000:]
    effect, spot = json.loads(done.stdout)
    src = doc.materials["red-id"]
    assert effect["shadingtype"] == "phong"
    assert tuple(F32(effect["diffuse"][:3])) == tuple(F32(src.color("diffuse")))
    assert tuple(F32(effect["specular"][:3])) == tuple(F32(src.color("specular")))
    assert effect["shininess"] == 25.0
    assert (spot["falloff_ang"], spot["falloff_exp"]) == (60.0, 3.0)


def test_names_are_ncnames_with_the_exact_name_in_an_extra():
    """COLLADA 1.4.1's name attributes are NCNames: a name that is not one is written with
    "_" for what it cannot hold (what other readers show) and kept exactly in an <extra>."""
    for name in ("Red Paint", "1st", "über-ß", "a:b"):
        assert re.fullmatch(r"[A-Za-z_][A-Za-z0-9_.\-]*", collada.ncname(name))
    assert collada.ncname("Red Paint") == "Red_Paint"
    doc = collada.load(LIT)
    text = collada.dumps(doc)
    root = ET.fromstring(text)
    ns = {"c": collada.NS14}
    material = root.find(".//c:library_materials/c:material", ns)
    assert material.get("name") == "Red_Paint"
    assert material.find("c:extra/c:technique[@profile='phong_nodes']/c:name", ns).text == \
        "Red Paint"
    assert list(material)[-1].tag.endswith("extra"), "the schema's place: last"
    (again,) = collada.parse_bytes(text.encode()).materials.values()
    assert again.name == "Red Paint"


# -- Blender ---------------------------------------------------------------------------------


def test_import_sets_lights_materials_and_transforms_exactly(bpy_clean):
    bpy = bpy_clean
    assert bpy.ops.phong.import_collada(filepath=LIT) == {"FINISHED"}
    got = linked_controls(bpy.data.materials["Red Paint"])
    assert got["Object Color"] == _f32((0.8, 0.1, 0.1))
    assert got["Ambient Object Color"] == _f32((0.1, 0.2, 0.3))
    assert got["Specular Color"] == _f32((0.5, 0.4, 0.3))
    assert got["Irradiant Color"] == _f32((0.01, 0.02, 0.03))
    assert (got["Exponent"], got["Blinn"]) == (25.0, 0.0)
    bulb = bpy.data.objects["Bulb node"]
    assert bulb.data.type == "POINT"
    assert tuple(bulb.data.color) == _f32((0.9, 0.8, 0.7))
    assert bulb.data["phong_constant"] == 0.5
    assert bulb.data["phong_linear"] == pytest.approx(0.1 / 0.0254, rel=1e-15)
    assert bulb.data["phong_quadratic"] == pytest.approx(0.01 / 0.0254 ** 2, rel=1e-15)
    assert tuple(bulb.matrix_world.translation) == pytest.approx((0, 0, 2.54), abs=1e-6)
    spot = bpy.data.objects["Spot node"]
    assert spot.data.spot_size == pytest.approx(math.radians(60.0), abs=1e-7), "full cone"
    assert spot.data["phong_edge_exponent"] == 3.0
    direction = spot.matrix_world.to_3x3() @ __import__("mathutils").Vector((0, 0, -1))
    assert tuple(direction) == pytest.approx((0, 0, -1), abs=1e-6), "lookat down at the quad"
    assert tuple(spot.matrix_world.translation) == pytest.approx((0.254, 0, 1.27), abs=1e-6)
    world = bpy.context.scene.world
    assert world.phong.ambient_intensity == 1.0
    assert tuple(world.phong.ambient_color) == _f32((0.2, 0.1, 0.05))
    quad = bpy.data.objects["Quad node"]
    corners = sorted(tuple(round(c, 6) for c in quad.matrix_world @ v.co)
                     for v in quad.data.vertices)
    # (±1, 0, ±1) inches around x = 10 inches, Y up: z = file y = 0, y = -file z
    assert corners == sorted((round((10 + x) * 0.0254, 6), round(-z * 0.0254, 6), 0.0)
                             for x in (-1, 1) for z in (-1, 1))


def test_invisible_material_is_imported_opaque_with_one_warning(bpy_clean, tmp_path, capfd):
    bpy = bpy_clean
    # A_ONE with <transparency>0: the spec's opacity 1·0 = 0 (as several exporters write
    # meaning opaque)
    text = open(LIT).read().replace('<transparent opaque="RGB_ZERO"><color>0 0 0 1</color>',
                                    '<transparent opaque="A_ONE"><color>1 1 1 1</color>')
    assert 'opaque="A_ONE"' in text
    path = tmp_path / "glass.dae"
    path.write_text(text)
    capfd.readouterr()
    assert bpy.ops.phong.import_collada(filepath=str(path)) == {"FINISHED"}
    logged = "".join(capfd.readouterr())
    assert logged.count("material Red Paint: its transparency makes it wholly invisible") == 1
    node = bpy.data.materials["Red Paint"].node_tree.nodes.get("phong_opacity")
    if node is not None:
        assert node.outputs[0].default_value == 1.0
    be_reset(bpy)
    assert bpy.ops.phong.import_collada(filepath=str(path), literal_transparency=True) == \
        {"FINISHED"}
    node = bpy.data.materials["Red Paint"].node_tree.nodes.get("phong_opacity")
    if node is not None:
        assert node.outputs[0].default_value == 0.0


def test_a_failed_import_leaves_the_file_as_it_was(bpy_clean, tmp_path):
    bpy = bpy_clean
    before = _ids(bpy)
    bad = tmp_path / "bad.dae"
    bad.write_text(open(LIT).read()[:-200])
    with pytest.raises(RuntimeError, match="bad.dae: not well-formed XML"):
        bpy.ops.phong.import_collada(filepath=str(bad))
    laughs = tmp_path / "laughs.dae"
    laughs.write_text('<?xml version="1.0"?><!DOCTYPE c [<!ENTITY a "aaaa">]><COLLADA/>')
    with pytest.raises(RuntimeError, match="declares XML entities"):
        bpy.ops.phong.import_collada(filepath=str(laughs))
    with pytest.raises(RuntimeError, match="gone.dae: No such file"):
        bpy.ops.phong.import_collada(filepath=str(tmp_path / "gone.dae"))
    assert _ids(bpy) == before
    assert sorted(os.listdir(tmp_path)) == ["bad.dae", "laughs.dae"], "importing writes no file"
    from phong_nodes.addon.interchange import collada_import  # noqa: PLC0415

    with pytest.raises(collada_import.ColladaImportError, match="not well-formed"):
        collada_import.import_file(bpy.context, str(bad))


def test_real_files_of_pycollada_import(bpy_clean):
    bpy = bpy_clean
    for name in ("pycollada_trifans.dae", "pycollada_tristrips.dae",
                 "pycollada_cube_tristrips.dae", "pycollada_empty_triangles_with_multiple_ns.dae"):
        assert bpy.ops.phong.import_collada(filepath=os.path.join(DATA, name)) == {"FINISHED"}, name
    cube = next(o for o in bpy.data.objects if o.type == "MESH" and o.data.name == "BlueSG")
    assert len(cube.data.polygons) == sum(n - 2 for n in _p_counts(
        os.path.join(DATA, "pycollada_cube_tristrips.dae"), "tristrips"))
    assert any(o.type == "CAMERA" for o in bpy.data.objects)
    assert sum(o.type == "LIGHT" for o in bpy.data.objects) >= 1


def test_round_trip_import_export_import_keeps_names_and_values(bpy_clean, tmp_path):
    bpy = bpy_clean
    assert bpy.ops.phong.import_collada(filepath=LIT) == {"FINISHED"}

    def state():
        lights = {o.name: (o.data.type, tuple(F32(o.data.color)),
                           {k: F32(o.data[k]) for k in ("phong_constant", "phong_linear",
                                                         "phong_quadratic", "phong_edge_exponent")},
                           F32(getattr(o.data, "spot_size", 0.0)),
                           tuple(np.round(np.array(o.matrix_world), 5).reshape(-1)))
                  for o in bpy.data.objects if o.type == "LIGHT"}
        mats = {m.name: {k: tuple(F32(v)) if isinstance(v, tuple) else F32(v)
                         for k, v in linked_controls(m).items()}
                for m in bpy.data.materials if m.get("phong_nodes_material")}
        world = bpy.context.scene.world
        return lights, mats, (world.phong.ambient_intensity, tuple(world.phong.ambient_color))

    first = state()
    out = tmp_path / "out.dae"
    assert bpy.ops.phong.export_collada(filepath=str(out)) == {"FINISHED"}
    text = out.read_text()
    _valid(text)
    be_reset(bpy)
    assert bpy.ops.phong.import_collada(filepath=str(out)) == {"FINISHED"}
    assert state() == first
    assert bpy.ops.phong.export_collada(filepath=str(tmp_path / "again.dae")) == {"FINISHED"}
    assert (tmp_path / "again.dae").read_text() == text


def test_menus_and_file_handler_exist(bpy_clean):
    bpy = bpy_clean
    assert hasattr(bpy.types, "PHONG_OT_import_collada")
    assert hasattr(bpy.types, "PHONG_OT_export_collada")
    if hasattr(bpy.types, "FileHandler"):
        handler = bpy.types.PHONG_FH_collada
        assert handler.bl_import_operator == "phong.import_collada"
        assert handler.bl_file_extensions == ".dae"
    # a dropped file's path is set before invoke; a path from an earlier run must not be
    prop = bpy.ops.phong.import_collada.get_rna_type().properties["filepath"]
    assert prop.is_skip_save
    labels = []

    class Layout:
        def operator(self, idname, text=""):
            labels.append((idname, text))

    for menu, idname in ((bpy.types.TOPBAR_MT_file_import, "phong.import_collada"),
                         (bpy.types.TOPBAR_MT_file_export, "phong.export_collada")):
        for draw in menu._dyn_ui_initialize():
            if getattr(draw, "__module__", "").endswith("collada_ui"):
                draw(type("Menu", (), {"layout": Layout()})(), bpy.context)
    assert ("phong.import_collada", "COLLADA (Phong) (.dae)") in labels
    assert ("phong.export_collada", "COLLADA (Phong) (.dae)") in labels
