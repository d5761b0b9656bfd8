# SPDX-License-Identifier: GPL-3.0-or-later
"""COLLADA (.dae) import and export (issue 26).

Pure tests of ``core/collada.py`` (no bpy): the spec's values read exactly (setparam,
effect-level params, transparency formulas of all four modes, the ``<lookat>`` that pycollada
builds wrongly, tristrips/trifans of pycollada's own test files counted from their ``<p>``),
liberal reading (decimal commas, swapped names) and hostile input (entity expansion,
external entities, indices out of range, absurd counts) in bounded time.  Blender tests:
values of lights and materials after the unit and axis conversion, a failed import leaves the
file as it was, import → export → import keeps names and values, the export validates against
the COLLADA 1.4.1 schema (pycollada's copy, lxml), and Cycles pixels against the Phong formula.
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
from phong_nodes.core import collada

DATA = os.path.join(os.path.dirname(os.path.abspath(__file__)), "data", "collada")
LIT = os.path.join(DATA, "hand_lit.dae")
F32 = np.float32


def _doc(body, asset="", version="1.4.1"):
    ns = collada.NS14 if version == "1.4.1" else collada.NS15
    return (f'<?xml version="1.0"?><COLLADA xmlns="{ns}" version="{version}">'
            f"<asset>{asset}</asset>{body}</COLLADA>").encode()


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
    start = time.perf_counter()
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
    assert time.perf_counter() - start < 1.0
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
    start = time.perf_counter()
    doc = collada.parse_bytes(_tri_mesh("0 1 2", count="999999999999", accessor_count="4000000000"))
    assert len(doc.meshes["g"].face_sizes) == 1, "counts are not trusted for allocation"
    assert time.perf_counter() - start < 1.0


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
_VALIDATE = """
import sys
import lxml.etree
from collada import schema
validator = schema.ColladaValidator()
document = lxml.etree.fromstring(sys.stdin.buffer.read())
if not validator.validate(document):
    print(validator.COLLADA_SCHEMA_1_4_1_INSTANCE.error_log)
    sys.exit(1)
"""


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


def _valid(text):
    """*text* validates against the COLLADA 1.4.1 schema.  In a Python of its own: lxml's
    libxml2 and the one bpy loads clash in one process (a segfault in lxml's XMLSchema once
    Blender has loaded its own, depending on which tests ran before)."""
    import subprocess  # noqa: PLC0415

    be.need_module("lxml")
    be.need_module("collada.schema")
    done = subprocess.run([sys.executable, "-c", _VALIDATE], input=text.encode("utf-8"),
                          capture_output=True, timeout=120)
    assert done.returncode == 0, (done.stdout + done.stderr).decode("utf-8", "replace")[-3000:]


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

def _controls(material):
    nodes = material.node_tree.nodes
    lights = nodes["phong_lights"]

    def colour(name):
        return tuple(lights.inputs[name].links[0].from_node.outputs[0].default_value)[:3]

    return {"Object Color": colour("Object Color"),
            "Ambient Object Color": colour("Ambient Object Color"),
            "Specular Color": colour("Specular Color"),
            "Irradiant Color": colour("Irradiant Color"),
            "Exponent": nodes["phong_exponent"].outputs[0].default_value,
            "Blinn": nodes["phong_blinn"].outputs[0].default_value}


def _f32(values):
    return pytest.approx(tuple(float(v) for v in F32(values)), abs=0)


def test_import_sets_lights_materials_and_transforms_exactly(bpy_clean):
    bpy = bpy_clean
    assert bpy.ops.phong.import_collada(filepath=LIT) == {"FINISHED"}
    got = _controls(bpy.data.materials["Red Paint"])
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


def be_reset(bpy):
    import blender_env as be  # noqa: PLC0415

    be.reset_empty_file()


def _ids(bpy):
    return {kind: {b.name for b in getattr(bpy.data, kind)} for kind in
            ("objects", "meshes", "materials", "lights", "cameras", "images", "worlds",
             "node_groups")}


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
                         for k, v in _controls(m).items()}
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


# -- rendered pixels --------------------------------------------------------------------------

M = 0.5   # the file's unit: half a metre, Y up: Blender (x, y, z) = M · (fx, −fz, fy)
TECHS = {
    "constant": {"emission": (0.3, 0.2, 0.1)},
    "lambert": {"emission": (0.01, 0.02, 0.03), "ambient": (0.2, 0.3, 0.4),
                "diffuse": (0.5, 0.4, 0.3)},
    "phong": {"ambient": (0.1, 0.1, 0.2), "diffuse": (0.3, 0.4, 0.5),
              "specular": (0.4, 0.3, 0.2), "shininess": 8.0},
    "blinn": {"emission": (0.0, 0.0, 0.05), "diffuse": (0.2, 0.3, 0.2),
              "specular": (0.5, 0.5, 0.4), "shininess": 12.0},
}
AMBIENT_LIGHT = (0.3, 0.25, 0.2)
#: light kind -> (COLLADA element, Blender position or direction source, target)
LIGHTS = {
    "directional": {"eye": (0.3, 0.2, 1.0), "color": (0.7, 0.6, 0.5)},
    "point": {"eye": (0.3, 0.2, 1.5), "color": (0.9, 0.8, 0.7), "att": (0.5, 0.3, 0.2)},
    "spot": {"eye": (0.5, 0.1, 1.2), "at": (0.2, 0.0, 0.0), "color": (1.0, 0.9, 0.8),
             "att": (1.0, 0.0, 0.25), "angle": 100.0, "exponent": 2.0},
}


def _file(b):
    """Blender metres -> the file's coordinates."""
    x, y, z = b
    return (x / M, z / M, -y / M)


def _j(values):
    return " ".join(repr(float(v)) for v in values)


def _pixel_dae(kind):
    light = LIGHTS[kind]
    effects, materials, geometries, nodes = [], [], [], []
    for index, (tech, values) in enumerate(TECHS.items()):
        inner = "".join(f"<{e}><color>{_j(values[e])} 1</color></{e}>"
                        for e in ("emission", "ambient", "diffuse", "specular") if e in values)
        if "shininess" in values:
            inner += f"<shininess><float>{values['shininess']}</float></shininess>"
        effects.append(f'<effect id="fx-{tech}"><profile_COMMON><technique sid="t"><{tech}>'
                       f"{inner}</{tech}></technique></profile_COMMON></effect>")
        materials.append(f'<material id="m-{tech}" name="{tech} paint">'
                         f'<instance_effect url="#fx-{tech}"/></material>')
        x0, x1 = -2.0 + index, -1.0 + index
        corners = [_file(c) for c in ((x0, -0.5, 0), (x1, -0.5, 0), (x1, 0.5, 0), (x0, 0.5, 0))]
        geometries.append(
            f'<geometry id="g-{tech}" name="{tech}"><mesh>'
            f'<source id="p-{tech}"><float_array id="pa-{tech}" count="12">'
            f'{_j(np.ravel(corners))}</float_array><technique_common><accessor source="#pa-{tech}" '
            f'count="4" stride="3"/></technique_common></source>'
            f'<source id="n-{tech}"><float_array id="na-{tech}" count="3">0 1 0</float_array>'
            f'<technique_common><accessor source="#na-{tech}" count="1" stride="3"/>'
            f'</technique_common></source>'
            f'<vertices id="v-{tech}"><input semantic="POSITION" source="#p-{tech}"/></vertices>'
            f'<polylist count="1" material="s"><input semantic="VERTEX" source="#v-{tech}" '
            f'offset="0"/><input semantic="NORMAL" source="#n-{tech}" offset="1"/>'
            f'<vcount>4</vcount><p>0 0 1 0 2 0 3 0</p></polylist></mesh></geometry>')
        nodes.append(f'<node id="node-{tech}" name="{tech}"><instance_geometry url="#g-{tech}">'
                     f'<bind_material><technique_common><instance_material symbol="s" '
                     f'target="#m-{tech}"/></technique_common></bind_material>'
                     f"</instance_geometry></node>")
    body = f"<color>{_j(light['color'])}</color>"
    if "att" in light:
        c, lin, q = light["att"]
        body += (f"<constant_attenuation>{c}</constant_attenuation><linear_attenuation>{lin}"
                 f"</linear_attenuation><quadratic_attenuation>{q}</quadratic_attenuation>")
    if kind == "spot":
        body += (f"<falloff_angle>{light['angle']}</falloff_angle>"
                 f"<falloff_exponent>{light['exponent']}</falloff_exponent>")
    at = _file(light.get("at", (0.0, 0.0, 0.0)))
    if kind == "point":
        place = f"<translate>{_j(_file(light['eye']))}</translate>"
    else:
        place = f"<lookat>{_j(_file(light['eye']))} {_j(at)} 0 0 -1</lookat>"
    nodes.append(f'<node id="lamp" name="Lamp">{place}<instance_light url="#L"/></node>')
    nodes.append('<node id="amb" name="Ambient"><instance_light url="#A"/></node>')
    nodes.append(f'<node id="cam" name="Camera"><lookat>{_j(_file((0, 0, 10)))} 0 0 0 '
                 f'{_j(_file((0, 1, 0)))}</lookat><instance_camera url="#C"/></node>')
    return _doc(f"""<library_cameras><camera id="C" name="Camera"><optics><technique_common>
      <orthographic><xmag>{2.0 / M}</xmag><znear>0.1</znear><zfar>100</zfar></orthographic>
      </technique_common></optics></camera></library_cameras>
      <library_lights><light id="L" name="Lamp"><technique_common><{kind}>{body}</{kind}>
      </technique_common></light><light id="A" name="Ambient"><technique_common><ambient>
      <color>{_j(AMBIENT_LIGHT)}</color></ambient></technique_common></light></library_lights>
      <library_effects>{''.join(effects)}</library_effects>
      <library_materials>{''.join(materials)}</library_materials>
      <library_geometries>{''.join(geometries)}</library_geometries>
      <library_visual_scenes><visual_scene id="vs">{''.join(nodes)}</visual_scene>
      </library_visual_scenes><scene><instance_visual_scene url="#vs"/></scene>""",
                asset=f'<unit meter="{M}"/><up_axis>Y_UP</up_axis>').decode()


def _spec_colour(kind, width, height):
    """The spec's formula (profile_COMMON: emission + ambient·La + Σ att·Lc·(diffuse·max(N·L,
    0) + specular·max(R·V or N·H, 0)^s)) at each pixel centre of the top view, in metres
    (d in the file's units for the attenuation), clamped to 1 as the Phong Color output is;
    and a mask of pixels within 1e-4 of the spot's cone edge."""
    light = LIGHTS[kind]
    cols = (np.arange(width) + 0.5) / width * 4.0 - 2.0
    rows = (np.arange(height) + 0.5) / height * 1.0 - 0.5
    x, y = np.meshgrid(cols, rows)
    P = np.stack([x, y, np.zeros_like(x)], axis=-1)
    N = np.array([0.0, 0.0, 1.0])
    V = np.array([0.0, 0.0, 1.0])
    eye = np.array(light["eye"])
    if kind == "directional":
        L = np.broadcast_to(eye / np.linalg.norm(eye), P.shape)
        att = np.ones(x.shape)
    else:
        to = eye - P
        d = np.linalg.norm(to, axis=-1)
        L = to / d[..., None]
        c, lin, q = light["att"]
        d_file = d / M
        att = 1.0 / (c + lin * d_file + q * d_file ** 2)
    edge = np.zeros(x.shape, bool)
    if kind == "spot":
        axis = np.array(light["at"]) - eye
        axis /= np.linalg.norm(axis)
        cos_w = np.einsum("...i,i->...", -L, axis)
        cos_half = math.cos(math.radians(light["angle"] / 2.0))
        att = att * np.where(cos_w >= cos_half, np.maximum(cos_w, 0) ** light["exponent"], 0.0)
        edge = np.abs(cos_w - cos_half) < 1e-4
        _spec_colour.inside = cos_w >= cos_half
    ndl = np.maximum(L @ N, 0.0)
    R = 2.0 * ndl[..., None] * N - L
    H = (L + V) / np.linalg.norm(L + V, axis=-1, keepdims=True)
    out = np.zeros(P.shape)
    for index, (tech, values) in enumerate(TECHS.items()):
        m = (x >= -2.0 + index) & (x < -1.0 + index)
        ke, ka, kd, ks = (np.array(values.get(e, (0.0, 0.0, 0.0)))
                          for e in ("emission", "ambient", "diffuse", "specular"))
        if tech == "constant":
            colour = np.broadcast_to(ke, P.shape)
        else:
            spec = 0.0
            if tech == "phong":
                spec = np.maximum(R @ V, 0.0) ** values["shininess"]
            elif tech == "blinn":
                spec = np.maximum(H @ N, 0.0) ** values["shininess"]
            colour = ke + ka * np.array(AMBIENT_LIGHT) + att[..., None] * np.array(
                light["color"]) * (kd * ndl[..., None] + ks * np.asarray(spec)[..., None])
        out[m] = np.minimum(colour, 1.0)[m]
    return out, edge


def _render_dae(bpy, kind, engine, tmp_path):
    import blender_env as be  # noqa: PLC0415
    from phong_scene import render  # noqa: PLC0415

    width, height = 64, 16
    scene = be.new_scene(f"dae {kind} {engine}", width, height, engine)
    bpy.context.window.scene = scene
    path = tmp_path / f"{kind}.dae"
    path.write_text(_pixel_dae(kind))
    assert bpy.ops.phong.import_collada(filepath=str(path)) == {"FINISHED"}
    assert scene.camera is not None and scene.camera.data.type == "ORTHO"
    assert bpy.ops.phong.add_term_passes() == {"FINISHED"}
    if engine == "eevee":   # Eevee: the one AOV the check reads
        layer = scene.view_layers[0]
        for aov in [a for a in layer.aovs if a.name != "Phong Color"]:
            layer.aovs.remove(aov)
    passes, seconds = render(bpy, scene, str(tmp_path / f"{kind}_{engine}.exr"))
    got = passes["Phong Color"][..., :3].astype(np.float64)
    want, edge = _spec_colour(kind, width, height)
    assert want.max() > 0.2 and want.std() > 0.02, "lit, not flat"
    if kind == "spot":   # the cone's edge crosses the picture: pixels in and out of it
        inside = _spec_colour.inside
        assert inside.any() and (~inside).any()
    err = np.abs(got - want).max(axis=-1)[~edge]
    be.report(f"[collada {kind} {engine}] {seconds:.1f} s, max |Phong Color - spec| = "
              f"{err.max():.2e}, within 1/255: {float((err <= 1 / 255).mean()):.2%}, "
              f"spot-edge pixels left out: {int(edge.sum())}")
    return err, edge


@pytest.mark.cycles
@pytest.mark.parametrize("kind", sorted(LIGHTS))
def test_techniques_and_lights_render_the_spec_formula_cycles(bpy_clean, tmp_path, kind):
    err, edge = _render_dae(bpy_clean, kind, "cycles", tmp_path)
    assert edge.sum() <= 4
    assert err.max() <= 1e-4


@pytest.mark.eevee
@pytest.mark.parametrize("kind", sorted(LIGHTS))
def test_techniques_and_lights_render_the_spec_formula_eevee(bpy_clean, tmp_path, kind):
    err, _edge = _render_dae(bpy_clean, kind, "eevee", tmp_path)
    assert float((err <= 1 / 255).mean()) >= 0.995


# -- real files ---------------------------------------------------------------------------------

def _et(name):
    """A data file parsed here with ElementTree (namespaces removed), independent of the
    reader under test."""
    root = ET.parse(os.path.join(DATA, name)).getroot()
    for element in root.iter():
        element.tag = element.tag.rsplit("}", 1)[-1]
    return root


def _text_floats(element):
    return [float(v) for v in element.text.split()]


def test_khronos_point_light_attenuation_is_rescaled_to_metres(bpy_clean):
    bpy = bpy_clean
    name = "cts_point_quadratic_attenuation_light.dae"
    root = _et(name)
    meter = float(root.find("asset/unit").get("meter"))
    point = root.find(".//light/technique_common/point")
    c, lin, q = (float(point.find(t).text) for t in (
        "constant_attenuation", "linear_attenuation", "quadratic_attenuation"))
    assert bpy.ops.phong.import_collada(filepath=os.path.join(DATA, name)) == {"FINISHED"}
    (light,) = [o for o in bpy.data.objects if o.type == "LIGHT"]
    got = light.data
    assert (got["phong_constant"], got["phong_linear"], got["phong_quadratic"]) == pytest.approx(
        (c, lin / meter, q / meter ** 2), rel=1e-12)
    assert tuple(got.color) == _f32(_text_floats(point.find("color")))
    # its node's translation, in metres, Y up turned to Z up
    node = next(n for n in root.iter("node") if n.find("instance_light") is not None)
    tx, ty, tz = _text_floats(node.find("translate"))
    assert tuple(light.matrix_world.translation) == pytest.approx(
        (tx * meter, -tz * meter, ty * meter), abs=1e-6)


def test_khronos_spot_keeps_full_cone_and_exponent(bpy_clean):
    bpy = bpy_clean
    name = "cts__reference_spot_white_light.dae"
    spot = _et(name).find(".//light/technique_common/spot")
    assert bpy.ops.phong.import_collada(filepath=os.path.join(DATA, name)) == {"FINISHED"}
    (light,) = [o.data for o in bpy.data.objects if o.type == "LIGHT"]
    assert light.type == "SPOT"
    assert light.spot_size == pytest.approx(math.radians(float(spot.find("falloff_angle").text)),
                                            abs=1e-7)
    assert light["phong_edge_exponent"] == float(spot.find("falloff_exponent").text)


def test_khronos_setparam_and_swapped_names(bpy_clean):
    """Maya's material ids and names differ ("lambert1" named "lambert2"); the transparency
    comes from the material's <setparam>, the colours from newparams in the technique."""
    bpy = bpy_clean
    name = "cts_material_setparam_transparency.dae"
    root = _et(name)
    doc = collada.load(os.path.join(DATA, name))
    assert {m.name for m in doc.materials.values()} == {
        m.get("name") for m in root.iter("material")}
    setparam = root.find(".//instance_effect/setparam")
    phong = doc.materials["phong1"]
    assert phong.transparency == float(setparam.find("float").text) == 0.5
    assert phong.color("diffuse") == (1.0, 1.0, 1.0)
    assert phong.shininess == 1.0
    assert bpy.ops.phong.import_collada(filepath=os.path.join(DATA, name)) == {"FINISHED"}
    assert {"lambert2", "phong1"} <= {m.name for m in bpy.data.materials}


def test_khronos_15_transparency_param_opacity(bpy_clean):
    bpy = bpy_clean
    name = "cts15_halfTransparency.dae"
    doc = collada.load(os.path.join(DATA, name))
    assert doc.version.startswith("1.5")
    half = next(m for m in doc.materials.values() if m.effect_id == "lambert1-fx")
    assert (half.opaque, half.transparent, half.transparency) == ("A_ONE", (0, 0, 0, 1), 0.5)
    assert half.opacity() == 0.5   # A_ONE: a · t
    assert bpy.ops.phong.import_collada(filepath=os.path.join(DATA, name)) == {"FINISHED"}
    material = bpy.data.materials[half.name]
    node = material.node_tree.nodes.get("phong_opacity")
    assert node is not None and node.outputs[0].default_value == 0.5


def test_khronos_instance_node_skew_and_inch(bpy_clean):
    bpy = bpy_clean
    name = "cts_instances_of_same_node.dae"
    root = _et(name)
    uses = [i.get("url") for i in root.iter("instance_node")]
    assert bpy.ops.phong.import_collada(filepath=os.path.join(DATA, name)) == {"FINISHED"}
    meshes = [o for o in bpy.data.objects if o.type == "MESH"]
    assert len(meshes) == len(uses) >= 2, "each instance_node a copy of the node"
    assert len({o.data for o in meshes}) == 1, "sharing one mesh"
    # skew: exact through the parent inverse matrix (world = A · M · skew) on a vertex
    be_reset(bpy)
    name = "cts_node_skew_cube.dae"
    root = _et(name)
    skew = _text_floats(root.find(".//node/skew"))
    assert bpy.ops.phong.import_collada(filepath=os.path.join(DATA, name)) == {"FINISHED"}
    cube = next(o for o in bpy.data.objects if o.type == "MESH")
    angle = math.radians(skew[0])
    a = np.array(skew[1:4]) / np.linalg.norm(skew[1:4])
    b = np.array(skew[4:7]) / np.linalg.norm(skew[4:7])
    # RenderMan's skew for perpendicular axes: p + tan(angle) (p · a) b
    meter = float(root.find("asset/unit").get("meter"))
    world = np.array(cube.matrix_world)
    for vertex in cube.data.vertices[:4]:
        p_file = np.array(vertex.co) / meter
        want_file = p_file + math.tan(angle) * np.dot(p_file, a) * b
        want = meter * np.array([want_file[0], -want_file[2], want_file[1]])
        got = world[:3, :3] @ np.array(vertex.co) + world[:3, 3]
        np.testing.assert_allclose(got, want, atol=1e-6)
    be_reset(bpy)
    name = "cts_inch.dae"
    root = _et(name)
    assert float(root.find("asset/unit").get("meter")) == 0.0254
    first = _text_floats(root.find(".//float_array"))[:3]
    assert bpy.ops.phong.import_collada(filepath=os.path.join(DATA, name)) == {"FINISHED"}
    cube = next(o for o in bpy.data.objects if o.type == "MESH")
    assert tuple(cube.data.vertices[0].co) == pytest.approx(
        tuple(v * 0.0254 for v in first), abs=1e-7), "positions in metres"


def test_ros_mesh_with_a_missing_texture_imports_with_one_warning(bpy_clean, capfd):
    bpy = bpy_clean
    name = "ros_l_finger_tip.dae"
    root = _et(name)
    image = root.find(".//library_images/image/init_from").text
    capfd.readouterr()
    assert bpy.ops.phong.import_collada(filepath=os.path.join(DATA, name)) == {"FINISHED"}
    logged = "".join(capfd.readouterr())
    assert logged.count(f"texture {image} not found") == 1
    (mesh,) = [o for o in bpy.data.objects if o.type == "MESH"]
    triangles = sum(int(t.get("count")) for t in root.iter("triangles")) + sum(
        len(p.get("count", "") and p.find("vcount").text.split()) for p in root.iter("polylist"))
    assert len(mesh.data.polygons) == triangles
    assert mesh.data.uv_layers, "texture coordinates kept"


def _png(bpy, path):
    image = bpy.data.images.new("tiles", 2, 2)
    image.filepath_raw = str(path)
    image.file_format = "PNG"
    image.save()
    bpy.data.images.remove(image)


def test_texture_chain_feeds_its_input_and_exports_back(bpy_clean, tmp_path):
    """A diffuse texture through newparam → sampler2D → surface → image (and a texcoord bound
    to set 1) feeds Object Color; export writes the chain again, relative to the file, and
    it validates and reads back."""
    bpy = bpy_clean
    (tmp_path / "maps").mkdir()
    _png(bpy, tmp_path / "maps" / "wood grain.png")
    text = open(LIT).read()
    text = text.replace("<library_effects>", '<library_images><image id="img-wood" name="wood">'
                        "<init_from>maps/wood%20grain.png</init_from></image></library_images>"
                        "<library_effects>")
    text = text.replace('<newparam sid="shine">',
                        '<newparam sid="surf"><surface type="2D"><init_from>img-wood</init_from>'
                        '</surface></newparam><newparam sid="samp"><sampler2D><source>surf'
                        '</source></sampler2D></newparam><newparam sid="shine">')
    text = text.replace("<diffuse><color>0,8 0,1 0,1 1</color></diffuse>",
                        '<diffuse><texture texture="samp" texcoord="CH1"/></diffuse>')
    text = text.replace('<input semantic="VERTEX" source="#quad-v" offset="0"/>',
                        '<input semantic="VERTEX" source="#quad-v" offset="0"/>'
                        '<input semantic="TEXCOORD" source="#quad-uv0" offset="0" set="0"/>'
                        '<input semantic="TEXCOORD" source="#quad-uv1" offset="0" set="1"/>')
    uv = ('<source id="quad-uv{n}"><float_array id="quad-uv{n}-a" count="8">{v}</float_array>'
          '<technique_common><accessor source="#quad-uv{n}-a" count="4" stride="2"/>'
          "</technique_common></source>")
    text = text.replace('<vertices id="quad-v">',
                        uv.format(n=0, v="0 0 1 0 1 1 0 1") + uv.format(n=1, v="0 0 2 0 2 2 0 2")
                        + '<vertices id="quad-v">')
    text = text.replace('target="#red-id"/>', 'target="#red-id"><bind_vertex_input semantic="CH1" '
                        'input_semantic="TEXCOORD" input_set="1"/></instance_material>')
    path = tmp_path / "textured.dae"
    path.write_text(text)
    assert bpy.ops.phong.import_collada(filepath=str(path)) == {"FINISHED"}
    tree = bpy.data.materials["Red Paint"].node_tree
    feed = tree.nodes["phong_lights"].inputs["Object Color"].links[0].from_node
    assert feed.bl_idname == "ShaderNodeTexImage"
    assert os.path.samefile(bpy.path.abspath(feed.image.filepath),
                            tmp_path / "maps" / "wood grain.png")
    uv_node = feed.inputs["Vector"].links[0].from_node
    quad = bpy.data.objects["Quad node"].data
    assert uv_node.uv_map in quad.uv_layers, "the texcoord's bound set"
    layer = quad.uv_layers[uv_node.uv_map]
    assert max(max(d.uv) for d in layer.data) == 2.0, "set 1's coordinates"
    out = tmp_path / "out" / "again.dae"
    out.parent.mkdir()
    assert bpy.ops.phong.export_collada(filepath=str(out)) == {"FINISHED"}
    written = out.read_text()
    _valid(written)
    assert "../maps/wood%20grain.png" in written
    doc = collada.load(str(out))
    (mat,) = doc.materials.values()
    assert os.path.samefile(mat.textures["diffuse"].resolved, tmp_path / "maps" / "wood grain.png")


def test_an_error_while_building_removes_everything_added(bpy_clean, monkeypatch):
    bpy = bpy_clean
    from phong_nodes.addon.interchange import collada_import  # noqa: PLC0415

    bpy.context.scene.world = bpy.data.worlds.new("Kept")
    bpy.context.scene.world.phong.ambient_intensity = 0.4
    before = _ids(bpy)

    real = collada_import._Builder.bind_materials

    def broken(self):   # fails after the materials, lights groups and images were made
        real(self)
        raise RuntimeError("simulated failure")

    monkeypatch.setattr(collada_import._Builder, "bind_materials", broken)
    with pytest.raises(RuntimeError, match="simulated failure.*nothing imported"):
        bpy.ops.phong.import_collada(filepath=LIT)
    assert _ids(bpy) == before
    assert bpy.context.scene.world.phong.ambient_intensity == pytest.approx(0.4)
    assert bpy.context.scene.camera is None


def test_round_trip_keeps_meshes_and_cameras(bpy_clean, tmp_path):
    bpy = bpy_clean
    path = os.path.join(DATA, "cts_node_skew_cube.dae")
    assert bpy.ops.phong.import_collada(filepath=path) == {"FINISHED"}

    def state():
        out = {}
        for o in bpy.data.objects:
            world = tuple(np.round(np.array(o.matrix_world), 5).reshape(-1))
            if o.type == "MESH":
                co = np.array([tuple(v.co) for v in o.data.vertices], dtype=np.float32)
                out[o.name] = ("MESH", world, co.tobytes(), len(o.data.polygons),
                               np.round(np.array([tuple(n.vector) for n in
                                                  o.data.corner_normals]), 5).tobytes())
            elif o.type == "CAMERA":
                c = o.data
                out[o.name] = ("CAMERA", world, c.type, F32(c.angle), c.sensor_fit,
                               F32(c.clip_start), F32(c.clip_end))
        return out

    first = state()
    assert any(v[0] == "CAMERA" for v in first.values())
    out = tmp_path / "cube.dae"
    assert bpy.ops.phong.export_collada(filepath=str(out)) == {"FINISHED"}
    _valid(out.read_text())
    be_reset(bpy)
    assert bpy.ops.phong.import_collada(filepath=str(out)) == {"FINISHED"}
    assert state() == first


def test_khronos_bind_vertex_input_names_the_texture_set(bpy_clean, capfd):
    bpy = bpy_clean
    name = "cts_cube_texture_coord.dae"
    root = _et(name)
    bvi = root.find(".//bind_vertex_input")
    texture = root.find(".//diffuse/texture")
    doc = collada.load(os.path.join(DATA, name))
    (mat,) = doc.materials.values()
    assert mat.textures["diffuse"].texcoord == texture.get("texcoord") == bvi.get("semantic")
    assert mat.textures["diffuse"].path == root.find(".//image/init_from").text
    inst = next(i for n in doc.nodes for i in n.instances if i.kind == "geometry")
    (symbol,) = inst.uv_bindings
    assert inst.uv_bindings[symbol] == {bvi.get("semantic"): int(bvi.get("input_set"))}
    capfd.readouterr()
    assert bpy.ops.phong.import_collada(filepath=os.path.join(DATA, name)) == {"FINISHED"}
    assert "texture collada.png not found" in "".join(capfd.readouterr())
    cube = next(o for o in bpy.data.objects if o.type == "MESH")
    assert [layer.name for layer in cube.data.uv_layers] == ["UVMap"]


def test_instance_node_fan_out_is_bounded(bpy_clean, monkeypatch, tmp_path, capfd):
    """Each node instancing the next one twice, 30 deep: 2^30 copies; the import stops at
    the node limit with one warning, in bounded time."""
    bpy = bpy_clean
    from phong_nodes.addon.interchange import collada_import  # noqa: PLC0415

    monkeypatch.setattr(collada_import, "MAX_NODES", 200)
    nodes = "".join(f'<node id="n{i}"><instance_node url="#n{i + 1}"/>'
                    f'<instance_node url="#n{i + 1}"/></node>' for i in range(30))
    path = tmp_path / "fan.dae"
    path.write_bytes(_doc(f"""<library_nodes>{nodes}<node id="n30"/></library_nodes>
      <library_visual_scenes><visual_scene id="vs"><node id="root">
      <instance_node url="#n0"/></node></visual_scene></library_visual_scenes>
      <scene><instance_visual_scene url="#vs"/></scene>"""))
    start = time.perf_counter()
    capfd.readouterr()
    assert bpy.ops.phong.import_collada(filepath=str(path)) == {"FINISHED"}
    assert time.perf_counter() - start < 30.0
    # the root and n0 ... n30, each instance doubling: 1 + (2^31 - 1) objects asked for
    asked = 1 + sum(2 ** k for k in range(31))
    assert "".join(capfd.readouterr()).count(
        f"would make {asked:,} objects, more than 200; the first 200 imported") == 1
    assert len(bpy.data.objects) == 200


def test_fbx_exporter_file_with_decimal_commas_and_a_plain_image_reference(bpy_clean, capfd):
    """Autodesk's "FBX COLLADA exporter" (COLLADA 1.4.0) writes decimal commas everywhere,
    <unit meter="0,010000">, a texture naming the image id and a Windows path."""
    bpy = bpy_clean
    name = "pycollada_earthCylindrical.dae"
    root = _et(name)
    ambient = [float(v.replace(",", ".")) for v in root.find(".//ambient/color").text.split()]
    doc = collada.load(os.path.join(DATA, name))
    assert doc.meter == 0.01
    (mat,) = doc.materials.values()
    assert mat.color("ambient") == tuple(ambient[:3])
    image = root.find(".//image/init_from").text
    assert mat.textures["diffuse"].path == image
    assert os.path.basename(mat.textures["diffuse"].resolved) == image.split("\\")[-1]
    assert len([w for w in doc.warnings if "decimal commas" in w]) == 1
    capfd.readouterr()
    assert bpy.ops.phong.import_collada(filepath=os.path.join(DATA, name)) == {"FINISHED"}
    logged = "".join(capfd.readouterr())
    assert logged.count("decimal commas") == 1
    assert logged.count(f"texture {image} not found") == 1
    got = _controls(bpy.data.materials[mat.name])
    assert got["Ambient Object Color"] == _f32(ambient[:3])


def test_polygons_holes_colours_and_x_up():
    data = _doc("""<library_geometries><geometry id="g"><mesh>
      <source id="pos"><float_array id="pa" count="15">0 0 0 1 0 0 1 1 0 0 1 0 2 0 0</float_array>
      <technique_common><accessor source="#pa" count="5" stride="3"/></technique_common></source>
      <source id="col"><float_array id="ca" count="6">1 0 0 0 0.5 1</float_array>
      <technique_common><accessor source="#ca" count="2" stride="3"/></technique_common></source>
      <vertices id="v"><input semantic="POSITION" source="#pos"/></vertices>
      <polygons count="3"><input semantic="VERTEX" source="#v" offset="0"/>
      <input semantic="COLOR" source="#col" offset="1"/>
      <p>0 0 1 0 2 0 3 0</p><p>1 1 4 1 2 1</p><ph><p>0 0 1 0 2 0</p><h>0 0 0 0 0 0</h></ph>
      </polygons></mesh></geometry></library_geometries>""",
                asset="<up_axis>X_UP</up_axis>")
    doc = collada.parse_bytes(data)
    mesh = doc.meshes["g"]
    assert mesh.face_sizes.tolist() == [4, 3, 3]
    assert mesh.corners.tolist() == [0, 1, 2, 3, 1, 4, 2, 0, 1, 2]
    np.testing.assert_array_equal(mesh.colors[0][4], (0, 0.5, 1, 1)), "RGB with alpha 1"
    assert any("holes (<ph>)" in w for w in doc.warnings)
    # X_UP: right is −Y, up is +X, in is +Z (the spec's table); Blender: right +X, up +Z, in −Y
    axes = doc.axes()
    np.testing.assert_allclose(axes @ (1, 0, 0, 1), (0, 0, 1, 1), atol=1e-15)
    np.testing.assert_allclose(axes @ (0, -1, 0, 1), (1, 0, 0, 1), atol=1e-15)
    np.testing.assert_allclose(axes @ (0, 0, 1, 1), (0, -1, 0, 1), atol=1e-15)
    assert np.linalg.det(axes[:3, :3]) == pytest.approx(1.0)


def test_vertex_colours_and_selection_only_export(bpy_clean, tmp_path):
    bpy = bpy_clean
    text = open(LIT).read().replace(
        '<vertices id="quad-v">',
        '<source id="quad-col"><float_array id="quad-col-a" count="16">1 0 0 1 0 1 0 1 0 0 1 1 '
        '1 1 1 0.5</float_array><technique_common><accessor source="#quad-col-a" count="4" '
        'stride="4"/></technique_common></source><vertices id="quad-v">').replace(
        '<input semantic="VERTEX" source="#quad-v" offset="0"/>',
        '<input semantic="VERTEX" source="#quad-v" offset="0"/>'
        '<input semantic="COLOR" source="#quad-col" offset="0" set="0"/>')
    path = tmp_path / "colours.dae"
    path.write_text(text)
    assert bpy.ops.phong.import_collada(filepath=str(path)) == {"FINISHED"}
    quad = bpy.data.objects["Quad node"]
    attribute = quad.data.color_attributes[0]
    assert attribute.domain == "CORNER"
    # corners 0 3 2 1 take the colours of vertices 0 3 2 1
    assert [tuple(d.color) for d in attribute.data] == [
        (1, 0, 0, 1), (1, 1, 1, 0.5), (0, 0, 1, 1), (0, 1, 0, 1)]
    for obj in bpy.context.scene.objects:
        obj.select_set(obj.name == "Quad node")
    out = tmp_path / "only.dae"
    assert bpy.ops.phong.export_collada(filepath=str(out), use_selection=True) == {"FINISHED"}
    _valid(out.read_text())
    doc = collada.load(str(out))
    assert [n.name for n in doc.nodes if n.instances[0].kind != "light"] == ["Quad node"]
    assert not [light for light in doc.lights.values() if light.kind != "ambient"]
    (mesh,) = doc.meshes.values()
    np.testing.assert_array_equal(mesh.colors[0][1], (1, 1, 1, 0.5))


OPACITY = 0.4   # the phong quad's A_ONE: a · t = 1 · 0.4


@pytest.mark.parametrize("engine", [pytest.param("cycles", marks=pytest.mark.cycles),
                                    pytest.param("eevee", marks=pytest.mark.eevee)])
def test_transparency_renders_opacity_times_the_colour(bpy_clean, tmp_path, engine):
    """The phong quad with <transparent opaque="A_ONE">1 1 1 1</transparent> and
    <transparency>0.4</transparency> over the black world: Combined = 0.4 × the spec's colour
    there, the spec's colour on the other quads."""
    import blender_env as be  # noqa: PLC0415
    from phong_scene import render  # noqa: PLC0415

    bpy = bpy_clean
    width, height = 64, 16
    scene = be.new_scene(f"dae opacity {engine}", width, height, engine)
    bpy.context.window.scene = scene
    text = _pixel_dae("directional").replace(
        "<shininess><float>8.0</float></shininess></phong>",
        "<shininess><float>8.0</float></shininess><transparent opaque=\"A_ONE\"><color>1 1 1 1"
        f"</color></transparent><transparency><float>{OPACITY}</float></transparency></phong>")
    assert f"<float>{OPACITY}</float>" in text
    path = tmp_path / "opacity.dae"
    path.write_text(text)
    assert bpy.ops.phong.import_collada(filepath=str(path)) == {"FINISHED"}
    passes, _seconds = render(bpy, scene, str(tmp_path / f"opacity_{engine}.exr"))
    got = passes["Combined"][..., :3].astype(np.float64)
    want, _edge = _spec_colour("directional", width, height)
    x = (np.arange(width) + 0.5) / width * 4.0 - 2.0
    phong = (x >= 0.0) & (x < 1.0)
    want[:, phong] *= OPACITY
    err = np.abs(got - want).max(axis=-1)
    be.report(f"[collada opacity {engine}] max |Combined - spec| = {err.max():.2e}, "
              f"within 1/255: {float((err <= 1 / 255).mean()):.2%}")
    if engine == "cycles":
        assert err.max() <= 1e-4
    else:
        assert float((err <= 1 / 255).mean()) >= 0.995


def test_export_of_a_blender_scene_writes_the_controls_and_says_what_it_cannot(bpy_clean,
                                                                               tmp_path):
    """A scene made in Blender (Apply Phong Material, lights set by hand): the file's values
    read back with ElementTree here; a power falloff of k = 1 is 1/(0 + 1·d + 0·d²); the
    Diffuse factor and a changed Opacity are reported / written."""
    bpy = bpy_clean
    scene = bpy.context.scene
    mesh = bpy.data.meshes.new("Tile")
    mesh.from_pydata([(0, 0, 0), (1, 0, 0), (1, 1, 0), (0, 1, 0)], [], [(0, 1, 2, 3)])
    tile = bpy.data.objects.new("Tile", mesh)
    scene.collection.objects.link(tile)
    lamp = bpy.data.objects.new("Lamp", bpy.data.lights.new("Lamp", "POINT"))
    scene.collection.objects.link(lamp)
    lamp.location = (0.5, 0.5, 2.0)
    lamp.data.color = (0.25, 0.5, 1.0)
    lamp.data["phong_falloff"] = "POWER"
    lamp.data["phong_power_k"] = 1.0
    lamp.data["phong_diffuse"] = 0.5
    for obj in scene.objects:
        obj.select_set(obj is tile)
    bpy.context.view_layer.objects.active = tile
    assert bpy.ops.phong.apply_material() == {"FINISHED"}
    material = tile.active_material
    nodes = material.node_tree.nodes
    nodes["phong_object_color"].outputs[0].default_value = (0.1, 0.2, 0.3, 1.0)
    nodes["phong_specular_color"].outputs[0].default_value = (0.7, 0.6, 0.5, 1.0)
    nodes["phong_exponent"].outputs[0].default_value = 42.0
    nodes["phong_blinn"].outputs[0].default_value = 1.0
    from phong_nodes.addon.lighting import materials  # noqa: PLC0415

    materials.set_opacity(material, 0.75)
    out = tmp_path / "made.dae"
    from phong_nodes.addon.interchange import collada_export  # noqa: PLC0415

    warnings = collada_export.export(bpy.context, str(out))
    assert any("light Lamp: Diffuse 0.5 / Specular 1 factors" in w for w in warnings)
    text = out.read_text()
    _valid(text)
    root = ET.fromstring(text)
    for element in root.iter():
        element.tag = element.tag.rsplit("}", 1)[-1]
    blinn = root.find(".//effect/profile_COMMON/technique/blinn")
    assert blinn is not None, "Blinn 1: <blinn>"
    assert F32(_text_floats(blinn.find("diffuse/color"))).tobytes() == F32(
        (0.1, 0.2, 0.3, 1.0)).tobytes(), "float32 exact"
    assert _text_floats(blinn.find("ambient/color"))[:3] == _text_floats(
        blinn.find("diffuse/color"))[:3], "the seeds' model: Ka = Object Color"
    assert _text_floats(blinn.find("shininess/float")) == [42.0]
    assert blinn.find("transparent").get("opaque") == "A_ONE"
    assert _text_floats(blinn.find("transparency/float")) == [0.75]
    point = root.find(".//light/technique_common/point")
    assert [float(point.find(t).text) for t in ("constant_attenuation", "linear_attenuation",
                                                "quadratic_attenuation")] == [0.0, 1.0, 0.0]
    assert _text_floats(point.find("color")) == [0.25, 0.5, 1.0]
    assert root.find("asset/up_axis").text == "Z_UP"
    assert root.find("asset/unit").get("meter") == "1"


def test_opacity_changed_after_import_is_exported(bpy_clean, tmp_path):
    bpy = bpy_clean
    assert bpy.ops.phong.import_collada(filepath=LIT) == {"FINISHED"}
    from phong_nodes.addon.lighting import materials  # noqa: PLC0415

    material = bpy.data.materials["Red Paint"]
    out = tmp_path / "kept.dae"
    assert bpy.ops.phong.export_collada(filepath=str(out)) == {"FINISHED"}
    (mat,) = collada.load(str(out)).materials.values()
    assert (mat.opaque, mat.transparent, mat.transparency) == ("RGB_ZERO", (0, 0, 0, 1), 0.0), \
        "unchanged: the file's own transparency"
    materials.set_opacity(material, 0.5)
    assert bpy.ops.phong.export_collada(filepath=str(out)) == {"FINISHED"}
    (mat,) = collada.load(str(out)).materials.values()
    assert mat.opacity() == 0.5 and mat.opaque == "A_ONE"


def _strip_dae():
    """Two strips stitched into one with repeated vertices (the usual way to join strips):
    0 1 2 3 | 3 4 (stitch) | 4 5 6 7."""
    return _doc("""<library_geometries><geometry id="g" name="stitched"><mesh>
      <source id="pos"><float_array id="pa" count="24">0 0 0 1 0 0 0 1 0 1 1 0
        3 0 0 4 0 0 3 1 0 4 1 0</float_array>
      <technique_common><accessor source="#pa" count="8" stride="3"/></technique_common></source>
      <source id="nor"><float_array id="na" count="3">0 0 1</float_array>
      <technique_common><accessor source="#na" count="1" stride="3"/></technique_common></source>
      <vertices id="v"><input semantic="POSITION" source="#pos"/></vertices>
      <tristrips count="1"><input semantic="VERTEX" source="#v" offset="0"/>
      <input semantic="NORMAL" source="#nor" offset="1"/>
      <p>0 0 1 0 2 0 3 0 3 0 4 0 4 0 5 0 6 0 7 0</p></tristrips></mesh></geometry>
      </library_geometries><library_visual_scenes><visual_scene id="vs"><node id="n" name="n">
      <instance_geometry url="#g"/></node></visual_scene></library_visual_scenes>
      <scene><instance_visual_scene url="#vs"/></scene>""")


def test_stitched_strips_lose_their_degenerate_triangles():
    doc = collada.parse_bytes(_strip_dae())
    mesh = doc.meshes["g"]
    assert len(mesh.face_sizes) == 8, "10 strip vertices: 8 triangles"
    assert collada.drop_degenerate(mesh) == 4, "the 4 triangles of the stitch"
    def cyclic(t):   # the same triangle and winding, whichever corner comes first
        k = t.index(min(t))
        return t[k:] + t[:k]

    tris = [cyclic(t) for t in mesh.corners.reshape(-1, 3).tolist()]
    # OpenGL's strip rule: triangle n is (n, n+1, n+2) for even n, (n+1, n, n+2) for odd n
    assert tris == [cyclic(t) for t in ([0, 1, 2], [2, 1, 3], [4, 5, 6], [6, 5, 7])]
    assert mesh.normals.shape == (12, 3) and len(mesh.face_symbols) == 4


def test_stitched_strips_import_into_a_valid_mesh(bpy_clean, tmp_path, capfd):
    bpy = bpy_clean
    path = tmp_path / "strips.dae"
    path.write_bytes(_strip_dae())
    capfd.readouterr()
    assert bpy.ops.phong.import_collada(filepath=str(path)) == {"FINISHED"}
    mesh = bpy.data.objects["n"].data
    assert (len(mesh.polygons), len(mesh.edges)) == (4, 10)
    assert not mesh.validate(verbose=False), "nothing left for Blender to repair"
    assert "using a vertex twice" not in "".join(capfd.readouterr()), "strips: no warning"
    normals = np.array([tuple(n.vector) for n in mesh.corner_normals])
    np.testing.assert_allclose(normals, np.tile((0, 0, 1), (12, 1)), atol=1e-6)


def test_instances_of_one_mesh_binding_different_materials(bpy_clean, tmp_path):
    bpy = bpy_clean
    text = open(LIT).read()
    text = text.replace("</library_materials>",
                        '<material id="blue-id" name="Blue"><instance_effect url="#fx-red">'
                        '<setparam ref="spec"><float3>0 0 1</float3></setparam></instance_effect>'
                        "</material></library_materials>")
    text = text.replace('<node id="n-amb"',
                        '<node id="n-quad2" name="Second quad"><translate>0 0 5</translate>'
                        '<instance_geometry url="#quad"><bind_material><technique_common>'
                        '<instance_material symbol="mat" target="#blue-id"/></technique_common>'
                        '</bind_material></instance_geometry></node><node id="n-amb"')
    path = tmp_path / "two.dae"
    path.write_text(text)

    def bound():
        return {name: bpy.data.objects[name].material_slots[0].material.name
                for name in ("Quad node", "Second quad")}

    assert bpy.ops.phong.import_collada(filepath=str(path)) == {"FINISHED"}
    assert bpy.data.objects["Quad node"].data is bpy.data.objects["Second quad"].data
    assert bound() == {"Quad node": "Red Paint", "Second quad": "Blue"}
    assert _controls(bpy.data.materials["Blue"])["Specular Color"] == (0.0, 0.0, 1.0)
    assert "phong_collada_symbols" not in bpy.data.objects["Quad node"].data.keys()
    out = tmp_path / "two_out.dae"
    assert bpy.ops.phong.export_collada(filepath=str(out)) == {"FINISHED"}
    _valid(out.read_text())
    be_reset(bpy)
    assert bpy.ops.phong.import_collada(filepath=str(out)) == {"FINISHED"}
    assert bound() == {"Quad node": "Red Paint", "Second quad": "Blue"}


def test_instance_node_chain_deeper_than_the_limit(bpy_clean, tmp_path, capfd):
    bpy = bpy_clean
    nodes = "".join(f'<node id="n{i}"><instance_node url="#n{i + 1}"/></node>'
                    for i in range(2000))
    path = tmp_path / "deep.dae"
    path.write_bytes(_doc(f"""<library_nodes>{nodes}<node id="n2000"/></library_nodes>
      <library_visual_scenes><visual_scene id="vs"><node id="root">
      <instance_node url="#n0"/></node></visual_scene></library_visual_scenes>
      <scene><instance_visual_scene url="#vs"/></scene>"""))
    capfd.readouterr()
    assert bpy.ops.phong.import_collada(filepath=str(path)) == {"FINISHED"}
    assert "".join(capfd.readouterr()).count("nested more than 256 deep") == 1
    assert len(bpy.data.objects) == 257


def test_blender_42_exporter_file_full_cone_and_values(bpy_clean):
    """Blender 4.2's own exporter (tests/data/collada/make_blender42_scene.py) wrote the
    spot's full cone (spot_size 60°) as falloff_angle 60: read back as the same cone."""
    bpy = bpy_clean
    name = "blender42_scene.dae"
    root = _et(name)
    assert root.find("asset/contributor/authoring_tool").text.startswith("Blender 4.2")
    spot_xml = next(light for light in root.iter("light") if light.get("name") == "Spot")
    angle = float(spot_xml.find(".//falloff_angle").text)
    assert angle == 60.0, "the exporter's spot_size in degrees: the full cone"
    assert bpy.ops.phong.import_collada(filepath=os.path.join(DATA, name)) == {"FINISHED"}
    spot = next(o for o in bpy.data.objects if o.type == "LIGHT" and o.data.type == "SPOT")
    assert spot.data.spot_size == pytest.approx(math.radians(60.0), abs=1e-7)
    assert tuple(spot.data.color) == _f32(_text_floats(spot_xml.find(".//color")))
    tile = next(o for o in bpy.data.objects if o.type == "MESH")
    diffuse = _text_floats(root.find(".//lambert/diffuse/color"))
    got = _controls(tile.active_material)
    assert got["Object Color"] == _f32(diffuse[:3])
    assert got["Specular Color"] == (0.0, 0.0, 0.0), "lambert"
    assert bpy.context.scene.camera is not None
    assert {o.data.type for o in bpy.data.objects if o.type == "LIGHT"} == {"SPOT", "POINT", "SUN"}


def test_blender_4_importer_reads_the_export(bpy_clean, tmp_path):
    """Blender 4.x's own COLLADA importer (removed in 5.0) opens the exported file: the
    objects by name, the spot's full cone and the diffuse colour."""
    bpy = bpy_clean
    if bpy.app.version >= (5, 0, 0):
        pytest.skip("Blender 5 has no COLLADA importer")
    assert bpy.ops.phong.import_collada(filepath=LIT) == {"FINISHED"}
    out = tmp_path / "for_blender.dae"
    assert bpy.ops.phong.export_collada(filepath=str(out)) == {"FINISHED"}
    be_reset(bpy)
    assert bpy.ops.wm.collada_import(filepath=str(out)) == {"FINISHED"}
    names = {o.name for o in bpy.data.objects}
    # the names as the file's name attributes give them (spaces cannot be there)
    assert {"Quad_node", "Bulb_node", "Spot_node"} <= names
    spot = bpy.data.objects["Spot_node"].data
    assert spot.spot_size == pytest.approx(math.radians(60.0), abs=1e-6)
    material = bpy.data.objects["Quad_node"].active_material
    base = material.node_tree.nodes["Principled BSDF"].inputs["Base Color"].default_value
    assert tuple(base)[:3] == _f32((0.8, 0.1, 0.1))


@pytest.mark.parametrize("written, path", [
    ("file:///C:/maps/a%20b.png", "C:/maps/a b.png"),
    ("file://server/share/x.png", "/share/x.png"),
    ("file:/tex/x.png", "/tex/x.png"),
    ("tex/caf%C3%A9.png", "tex/café.png"),
    ("odd%zz.png", "odd%zz.png"),
])
def test_image_references_as_other_readers_take_them(written, path):
    """file: URIs and percent-escapes, read without urllib (the zip imports no network
    module)."""
    from phong_nodes.core import collada  # noqa: PLC0415

    assert collada._uri_path(written) == path


def test_written_image_references_read_back():
    from phong_nodes.core import collada  # noqa: PLC0415

    for path in ("C:\\maps\\a b.png", "tex/café #1.png", "/abs/x%y.png"):
        quoted = collada.uri_quote(path)
        assert " " not in quoted and "#" not in quoted
        assert collada._uri_path(quoted) == path.replace("\\", "/")
