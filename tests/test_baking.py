# SPDX-License-Identifier: GPL-3.0-or-later
"""Bake Phong Lighting: baked values against the numpy reference at vertices and at texel
centres; showing the bake and putting the Phong material back; glTF export."""

import json
import math
import os
import shutil
from types import SimpleNamespace

import numpy as np
import pytest

import blender_env as be
from test_threejs import need_browser

#: Float bakes: Cycles' Emit bake against the reference at the exact vertex or texel centre:
#: at least FLOAT_SHARE of the samples within FLOAT_TOL, every one within FLOAT_MAX.  Cycles
#: places and shades the sample in float32: on the 64-segment spheres of the demo scenes a
#: sample sits up to ~1e-5 off the exact point, which a highlight of exponent 30 turns into
#: up to 5e-4 (the coarse spheres of phong_vs_gouraud: all within 5e-5).
FLOAT_TOL, FLOAT_SHARE, FLOAT_MAX = 1e-4, 0.97, 1e-3
#: 8-bit sRGB PNG: the reference encoded to sRGB, within one step of 1/255.
BYTE_TOL = 1.0 / 255.0


def _build(bpy, name, resolution=16):
    before = set(bpy.data.scenes)
    assert bpy.ops.phong.build_demo_scene(name=name, resolution=resolution) == {"FINISHED"}
    (scene,) = set(bpy.data.scenes) - before
    bpy.context.window.scene = scene
    return scene


def _meshes(scene):
    return sorted((o for o in scene.objects if o.type == "MESH"), key=lambda o: o.name)


def _settings(**values):
    from phong_nodes.addon.baking import lighting  # noqa: PLC0415

    return lighting.Settings(**values)


def _bake(scene, objects, **values):
    from phong_nodes.addon.baking import lighting  # noqa: PLC0415

    return lighting.bake(scene, objects, _settings(**values))


def _control(material, name, channels=3):
    value = material.node_tree.nodes[name].outputs[0].default_value
    return np.array(value[:channels], np.float64) if channels > 1 else float(value)


def reference_at(bpy, scene, obj, P, N, view, color=None):
    """The numpy reference (core.compare.reference_image: node_groups/reference.py) of
    *obj*'s Phong material at world points P with unit normals N, seen along *view*
    (zero rows: no viewer); *color*: the object (and ambient object) colour per point, (n, 3),
    where a texture gives it.  Returns {"Color", "Irradiant", ...}: (n, 3)."""
    from phong_nodes.addon.scene import describe  # noqa: PLC0415
    from phong_nodes.core import compare  # noqa: PLC0415

    layer = scene.view_layers[0]
    data = describe.describe(scene, layer, [obj])
    from phong_nodes.addon.baking import lighting  # noqa: PLC0415

    material = lighting.phong_material(obj, 0)  # also while the bake is shown
    n = len(P)
    row = lambda v: np.broadcast_to(np.asarray(v, np.float64), (n, len(v)))[None]  # noqa: E731
    color = row(_control(material, "phong_object_color")) if color is None else color[None]
    aovs = {compare.probe_name(k): v for k, v in {
        "P": P[None], "N": N[None], "I": N[None], "normal": np.zeros((1, n, 3)),
        "view": view[None], "color": color, "ambient": color,
        "specular": row(_control(material, "phong_specular_color")),
        "irradiant": row(_control(material, "phong_irradiant_color")),
        "params": row((_control(material, "phong_exponent", 1),
                       _control(material, "phong_blinn", 1), 1.0)),
        "strength": row((_control(material, "phong_specular_strength", 1),)),
    }.items()}
    out = compare.reference_image(data, aovs)
    return {key: value[0] for key, value in out.items()}


def _toward_camera(scene, P):
    # the evaluated camera: bpy 4.x leaves the object's own matrix_world of a camera the
    # demo builder placed at the identity until a depsgraph of the active scene evaluates it
    import bpy  # noqa: PLC0415

    camera = scene.camera.evaluated_get(bpy.context.evaluated_depsgraph_get())
    cam = np.array(camera.matrix_world, np.float64)
    if scene.camera.data.type == "ORTHO":
        return np.broadcast_to(cam[:3, 2] / np.linalg.norm(cam[:3, 2]), P.shape).copy()
    d = cam[:3, 3] - P
    return d / np.linalg.norm(d, axis=1, keepdims=True)


def _vertices(obj):
    mesh = obj.data
    m = np.array(obj.matrix_world, np.float64)
    co = np.array([v.co for v in mesh.vertices], np.float64)
    normals = np.array([v.normal for v in mesh.vertices], np.float64)
    P = co @ m[:3, :3].T + m[:3, 3]
    N = normals @ np.linalg.inv(m[:3, :3])
    return P, N / np.linalg.norm(N, axis=1, keepdims=True)


def _attribute(obj, name="Phong Bake"):
    attribute = obj.data.color_attributes[name]
    assert attribute.domain == "POINT" and attribute.data_type == "FLOAT_COLOR"
    values = np.empty(len(attribute.data) * 4, np.float32)
    attribute.data.foreach_get("color", values)
    return values.reshape(-1, 4)[:, :3].astype(np.float64)


def _expected(bpy, scene, obj, P, N, term="Color", view="CAMERA", color=None):
    toward = _toward_camera(scene, P) if view == "CAMERA" else np.zeros_like(P)
    out = reference_at(bpy, scene, obj, P, N, toward, color)
    if view == "NONE" and term == "Color":
        return np.minimum(out["Irradiant"] + out["Ambient"] + out["Diffuse"], 1.0)
    return out[term]


@pytest.mark.parametrize("term,view", [("COLOR", "CAMERA"), ("COLOR", "NONE"),
                                       ("SPECULAR", "CAMERA"), ("DIFFUSE", "NONE")])
def test_vertex_bake_matches_the_reference_at_every_vertex(bpy_clean, term, view):
    bpy = bpy_clean
    scene = _build(bpy, "phong_vs_gouraud")
    objects = _meshes(scene)
    results, warnings = _bake(scene, objects, target="VERTEX", term=term, view=view)
    assert [r["object"] for r in results] == [o.name for o in objects] and not warnings
    for obj in objects:
        P, N = _vertices(obj)
        want = _expected(bpy, scene, obj, P, N, term.title(), view)
        got = _attribute(obj)
        err = np.abs(got - want).max()
        slack = _normal_slack(bpy, scene, obj, P, N, want, term.title(), view)
        be.report(f"vertex bake {term}/{view} {obj.name}: {len(P)} vertices, max |Δ| {err:.2e}"
                  f" (allowed {FLOAT_TOL:.0e} + {slack:.1e} for 16-bit normals)")
        assert err <= FLOAT_TOL + slack, (obj.name, err, slack)  # the coarse spheres: every vertex
        assert want.max() > 0.05  # something lit was compared


def _checker(co, node):
    """Blender's Checker Texture (Cycles' svm_checker) at object coordinates *co*: (colours,
    a mask of the points at least 1e-3 away from a square's edge, where the colour is
    unambiguous)."""
    color1 = np.array(node.inputs["Color1"].default_value[:3], np.float64)
    color2 = np.array(node.inputs["Color2"].default_value[:3], np.float64)
    p = (co * node.inputs["Scale"].default_value + 1e-6) * 0.999999
    frac = p - np.floor(p)
    clear = (np.minimum(frac, 1.0 - frac) > 1e-3).all(axis=1)
    odd = np.abs(np.floor(p)).astype(np.int64) % 2
    first = (odd[:, 0] == odd[:, 1]).astype(np.int64) == odd[:, 2]
    return np.where(first[:, None], color1, color2), clear


def test_vertex_bake_of_a_checker_texture_on_object_color(bpy_clean):
    """The textured demo scene: a checker texture (object coordinates) feeds Object Color
    (and the ambient object colour); the bake at each vertex is the reference with the
    checker's colour there, worked out here from Blender's checker formula."""
    bpy = bpy_clean
    from phong_nodes.addon.baking import lighting  # noqa: PLC0415
    from phong_nodes.addon.lighting import recipe  # noqa: PLC0415

    scene = _build(bpy, "textured")
    objects = _meshes(scene)
    _bake(scene, objects, target="VERTEX", term="COLOR", view="CAMERA")
    seen, compared = set(), 0
    for obj in objects:
        tree = lighting.phong_material(obj, 0).node_tree
        checker = next(n for n in tree.nodes if n.bl_idname == "ShaderNodeTexChecker")
        lights = tree.nodes[recipe.LIGHTS_NODE]
        for name in ("Object Color", recipe.AMBIENT_INPUT):
            assert lights.inputs[name].links[0].from_node == checker, name
        co = np.array([v.co for v in obj.data.vertices], np.float64)
        color, clear = _checker(co, checker)
        P, N = _vertices(obj)
        want = _expected(bpy, scene, obj, P, N, color=color)
        got = _attribute(obj)
        slack = _normal_slack(bpy, scene, obj, P, N, want, "Color", "CAMERA", color)
        if not clear.any():
            continue  # a floor whose vertices all lie on the squares' edges
        err = np.abs(got - want)[clear].max(axis=1)
        share = float((err <= FLOAT_TOL + slack).mean())
        be.report(f"vertex bake, checker on Object Color, {obj.name}: {clear.sum()} of "
                  f"{len(P)} vertices clear of the squares' edges, {share:.2%} within "
                  f"{FLOAT_TOL:.0e} + {slack:.1e}, max |Δ| {err.max():.2e}")
        # the 64-segment ball's highlight (exponent 40) and float32 sample placement: the
        # image bake's rule (see FLOAT_TOL)
        assert share >= FLOAT_SHARE and err.max() <= FLOAT_MAX, (obj.name, share, err.max())
        seen |= {tuple(c) for c in color[clear]}
        compared += int(clear.sum())
    assert compared >= 100 and len(seen) >= 2  # both colours of a checker were compared


def _normal_slack(bpy, scene, obj, P, N, want, term, view, color=None):
    """Cycles 5.1 and later keep shading normals with 16 bits per component: a face normal
    (0, 0, 1) renders as (1.5e-5, 1.5e-5, 1) (measured, see test_obj_import).  The largest
    change of the reference when each component of N moves by 2e-5, which a high exponent
    magnifies in the highlight; 0 before 5.1, where Cycles' normals are exact."""
    if bpy.app.version < (5, 1, 0):
        return 0.0
    worst = 0.0
    for axis in range(3):
        for sign in (-1.0, 1.0):
            moved = N.copy()
            moved[:, axis] += sign * 2e-5
            moved /= np.linalg.norm(moved, axis=1, keepdims=True)
            worst = max(worst, float(np.abs(_expected(bpy, scene, obj, P, moved, term, view,
                                                      color) - want).max()))
    return worst


def _texel_samples(obj, size, keep=0.5):
    """World points, unit normals and texel indices (x, y from the bottom) of the texel
    centres of a size × size image that lie at least *keep* texels inside a UV triangle
    of *obj* (Blender's smooth normals: the corner normals interpolated, normalised)."""
    mesh = obj.data
    mesh.calc_loop_triangles()
    m = np.array(obj.matrix_world, np.float64)
    uv = mesh.uv_layers.active.data
    normal_matrix = np.linalg.inv(m[:3, :3]).T
    points, normals, texels = [], [], []
    for tri in mesh.loop_triangles:
        t = np.array([uv[i].uv for i in tri.loops], np.float64) * size
        p = np.array([mesh.vertices[v].co for v in tri.vertices], np.float64)
        n = np.array([mesh.corner_normals[i].vector for i in tri.loops], np.float64)
        area2 = (t[1, 0] - t[0, 0]) * (t[2, 1] - t[0, 1]) - (t[2, 0] - t[0, 0]) * (t[1, 1] - t[0, 1])
        if abs(area2) < 1e-9:
            continue
        lo, hi = np.floor(t.min(axis=0)).astype(int), np.ceil(t.max(axis=0)).astype(int)
        xs, ys = np.meshgrid(np.arange(lo[0], hi[0] + 1), np.arange(lo[1], hi[1] + 1))
        c = np.stack([xs.ravel() + 0.5, ys.ravel() + 0.5], axis=1)
        bary = np.empty((len(c), 3))
        for k in range(3):
            a, b = t[(k + 1) % 3], t[(k + 2) % 3]
            bary[:, k] = ((b[0] - a[0]) * (c[:, 1] - a[1]) - (b[1] - a[1]) * (c[:, 0] - a[0])) / area2
            # distance of the centre to the edge opposite corner k, in texels
            bary[:, k] *= abs(area2) / max(np.linalg.norm(b - a), 1e-12)
        inside = (bary >= keep).all(axis=1) & (xs.ravel() >= 0) & (ys.ravel() >= 0) \
            & (xs.ravel() < size) & (ys.ravel() < size)
        if not inside.any():
            continue
        w = np.empty((inside.sum(), 3))
        for k in range(3):
            a, b = t[(k + 1) % 3], t[(k + 2) % 3]
            w[:, k] = ((b[0] - a[0]) * (c[inside, 1] - a[1])
                       - (b[1] - a[1]) * (c[inside, 0] - a[0])) / area2
        points.append(w @ p)
        normals.append(w @ n)
        texels.append(np.stack([xs.ravel()[inside], ys.ravel()[inside]], axis=1))
    P = np.concatenate(points) @ m[:3, :3].T + m[:3, 3]
    N = np.concatenate(normals) @ normal_matrix.T
    return P, N / np.linalg.norm(N, axis=1, keepdims=True), np.concatenate(texels)


def _read_image(path):
    import OpenImageIO as oiio  # noqa: PLC0415

    inp = oiio.ImageInput.open(path)
    assert inp is not None, oiio.geterror()
    try:
        spec = inp.spec()
        kind = oiio.UINT8 if spec.format == oiio.UINT8 else oiio.FLOAT
        pixels = np.asarray(inp.read_image(0, 0, 0, spec.nchannels, kind))
        return pixels.reshape(spec.height, spec.width, spec.nchannels), spec.format
    finally:
        inp.close()


@pytest.mark.parametrize("name,file_format", [
    ("phong_vs_gouraud", "PNG"),
    pytest.param("two_lights", "EXR", marks=pytest.mark.slow),
    pytest.param("threejs_phong_lab", "EXR", marks=pytest.mark.slow)])
def test_image_bake_matches_the_reference_at_texel_centres(bpy_clean, tmp_path, name,
                                                           file_format):
    """Light Linking (two_lights), the three.js model, 8-bit sRGB PNG and float EXR."""
    bpy = bpy_clean
    from phong_nodes.core import compare  # noqa: PLC0415

    scene = _build(bpy, name)
    objects = [o for o in _meshes(scene) if o.data.uv_layers]
    size = 128
    results, _warnings = _bake(scene, objects, target="IMAGE", resolution=size,
                               file_format=file_format, directory=str(tmp_path))
    for obj, result in zip(objects, results):
        assert result["path"] == os.path.join(str(tmp_path), f"{obj.name}_phong_bake."
                                              f"{file_format.lower()}")
        pixels, kind = _read_image(result["path"])
        assert pixels.shape[:2] == (size, size)
        P, N, texels = _texel_samples(obj, size)
        want = _expected(bpy, scene, obj, P, N)
        got = pixels[size - 1 - texels[:, 1], texels[:, 0], :3].astype(np.float64)
        if file_format == "PNG":
            err = np.abs(got / 255.0 - compare.srgb_encode(want)).max()
            tol = BYTE_TOL + 1e-9
        else:
            d = np.abs(got - want).max(axis=1)
            err, tol = d.max(), FLOAT_MAX
            share = float(np.mean(d <= FLOAT_TOL))
            be.report(f"image bake {name}/{obj.name}: {share:.2%} of texels within 1e-4")
            assert share >= FLOAT_SHARE, (obj.name, share)
        be.report(f"image bake {name}/{obj.name} {file_format}: {len(P)} texel centres, "
                  f"max |Δ| {err:.2e}" + (f" ({err * 255:.2f}/255)" if file_format == "PNG" else ""))
        assert len(P) > 50, obj.name
        assert err <= tol, (obj.name, err)


def test_show_restore_and_baking_again_replaces(bpy_clean, tmp_path):
    bpy = bpy_clean
    from phong_nodes.addon.baking import lighting, show  # noqa: PLC0415

    scene = _build(bpy, "phong_vs_gouraud")
    ball = scene.objects["phong"]
    phong = ball.material_slots[0].material.name
    images = len(bpy.data.images)
    for _ in range(2):  # the second bake replaces the first
        show.bake_objects(scene, [ball], _settings(target="IMAGE", resolution=32, pack=True),
                          display=True)
    assert len(bpy.data.images) == images + 1
    image = bpy.data.images[f"Phong Bake {ball.name}"]
    assert image.packed_file is not None and ball[lighting.IMAGE_KEY] == image
    display = ball.material_slots[0].material
    assert display.name == f"Phong Bake {ball.name}" and display.name != phong
    nodes = {n.bl_idname: n for n in display.node_tree.nodes}
    assert nodes["ShaderNodeTexImage"].image == image and "ShaderNodeBackground" in nodes
    # a vertex bake of a shown object: shown at once, the image is gone
    show.bake_objects(scene, [ball], _settings(target="VERTEX"))
    assert f"Phong Bake {ball.name}" not in bpy.data.images
    nodes = {n.bl_idname: n for n in ball.material_slots[0].material.node_tree.nodes}
    assert nodes["ShaderNodeVertexColor"].layer_name == lighting.ATTRIBUTE
    show.bake_objects(scene, [ball], _settings(target="VERTEX"))
    assert [a.name for a in ball.data.color_attributes].count(lighting.ATTRIBUTE) == 1
    # the Phong material survives save and reload while the bake is shown
    path = str(tmp_path / "shown.blend")
    bpy.ops.wm.save_as_mainfile(filepath=path)
    bpy.ops.wm.open_mainfile(filepath=path)
    ball = bpy.data.objects["phong"]
    assert show.restore(ball) == 1
    assert ball.material_slots[0].material.name == phong
    assert f"Phong Bake {ball.name}" not in bpy.data.materials
    assert not show.is_shown(ball)


def test_objects_whose_names_clean_alike_never_share_an_image_file(bpy_clean, tmp_path):
    """"ball 1" and "ball/1" both clean to "ball_1": baked one after the other into one
    folder, each keeps its own file."""
    bpy = bpy_clean
    from phong_nodes.addon.baking import lighting  # noqa: PLC0415

    scene = _build(bpy, "phong_vs_gouraud")
    first, second = scene.objects["phong"], scene.objects["gouraud"]
    first.name, second.name = "ball 1", "ball/1"
    folder = tmp_path / "bakes"
    results = {}
    for obj in (first, second):
        (result,), _ = _bake(scene, [obj], target="IMAGE", resolution=32,
                             directory=str(folder))
        results[obj.name] = result["path"]
        if obj is first:
            with open(result["path"], "rb") as stream:
                first_bytes = stream.read()
    assert len(set(results.values())) == 2 and len(os.listdir(folder)) == 2
    for obj in (first, second):
        image = obj[lighting.IMAGE_KEY]
        assert os.path.samefile(bpy.path.abspath(image.filepath_raw), results[obj.name])
    with open(results["ball 1"], "rb") as stream:
        assert stream.read() == first_bytes  # the second bake left the first's file alone
    # a plain name stays as it is; names equal but for case get their hash (one file on
    # Windows and macOS)
    names = lighting.file_names([SimpleNamespace(name=n) for n in ("Cube", "cube", "Sphere")],
                                "PNG")
    assert names["Sphere"] == "Sphere_phong_bake.png"
    assert len({names["Cube"].lower(), names["cube"].lower()}) == 2
    assert lighting.file_names([SimpleNamespace(name="Cube")], "EXR") == {
        "Cube": "Cube_phong_bake.exr"}


def test_bad_input_names_the_problem_and_changes_nothing(bpy_clean):
    bpy = bpy_clean
    from phong_nodes.addon.baking import lighting  # noqa: PLC0415

    scene = _build(bpy, "phong_vs_gouraud")
    ball = scene.objects["phong"]
    ball.data.uv_layers.remove(ball.data.uv_layers[0])
    with pytest.raises(lighting.BakeError, match="no UV map on 'phong'"):
        _bake(scene, [ball], target="IMAGE", pack=True)
    with pytest.raises(lighting.BakeError, match="Specular term needs a viewer"):
        _bake(scene, [ball], target="VERTEX", term="SPECULAR", view="NONE")
    with pytest.raises(lighting.BakeError, match="not saved yet"):
        _bake(scene, [scene.objects["gouraud"]], target="IMAGE")
    assert not bpy.data.images and lighting.ATTRIBUTE not in ball.data.color_attributes
    assert all(m.get(lighting.TEMP_KEY) is None for m in bpy.data.materials)
    # Smart UV Project when asked
    results, _ = _bake(scene, [ball], target="IMAGE", pack=True, smart_uv=True, resolution=16)
    assert ball.data.uv_layers and results[0]["image"].packed_file is not None
    assert all(m.get(lighting.TEMP_KEY) is None for m in bpy.data.materials)


def test_check_keeps_phong_meshes_in_order_and_names_the_meshes_it_leaves_out(bpy_clean):
    """``check``: the objects with a Phong material, in the order given; a warning names the
    meshes (and curves, text, ...) without one, never a camera or a light."""
    bpy = bpy_clean
    from phong_nodes.addon.baking import lighting  # noqa: PLC0415

    scene = _build(bpy, "phong_vs_gouraud")
    plain = bpy.data.objects.new("plain", bpy.data.meshes.new("plain"))
    scene.collection.objects.link(plain)
    phong, gouraud = scene.objects["phong"], scene.objects["gouraud"]
    given = [gouraud, scene.camera, plain, phong]
    chosen, warnings = lighting.check(scene, given, _settings(target="VERTEX"))
    assert chosen == [gouraud, phong]
    assert warnings == ["left out (no mesh with a Phong material): 'plain'"]
    with pytest.raises(lighting.BakeError, match="no selected mesh has a Phong material"):
        lighting.check(scene, [plain, scene.camera], _settings(target="VERTEX"))


def _glb_json(path):
    import struct  # noqa: PLC0415

    with open(path, "rb") as stream:
        data = stream.read()
    assert data[:4] == b"glTF"
    length, kind = struct.unpack_from("<I4s", data, 12)
    assert kind == b"JSON"
    return json.loads(data[20:20 + length])


@pytest.mark.parametrize("target", ["VERTEX", "IMAGE"])
def test_export_gltf_writes_unlit_materials_with_the_bake(bpy_clean, tmp_path, target):
    bpy = bpy_clean
    scene = _build(bpy, "phong_vs_gouraud")
    path = str(tmp_path / "baked.glb")
    bpy.ops.object.select_all(action="DESELECT")
    result = bpy.ops.phong.export_gltf(filepath=path, target=target, resolution=64)
    assert result == {"FINISHED"}
    doc = _glb_json(path)
    assert "KHR_materials_unlit" in doc.get("extensionsUsed", [])
    assert len(doc["meshes"]) == 2 and doc.get("cameras")
    for mesh in doc["meshes"]:
        for primitive in mesh["primitives"]:
            material = doc["materials"][primitive["material"]]
            assert "KHR_materials_unlit" in material.get("extensions", {})
            if target == "VERTEX":
                assert "COLOR_0" in primitive["attributes"]
            else:
                assert "baseColorTexture" in material["pbrMetallicRoughness"]
    # each object shows what it showed before: its Phong material (the demo scene's
    # "gouraud" sphere: its Per Vertex Phong material, test_shading_modes.py)
    assert scene.objects["phong"].material_slots[0].material.get("phong_nodes_material")
    gouraud = scene.objects["gouraud"].material_slots[0].material
    assert gouraud.get("phong_nodes_material") and gouraud["phong_shading"] == "VERTEX"


@pytest.mark.parametrize("target,resolution", [("VERTEX", 64), ("IMAGE", 256)])
def test_gltf_in_threejs_matches_cycles_rendering_the_bake(bpy_clean, tmp_path, target,
                                                           resolution):
    """The .glb in three.js's own GLTFLoader (headless Chromium) against Cycles rendering the
    baked scene from the same camera: >= 99% of the pixels both cover within 2/255."""
    need_browser()  # skips with its reason, fails when CI is set
    bpy = bpy_clean
    from phong_nodes.addon.baking import check, gltf, lighting  # noqa: PLC0415

    scene = _build(bpy, "phong_vs_gouraud")
    objects = _meshes(scene)
    glb = str(tmp_path / "scene.glb")
    gltf.export(glb, scene, objects, lighting.Settings(target=target, resolution=resolution,
                                                       pack=True))
    result = check.check(scene, objects, glb, str(tmp_path / "check"), 256)
    m = result["metrics"]
    be.report(f"glTF {target} in three.js vs Cycles: {m['share_within_2_255']:.3%} of "
              f"{m['pixels']} pixels within 2/255, max {m['max_abs'] * 255:.1f}/255, "
              f"browser {result['seconds']['browser']:.1f} s")
    assert result["covered"]["both"] > 0.9 * result["covered"]["cycles"] > 1000
    assert result["verdict"]["ok"], result["verdict"]
    for name in ("cycles.png", "threejs.png", "difference.png", "sheet.png"):
        assert os.path.isfile(tmp_path / "check" / name)


def _cli(tmp_path, *args):
    import subprocess  # noqa: PLC0415
    import sys  # noqa: PLC0415

    env = dict(os.environ, PHONG_VERBOSE="0", BLENDER_USER_RESOURCES=str(tmp_path / "user"))
    return subprocess.run([sys.executable, "-m", "phong_nodes.cli", *args],
                          capture_output=True, text=True, env=env, timeout=600, check=False)


@pytest.mark.slow
def test_bake_command_writes_glb_per_scene_and_a_line_per_object(bpy_clean, tmp_path):
    bpy = bpy_clean
    scene = _build(bpy, "phong_vs_gouraud")
    blend = str(tmp_path / "scene.blend")
    bpy.data.libraries.write(blend, {scene}, path_remap="NONE", fake_user=False)
    out = tmp_path / "out"
    run = _cli(tmp_path, "bake", blend, "--target", "image", "--resolution", "32", "--out", str(out))
    assert run.returncode == 0, run.stderr
    assert "[1/2] " in run.stdout and "[2/2] " in run.stdout
    folder = out / "phong_vs_gouraud"
    assert _glb_json(str(folder / "phong_vs_gouraud.glb"))["meshes"]
    assert sorted(os.listdir(folder / "textures")) == ["gouraud_phong_bake.png",
                                                       "phong_phong_bake.png"]
    # bad input: exit 2, one line, nothing written
    for args, words in ((("bake", str(tmp_path / "missing.blend"), "--target", "vertex"),
                         "no such file"),
                        (("bake", blend, "--target", "vertex", "--scenes", "nope"),
                         "no scene 'nope'"),
                        (("bake", blend, "--target", "image", "--resolution", "2"),
                         "--resolution")):
        run = _cli(tmp_path, *args, "--out", str(tmp_path / "bad"))
        assert run.returncode == 2 and words in run.stderr, run.stderr
        assert not (tmp_path / "bad").exists()


@pytest.mark.slow
def test_bake_shards_into_one_folder_and_report_checks_the_run(bpy_clean, tmp_path):
    """Three scenes ("textured copy" and "textured_copy" clean alike) baked by two shards
    into one folder; report says the run is whole, then names the scene whose folder was
    deleted."""
    bpy = bpy_clean
    first = _build(bpy, "phong_vs_gouraud")
    second = _build(bpy, "textured")
    second.name = "textured copy"
    third = _build(bpy, "textured")
    third.name = "textured_copy"
    blend = str(tmp_path / "three.blend")
    bpy.data.libraries.write(blend, {first, second, third}, path_remap="NONE",
                             fake_user=False)
    out = tmp_path / "out"
    for part in ("1/2", "2/2"):
        run = _cli(tmp_path, "bake", blend, "--target", "vertex", "--shard", part,
                   "--out", str(out))
        assert run.returncode == 0, run.stderr
    folders = json.loads((out / "run.json").read_text())["scenes"]
    assert sorted(folders) == ["phong_vs_gouraud", "textured_copy", "textured_copy_"]
    assert sorted(p.name for p in out.iterdir() if p.is_dir()) == sorted(folders)
    check = _cli(tmp_path, "report", str(out))
    assert check.returncode == 0 and "complete: 3 of 3 scene(s)" in check.stdout, \
        check.stdout + check.stderr
    shutil.rmtree(out / folders[1])
    check = _cli(tmp_path, "report", str(out))
    assert check.returncode == 1 and f"missing {folders[1]}" in check.stdout


def test_operators_bake_show_restore_and_refuse_bad_input(bpy_clean):
    bpy = bpy_clean
    from phong_nodes.addon.baking import lighting, show  # noqa: PLC0415

    scene = _build(bpy, "phong_vs_gouraud")
    ball = scene.objects["phong"]
    phong = ball.material_slots[0].material.name
    bpy.ops.object.select_all(action="DESELECT")
    with pytest.raises(RuntimeError, match="nothing is selected"):
        bpy.ops.phong.bake_lighting(target="VERTEX")
    ball.select_set(True)
    bpy.context.view_layer.objects.active = ball
    with pytest.raises(RuntimeError, match="not saved yet"):  # an image into "//"
        bpy.ops.phong.bake_lighting(target="IMAGE")
    assert lighting.INFO_KEY not in ball.keys() and not bpy.data.images
    assert bpy.ops.phong.bake_lighting(target="VERTEX", view="NONE") == {"FINISHED"}
    assert ball[lighting.INFO_KEY]["view"] == "NONE" and show.is_shown(ball)
    assert bpy.ops.phong.restore_bake() == {"FINISHED"}
    assert ball.material_slots[0].material.name == phong
    assert bpy.ops.phong.show_bake() == {"FINISHED"}
    assert ball.material_slots[0].material.name == f"Phong Bake {ball.name}"
    assert bpy.ops.phong.restore_bake() == {"FINISHED"}
    assert bpy.ops.phong.restore_bake() == {"CANCELLED"}  # nothing shown any more


@pytest.mark.slow
def test_bake_benchmark_runs_and_writes_its_figures(tmp_path):
    """benchmarks/bake_lighting.py at a tiny size (the numbers are the benchmark's, not a
    test's): both cases run, every object is baked, the figures are written."""
    import json  # noqa: PLC0415
    import subprocess  # noqa: PLC0415
    import sys  # noqa: PLC0415

    root = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
    out = tmp_path / "bake.json"
    env = dict(os.environ, BLENDER_USER_RESOURCES=str(tmp_path / "user"))
    run = subprocess.run([sys.executable, os.path.join(root, "benchmarks", "bake_lighting.py"),
                          "--objects", "3", "--repeats", "1", "--out", str(out)],
                         capture_output=True, text=True, env=env, timeout=600, check=False)
    assert run.returncode == 0, run.stderr[-2000:]
    figures = json.loads(out.read_text())
    assert figures["objects"] == 3 and len(figures["seconds"]["phong"]) == 1
    assert figures["median"]["phong"] > 0 and figures["median"]["blender"] > 0
    assert "| 8. Bake to vertex colours, 3 spheres" in run.stdout
