# SPDX-License-Identifier: GPL-3.0-or-later
"""Per Vertex (Gouraud) and Per Face (flat) shading of Phong materials (docs/shading_modes.md).

The expectations come from the numpy reference (node_groups/reference.py, through
phong_scene.reference_color), evaluated at the vertices / face centres read from the
evaluated mesh and at positions computed here from the objects' matrices; rendered pixels are
compared with the barycentric interpolation of those reference values, computed here from
the rendered world position (an AOV) and the mesh's triangles."""

from __future__ import annotations

import math
import os
import subprocess
import sys
import textwrap

import numpy as np
import pytest

import blender_env as be
from phong_scene import AOVS, _add_probe_aovs, _controls, _light, reference_color

SIZE = 48
#: Cycles and the GN evaluation compute in float32; the reference in float64.
VERTEX_TOL = 1e-5
#: A pixel: Cycles interpolates the stored float32 colours at a float32 hit point.
PIXEL_TOL = 1e-4
#: How far from a triangle's edges (smallest barycentric weight) a pixel counts as interior.
INTERIOR = 0.03
SPHERE_ID = 2
#: A vertex bake against the live colours: the bake reads Cycles' 16-bit shading normals
#: (test_baking.py allows 1e-4 plus a slack for them).
BAKE_TOL = 2e-4


def _principled(bpy, name, color):
    material = be.plain_source(name)
    material.node_tree.nodes["Principled BSDF"].inputs["Base Color"].default_value = color
    return material


def _scene(bpy, mode, light_types=("POINT", "SUN", "SPOT"), model="seeds", segments=12,
           rings=6, before=None):
    """A coarse sphere in *mode* under lights of *light_types*, a perspective camera;
    *before*: a modifier type the sphere has before Phong's (the lit mesh is the modified one)."""
    scene = be.new_scene("Shading modes", SIZE, SIZE, "cycles")
    bpy.context.window.scene = scene
    scene["phong_model"] = model
    scene.world.phong.ambient_intensity = 0.08
    scene.world.phong.ambient_color = (1.0, 0.9, 0.8)
    for name, kind in AOVS:
        be.add_aov(scene, name, kind)
    camera = be.add_persp_camera(scene, (0.6, -5.0, 2.2), (0.0, 0.0, 0.0))
    sphere = be.add_uv_sphere(scene, "Sphere", (0.1, 0.2, -0.1), 1.25,
                              _principled(bpy, "Old", (0.2, 0.5, 0.8, 1.0)), segments, rings)
    sphere.rotation_euler = (0.2, -0.1, 0.4)
    sphere.scale = (1.0, 1.1, 0.9)  # the normals need the inverse transpose
    if before is not None:
        modifier = sphere.modifiers.new("Before", before)
        if before == "SUBSURF":
            modifier.levels = modifier.render_levels = 1
    lights = []
    if "POINT" in light_types:
        point = _light(bpy, scene, "Point", "POINT", (1.5, -2.5, 2.5))
        point.data.color = (1.0, 0.8, 0.6)
        point.data.phong.intensity = 8.0
        point.data.phong.quadratic, point.data.phong.linear = 0.6, 0.2
        point.data.phong.constant = 0.1
        lights.append(point)
    if "SUN" in light_types:
        sun = _light(bpy, scene, "Sun", "SUN", (0.0, 0.0, 5.0), (0.6, 0.3, 0.2))
        sun.data.color = (0.6, 0.7, 1.0)
        sun.data.phong.intensity = 0.5
        sun.data.phong.specular = 0.6
        lights.append(sun)
    if "SPOT" in light_types:
        spot = _light(bpy, scene, "Spot", "SPOT", (-1.5, -2.0, 3.0), (0.6, 0.0, -0.6))
        spot.data.color = (1.0, 1.0, 0.5)
        spot.data.spot_size = math.radians(60.0)
        spot.data.phong.intensity = 10.0
        spot.data.phong.edge_exponent = 2.0
        spot.data.phong.diffuse = 0.9
        lights.append(spot)
    be.apply_phong(scene, [sphere])
    material = sphere.active_material
    nodes = material.node_tree.nodes
    nodes["phong_exponent"].outputs[0].default_value = 18.0
    nodes["phong_blinn"].outputs[0].default_value = 0.3
    nodes["phong_specular_color"].outputs[0].default_value = (0.9, 0.8, 1.0, 1.0)
    nodes["phong_irradiant_color"].outputs[0].default_value = (0.02, 0.0, 0.03, 1.0)
    material.phong.shading = mode
    _add_probe_aovs(bpy, material, SPHERE_ID)
    return scene, sphere, camera, sorted(lights, key=lambda o: o.name)


def _evaluated(bpy, obj):
    return obj.evaluated_get(bpy.context.evaluated_depsgraph_get()).data


#: Object name -> the world matrix it is seen with (an instance of it: see _seen_as).
_SEEN_AS: dict = {}


def _matrix(obj):
    """The evaluated world matrix (bpy 4.2 in the background does not write it back to an
    object created after the last update), or the matrix of the instance it stands for."""
    import bpy  # noqa: PLC0415

    if obj.name in _SEEN_AS:
        return _SEEN_AS[obj.name]
    evaluated = obj.evaluated_get(bpy.context.evaluated_depsgraph_get())
    return np.array(evaluated.matrix_world, dtype=np.float64)


def _evaluated_lights(lights):
    import bpy  # noqa: PLC0415

    depsgraph = bpy.context.evaluated_depsgraph_get()
    return [light.evaluated_get(depsgraph) for light in lights]


def _lit_mesh(bpy, obj):
    """(positions, vertex normals, faces) in object space of the mesh the model is evaluated
    on: the evaluated mesh without Phong's modifier (which triangulates it; the points stay)."""
    from phong_nodes.addon.shading import modes  # noqa: PLC0415

    ours = [m for m in obj.modifiers if m.type == "NODES" and m.node_group == modes.geometry_tree()]
    for modifier in ours:
        modifier.show_viewport = False
    try:
        mesh = _evaluated(bpy, obj)
        co = np.array([v.co for v in mesh.vertices], dtype=np.float64)
        normals = np.array([v.normal for v in mesh.vertices], dtype=np.float64)
        faces = [tuple(p.vertices) for p in mesh.polygons]
        face_normals = np.array([p.normal for p in mesh.polygons], dtype=np.float64)
    finally:
        for modifier in ours:
            modifier.show_viewport = True
    return co, normals, faces, face_normals


def _live(bpy, obj, scale=200):
    """(domain, ids, colours) that a Cycles render shows of *obj* Per Vertex or Per Face, one
    row per interior pixel: Per Vertex the model at each vertex of the pixel's triangle (the
    shading group's Vertex k outputs as AOVs: ids are vertex indices), Per Face the pixel's
    colour (ids are the faces of the lit mesh)."""
    import tempfile  # noqa: PLC0415

    from phong_nodes.addon.shading import modes  # noqa: PLC0415

    scene = bpy.context.scene
    material = obj.active_material
    tree = material.node_tree
    mode = material["phong_shading"]
    layer = scene.view_layers[0]
    for name, kind in AOVS:
        if name not in layer.aovs:
            be.add_aov(scene, name, kind)
    if not any(n.bl_idname == "ShaderNodeOutputAOV" and n.aov_name == "id" for n in tree.nodes):
        _add_probe_aovs(bpy, material, SPHERE_ID)
    be.configure_engine(scene, "cycles")
    be.set_output_multilayer_exr(scene)
    added = []
    if "object" not in layer.aovs:  # which object a pixel shows (linked duplicates share all)
        be.add_aov(scene, "object", "VALUE")
    info = tree.nodes.new("ShaderNodeObjectInfo")
    aov = tree.nodes.new("ShaderNodeOutputAOV")
    aov.aov_name = "object"
    tree.links.new(info.outputs["Object Index"], aov.inputs["Value"])
    added += [info, aov]
    pass_index, obj.pass_index = obj.pass_index, 77
    if mode == "VERTEX":
        group = tree.nodes[modes.SHADING_NODE]
        for name in modes.VERTEX_OUTPUTS:
            if name not in layer.aovs:
                be.add_aov(scene, name, "COLOR")
            aov = tree.nodes.new("ShaderNodeOutputAOV")
            aov.aov_name = name
            tree.links.new(group.outputs[name], aov.inputs["Color"])
            added.append(aov)
    percentage = scene.render.resolution_percentage
    scene.render.resolution_percentage = scale
    try:
        with tempfile.TemporaryDirectory() as folder:
            passes = _render(bpy, scene, os.path.join(folder, "live.exr"))
    finally:
        scene.render.resolution_percentage = percentage
        obj.pass_index = pass_index
        for node in added:
            tree.nodes.remove(node)
    P = passes["P"][..., :3].astype(np.float64)
    mask = ((np.rint(passes["id"][..., 0]).astype(int) == SPHERE_ID)
            & (np.rint(passes["object"][..., 0]).astype(int) == 77))
    tri, weights, tris, _faces = _barycentric(bpy, obj, P[mask])
    interior = (tri >= 0) & (weights.min(axis=1) > INTERIOR)
    if mode == "VERTEX":
        ids = np.concatenate([tris[tri[interior], k] for k in range(3)])
        colors = np.concatenate([passes[name][..., :3][mask][interior]
                                 for name in modes.VERTEX_OUTPUTS])
        return "POINT", ids, colors.astype(np.float64)
    _co, _normals, faces, _face_normals = _lit_mesh(bpy, obj)
    face_of = {}
    for index, face in enumerate(faces):
        for a in range(len(face)):
            for b in range(a + 1, len(face)):
                for c in range(b + 1, len(face)):
                    face_of[frozenset((face[a], face[b], face[c]))] = index
    ids = np.array([face_of[frozenset(t)] for t in tris[tri[interior]]])
    return "FACE", ids, passes["Combined"][..., :3][mask][interior].astype(np.float64)


def _world(obj, co, normals):
    """World positions and unit normals from object-space ones (inverse transpose)."""
    mw = _matrix(obj)
    P = co @ mw[:3, :3].T + mw[:3, 3]
    N = normals @ np.linalg.inv(mw[:3, :3])
    return P, N / np.linalg.norm(N, axis=1)[:, None]


def _vertices(bpy, obj):
    co, normals, _faces, _face_normals = _lit_mesh(bpy, obj)
    return _world(obj, co, normals)


def _face_centres(bpy, obj):
    """Each face's centre (the mean of its corners' positions) and its face normal."""
    co, _normals, faces, face_normals = _lit_mesh(bpy, obj)
    centres = np.array([co[list(face)].mean(axis=0) for face in faces])
    return _world(obj, centres, face_normals)


def _reference(scene, obj, camera, lights, P, N):
    """The reference at P, N seen from *camera* (an orthographic camera looks along its axis)."""
    if camera.data.type == "ORTHO":
        I = np.tile(_matrix(camera)[:3, 2] / np.linalg.norm(_matrix(camera)[:3, 2]), (len(P), 1))
        return reference_color(scene.world, _evaluated_lights(lights),
                               _controls(obj.active_material), P, N, I)
    eye = _matrix(camera)[:3, 3]
    I = eye - P
    I /= np.linalg.norm(I, axis=1)[:, None]
    return reference_color(scene.world, _evaluated_lights(lights), _controls(obj.active_material),
                           P, N, I)


def _render(bpy, scene, path):
    be.render_exr(scene, str(path))
    return {k: v[::-1] for k, v in be.read_multilayer_exr(str(path)).items()}  # row 0 = bottom


def _seen(bpy, scene, obj, camera, lights):
    """What a Cycles render shows of *obj* (``_live``) beside the reference at the same
    vertices (Per Vertex) or face centres (Per Face): (ids, shown, expected, near), one row
    per sample; *near*: the reference's spot-edge samples."""
    domain, ids, got = _live(bpy, obj)
    P, N = (_vertices if domain == "POINT" else _face_centres)(bpy, obj)
    want, near = _reference(scene, obj, camera, lights, P, N)
    return ids, got, want[ids], near[ids]


def _barycentric(bpy, obj, points):
    """For world points on the mesh: (triangle index, barycentric weights (n, 3), the
    triangles' vertex indices (t, 3), their face indices)."""
    mesh = _evaluated(bpy, obj)
    mesh.calc_loop_triangles()
    tris = np.array([t.vertices[:] for t in mesh.loop_triangles])
    faces = np.array([t.polygon_index for t in mesh.loop_triangles])
    co = np.array([v.co for v in mesh.vertices], dtype=np.float64)
    V, _ = _world(obj, co, np.tile((0.0, 0.0, 1.0), (len(co), 1)))
    a, b, c = V[tris[:, 0]], V[tris[:, 1]], V[tris[:, 2]]
    e1, e2 = b - a, c - a
    d00, d01, d11 = (e1 * e1).sum(1), (e1 * e2).sum(1), (e2 * e2).sum(1)
    normal = np.cross(e1, e2)
    normal /= np.linalg.norm(normal, axis=1)[:, None]
    best, weights = np.full(len(points), -1), np.zeros((len(points), 3))
    for i, p in enumerate(points):
        d = p - a
        distance = np.abs((d * normal).sum(1))
        d20, d21 = (d * e1).sum(1), (d * e2).sum(1)
        denom = d00 * d11 - d01 * d01
        v = (d11 * d20 - d01 * d21) / denom
        w = (d00 * d21 - d01 * d20) / denom
        u = 1.0 - v - w
        inside = (np.minimum(np.minimum(u, v), w) > -1e-4) & (distance < 1e-3)
        if inside.any():
            k = np.flatnonzero(inside)[np.argmin(distance[inside])]
            best[i], weights[i] = k, (u[k], v[k], w[k])
    return best, weights, tris, faces


def _pixels(bpy, obj, passes):
    """(mask of the sphere's interior pixels, their triangles, weights, tris, faces)."""
    ident = np.rint(passes["id"][..., 0]).astype(int)
    P = passes["P"][..., :3].astype(np.float64)
    mask = ident == SPHERE_ID
    tri, weights, tris, faces = _barycentric(bpy, obj, P[mask])
    interior = (tri >= 0) & (weights.min(axis=1) > INTERIOR)
    return mask, tri, weights, tris, faces, interior


def _check_vertex_pixels(bpy, scene, obj, camera, lights, passes, label):
    """Interior pixels against the barycentric interpolation of the reference's vertex values."""
    P, N = _vertices(bpy, obj)
    want_vertex, near = _reference(scene, obj, camera, lights, P, N)
    mask, tri, weights, tris, _faces, interior = _pixels(bpy, obj, passes)
    ok = interior & ~near[tris[np.maximum(tri, 0)]].any(axis=1)
    corners = want_vertex[tris[tri[ok]]]  # (n, 3 corners, rgb)
    want = (weights[ok][..., None] * corners).sum(axis=1)
    got = passes["Combined"][..., :3][mask][ok].astype(np.float64)
    err = np.abs(got - want).max()
    be.report(f"[shading {label}] {int(ok.sum())} interior pixels of {int(mask.sum())}: "
              f"max |pixel - interpolated reference| {err:.2e}")
    assert ok.sum() > 150, "enough interior pixels compared"
    assert want.std() > 0.02, "lit, not flat"
    assert err <= PIXEL_TOL, (label, err)
    return err


# -- the model as one expression (no Blender) ----------------------------------------------

def test_the_composed_model_equals_the_reference_on_every_light_type():
    from phong_nodes.node_groups import reference as ref  # noqa: PLC0415
    from phong_nodes.node_groups import shading_modes as sm  # noqa: PLC0415
    from phong_nodes.node_groups.expr import evaluate  # noqa: PLC0415

    rng = np.random.default_rng(3)
    P = rng.normal(size=(400, 3))
    N = rng.normal(size=(400, 3))
    camera = np.array([0.5, -7.0, 2.0])
    lights = [("POINT", "Phong Point Light", {"Position": np.array([1.0, -3.0, 2.0]),
                                              "Intensity": 6.0, "Quadratic": 0.5,
                                              "Linear": 0.3, "Constant": 0.2}),
              ("SUN", "Phong Directional Light", {"Direction": np.array([0.2, 0.5, -1.0]),
                                                  "Intensity": 0.7}),
              ("SPOT", "Phong Spot Light", {"Position": np.array([-1.0, -2.0, 3.0]),
                                            "Direction": np.array([0.3, 0.6, -1.0]),
                                            "Half Angle": 0.6, "Edge Exponent": 3.0,
                                            "Intensity": 9.0, "Quadratic": 1.0,
                                            "Linear": 0.0, "Constant": 0.0})]
    controls = {"Object Color": np.array([0.2, 0.5, 0.8]), "Specular Color": np.array([0.9, 0.8, 1.0]),
                "Exponent": 25.0, "Blinn": 0.4, "Irradiant Color": np.array([0.03, 0.0, 0.02]),
                "Ambient Object Color": np.array([0.2, 0.5, 0.8]), "Specular Strength": 1.0,
                "Ambient Intensity": 0.1, "Ambient Color": np.array([1.0, 0.9, 0.8])}
    n = N / np.linalg.norm(N, axis=1)[:, None]
    v = (camera - P) / np.linalg.norm(camera - P, axis=1)[:, None]
    geo = {"Position": P, "Normal": n, "Incoming": v}
    for count in range(len(lights) + 1):
        used = lights[:count]
        values = {"P": P, "N": N, "Camera": camera, **controls}
        want = ref.ambient(0.1, (1.0, 0.9, 0.8), controls["Object Color"])["Color"] * np.ones((400, 1))
        for index, (kind, group, inputs) in enumerate(used):
            values.update({sm.light_input(index, k): x for k, x in inputs.items()})
            color = np.array([1.0, 0.9 - 0.1 * index, 0.7])
            values.update({sm.light_input(index, "Color"): color,
                           sm.light_input(index, "Diffuse"): 0.9,
                           sm.light_input(index, "Specular"): 0.7})
            out = ref.GROUPS[group](inputs, geo)
            shading = ref.phong_shading(
                out["Light Vector"], out["Intensity"], color, controls["Object Color"],
                controls["Irradiant Color"] if index == 0 else (0.0, 0.0, 0.0), 0.0, (1, 1, 1),
                0.9, 0.7, controls["Specular Color"], 25.0, 0.4, geometry_normal=n, incoming=v)
            want = np.minimum(want + shading["Color"], 1.0)
        if not used:
            want = np.minimum(want + controls["Irradiant Color"], 1.0)
        got = evaluate(sm.model_color([k for k, _g, _i in used]), values, {})
        assert np.abs(got - want).max() < 1e-12, count
        assert want.std() > 0.01 or not used


def test_modes_are_validated():
    from phong_nodes.node_groups import shading_modes as sm  # noqa: PLC0415

    assert sm.MODES == ("PIXEL", "VERTEX", "FACE")
    with pytest.raises(ValueError, match="unknown lighting model"):
        sm.model_color(["POINT"], "pbr")


# -- in Blender -------------------------------------------------------------------------

@pytest.mark.slow
def test_power_falloff_lights_per_vertex_and_per_face(bpy_clean):
    """A Point and a Spot whose falloff is i0/d^k (phong_falloff POWER, k = 3 and 1.5) light
    Per Vertex and Per Face materials as the reference's Power Falloff says, and a change of
    k or of the falloff is followed."""
    bpy = bpy_clean
    scene, sphere, camera, lights = _scene(bpy, "VERTEX", ("POINT", "SPOT"))
    point, spot = (next(o for o in lights if o.data.type == t) for t in ("POINT", "SPOT"))
    point.data.phong.falloff, point.data.phong.power_k = "POWER", 3.0
    spot.data.phong.falloff, spot.data.phong.power_k = "POWER", 1.5
    bpy.context.view_layer.update()
    results = []
    for step in ("k 3 / 1.5", "k 2 / 1.5", "point quadratic"):
        if step == "k 2 / 1.5":
            point.data.phong.power_k = 2.0
        elif step == "point quadratic":
            point.data.phong.falloff = "QUADRATIC"
        bpy.context.view_layer.update()
        _ids, got, want, near = _seen(bpy, scene, sphere, camera, lights)
        err = np.abs(got - want)[~near].max()
        results.append(f"{step}: {err:.2e}")
        assert err <= VERTEX_TOL, (step, err)
    sphere.active_material.phong.shading = "FACE"
    bpy.context.view_layer.update()
    _ids, got, want, near = _seen(bpy, scene, sphere, camera, lights)
    assert np.abs(got - want)[~near].max() <= VERTEX_TOL
    be.report("[shading power falloff] " + "; ".join(results))


@pytest.mark.parametrize("light_types", [("POINT",), ("SUN",), ("SPOT",), ("POINT", "SUN", "SPOT")])
def test_per_vertex_colours_equal_the_reference_at_every_vertex(bpy_clean, light_types):
    bpy = bpy_clean
    scene, sphere, camera, lights = _scene(bpy, "VERTEX", light_types)
    domain, ids, got = _live(bpy, sphere)
    P, N = _vertices(bpy, sphere)
    want, near = _reference(scene, sphere, camera, lights, P, N)
    assert domain == "POINT"
    seen = np.unique(ids)
    err = np.abs(got - want[ids])[~near[ids]].max()
    be.report(f"[shading vertex {'+'.join(light_types)}] {len(seen)} vertices seen "
              f"({len(got)} samples, {int(near[seen].sum())} at the spot edge skipped): "
              f"max |Δ| {err:.2e}")
    assert err <= VERTEX_TOL
    assert len(seen) >= 25 and near[seen].sum() <= 2 and want[seen].std() > 0.02


def test_per_face_colours_equal_the_reference_at_every_face_centre(bpy_clean):
    """Every interior pixel of a face (both triangles of a quad) shows the model at the
    face's centre with its face normal."""
    bpy = bpy_clean
    scene, sphere, camera, lights = _scene(bpy, "FACE")
    domain, ids, got = _live(bpy, sphere)
    P, N = _face_centres(bpy, sphere)
    want, near = _reference(scene, sphere, camera, lights, P, N)
    assert domain == "FACE"
    seen = np.unique(ids)
    err = np.abs(got - want[ids])[~near[ids]].max()
    be.report(f"[shading face] {len(seen)} faces seen ({len(got)} pixels at 96 px): "
              f"max |pixel - face-centre value| {err:.2e}")
    assert len(seen) >= 20 and err <= VERTEX_TOL and want[seen].std() > 0.02


@pytest.mark.slow
def test_pixels_interpolate_the_vertex_values_and_follow_light_and_camera(bpy_clean, tmp_path):
    """Two renders with only a light and the camera moved between them (no call of ours);
    then Eevee within 1/255 of Cycles."""
    bpy = bpy_clean
    scene, sphere, camera, lights = _scene(bpy, "VERTEX")
    first = _render(bpy, scene, tmp_path / "first.exr")
    _check_vertex_pixels(bpy, scene, sphere, camera, lights, first, "vertex, first")
    point = bpy.data.objects["Point"]
    point.location = (-2.0, -2.0, 1.0)
    camera.location = (-1.5, -4.5, 1.0)
    second = _render(bpy, scene, tmp_path / "second.exr")
    _check_vertex_pixels(bpy, scene, sphere, camera, lights, second, "vertex, moved")
    assert np.abs(second["Combined"] - first["Combined"]).max() > 0.05, "the picture changed"
    # Eevee
    be.configure_engine(scene, "eevee")
    eevee = _render(bpy, scene, tmp_path / "eevee.exr")
    mask, _tri, _weights, _tris, _faces, interior = _pixels(bpy, sphere, second)
    both = mask & (np.rint(eevee["id"][..., 0]) == SPHERE_ID)
    inner = np.zeros_like(mask)
    inner[mask] = interior
    inner &= both
    diff = np.abs(eevee["Combined"][..., :3] - second["Combined"][..., :3])[inner].max()
    be.report(f"[shading eevee] {int(inner.sum())} pixels: max |Eevee - Cycles| {diff:.2e}")
    assert inner.sum() > 150 and diff <= 1.0 / 255.0


@pytest.mark.slow
def test_a_saved_file_renders_the_same_without_the_extension(bpy_clean, tmp_path):
    bpy = bpy_clean
    scene, sphere, _camera, _lights = _scene(bpy, "VERTEX")
    here = _render(bpy, scene, tmp_path / "here.exr")
    blend = tmp_path / "vertex.blend"
    bpy.ops.wm.save_as_mainfile(filepath=str(blend), copy=True)
    out = tmp_path / "there.exr"
    script = textwrap.dedent(f"""
        import bpy
        assert "phong_nodes" not in bpy.context.preferences.addons
        bpy.ops.wm.open_mainfile(filepath={str(blend)!r})
        assert not hasattr(bpy.types.Material, "phong")
        scene = bpy.data.scenes[{scene.name!r}]
        bpy.data.objects["Point"].location = (-2.0, -2.0, 1.0)
        scene.render.filepath = {str(out)!r}
        scene.render.use_file_extension = False
        bpy.ops.render.render(write_still=True, scene=scene.name)
    """)
    resources = tmp_path / "resources"
    resources.mkdir()
    env = {k: v for k, v in os.environ.items() if not k.startswith("BLENDER_USER")}
    env["BLENDER_USER_RESOURCES"] = str(resources)
    result = subprocess.run([sys.executable, "-c", script], capture_output=True, text=True,
                            timeout=300, env=env, cwd=str(tmp_path))
    assert result.returncode == 0, result.stderr[-3000:]
    there = {k: v[::-1] for k, v in be.read_multilayer_exr(str(out)).items()}
    # the same light moved here: the fresh process must show what this one shows
    bpy.data.objects["Point"].location = (-2.0, -2.0, 1.0)
    moved = _render(bpy, scene, tmp_path / "moved.exr")
    diff = np.abs(there["Combined"] - moved["Combined"]).max()
    be.report(f"[shading fresh process] max |fresh - here| {diff:.2e}")
    assert diff <= 1e-6
    assert np.abs(there["Combined"] - here["Combined"]).max() > 0.05, "the light moved there"


def test_modifiers_come_first_and_pixel_mode_leaves_nothing_behind(bpy_clean):
    bpy = bpy_clean
    from phong_nodes.addon.shading import modes  # noqa: PLC0415

    scene, sphere, camera, lights = _scene(bpy, "VERTEX", ("POINT",), before="SUBSURF")
    assert [m.type for m in sphere.modifiers] == ["SUBSURF", "NODES"]
    _domain, ids, got = _live(bpy, sphere)
    P, N = _vertices(bpy, sphere)
    assert len(P) > len(sphere.data.vertices)  # the subdivided mesh is the lit one
    want, _near = _reference(scene, sphere, camera, lights, P, N)
    assert np.abs(got - want[ids]).max() <= VERTEX_TOL
    material = sphere.active_material
    aovs = {n.aov_name: n.inputs["Color"] for n in material.node_tree.nodes
            if n.name.startswith("phong_aov:")}
    assert aovs["Phong Color"].links[0].from_node.name == modes.SHADING_NODE
    assert not any(aovs[t].is_linked for t in ("Phong Irradiant", "Phong Ambient",
                                               "Phong Diffuse", "Phong Specular"))
    # Opacity below 1 mixes the shown shader, the stored colour's emission
    from phong_nodes.addon.lighting import opacity, recipe  # noqa: PLC0415

    opacity.set_opacity(material, 0.5)
    mix = material.node_tree.nodes[recipe.OPACITY_MIX]
    assert mix.inputs[2].links[0].from_node.name == modes.EMISSION_NODE
    opacity.set_opacity(material, 1.0)
    surface = material.node_tree.nodes["phong_output"].inputs["Surface"].links[0]
    assert surface.from_node.name == modes.EMISSION_NODE
    groups_before = {t.name for t in bpy.data.node_groups}
    material.phong.shading = "PIXEL"
    assert material["phong_shading"] == "PIXEL"
    assert [m.type for m in sphere.modifiers] == ["SUBSURF"]
    assert modes.group_of(material) is None and modes.geometry_tree() is None
    assert not {t.name for t in bpy.data.node_groups} - groups_before
    assert not [t for t in bpy.data.node_groups if t.name.startswith("Phong Per ")
                or t.name.startswith(modes.GEOMETRY_TREE)], "nothing of the mode is left"
    nodes = material.node_tree.nodes
    assert modes.SHADING_NODE not in nodes and modes.EMISSION_NODE not in nodes
    surface = nodes["phong_output"].inputs["Surface"].links[0]
    from phong_nodes.addon.lighting import shadows  # noqa: PLC0415

    # with shadow rays (5.2+) the first output is Cycles' only and shows the Cycles Shader
    shown = ("Cycles Shader" if shadows.has_shadows(nodes["phong_lights"].node_tree)
             else "Shader")
    assert surface.from_node.name == "phong_lights" and surface.from_socket.name == shown
    if recipe.OUTPUT_EEVEE in nodes:  # 5.2+: Eevee shows the loop or the unshadowed Shader
        assert not any(n.name.startswith("phong_aov:") for n in nodes)
    else:
        for name, socket in aovs.items():  # every AOV from the lights group again
            assert socket.links[0].from_node.name == "phong_lights", name
        assert socket.links[0].from_socket.name == name.removeprefix("Phong "), name
    with pytest.raises(ValueError, match="unknown shading"):
        modes.set_mode(material, "SMOOTH")


@pytest.mark.slow
def test_a_light_added_is_followed(bpy_clean):
    bpy = bpy_clean
    scene, sphere, camera, lights = _scene(bpy, "VERTEX", ("POINT",))
    sun = _light(bpy, scene, "Sun", "SUN", (0.0, 0.0, 5.0), (0.6, 0.3, 0.2))
    sun.data.phong.intensity = 0.5
    bpy.context.view_layer.update()  # the depsgraph handler relinks (as after a click)
    _ids, got, want, _near = _seen(bpy, scene, sphere, camera,
                                   sorted([*lights, sun], key=lambda o: o.name))
    assert np.abs(got - want).max() <= VERTEX_TOL


def test_the_phong_vs_gouraud_demo_is_live_and_its_bake_equals_the_live_colours(bpy_clean):
    bpy = bpy_clean
    from phong_nodes.addon.baking import lighting, show  # noqa: PLC0415

    before = set(bpy.data.scenes)
    assert bpy.ops.phong.build_demo_scene(name="phong_vs_gouraud", resolution=16) == {"FINISHED"}
    (scene,) = set(bpy.data.scenes) - before
    bpy.context.window.scene = scene
    gouraud, phong = bpy.data.objects["gouraud"], bpy.data.objects["phong"]
    assert gouraud.active_material["phong_shading"] == "VERTEX"
    assert phong.active_material.get("phong_shading", "PIXEL") == "PIXEL"
    assert not bpy.data.images, "nothing baked"
    lamp = bpy.data.objects["lamp"]
    for location in (tuple(lamp.location), (2.0, -4.0, 3.0)):
        lamp.location = location
        ids, live, want, _near = _seen(bpy, scene, gouraud, scene.camera, [lamp])
        assert len(np.unique(ids)) >= 20
        assert np.abs(live - want).max() <= VERTEX_TOL, location
    settings = lighting.Settings(target="VERTEX", view="CAMERA")
    show.bake_objects(scene, [gouraud], settings, display=False)
    baked = gouraud.data.attributes[lighting.ATTRIBUTE]
    values = np.empty(len(baked.data) * 4, dtype=np.float32)
    baked.data.foreach_get("color", values)
    err = np.abs(values.reshape(-1, 4)[:, :3][ids] - live).max()
    be.report(f"[shading demo] vertex bake against live Per Vertex colours: max |Δ| {err:.2e}")
    # the bake shades with Cycles' 16-bit normals: test_baking's tolerance (1e-4 and a slack)
    assert err <= BAKE_TOL


def test_a_camera_switch_is_followed(bpy_clean):
    """The viewer is the camera that renders (the eye of the pixel's ray): switching the
    scene's camera changes the highlights with no call of ours."""
    bpy = bpy_clean
    scene, sphere, first, lights = _scene(bpy, "VERTEX", ("POINT",))
    _domain, ids_before, before = _live(bpy, sphere)
    second = be.add_persp_camera(scene, (-4.0, -2.0, 1.0), (0.0, 0.0, 0.0))  # sets scene.camera
    scene.camera = second
    ids, got, want, _near = _seen(bpy, scene, sphere, second, lights)
    assert np.abs(got - want).max() <= VERTEX_TOL
    seen_first = dict(zip(ids_before.tolist(), before))
    common = [i for i, v in enumerate(ids.tolist()) if v in seen_first]
    assert common and max(np.abs(got[i] - seen_first[ids[i]]).max() for i in common) > 0.05, \
        "the highlight moved with the camera"


def _threejs_reference(scene, obj, camera, lights, P, N):
    """The three.js model (docs/threejs.md) from reference.py's three.js functions: ambient
    + emissive + each light's MeshPhongMaterial colour, added with min(a + b, 1)."""
    from phong_nodes.node_groups import reference as ref  # noqa: PLC0415

    nodes = obj.active_material.node_tree.nodes
    value = lambda n: nodes[n].outputs[0].default_value  # noqa: E731
    color = lambda n: np.array(value(n)[:3], dtype=np.float64)  # noqa: E731
    eye = _matrix(camera)[:3, 3]
    I = (eye - P) / np.linalg.norm(eye - P, axis=1)[:, None]
    world = scene.world.phong
    total = ref.threejs_ambient(world.ambient_intensity, tuple(world.ambient_color),
                                color("phong_object_color"))["Color"] * np.ones((len(P), 1))
    total = np.minimum(total + color("phong_irradiant_color"), 1.0)
    for light in lights:
        mw = _matrix(light)
        s = light.data.phong
        if light.data.type == "SUN":
            out = ref.directional_light(-mw[:3, 2], s.intensity)
            out = {"Light Vector": np.broadcast_to(out["Light Vector"], P.shape),
                   "Intensity": out["Intensity"]}
        elif light.data.type == "POINT":
            out = ref.threejs_point_light(mw[:3, 3], s.intensity, s.distance, s.decay, P)
        else:
            out = ref.threejs_spot_light(mw[:3, 3], -mw[:3, 2], light.data.spot_size / 2.0,
                                         s.penumbra, s.intensity, s.distance, s.decay, P)
        shade = ref.threejs_phong(out["Light Vector"], out["Intensity"], tuple(light.data.color),
                                  color("phong_object_color"), color("phong_specular_color"),
                                  float(value("phong_exponent")),
                                  float(value("phong_specular_strength")),
                                  geometry_normal=N, incoming=I)
        total = np.minimum(total + shade["Color"], 1.0)
    return total


def _x3d_reference(scene, obj, camera, lights, P, N):
    """The X3D / VRML97 model (docs/x3d.md) from reference.py's X3D functions: the World's
    ambient ⊗ Ka + emissive + Σ per light (Ia·IL ⊗ Ka + I·max(N·L, 0)·IL ⊗ Kd +
    I·max(N·H, 0)^e·IL ⊗ Ks), min(…, 1)."""
    from phong_nodes.node_groups import reference as ref  # noqa: PLC0415

    nodes = obj.active_material.node_tree.nodes
    value = lambda n: nodes[n].outputs[0].default_value  # noqa: E731
    color = lambda n: np.array(value(n)[:3], dtype=np.float64)  # noqa: E731
    kd = color("phong_object_color")
    ka = kd  # the recipe's Ambient Object Color follows the Object Color
    eye = _matrix(camera)[:3, 3]
    v = (eye - P) / np.linalg.norm(eye - P, axis=1)[:, None]
    n = N / np.linalg.norm(N, axis=1)[:, None]
    world = scene.world.phong
    total = ref.ambient(world.ambient_intensity, tuple(world.ambient_color), ka)["Color"] \
        + color("phong_irradiant_color")
    for light in lights:
        mw = _matrix(light)
        s = light.data.phong
        near = (s.ambient, s.constant, s.linear, s.quadratic, s.radius)
        if light.data.type == "SUN":
            out = ref.x3d_directional_light(-mw[:3, 2], s.intensity, s.ambient, P)
        elif light.data.type == "POINT":
            out = ref.x3d_point_light(mw[:3, 3], s.intensity, *near, P)
        else:
            out = ref.x3d_spot_light(mw[:3, 3], -mw[:3, 2], s.beam_width,
                                     light.data.spot_size / 2.0, s.intensity, *near, P)
        terms = ref.x3d_light_terms(out["Light Vector"], out["Intensity"], out["Ambient"],
                                    tuple(light.data.color), float(value("phong_exponent")), n, v)
        total = total + terms["Ambient Light"] * ka + terms["Diffuse Light"] * kd \
            + terms["Specular Light"] * color("phong_specular_color")
    return np.minimum(total, 1.0)


@pytest.mark.slow
def test_per_vertex_in_the_x3d_model_equals_its_reference(bpy_clean):
    bpy = bpy_clean
    scene, sphere, camera, lights = _scene(bpy, "VERTEX", model="x3d")
    point, spot, sun = (bpy.data.objects[name] for name in ("Point", "Spot", "Sun"))
    point.data.phong.radius = 4.3          # the far side of the sphere is out of its reach
    point.data.phong.constant, point.data.phong.quadratic = 0.5, 0.3
    spot.data.phong.beam_width = math.radians(12.0)   # a ramp to the 30° cut-off
    sun.data.phong.ambient = 0.3
    spot.data.phong.ambient = 0.2
    _domain, ids, got = _live(bpy, sphere)
    P, N = _vertices(bpy, sphere)
    want = _x3d_reference(scene, sphere, camera, lights, P, N)
    err = np.abs(got - want[ids]).max()
    be.report(f"[shading vertex X3D] {len(np.unique(ids))} vertices seen: max |Δ| {err:.2e}")
    assert err <= VERTEX_TOL and want.std() > 0.02
    d = np.linalg.norm(P - _matrix(point)[:3, 3], axis=1)
    assert (d > 4.3).any() and (d < 4.3).any()  # the radius cuts the sphere
    assert sphere.active_material.node_tree.nodes["phong_lights"].node_tree.name.startswith(
        "X3D Lights")


@pytest.mark.slow
def test_per_vertex_in_the_threejs_model_equals_its_reference(bpy_clean):
    bpy = bpy_clean
    scene, sphere, camera, lights = _scene(bpy, "VERTEX", model="threejs")
    for light in lights:
        light.data.phong.distance = 12.0 if light.data.type != "SUN" else 0.0
        light.data.phong.decay = 1.5
    bpy.data.objects["Spot"].data.phong.penumbra = 0.4
    nodes = sphere.active_material.node_tree.nodes
    nodes["phong_specular_strength"].outputs[0].default_value = 0.7
    _domain, ids, got = _live(bpy, sphere)
    P, N = _vertices(bpy, sphere)
    want = _threejs_reference(scene, sphere, camera, lights, P, N)
    err = np.abs(got - want[ids]).max()
    be.report(f"[shading vertex three.js] {len(np.unique(ids))} vertices seen: max |Δ| {err:.2e}")
    assert err <= VERTEX_TOL and want.std() > 0.02
    assert sphere.active_material.node_tree.nodes["phong_lights"].node_tree.name.startswith(
        "three.js Lights")


# -- a peer: OpenGL's fixed-function Gouraud pipeline (Mesa, EGL surfaceless) ---------------

def _gl():
    """PyOpenGL's GL on a Mesa EGL surfaceless context (compatibility profile), or skip."""
    os.environ.setdefault("PYOPENGL_PLATFORM", "egl")
    if os.environ["PYOPENGL_PLATFORM"] != "egl":
        be.skip_unless_ci("PyOpenGL is set to another platform than EGL")
    egl = be.need_module("OpenGL.EGL")
    gl = be.need_module("OpenGL.GL")
    import ctypes  # noqa: PLC0415

    try:
        display = egl.eglGetPlatformDisplayEXT(0x31DD, egl.EGL_DEFAULT_DISPLAY, None)  # surfaceless
        major, minor = egl.EGLint(), egl.EGLint()
        if not display or not egl.eglInitialize(display, ctypes.pointer(major),
                                                ctypes.pointer(minor)):
            be.skip_unless_ci("no EGL surfaceless display (Mesa)")
        attributes = (egl.EGLint * 5)(egl.EGL_SURFACE_TYPE, egl.EGL_PBUFFER_BIT,
                                      egl.EGL_RENDERABLE_TYPE, egl.EGL_OPENGL_BIT, egl.EGL_NONE)
        config, count = egl.EGLConfig(), egl.EGLint()
        egl.eglChooseConfig(display, attributes, ctypes.pointer(config), 1, ctypes.pointer(count))
        egl.eglBindAPI(egl.EGL_OPENGL_API)
        context = egl.eglCreateContext(display, config, egl.EGL_NO_CONTEXT, None)
        if not context or not egl.eglMakeCurrent(display, egl.EGL_NO_SURFACE,
                                                 egl.EGL_NO_SURFACE, context):
            be.skip_unless_ci("no OpenGL context on the EGL display")
    except Exception as error:  # noqa: BLE001  (any missing piece of the stack: skip)
        be.skip_unless_ci(f"OpenGL through EGL unavailable: {error}")
    return gl, (egl, display, context)


def _gl_gouraud(bpy, scene, obj, lights):
    """The object rendered by OpenGL 1.x fixed-function lighting (GL_SMOOTH, local viewer),
    float framebuffer: (RGB (H, W, 3), covered mask), row 0 = bottom.  The material's and
    lights' values are set as the textbook maps them: light diffuse = i0·kd·colour, specular
    = i0·ks·colour, attenuation 1/(γ + βd + αd²), spot cut-off = half angle, exponent = e_att;
    material ambient = diffuse = Object Color, emission = Irradiant, shininess = Exponent;
    global ambient = the world's ambient."""
    gl, (egl, display, context) = _gl()
    nodes = obj.active_material.node_tree.nodes
    value = lambda n: nodes[n].outputs[0].default_value  # noqa: E731
    rgba = lambda c: (float(c[0]), float(c[1]), float(c[2]), 1.0)  # noqa: E731
    depsgraph = bpy.context.evaluated_depsgraph_get()
    mesh = obj.evaluated_get(depsgraph).data
    mesh.calc_loop_triangles()
    co = np.array([v.co for v in mesh.vertices], dtype=np.float64)
    normals = np.array([v.normal for v in mesh.vertices], dtype=np.float64)
    tris = np.array([t.vertices[:] for t in mesh.loop_triangles])
    camera = scene.camera
    projection = np.array(camera.calc_matrix_camera(depsgraph, x=SIZE, y=SIZE), np.float64)
    view = np.linalg.inv(_matrix(camera))
    model = _matrix(obj)
    try:
        fbo = gl.glGenFramebuffers(1)
        gl.glBindFramebuffer(gl.GL_FRAMEBUFFER, fbo)
        color_rb, depth_rb = gl.glGenRenderbuffers(2)
        gl.glBindRenderbuffer(gl.GL_RENDERBUFFER, color_rb)
        gl.glRenderbufferStorage(gl.GL_RENDERBUFFER, gl.GL_RGBA32F, SIZE, SIZE)
        gl.glFramebufferRenderbuffer(gl.GL_FRAMEBUFFER, gl.GL_COLOR_ATTACHMENT0,
                                     gl.GL_RENDERBUFFER, color_rb)
        gl.glBindRenderbuffer(gl.GL_RENDERBUFFER, depth_rb)
        gl.glRenderbufferStorage(gl.GL_RENDERBUFFER, gl.GL_DEPTH_COMPONENT24, SIZE, SIZE)
        gl.glFramebufferRenderbuffer(gl.GL_FRAMEBUFFER, gl.GL_DEPTH_ATTACHMENT,
                                     gl.GL_RENDERBUFFER, depth_rb)
        gl.glViewport(0, 0, SIZE, SIZE)
        gl.glClampColor(gl.GL_CLAMP_READ_COLOR, gl.GL_FALSE)
        gl.glClearColor(0.0, 0.0, 0.0, 0.0)
        gl.glClear(gl.GL_COLOR_BUFFER_BIT | gl.GL_DEPTH_BUFFER_BIT)
        gl.glEnable(gl.GL_DEPTH_TEST)
        gl.glShadeModel(gl.GL_SMOOTH)
        gl.glEnable(gl.GL_LIGHTING)
        gl.glEnable(gl.GL_NORMALIZE)
        gl.glMatrixMode(gl.GL_PROJECTION)
        gl.glLoadMatrixd(projection.T.ravel())
        gl.glMatrixMode(gl.GL_MODELVIEW)
        gl.glLoadMatrixd(view.T.ravel())  # lights are given in world space
        world = scene.world.phong
        ambient = world.ambient_intensity * np.array(world.ambient_color)
        gl.glLightModelfv(gl.GL_LIGHT_MODEL_AMBIENT, rgba(ambient))
        gl.glLightModeli(gl.GL_LIGHT_MODEL_LOCAL_VIEWER, gl.GL_TRUE)
        for index, light in enumerate(lights):
            number = gl.GL_LIGHT0 + index
            s, mw = light.data.phong, _matrix(light)
            color = np.array(light.data.color)
            gl.glEnable(number)
            gl.glLightfv(number, gl.GL_AMBIENT, (0.0, 0.0, 0.0, 1.0))
            gl.glLightfv(number, gl.GL_DIFFUSE, rgba(s.intensity * s.diffuse * color))
            gl.glLightfv(number, gl.GL_SPECULAR, rgba(s.intensity * s.specular * color))
            if light.data.type == "SUN":
                gl.glLightfv(number, gl.GL_POSITION, (*mw[:3, 2], 0.0))  # toward the light
                continue
            gl.glLightfv(number, gl.GL_POSITION, (*mw[:3, 3], 1.0))
            gl.glLightf(number, gl.GL_CONSTANT_ATTENUATION, s.constant)
            gl.glLightf(number, gl.GL_LINEAR_ATTENUATION, s.linear)
            gl.glLightf(number, gl.GL_QUADRATIC_ATTENUATION, s.quadratic)
            if light.data.type == "SPOT":
                gl.glLightfv(number, gl.GL_SPOT_DIRECTION, tuple(-mw[:3, 2]))
                gl.glLightf(number, gl.GL_SPOT_CUTOFF, math.degrees(light.data.spot_size / 2))
                gl.glLightf(number, gl.GL_SPOT_EXPONENT, s.edge_exponent)
        base = value("phong_object_color")
        gl.glMaterialfv(gl.GL_FRONT_AND_BACK, gl.GL_AMBIENT, rgba(base))
        gl.glMaterialfv(gl.GL_FRONT_AND_BACK, gl.GL_DIFFUSE, rgba(base))
        gl.glMaterialfv(gl.GL_FRONT_AND_BACK, gl.GL_SPECULAR, rgba(value("phong_specular_color")))
        gl.glMaterialfv(gl.GL_FRONT_AND_BACK, gl.GL_EMISSION, rgba(value("phong_irradiant_color")))
        gl.glMaterialf(gl.GL_FRONT_AND_BACK, gl.GL_SHININESS, float(value("phong_exponent")))
        gl.glMultMatrixd(model.T.ravel())
        gl.glBegin(gl.GL_TRIANGLES)
        for tri in tris:
            for index in tri:
                gl.glNormal3dv(normals[index])
                gl.glVertex3dv(co[index])
        gl.glEnd()
        gl.glFinish()
        pixels = gl.glReadPixels(0, 0, SIZE, SIZE, gl.GL_RGBA, gl.GL_FLOAT)
        image = np.frombuffer(pixels, dtype=np.float32).reshape(SIZE, SIZE, 4)
        gl.glDeleteFramebuffers(1, [fbo])
        gl.glDeleteRenderbuffers(2, [color_rb, depth_rb])
    finally:
        egl.eglMakeCurrent(display, egl.EGL_NO_SURFACE, egl.EGL_NO_SURFACE, egl.EGL_NO_CONTEXT)
        egl.eglDestroyContext(display, context)
    return image[..., :3].astype(np.float64), image[..., 3] > 0.5


@pytest.mark.slow
def test_per_vertex_renders_what_opengl_fixed_function_gouraud_renders(bpy_clean, tmp_path):
    """Issue 28's 'done when': a coarse sphere Per Vertex (Blinn: OpenGL's specular) in Cycles
    and Eevee against Mesa's fixed-function pipeline, >= 99% of the pixels both cover within
    2/255 (point, sun and spot, with kc/kl/kq attenuation and a spot cut-off/exponent)."""
    bpy = bpy_clean
    scene, sphere, _camera, lights = _scene(bpy, "VERTEX")
    sphere.active_material.node_tree.nodes["phong_blinn"].outputs[0].default_value = 1.0
    for light in lights:  # OpenGL's spot cut-off is at most 90°
        if light.data.type == "SPOT":
            assert math.degrees(light.data.spot_size / 2) <= 90
    peer, covered = _gl_gouraud(bpy, scene, sphere, lights)
    for engine in ("cycles", "eevee"):
        be.configure_engine(scene, engine)
        passes = _render(bpy, scene, tmp_path / f"{engine}.exr")
        ours = passes["Combined"][..., :3].astype(np.float64)
        both = covered & (np.rint(passes["id"][..., 0]) == SPHERE_ID)
        diff = np.abs(ours - peer).max(axis=-1)[both]
        share = float((diff <= 2.0 / 255.0).mean())
        be.report(f"[shading OpenGL peer, {engine}] {int(both.sum())} pixels: "
                  f"{100 * share:.2f}% within 2/255, median {np.median(diff):.1e}, "
                  f"max {diff.max():.1e}")
        assert both.sum() > 300 and share >= 0.99


def test_a_material_assigned_by_hand_and_a_modifier_added_later_are_followed(bpy_clean):
    """No operator: a slot given the Per Vertex material gets the modifier, a modifier added
    after Phong Shading puts it last again (the depsgraph handler)."""
    bpy = bpy_clean
    from phong_nodes.addon.shading import modes  # noqa: PLC0415

    scene, sphere, camera, lights = _scene(bpy, "VERTEX", ("POINT",))
    other = be.add_uv_sphere(scene, "Other", (1.5, 1.0, 0.5), 0.5, None, 10, 5)
    bpy.context.view_layer.update()
    assert not other.modifiers
    other.data.materials[0] = sphere.active_material
    bpy.context.view_layer.update()
    assert [m.node_group for m in other.modifiers] == [modes.geometry_tree()]
    ids, got, want, _near = _seen(bpy, scene, other, camera, lights)
    assert len(np.unique(ids)) >= 10 and np.abs(got - want).max() <= VERTEX_TOL
    other.modifiers.new("Later", "SUBSURF")
    bpy.context.view_layer.update()
    assert [m.type for m in other.modifiers] == ["SUBSURF", "NODES"]


@pytest.mark.slow
def test_linked_duplicates_are_each_lit_where_they_stand(bpy_clean):
    bpy = bpy_clean
    scene, sphere, camera, lights = _scene(bpy, "VERTEX", ("POINT", "SPOT"))
    twin = bpy.data.objects.new("Twin", sphere.data)  # the same mesh (Alt+D)
    twin.location = (-1.2, 0.8, 0.3)
    scene.collection.objects.link(twin)
    bpy.context.view_layer.update()
    lit = {}
    for obj in (sphere, twin):
        ids, got, want, near = _seen(bpy, scene, obj, camera, lights)
        assert len(np.unique(ids)) >= 20
        assert np.abs(got - want)[~near].max() <= VERTEX_TOL, obj.name
        lit[obj.name] = dict(zip(ids.tolist(), got))
    common = set(lit[sphere.name]) & set(lit[twin.name])
    assert common and max(np.abs(lit[sphere.name][v] - lit[twin.name][v]).max()
                          for v in common) > 0.05


def test_collection_instances_are_lit_where_they_stand(bpy_clean):
    """A collection instance of a Per Vertex object (the object itself not in the scene) is lit
    with the instance's transform: its vertices' values equal the reference at the vertices
    where the instance puts them."""
    bpy = bpy_clean
    scene, sphere, camera, lights = _scene(bpy, "VERTEX", ("POINT", "SUN"))
    collection = bpy.data.collections.new("Instanced")
    twin = bpy.data.objects.new("Twin", sphere.data)  # the same mesh, material and modifier
    twin.modifiers.new("Phong Shading", "NODES").node_group = sphere.modifiers[-1].node_group
    twin.rotation_euler = (0.0, 0.3, 0.0)
    collection.objects.link(twin)
    empty = bpy.data.objects.new("Instance", None)
    empty.instance_type = "COLLECTION"
    empty.instance_collection = collection
    empty.location = (-1.6, 1.2, 0.4)
    empty.scale = (0.8, 0.8, 1.2)
    scene.collection.objects.link(empty)
    sphere.hide_render = True
    bpy.context.view_layer.update()
    matrix = _matrix(empty) @ np.array(twin.matrix_world, dtype=np.float64)
    _SEEN_AS[twin.name] = matrix
    try:
        ids, got, want, near = _seen(bpy, scene, twin, camera, lights)
    finally:
        _SEEN_AS.clear()
    err = np.abs(got - want)[~near].max()
    be.report(f"[shading instance] {len(np.unique(ids))} vertices seen: max |Δ| {err:.2e}")
    assert len(np.unique(ids)) >= 20 and err <= VERTEX_TOL


def test_a_mirrored_object_is_lit_with_its_normals(bpy_clean):
    """Negative scale (a mirrored object): the normals' inverse transpose keeps their side."""
    bpy = bpy_clean
    scene, sphere, camera, lights = _scene(bpy, "VERTEX", ("POINT", "SUN"))
    sphere.scale = (-1.0, 1.1, 0.9)
    bpy.context.view_layer.update()
    _domain, ids, got = _live(bpy, sphere)
    P, N = _vertices(bpy, sphere)
    want, near = _reference(scene, sphere, camera, lights, P, N)
    err = np.abs(got - want[ids])[~near[ids]].max()
    be.report(f"[shading mirrored] {len(np.unique(ids))} vertices seen: max |Δ| {err:.2e}")
    assert len(np.unique(ids)) >= 20 and err <= VERTEX_TOL and want.std() > 0.02


def test_a_file_of_the_design_before_is_upgraded(bpy_clean):
    """The 0.3 development design (a Geometry Nodes group per material with the custom
    property phong_shading_material, storing a colour attribute that an Attribute node named
    phong_shading_attribute showed) is replaced on load by this one, the Shading kept."""
    bpy = bpy_clean
    from phong_nodes.addon.shading import modes  # noqa: PLC0415

    scene, sphere, camera, lights = _scene(bpy, "VERTEX", ("POINT",))
    material = sphere.active_material
    sphere.modifiers.remove(sphere.modifiers[-1])  # what the old design had instead
    tree = material.node_tree
    tree.nodes.remove(tree.nodes[modes.SHADING_NODE])
    old = bpy.data.node_groups.new("Phong Per Vertex Phong Old", "GeometryNodeTree")
    old[modes.LEGACY_TREE_KEY] = material
    sphere.modifiers.new("Phong Shading", "NODES").node_group = old
    attribute = tree.nodes.new("ShaderNodeAttribute")
    attribute.name = modes.LEGACY_ATTRIBUTE_NODE
    attribute.attribute_name = f"phong_lit:{material.name}"
    tree.links.new(attribute.outputs["Color"], tree.nodes[modes.EMISSION_NODE].inputs["Color"])
    old_name = old.name
    modes.upgrade_on_load()
    assert old_name not in bpy.data.node_groups
    assert modes.LEGACY_ATTRIBUTE_NODE not in tree.nodes
    assert [m.node_group for m in sphere.modifiers] == [modes.geometry_tree()]
    assert material["phong_shading"] == "VERTEX" and modes.group_of(material) is not None
    _ids, got, want, _near = _seen(bpy, scene, sphere, camera, lights)
    assert np.abs(got - want).max() <= VERTEX_TOL


@pytest.mark.slow
def test_an_orthographic_camera_views_along_its_axis(bpy_clean):
    """Switching the camera to orthographic (no call of ours) makes every vertex's view vector
    the camera's axis, Per Vertex and Per Face."""
    bpy = bpy_clean
    scene, sphere, camera, lights = _scene(bpy, "VERTEX", ("POINT", "SPOT"))
    camera.data.type = "ORTHO"
    camera.data.ortho_scale = 3.2
    bpy.context.view_layer.update()
    ids, got, want, near = _seen(bpy, scene, sphere, camera, lights)
    err = np.abs(got - want)[~near].max()
    be.report(f"[shading orthographic] {len(np.unique(ids))} vertices seen: max |Δ| {err:.2e}")
    assert len(np.unique(ids)) >= 20 and err <= VERTEX_TOL
    sphere.active_material.phong.shading = "FACE"
    _ids, got, want, near = _seen(bpy, scene, sphere, camera, lights)
    assert np.abs(got - want)[~near].max() <= VERTEX_TOL


def test_a_control_linked_later_reaches_the_shading_group_at_relink(bpy_clean):
    """A node linked into the lights group node's Object Color after the mode was set feeds
    the shading group after Relink Phong Lights; a value edited on a control node is live."""
    bpy = bpy_clean
    from phong_nodes.addon.shading import modes  # noqa: PLC0415

    scene, sphere, camera, lights = _scene(bpy, "VERTEX", ("POINT",))
    tree = sphere.active_material.node_tree
    group = tree.nodes[modes.SHADING_NODE]
    rgb = tree.nodes.new("ShaderNodeRGB")
    rgb.outputs[0].default_value = (0.1, 0.7, 0.2, 1.0)
    for name in ("Object Color", "Ambient Object Color"):
        tree.links.new(rgb.outputs[0], tree.nodes["phong_lights"].inputs[name])
    assert group.inputs["Object Color"].links[0].from_node.name == "phong_object_color"
    with bpy.context.temp_override(scene=scene):
        assert bpy.ops.phong.relink_lights() == {"FINISHED"}
    group = tree.nodes[modes.SHADING_NODE]
    assert group.inputs["Object Color"].links[0].from_node == rgb
    _domain, ids, got = _live(bpy, sphere)
    P, N = _vertices(bpy, sphere)
    # the reference reads the control node: give it the linked colour (after the render)
    tree.nodes["phong_object_color"].outputs[0].default_value = (0.1, 0.7, 0.2, 1.0)
    want, _near = _reference(scene, sphere, camera, lights, P, N)
    assert np.abs(got - want[ids]).max() <= VERTEX_TOL
