# SPDX-License-Identifier: GPL-3.0-or-later
"""COLLADA (.dae): Cycles pixels of imported files against the Phong formula, and real files of
other programs (tests/data/collada, origins and licences in tests/data/README.md) imported,
exported and read back.  Helpers shared with ``test_collada.py``: ``collada_text.py``.
"""

from __future__ import annotations

import math
import os
import time
import xml.etree.ElementTree as ET

import numpy as np
import pytest

import blender_env as be
from collada_text import DATA, F32, LIT, _doc, _f32, _ids, _valid, be_reset
from phong_scene import linked_controls

from phong_nodes.core import collada


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


@pytest.mark.slow
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
    got = linked_controls(bpy.data.materials[mat.name])
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
                                    pytest.param("eevee", marks=(pytest.mark.eevee,
                                                                 pytest.mark.slow))])
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
    lamp.data.phong.intensity = 1.0  # its own i0, not its watts'
    lamp.data["phong_falloff"] = "POWER"
    lamp.data["phong_power_k"] = 1.0
    lamp.data["phong_diffuse"] = 0.5
    be.apply_phong(scene, [tile])
    material = tile.active_material
    nodes = material.node_tree.nodes
    nodes["phong_object_color"].outputs[0].default_value = (0.1, 0.2, 0.3, 1.0)
    nodes["phong_specular_color"].outputs[0].default_value = (0.7, 0.6, 0.5, 1.0)
    nodes["phong_exponent"].outputs[0].default_value = 42.0
    nodes["phong_blinn"].outputs[0].default_value = 1.0
    from phong_nodes.addon.lighting import opacity  # noqa: PLC0415

    opacity.set_opacity(material, 0.75)
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
    from phong_nodes.addon.lighting import opacity  # noqa: PLC0415

    material = bpy.data.materials["Red Paint"]
    out = tmp_path / "kept.dae"
    assert bpy.ops.phong.export_collada(filepath=str(out)) == {"FINISHED"}
    (mat,) = collada.load(str(out)).materials.values()
    assert (mat.opaque, mat.transparent, mat.transparency) == ("RGB_ZERO", (0, 0, 0, 1), 0.0), \
        "unchanged: the file's own transparency"
    opacity.set_opacity(material, 0.5)
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
    assert linked_controls(bpy.data.materials["Blue"])["Specular Color"] == (0.0, 0.0, 1.0)
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
    got = linked_controls(tile.active_material)
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
