# SPDX-License-Identifier: GPL-3.0-or-later
"""Shadows (issue 43).

* Nothing else loses its shadows: on Blender 5.3 the lights that drive Phong materials get a
  custom influence distance for Eevee's light loop (``compat.LOOP_LIGHT_DISTANCE``); from
  5,000 m on Eevee drops those lights' shadows for every material.  A Principled scene keeps
  its Eevee shadows after Apply Phong Material ran on another object of it.
"""

from __future__ import annotations

import math
import os

import numpy as np
import pytest

import blender_env as be
from blender_env import report

SIZE = 48


def _light(bpy, scene, name, kind, location, rotation=(0.0, 0.0, 0.0)):
    data = bpy.data.lights.new(name, kind)
    obj = bpy.data.objects.new(name, data)
    scene.collection.objects.link(obj)
    obj.location = location
    obj.rotation_euler = rotation
    return obj


def _principled(bpy, name, color):
    material = bpy.data.materials.new(name)
    be.compat().new_material_tree(material)
    material.node_tree.nodes["Principled BSDF"].inputs["Base Color"].default_value = (
        *color, 1.0)
    return material


def _render(bpy, scene, path):
    be.render_exr(scene, path)
    return be.read_multilayer_exr(path)["Combined"][..., :3].astype(np.float64)


def _principled_scene(bpy):
    """A floor and a cube of Principled materials under a point light and a spot (Eevee,
    shadows on), seen from above; a third object, out of the camera's view, to Apply."""
    scene = be.new_scene("Keep shadows", SIZE, SIZE, "eevee")
    bpy.context.window.scene = scene
    scene.eevee.use_shadows = True
    be.add_ortho_camera(scene, (0.0, 0.0), 6.0, 6.0)
    floor = be.add_quad(scene, "Floor", -4, -4, 4, 4)
    floor.data.materials.append(_principled(bpy, "Floor grey", (0.7, 0.7, 0.7)))
    cube = be.add_uv_sphere(scene, "Ball", (0.0, 0.0, 1.0), 0.8,
                            _principled(bpy, "Ball red", (0.8, 0.2, 0.2)), segments=24, rings=12)
    other = be.add_uv_sphere(scene, "Elsewhere", (30.0, 0.0, 1.0), 0.5,
                             _principled(bpy, "Elsewhere blue", (0.2, 0.2, 0.8)),
                             segments=8, rings=4)
    point = _light(bpy, scene, "Point", "POINT", (1.5, 1.0, 4.0))
    spot = _light(bpy, scene, "Spot", "SPOT", (-1.5, -1.0, 4.0), (0.3, -0.3, 0.0))
    spot.data.spot_size = math.radians(90.0)
    for obj in (point, spot):
        obj.data.energy = 400.0
        obj.data.shadow_soft_size = 0.0
    return scene, (floor, cube, other), (point, spot)


def _shadowed(lit, unshadowed):
    """Pixels darker by more than 0.05 (RGB sum) than without shadows: in the shadow of a
    light (each of the two lights gives a floor pixel about half its light)."""
    return lit.sum(axis=-1) < unshadowed.sum(axis=-1) - 0.05


@pytest.mark.slow
@pytest.mark.eevee
def test_apply_keeps_the_scene_s_eevee_shadows(bpy_clean, blender_tmp):
    """The shadowed pixels of a Principled floor under a ball, lit by a point light and a
    spot, are the same before and after Apply Phong Material ran on an object out of view;
    the lights' custom distance is at most 3,000 m on 5.3 and untouched before."""
    bpy = bpy_clean
    compat = be.compat()
    scene, (_floor, _ball, other), lights = _principled_scene(bpy)
    before = _render(bpy, scene, str(blender_tmp / "keep_before.exr"))
    for obj in lights:
        obj.data.use_shadow = False
    unshadowed = _render(bpy, scene, str(blender_tmp / "keep_unshadowed.exr"))
    for obj in lights:
        obj.data.use_shadow = True
    distances = [(o.data.use_custom_distance, o.data.cutoff_distance) for o in lights]
    be.apply_phong(scene, [other])
    assert other.active_material.get("phong_nodes_material")
    after = _render(bpy, scene, str(blender_tmp / "keep_after.exr"))
    shadowed_before = _shadowed(before, unshadowed)
    shadowed_after = _shadowed(after, unshadowed)
    diff = np.abs(after - before).max(axis=-1)
    report(f"[keep shadows] {int(shadowed_before.sum())} shadowed px before Apply, "
           f"{int(shadowed_after.sum())} after; max change {diff.max():.2e}, "
           f"{int((diff > 1.0 / 255.0).sum())} px beyond 1/255")
    assert shadowed_before.sum() > 0.03 * shadowed_before.size, "the ball casts shadows"
    assert shadowed_after.sum() == shadowed_before.sum()
    assert (shadowed_after == shadowed_before).all()
    if compat.HAS_LIGHT_LOOP:
        for obj in lights:
            assert obj.data.use_custom_distance
            assert obj.data.cutoff_distance <= 3000.0
    else:
        assert [(o.data.use_custom_distance, o.data.cutoff_distance) for o in lights] == distances


def test_an_earlier_version_s_distance_comes_down(bpy_clean):
    """A light given 10⁴ m by an earlier version (shadows gone in Eevee) is set to the
    distance that keeps them when the extension writes its settings again."""
    bpy = bpy_clean
    compat = be.compat()
    if not compat.HAS_LIGHT_LOOP:
        pytest.skip("no custom distance before Blender 5.3 (no light loop)")
    from phong_nodes.addon.lighting import loop, properties  # noqa: PLC0415

    light = bpy.data.lights.new("Old", "POINT")
    properties.ensure_light_props(light)
    light.use_custom_distance = True
    light.cutoff_distance = 1.0e4
    loop.write_parameters(light)
    assert light.cutoff_distance == 3000.0


# -- the reference's visibility (pure) ---------------------------------------------------------

def _ref():
    from phong_nodes.node_groups import reference  # noqa: PLC0415

    return reference


#: One triangle at z = 1 over the unit square's lower-left half.
TRIANGLE = np.array([[[0.0, 0.0, 1.0], [1.0, 0.0, 1.0], [0.0, 1.0, 1.0]]])


def test_visibility_of_a_point_light_by_hand():
    """Points on z = 0 under a triangle at z = 1: a light above the triangle is hidden from
    the points under it (the segment crosses z = 1 inside the triangle), seen from the others
    and from every point when it hangs below the triangle (the segment stops before)."""
    points = np.array([[0.2, 0.2, 0.0], [0.8, 0.8, 0.0], [2.0, 0.1, 0.0], [0.1, 0.3, 0.0]])
    above = {"type": "point", "position": [0.25, 0.25, 3.0], "shadows": True}
    # by hand: the segment from (x, y, 0) to (0.25, 0.25, 3) meets z = 1 at
    # (x + (0.25 - x)/3, y + (0.25 - y)/3): (0.217, 0.217) in, (0.617, 0.617) out (u+v > 1),
    # (1.417, 0.15) out, (0.15, 0.283) in
    assert _ref().visibility(points, above, TRIANGLE).tolist() == [0.0, 1.0, 1.0, 0.0]
    below = dict(above, position=[0.25, 0.25, 0.5])
    assert _ref().visibility(points, below, TRIANGLE).tolist() == [1.0] * 4
    assert _ref().visibility(points, dict(above, shadows=False), TRIANGLE).tolist() == [1.0] * 4


def test_visibility_of_a_sun_and_of_the_surface_itself():
    """A sun shining straight down: hidden under the triangle, whatever its distance; a point
    on the triangle itself is not its own shadow."""
    sun = {"type": "directional", "direction": [0.0, 0.0, -1.0], "shadows": True}
    points = np.array([[0.3, 0.3, -50.0], [0.3, 0.3, 0.0], [0.9, 0.9, 0.0], [0.3, 0.3, 1.0]])
    assert _ref().visibility(points, sun, TRIANGLE).tolist() == [0.0, 0.0, 1.0, 1.0]
    slanted = dict(sun, direction=[-1.0, 0.0, -1.0])  # rays travel toward -x: light from +x
    # from (x, 0.3, 0) the ray toward the sun (+x, +z) meets z = 1 at (x + 1, 0.3): inside
    # (x + 1 + 0.3 <= 1) for x = -0.8, outside for x = 0
    hits = _ref().visibility(np.array([[-0.8, 0.3, 0.0], [0.0, 0.3, 0.0]]), slanted, TRIANGLE)
    assert hits.tolist() == [0.0, 1.0]


def test_shadow_edge_marks_both_sides():
    from phong_nodes.core import compare  # noqa: PLC0415

    lit = np.array([[1.0, 1.0, 0.0, 0.0], [1.0, 1.0, 1.0, np.nan]])
    # (0, 2) is 0 beside a 1 on its left and below; (0, 3)'s neighbours are 0 and no surface
    assert compare.shadow_edge(lit).tolist() == [[False, True, True, False],
                                                 [False, False, True, False]]


# -- Cycles: Phong plus shadow rays ---------------------------------------------------------

def _grid(bpy, scene, name, half, cells):
    """A floor [-half, half]² at z = 0 of cells × cells quads (normal +Z)."""
    xs = np.linspace(-half, half, cells + 1)
    verts = [(x, y, 0.0) for y in xs for x in xs]
    faces = [(j * (cells + 1) + i, j * (cells + 1) + i + 1, (j + 1) * (cells + 1) + i + 1,
              (j + 1) * (cells + 1) + i) for j in range(cells) for i in range(cells)]
    mesh = bpy.data.meshes.new(name)
    mesh.from_pydata(verts, [], faces)
    obj = bpy.data.objects.new(name, mesh)
    scene.collection.objects.link(obj)
    return obj


def _cube(bpy, scene, name, center, half):
    c = np.array(center)
    verts = [tuple(c + half * np.array(v)) for v in
             ((-1, -1, -1), (1, -1, -1), (1, 1, -1), (-1, 1, -1),
              (-1, -1, 1), (1, -1, 1), (1, 1, 1), (-1, 1, 1))]
    faces = [(0, 3, 2, 1), (4, 5, 6, 7), (0, 1, 5, 4), (1, 2, 6, 5), (2, 3, 7, 6), (3, 0, 4, 7)]
    mesh = bpy.data.meshes.new(name)
    mesh.from_pydata(verts, [], faces)
    obj = bpy.data.objects.new(name, mesh)
    scene.collection.objects.link(obj)
    return obj


def _shadow_scene(bpy, size=64, cells=40):
    """A floor of cells × cells quads, a sphere and a cube over it, a point light, a spot and
    a sun, all casting shadows; Apply Phong Material on the three (no term pass: shadow
    rays)."""
    scene = be.new_scene("Shadows", size, size, "cycles")
    bpy.context.window.scene = scene
    scene.world.phong.ambient_intensity = 0.05
    be.add_ortho_camera(scene, (0.0, 0.0), 8.0, 8.0)
    floor = _grid(bpy, scene, "Floor", 4.0, cells)
    ball = be.add_uv_sphere(scene, "Ball", (-1.0, 0.8, 1.0), 0.8,
                            _principled(bpy, "Ball blue", (0.3, 0.5, 0.8)), segments=32,
                            rings=16)
    box = _cube(bpy, scene, "Box", (1.2, -1.0, 0.7), 0.6)
    point = _light(bpy, scene, "Point", "POINT", (2.0, 1.5, 4.0))
    spot = _light(bpy, scene, "Spot", "SPOT", (-2.5, -2.0, 4.5), (0.45, -0.5, 0.0))
    spot.data.spot_size = math.radians(100.0)
    sun = _light(bpy, scene, "Sun", "SUN", (0.0, 0.0, 5.0), (0.5, 0.4, 0.0))
    point.data.phong.intensity = 9.0
    spot.data.phong.intensity = 12.0
    sun.data.phong.intensity = 0.35
    for obj in (point, spot, sun):
        assert obj.data.use_shadow, "Blender's lights cast shadows by default"
    be.apply_phong(scene, (floor, ball, box), active=ball)
    return scene, (floor, ball, box), (point, spot, sun)


def _compare_cycles(bpy, scene, folder):
    """(data, Cycles' picture, the reference's images, compared mask) as ``phong compare``
    computes them, Cycles only."""
    from phong_nodes.addon.comparison import engine  # noqa: PLC0415
    from phong_nodes.addon.lighting import sync  # noqa: PLC0415
    from phong_nodes.addon.scene import describe  # noqa: PLC0415
    from phong_nodes.core import compare  # noqa: PLC0415

    layer, objects = engine.check(scene)
    folder.mkdir(exist_ok=True)
    with sync.paused():
        data = describe.describe(scene, layer, objects)
        images, passes, terms = engine.render_all(scene, layer, objects, ["cycles"], str(folder))
    metrics, refimg, mask = compare.evaluate(data, images, passes, ["cycles"], terms)
    return data, images, passes, metrics, refimg, mask


@pytest.mark.cycles
def test_cycles_shows_each_light_s_shadow(bpy_clean, blender_tmp):
    """Cycles against the reference "Phong plus shadow rays" (each light's diffuse and specular
    times its visibility against the scene's triangles): within 1e-4 on every pixel away from
    the shadows' edges, on a floor of 40 × 40 quads (no acne); the shadows are there (the
    reference without them differs on many pixels); toggling one light's Cast Shadow changes
    the picture without a relink, and the reference follows."""
    if not be.compat().HAS_RAYCAST:
        pytest.skip(f"no Raycast node in bpy {be.bpy_release()}: no shadows (5.2+)")
    bpy = bpy_clean
    from phong_nodes.addon.lighting import shadows  # noqa: PLC0415
    from phong_nodes.core import compare  # noqa: PLC0415

    scene, (floor, ball, _box), (point, _spot, _sun) = _shadow_scene(bpy)
    group = ball.active_material.node_tree.nodes["phong_lights"].node_tree
    assert shadows.has_shadows(group)
    data, images, passes, metrics, refimg, mask = _compare_cycles(
        bpy, scene, blender_tmp / "shadows_on")
    assert len(data["triangles"]) == 40 * 40 * 2 + 32 * 14 * 2 + 32 * 2 + 12
    unshadowed = compare.reference_image(
        dict(data, lights=[dict(light, shadows=False) for light in data["lights"]]), passes)
    err = metrics["pairs"]["cycles-reference"]
    gap = np.abs(unshadowed["Color"] - refimg["Color"]).max(axis=-1)
    report(f"[shadows cycles] {err['pixels']} px compared, max |Cycles - ref| "
           f"{err['max_abs']:.2e}; {metrics['pixels']['shadow_edge']} shadow-edge px left out; "
           f"{int((gap[mask] > 0.01).sum())} compared px in some light's shadow")
    assert int((gap[mask] > 0.01).sum()) > 0.1 * mask.sum(), "the reference has shadows"
    assert metrics["pixels"]["shadow_edge"] < 0.2 * mask.size
    assert err["max_abs"] <= 1e-4
    assert err["pixels"] > 0.8 * mask.size
    # Cast Shadow off on the point light, live: the drivers, no relink
    nodes_before = len(group.nodes)
    point.data.use_shadow = False
    bpy.context.view_layer.update()
    assert ball.active_material.node_tree.nodes["phong_lights"].node_tree is group
    assert len(group.nodes) == nodes_before
    data2, images2, _passes2, metrics2, _refimg2, _mask2 = _compare_cycles(
        bpy, scene, blender_tmp / "shadows_point_off")
    assert [light["shadows"] for light in data2["lights"]] == [False, True, True]
    changed = np.abs(images2["cycles"] - images["cycles"]).max(axis=-1)
    err2 = metrics2["pairs"]["cycles-reference"]
    report(f"[shadows cycles, point's Cast Shadow off] {int((changed > 0.01).sum())} px "
           f"changed; max |Cycles - ref| {err2['max_abs']:.2e}")
    assert (changed > 0.01).sum() > 50
    assert err2["max_abs"] <= 1e-4


@pytest.mark.slow
@pytest.mark.eevee
@pytest.mark.cycles
def test_eevee_5_3_shows_the_shadows_through_the_loop(bpy_clean, blender_tmp):
    """Blender 5.3: the light loop's Shadow Raycast (Softness 0) multiplies each light's
    diffuse and specular light: Eevee within 1/255 of the reference "Phong plus shadow rays"
    on at least 99.5% of the pixels away from the shadows' edges, whatever the lights' radius;
    it shows the shadows (the reference without them is off on many of those pixels)."""
    if not be.compat().HAS_LIGHT_LOOP:
        pytest.skip(f"Eevee's shadows on Phong materials need the light loop (5.3+), bpy "
                    f"{be.bpy_release()}")
    bpy = bpy_clean
    from phong_nodes.addon.comparison import engine  # noqa: PLC0415
    from phong_nodes.core import compare  # noqa: PLC0415

    scene, _objects, lights = _shadow_scene(bpy)
    for obj in lights:
        obj.data.shadow_soft_size = 0.5  # hard shadows all the same
    metrics = engine.run(scene, str(blender_tmp / "eevee_shadows"), engines=("eevee", "cycles"))
    eevee = metrics["pairs"]["eevee-reference"]
    report(f"[shadows eevee 5.3] {eevee['pixels']} px: "
           f"{100.0 * (1.0 - eevee['share_over_1_255']):.3f}% within 1/255 (max "
           f"{eevee['max_abs']:.2e}); Cycles max "
           f"{metrics['pairs']['cycles-reference']['max_abs']:.2e}"
           f"; {metrics['pixels']['shadow_edge']} edge px out")
    assert metrics["ok"], metrics["verdict"]
    assert 1.0 - eevee["share_over_1_255"] >= compare.EEVEE_SHARE
    # the same scene without shadows in the reference: Eevee is far from it in the shadows
    exr = blender_tmp / "eevee_shadows" / "eevee_alone.exr"
    from phong_nodes.addon.scene import render  # noqa: PLC0415

    render.exact(scene, "eevee")
    be.render_exr(scene, str(exr))
    picture = np.minimum(be.read_multilayer_exr(str(exr))["Combined"][..., :3], 1.0)
    for obj in lights:
        obj.data.use_shadow = False
    bpy.context.view_layer.update()
    be.render_exr(scene, str(exr))
    unshadowed = np.minimum(be.read_multilayer_exr(str(exr))["Combined"][..., :3], 1.0)
    darker = int((np.abs(picture - unshadowed).max(axis=-1) > 0.05).sum())
    report(f"[shadows eevee 5.3] Cast Shadow off on every light: {darker} px change")
    assert darker > 400


def test_x3d_shadows_field_is_read():
    """X3D's lights cast no shadow unless their ``shadows`` field says TRUE (X3D 3.2+)."""
    from phong_nodes.core import x3d  # noqa: PLC0415

    text = ("#X3D V3.3 utf8\nPROFILE Interchange\n"
            "PointLight { location 0 2 0 shadows TRUE }\nSpotLight { }\n"
            "DirectionalLight { shadows FALSE }\n")
    doc = x3d.loads(text.encode())
    lights = [inst.light for inst in doc.lights]
    assert [x3d.light_values(doc, light)["shadows"] for light in lights] == [True, False, False]


def test_scene_files_say_which_lights_and_objects_cast_shadows(tmp_path):
    """The seeds' scenes cast no shadow (their figures have none); the shadows scene has
    lights that cast and one that does not, and an object that casts none; a value that is not
    true or false is refused with its key."""
    from phong_nodes.core import scenes  # noqa: PLC0415

    for name in scenes.available():
        data = scenes.load(os.path.join(scenes.SCENES_DIR, f"{name}.toml"))
        casting = [light["name"] for light in data["lights"] if light["shadows"]]
        if name == "shadows":
            assert casting == ["point", "spot", "sun"]
            assert [o["name"] for o in data["objects"] if not o["shadows"]] == ["pebble"]
        else:
            assert casting == [], name
    bad = tmp_path / "bad.toml"
    bad.write_text('title = "x"\n[camera]\nlocation = [0, 0, 5]\n'
                   '[[lights]]\ntype = "point"\nposition = [0, 0, 2]\nshadows = 1\n'
                   '[[objects]]\nname = "a"\n')
    with pytest.raises(scenes.SceneError, match=r"lights\[0\]\.shadows.*true or false"):
        scenes.load(str(bad))


@pytest.mark.slow
@pytest.mark.cycles
@pytest.mark.eevee
@pytest.mark.parametrize("model", ["threejs", "x3d"])
def test_the_other_models_cast_shadows_too(bpy_clean, blender_tmp, model):
    """The three.js and X3D models: Cycles within 1e-4 of the reference with shadows; Eevee
    with them where the light loop runs (5.3: both models, X3D's per-light ambient light
    unshadowed), else compared without them."""
    if not be.compat().HAS_RAYCAST:
        pytest.skip(f"no Raycast node in bpy {be.bpy_release()}")
    bpy = bpy_clean
    from phong_nodes.addon.comparison import engine  # noqa: PLC0415

    scene, _objects, lights = _shadow_scene(bpy, size=48)
    scene.phong.model = model
    if model == "x3d":  # each light's own ambient light, which no shadow darkens
        for light in lights:
            light.data.phong.ambient = 0.3
    assert bpy.ops.phong.relink_lights() == {"FINISHED"}
    metrics = engine.run(scene, str(blender_tmp / f"shadows_{model}"))
    report(f"[shadows {model}] {metrics['verdict']}, {metrics['pixels']['shadow_edge']} edge px, "
           f"Eevee with shadows: {metrics.get('eevee_shadows', True)}")
    assert metrics["ok"], metrics["verdict"]
    if model == "x3d":
        assert [light["ambient"] for light in metrics["parameters"]["lights"]] == \
            pytest.approx([0.3] * len(lights))
    loop = be.compat().HAS_LIGHT_LOOP
    assert metrics.get("eevee_shadows", True) == loop
    if loop:  # the shadows darken Eevee's picture where they darken Cycles'
        assert metrics["pairs"]["eevee-reference"]["share_over_1_255"] <= 0.005


def _blocked_by_solve(p, d, reach, start, tri):
    """Independent of Möller–Trumbore: solve p + t·d = a + u·(b - a) + v·(c - a)."""
    a, b, c = tri
    m = np.column_stack([d, a - b, a - c])
    if abs(np.linalg.det(m)) < 1e-12:
        return False
    t, u, v = np.linalg.solve(m, a - p)
    return u >= 0 and v >= 0 and u + v <= 1 and start < t < reach


@pytest.mark.slow
@pytest.mark.parametrize("kind", ["point", "directional"])
def test_visibility_matches_a_plain_solve_on_random_triangles(kind):
    """The cluster pre-test leaves out nothing: on 400 random points and 300 random triangles
    the visibility equals a 3 × 3 solve per (point, triangle)."""
    rng = np.random.default_rng(43)
    points = rng.uniform(-2.0, 2.0, (400, 3))
    centres = rng.uniform(-2.0, 2.0, (300, 1, 3))
    tris = centres + rng.normal(0.0, 0.3, (300, 3, 3))
    light = ({"type": "point", "position": [0.3, -0.2, 4.0], "shadows": True}
             if kind == "point" else
             {"type": "directional", "direction": [0.2, 0.4, -1.0], "shadows": True})
    got = _ref().visibility(points, light, tris)
    expected = []
    for p in points:
        if kind == "point":
            to = np.array(light["position"]) - p
            reach = np.linalg.norm(to)
            d = to / reach
        else:
            d = -np.array(light["direction"]) / np.linalg.norm(light["direction"])
            reach = np.inf
        start = 1e-4 * (1.0 + np.abs(p).max())
        expected.append(0.0 if any(_blocked_by_solve(p, d, reach, start, t) for t in tris)
                        else 1.0)
    expected = np.array(expected)
    assert 0.1 < expected.mean() < 0.95, "some points in shadow, some lit"
    assert (got == expected).all(), np.nonzero(got != expected)


@pytest.mark.cycles
def test_no_acne_far_from_the_origin(bpy_clean, blender_tmp):
    """The same scene 1,000 units from the origin (the ray's offset grows with max |P|):
    Cycles still within 1e-4 of the reference away from the shadows' edges, no acne on the
    floor's 3,200 triangles."""
    if not be.compat().HAS_RAYCAST:
        pytest.skip(f"no Raycast node in bpy {be.bpy_release()}")
    bpy = bpy_clean
    scene, _objects, _lights = _shadow_scene(bpy, size=48)
    for obj in scene.objects:
        if obj.parent is None:
            obj.location.x += 1000.0
            obj.location.y -= 600.0
    bpy.context.view_layer.update()
    data, _images, _passes, metrics, _refimg, mask = _compare_cycles(
        bpy, scene, blender_tmp / "shadows_far")
    err = metrics["pairs"]["cycles-reference"]
    report(f"[shadows far] {err['pixels']} px, max |Cycles - ref| {err['max_abs']:.2e}, "
           f"{metrics['pixels']['shadow_edge']} edge px")
    assert data["lights"][0]["position"][0] > 900.0
    assert err["pixels"] > 0.7 * mask.size
    assert err["max_abs"] <= 1e-4


def test_the_light_panel_says_where_shadows_show(bpy_clean):
    """Once, in the light's Phong panel: no shadows before 5.2; Cycles only on 5.2 (every
    model: each has its loop on 5.3); none while a term pass is on; on 5.3 what Cycles'
    Raycast node reads."""
    compat = be.compat()
    from phong_nodes.addon.lighting import shadows  # noqa: PLC0415

    seeds = " ".join(shadows.notes("seeds", True, compat.HAS_LIGHT_LOOP))
    if not compat.HAS_RAYCAST:
        assert "need Blender 5.2+" in seeds
        return
    assert ("Cycles only" in seeds) == (not compat.HAS_LIGHT_LOOP)
    for model in ("seeds", "threejs", "x3d"):
        assert "Cycles only (Blender before 5.3)" in " ".join(shadows.notes(model, True, False))
        assert "Cycles only" not in " ".join(shadows.notes(model, True, True))
    assert "term pass" in " ".join(shadows.notes("seeds", False, False))
    if compat.RAYCAST_VISIBILITY:
        assert "Ray Visibility ▸ Shadow (and Ray Cast)" in seeds
    else:
        assert "Ray Visibility ▸ Shadow not read" in seeds


@pytest.mark.cycles
def test_an_instanced_caster_is_in_the_reference(bpy_clean, blender_tmp):
    """A cube seen only as a collection instance (an Empty instancing its collection, twice)
    casts its shadows in Cycles and in the reference alike (the reference reads the
    depsgraph's instances)."""
    if not be.compat().HAS_RAYCAST:
        pytest.skip(f"no Raycast node in bpy {be.bpy_release()}")
    bpy = bpy_clean
    scene = be.new_scene("Instances", 48, 48, "cycles")
    bpy.context.window.scene = scene
    be.add_ortho_camera(scene, (0.0, 0.0), 8.0, 8.0)
    floor = _grid(bpy, scene, "Floor", 4.0, 8)
    parts = bpy.data.collections.new("Parts")  # not linked to the scene: seen as instances
    box = _cube(bpy, scene, "Part", (0.0, 0.0, 0.0), 0.5)
    scene.collection.objects.unlink(box)
    parts.objects.link(box)
    for name, where in (("Inst A", (-1.5, 1.0, 1.2)), ("Inst B", (1.5, -1.0, 0.8))):
        empty = bpy.data.objects.new(name, None)
        empty.instance_type = "COLLECTION"
        empty.instance_collection = parts
        empty.location = where
        scene.collection.objects.link(empty)
    point = _light(bpy, scene, "Point", "POINT", (0.5, 0.5, 5.0))
    point.data.phong.intensity = 20.0
    be.apply_phong(scene, [floor])
    data, _images, _passes, metrics, refimg, mask = _compare_cycles(
        bpy, scene, blender_tmp / "shadows_instances")
    err = metrics["pairs"]["cycles-reference"]
    in_shadow = int((refimg["in_shadow"] & mask).sum())
    report(f"[shadows instances] {len(data['triangles'])} triangles, {in_shadow} px in shadow, "
           f"max |Cycles - ref| {err['max_abs']:.2e}")
    assert len(data["triangles"]) == 8 * 8 * 2 + 2 * 12
    assert in_shadow > 40
    assert err["max_abs"] <= 1e-4


def test_x3d_shadows_field_is_written_back(tmp_path):
    """A light read with shadows TRUE is written with it (X3D encodings; FALSE, the default,
    is not written) and read back the same; VRML97 has no such field."""
    from phong_nodes.core import x3d  # noqa: PLC0415

    doc = x3d.loads(b"#X3D V3.3 utf8\nPROFILE Interchange\n"
                    b"PointLight { location 0 2 0 shadows TRUE }\nSpotLight { }\n")
    for name in ("back.x3d", "back.x3dv"):
        x3d.save(doc, str(tmp_path / name))
        text = (tmp_path / name).read_text()
        assert text.count("shadows") == 1, name
        again = x3d.load(str(tmp_path / name))
        assert [inst.light.shadows for inst in again.lights] == [True, False], name
    x3d.save(doc, str(tmp_path / "back.wrl"))
    assert "shadows" not in (tmp_path / "back.wrl").read_text()


# -- FBX: a light's CastShadows written and read back -----------------------------------------

FBX_DATA = os.path.join(os.path.dirname(os.path.abspath(__file__)), "data", "fbx")


@pytest.mark.parametrize("cast", [False, True])
def test_fbx_rewrite_sets_a_light_s_cast_shadows(tmp_path, cast):
    """Maya's binary FBX 7.7 (its light CastShadows 1) with the light rewritten: the reader
    finds the CastShadows written, on the object itself; the P record is ("CastShadows",
    "bool", "", "", int32), the property Blender's own exporter writes (p_bool, int32)."""
    be.need_module("ufbx")
    from phong_nodes.core import fbx  # noqa: PLC0415

    data = open(os.path.join(FBX_DATA, "maya_camera_light_axes_y_up_7700_binary.fbx"),
                "rb").read()
    light = fbx.Light(type="SUN", color=(1.0, 1.0, 1.0), intensity=1.0, decay=0,
                      cast_shadows=cast)
    out, missing = fbx.rewrite(data, lights={"": light})
    assert missing == []
    # the P record as bytes: 4 strings (S + uint32 length + text), then I + int32
    want = b"".join(b"S" + len(s).to_bytes(4, "little") + s
                    for s in (b"CastShadows", b"bool", b"", b"")) + b"I" + \
        int(cast).to_bytes(4, "little")
    assert out.count(want) == 1
    target = tmp_path / "rewritten.fbx"
    target.write_bytes(out)
    (read,) = fbx.read(str(target)).lights
    assert read.cast_shadows is cast
    assert read.sources["CastShadows"] == "object"


def _fbx_light_props(path):
    """{light: (type, label, flags, values) of its CastShadows P record, or None} as Blender's
    own ``io_scene_fbx.parse_fbx`` reads the file."""
    from io_scene_fbx import parse_fbx  # noqa: PLC0415

    root, _version = parse_fbx.parse(path)
    out = {}
    for section in root.elems:
        if section.id != b"Objects":
            continue
        for obj in section.elems:
            if obj.id != b"NodeAttribute" or obj.props[2] != b"Light":
                continue
            block = next(e for e in obj.elems if e.id == b"Properties70")
            found = [tuple(p.props[1:]) for p in block.elems if p.props[0] == b"CastShadows"]
            out[obj.props[1].split(b"\x00\x01")[0].decode()] = found[0] if found else None
    return out


def test_fbx_export_round_trip_keeps_cast_shadow(bpy_clean, tmp_path):
    """File ▸ Export ▸ FBX (Phong): each light's CastShadows is its Cast Shadow, written as
    Blender's own exporter writes it (the same P record where Blender writes one); File ▸
    Import ▸ FBX (Phong) of the file gives every light its Cast Shadow back."""
    bpy = bpy_clean
    scene = bpy.context.scene
    cast = {"Lamp": False, "Bulb": True, "Beam": False, "Sunny": True}
    kinds = {"Lamp": "POINT", "Bulb": "POINT", "Beam": "SPOT", "Sunny": "SUN"}
    for index, (name, on) in enumerate(cast.items()):
        obj = _light(bpy, scene, name, kinds[name], (index, 0.0, 3.0))
        obj.data.use_shadow = on
    path = str(tmp_path / "phong.fbx")
    assert bpy.ops.phong.export_fbx(filepath=path) == {"FINISHED"}
    ours = _fbx_light_props(path)
    assert {name: (p[0], p[1], p[2], p[3]) for name, p in ours.items()} == {
        name: (b"bool", b"", b"", int(on)) for name, on in cast.items()}
    plain = str(tmp_path / "blender.fbx")
    assert bpy.ops.export_scene.fbx(filepath=plain) == {"FINISHED"}
    theirs = _fbx_light_props(plain)
    written = [name for name, p in theirs.items() if p is not None]
    assert written, "Blender's exporter writes CastShadows on some light"
    for name in written:
        assert ours[name] == theirs[name], name
    be.reset_empty_file()
    assert bpy.ops.phong.import_fbx(filepath=path) == {"FINISHED"}
    assert {name: bpy.data.lights[name].use_shadow for name in cast} == cast


# -- three.js page: shadow maps where Blender casts Phong shadows -----------------------------

def test_threejs_page_export_casts_where_blender_does(bpy_clean, tmp_path):
    """File ▸ Export ▸ three.js Page of the shadows scene: where Blender casts Phong shadows
    (5.2+), ``renderer.shadowMap`` on, each light's castShadow its Cast Shadow (the point
    light's turned off here), every mesh receives and casts except an object whose shadow
    rays skip it; before 5.2 no shadows in the page, as in Blender.  In Chromium (where
    installed) the page renders without errors and the sun's shadow darkens floor pixels
    that the page without shadows shows lit."""
    bpy = bpy_clean
    from phong_nodes.core import browser, threejs  # noqa: PLC0415

    scene, (floor, ball, box), (point, _spot, _sun) = _shadow_scene(bpy, size=48)
    point.data.use_shadow = False
    if be.compat().RAYCAST_VISIBILITY:
        be.compat().set_casts_shadow(box, False)
    bpy.context.view_layer.update()
    page = tmp_path / "scene.html"
    assert bpy.ops.phong.export_threejs(filepath=str(page)) == {"FINISHED"}
    data = threejs.read_scene(str(page))
    if not be.compat().HAS_RAYCAST:
        assert "shadows" not in data
        assert not any(light.get("cast_shadow") for light in data["lights"])
        return
    assert data["shadows"] is True
    assert {light["name"]: light.get("cast_shadow", False) for light in data["lights"]} == {
        "Point": False, "Spot": True, "Sun": True}
    casts = {mesh["name"].split(" [")[0]: mesh["cast_shadow"] for mesh in data["meshes"]}
    assert casts == {"Floor": True, "Ball": True,
                     "Box": not be.compat().RAYCAST_VISIBILITY}
    assert all(mesh["receive_shadow"] for mesh in data["meshes"])
    if threejs.unavailable() is not None:
        return
    lit = browser.render_page(str(page), timeout=120)
    flat = tmp_path / "flat.html"
    threejs.write_page(str(flat), dict(data, shadows=False))
    plain = browser.render_page(str(flat), timeout=120)
    assert lit.errors == [] and plain.errors == []
    darker = (plain.rgba[..., :3].astype(int) - lit.rgba[..., :3].astype(int)).max(axis=-1)
    report(f"[shadows three.js page] {int((darker > 8).sum())} px darker with shadow maps")
    assert (darker > 8).sum() > 40
    assert (darker < -2).sum() == 0, "shadow maps only darken"


# -- Ray Visibility ▸ Shadow in Cycles (5.3) ----------------------------------------------------

@pytest.mark.slow
@pytest.mark.cycles
@pytest.mark.eevee
def test_shadow_visibility_toggled_on_a_caster_shows_in_cycles(bpy_clean, blender_tmp):
    """Blender 5.3: Object ▸ Visibility ▸ Ray Visibility ▸ Shadow turned off on the box (the
    active object, as in the Object properties) turns its Ray Cast off with it: the box's
    triangles leave the reference, Cycles within 1e-4 of it away from the shadows' edges and
    Eevee (which reads Shadow itself) within 1/255 on 99.5% of the pixels; the box's shadow is
    gone (pixels change).  Shadow on again gives Ray Cast back; a Ray Cast turned off by hand
    while Shadow is on stays off; Restore Original Materials gives back a Ray Cast the mirror
    turned off."""
    compat = be.compat()
    if not compat.RAYCAST_VISIBILITY:
        pytest.skip(f"bpy {be.bpy_release()}: Cycles' Raycast node reads no per-object "
                    "visibility but all ray visibility (5.3+)")
    bpy = bpy_clean
    from phong_nodes.addon.comparison import engine  # noqa: PLC0415
    from phong_nodes.core import compare  # noqa: PLC0415

    scene, (floor, ball, box), _lights = _shadow_scene(bpy)
    layer = bpy.context.view_layer
    _data, before, _p, _m, _r, _mask = _compare_cycles(bpy, scene, blender_tmp / "vis_before")
    for obj in scene.objects:
        obj.select_set(False)
    box.select_set(True)
    layer.objects.active = box
    box.visible_shadow = False
    layer.update()   # the depsgraph handler
    assert box.visible_raycast is False
    data, images, _passes, metrics, _refimg, mask = _compare_cycles(
        bpy, scene, blender_tmp / "vis_off")
    assert len(data["triangles"]) == 40 * 40 * 2 + 32 * 14 * 2 + 32 * 2   # no box
    err = metrics["pairs"]["cycles-reference"]
    changed = np.abs(images["cycles"] - before["cycles"]).max(axis=-1)
    both = engine.run(scene, str(blender_tmp / "vis_off_eevee"), engines=("eevee", "cycles"))
    eevee = both["pairs"]["eevee-reference"]
    report(f"[shadow visibility off, 5.3] Cycles max |Cycles - ref| {err['max_abs']:.2e} on "
           f"{err['pixels']} px; {int((changed > 0.01).sum())} px changed from the box's "
           f"shadow; Eevee {100.0 * (1.0 - eevee['share_over_1_255']):.3f}% within 1/255")
    assert err["max_abs"] <= 1e-4
    assert err["pixels"] > 0.8 * mask.size
    assert (changed > 0.01).sum() > 50, "the box's shadow is gone"
    assert both["ok"], both["verdict"]
    assert 1.0 - eevee["share_over_1_255"] >= compare.EEVEE_SHARE
    # Shadow on again: Ray Cast back
    box.visible_shadow = True
    layer.update()
    assert box.visible_raycast is True
    # a Ray Cast turned off by hand while Shadow is on: left off
    box.visible_raycast = False
    layer.update()
    assert (box.visible_shadow, box.visible_raycast) == (True, False)
    box.visible_raycast = True
    # an object not selected, its Shadow set by a script: Relink brings Ray Cast in step
    ball.visible_shadow = False
    layer.update()
    assert ball.visible_raycast is True, "the handler looks at the active and selected only"
    assert bpy.ops.phong.relink_lights() == {"FINISHED"}
    assert ball.visible_raycast is False
    # Restore Original Materials of the ball alone: the floor still receives Phong shadows,
    # the ball still casts none; of every Phong object: Ray Cast as it was
    for obj in scene.objects:
        obj.select_set(obj is ball)
    layer.objects.active = ball
    assert bpy.ops.phong.restore_materials() == {"FINISHED"}
    layer.update()
    assert (ball.visible_shadow, ball.visible_raycast) == (False, False)
    for obj in scene.objects:
        obj.select_set(obj in (floor, box))
    layer.objects.active = floor
    assert bpy.ops.phong.restore_materials() == {"FINISHED"}
    assert (ball.visible_shadow, ball.visible_raycast) == (False, True)
    assert "phong_raycast_own" not in ball.keys()


@pytest.mark.cycles
def test_shadow_blockers_are_said_not_read_by_cycles(bpy_clean, blender_tmp):
    """A light with a Light Linking blocker collection (only the ball blocks the spot):
    the light panel's note says Cycles' Phong shadows ignore it (and, on 5.3, that Eevee
    honours it); no note for a light without blockers; Cycles, whose Raycast node reads no
    blockers, is still within 1e-4 of the reference (every caster blocks every light)."""
    if not be.compat().HAS_RAYCAST:
        pytest.skip(f"no Raycast node in bpy {be.bpy_release()}")
    bpy = bpy_clean
    from phong_nodes.addon.lighting import shadows  # noqa: PLC0415

    scene, (_floor, ball, _box), (point, spot, _sun) = _shadow_scene(bpy, size=48)
    blockers = bpy.data.collections.new("Spot blockers")
    blockers.objects.link(ball)
    spot.light_linking.blocker_collection = blockers
    note = shadows.blocker_note(spot)
    assert note is not None and "ignore its shadow blockers" in note
    assert ("Eevee does" in note) == be.compat().HAS_LIGHT_LOOP
    assert shadows.blocker_note(point) is None
    bpy.context.view_layer.update()
    _data, _images, _passes, metrics, _refimg, _mask = _compare_cycles(
        bpy, scene, blender_tmp / "blockers")
    err = metrics["pairs"]["cycles-reference"]
    report(f"[shadow blockers] Cycles max |Cycles - ref| {err['max_abs']:.2e} with a blocker "
           "collection on the spot (not read)")
    assert err["max_abs"] <= 1e-4


class _Labels:
    """Records the labels a panel's draw() shows."""

    use_property_split = False

    def __init__(self):
        self.lines = []

    def label(self, text="", **_options):
        self.lines.append(text)

    def __getattr__(self, _name):
        return lambda *args, **kwargs: self


def _labels(panel, **context) -> str:
    layout = _Labels()
    panel.draw(type("Panel", (), {"layout": layout})(), type("Context", (), context)())
    return " | ".join(layout.lines)


@pytest.mark.slow
def test_panels_say_where_a_material_or_a_light_gets_no_shadow(bpy_clean):
    """The light panel warns of a light's shadow blockers (Cycles ignores them) where the
    scene casts shadow rays; the material panel says that Per Vertex / Per Face gets no Phong
    shadows and, on 5.3 (the light loop), that a material of Opacity below 1 gets them in
    Cycles only; an opaque per-pixel material has no such line."""
    bpy = bpy_clean
    compat = be.compat()
    from phong_nodes.addon.ui import panels  # noqa: PLC0415

    scene, (floor, ball, _box), (_point, spot, _sun) = _shadow_scene(bpy, size=16)
    spot.light_linking.blocker_collection = bpy.data.collections.new("Blockers")
    light_text = _labels(panels.DATA_PT_phong_light, light=spot.data, scene=scene, object=spot)
    material_text = _labels(panels.MATERIAL_PT_phong, material=floor.active_material,
                            scene=scene)
    if not compat.HAS_RAYCAST:
        assert "blockers" not in light_text and "shadows" not in material_text
        return
    assert "ignore its shadow blockers" in light_text
    assert "shadow" not in material_text.lower()
    ball.active_material.phong.opacity = 0.5
    text = _labels(panels.MATERIAL_PT_phong, material=ball.active_material, scene=scene)
    assert ("Opacity below 1: Phong shadows in Cycles only" in text) == compat.HAS_LIGHT_LOOP
    floor.active_material.phong.shading = "VERTEX"
    text = _labels(panels.MATERIAL_PT_phong, material=floor.active_material, scene=scene)
    assert "Per Vertex / Per Face: no Phong shadows" in text


def test_a_loaded_file_s_shadow_visibility_reaches_cycles(bpy_clean, blender_tmp):
    """Blender 5.3: a file saved with a caster's Shadow off and its Ray Cast still on (set by
    a script, no Relink) loads with Ray Cast off (load_post), so Cycles casts what Eevee
    does; another object's Ray Cast turned off by hand with Shadow on stays off."""
    compat = be.compat()
    if not compat.RAYCAST_VISIBILITY:
        pytest.skip(f"bpy {be.bpy_release()}: Cycles reads no Ray Cast visibility (5.3+)")
    bpy = bpy_clean
    scene, (floor, ball, box), _lights = _shadow_scene(bpy, size=16)
    for obj in scene.objects:
        obj.select_set(False)
    bpy.context.view_layer.objects.active = floor
    box.visible_shadow = False
    ball.visible_raycast = False
    bpy.context.view_layer.update()
    assert (box.visible_shadow, box.visible_raycast) == (False, True)
    path = str(blender_tmp / "shadow_visibility.blend")
    bpy.ops.wm.save_as_mainfile(filepath=path)
    bpy.ops.wm.open_mainfile(filepath=path)
    box, ball = bpy.data.objects["Box"], bpy.data.objects["Ball"]
    assert (box.visible_shadow, box.visible_raycast) == (False, False)
    assert (ball.visible_shadow, ball.visible_raycast) == (True, False)
