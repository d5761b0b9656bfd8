# SPDX-License-Identifier: GPL-3.0-or-later
"""Blender lights drive Phong materials through one lights group per scene.

A scene with one Point (with a Limit Location constraint), one Sun (parented to a rotated
Empty) and one Spot (rotated) light; a plane (no material) and a sphere (a Principled
material) get Phong materials from ``bpy.ops.phong.apply_material()``.  Cycles renders
Position / Normal / Incoming, the summed "Phong Color" and the four term passes through
AOVs; the numpy reference (node_groups/reference.py) computed from the lights' own
``matrix_world``, colours and settings must match within 1e-4.  Then a light is moved,
rotated, recoloured and re-rendered; then the file is saved, reopened with the extension
disabled and auto-run off, and must render the same pixels.
"""

from __future__ import annotations

import math
import os
import time

import numpy as np
import pytest

import blender_env as be
from blender_env import report
from phong_scene import (AOVS, CY_TOL, PLANE, SPHERE, SPHERE_COLOR, TERMS, _assert_drivers_ok, _assert_light_inputs,
                         _controls, _finish_materials, _light, be_drivers, build_scene, compare,
                         lights_tree, reference_color, render)

EE_TOL, EE_MAX, EE_FRACTION = 5e-3, 5e-2, 0.995


# -- tests ----------------------------------------------------------------------

@pytest.mark.cycles
@pytest.mark.slow
def test_lights_drive_phong_materials_cycles(bpy_clean, blender_tmp):
    bpy = bpy_clean
    scene, plane, sphere, lights = build_scene(bpy)
    point, sun, spot = lights
    area = _light(bpy, scene, "Area", "AREA", (0.0, 0.0, 4.0))
    area.data.energy = 4.0  # its i0 from its Power: 4/π²
    lights = (point, sun, spot, area)
    assert bpy.ops.phong.apply_material() == {"FINISHED"}
    assert plane.active_material.name == PLANE
    assert sphere.active_material.name == SPHERE
    got = sphere.active_material.node_tree.nodes["phong_object_color"].outputs[0].default_value
    assert tuple(got) == pytest.approx(SPHERE_COLOR), "Object Color from the Principled base colour"
    tree = lights_tree(sphere.active_material)
    assert tree is lights_tree(plane.active_material), "one lights group for the scene"
    assert list(tree["phong_lights"]) == ["Area", "Point", "Spot", "Sun"], "Area lights drive"
    _finish_materials(bpy, plane, sphere)
    n_drivers = _assert_drivers_ok(tree)
    assert not be_drivers(sphere.active_material.node_tree), "no driver in the materials"
    bpy.context.view_layer.update()
    # before 5.3 the sphere's Blinn 0.3 has moved it to the lights group of the blend
    # (lighting/rig.py, highlight_for), the groups rebuilt: read its group again
    tree = lights_tree(sphere.active_material)
    _assert_light_inputs(tree, lights)
    assert point.matrix_world.translation.z == pytest.approx(1.8), "constraint included"

    out = str(blender_tmp / "materials")
    os.makedirs(out, exist_ok=True)
    passes, seconds = render(bpy, scene, os.path.join(out, "first.exr"))
    e1 = compare(bpy, scene, passes, lights, f"first render {seconds:.2f} s, {n_drivers} drivers")

    # Move, rotate and recolour: drivers follow without running any operator.
    point.location = (0.4, -1.3, 1.2)
    point.data.phong.linear = 0.5
    pivot = bpy.data.objects["Pivot"]
    pivot.rotation_euler = (0.2, 0.6, -0.4)
    spot.rotation_euler = (0.1, 0.3, -0.2)
    target = bpy.data.objects.new("Target", None)
    scene.collection.objects.link(target)
    target.location = (0.5, 0.0, 0.0)
    track = spot.constraints.new("TRACK_TO")
    track.target, track.track_axis, track.up_axis = target, "TRACK_NEGATIVE_Z", "UP_Y"
    spot.data.color = (0.3, 1.0, 0.4)
    spot.data.spot_size = math.radians(55.0)
    sun.data.color = (1.0, 0.5, 0.2)
    scene.world.phong.ambient_intensity = 0.12
    bpy.context.view_layer.update()
    _assert_light_inputs(tree, (spot, sun, point))
    passes, seconds = render(bpy, scene, os.path.join(out, "moved.exr"))
    e2 = compare(bpy, scene, passes, lights, f"moved/rotated/recoloured {seconds:.2f} s")

    # Save; reopen with the extension disabled and auto-run off: same pixels.
    blend = os.path.join(out, "phong_lights.blend")
    bpy.ops.wm.save_as_mainfile(filepath=blend, copy=True)
    import addon_utils  # noqa: PLC0415

    prefs = bpy.context.preferences.filepaths
    auto_exec = prefs.use_scripts_auto_execute
    try:
        bpy.ops.wm.read_homefile(use_empty=True)
        addon_utils.disable(be.EXT_MODULE, default_set=True)
        assert not be.addon_enabled() and not hasattr(bpy.types.Light, "phong")
        prefs.use_scripts_auto_execute = False
        bpy.ops.wm.open_mainfile(filepath=blend, load_ui=False)
        scene2 = bpy.data.scenes["Phong lights"]
        bpy.context.window.scene = scene2
        tree2 = lights_tree(bpy.data.materials[SPHERE])
        for fc in be_drivers(tree2):
            assert fc.driver.is_valid, f"{fc.data_path} invalid without the add-on"
        t0 = time.perf_counter()
        be.render_exr(scene2, os.path.join(out, "reopened.exr"))
        seconds = time.perf_counter() - t0
        again = {k: v[::-1] for k, v in be.read_multilayer_exr(os.path.join(out, "reopened.exr")).items()}
        diff = max(float(np.abs(again[k] - passes[k]).max()) for k in ("Combined", "Phong Color"))
        report(f"[materials reopened without add-on, auto-run off] {seconds:.2f} s, "
               f"max|reopened-before|={diff:.2e}")
        assert diff <= 1e-6
        # The drivers still run (not just the values saved in the file): move things.
        spot2, point2 = bpy.data.objects["Spot"], bpy.data.objects["Point"]
        spot2.constraints.clear()
        spot2.rotation_euler = (0.9, -0.4, 2.0)
        point2.location = (-0.7, 0.3, 1.1)
        spot2.data.color = (0.1, 0.2, 0.3)
        spot2.data["phong_edge_exponent"] = 5.0
        spot2.data.update_tag()
        scene2.world["phong_ambient_intensity"] = 0.3
        scene2.world.update_tag()
        bpy.context.view_layer.update()
        _assert_light_inputs(tree2, (spot2, point2))
        assert tree2.nodes["light:Spot"].inputs["Edge Exponent"].default_value == 5.0
        np.testing.assert_allclose(tree2.nodes["light:Spot"].inputs["Light Color"].default_value[:3],
                                   (0.1, 0.2, 0.3), atol=1e-7)
        assert tree2.nodes["ambient"].inputs["Intensity"].default_value == pytest.approx(0.3)
    finally:
        prefs.use_scripts_auto_execute = auto_exec
        bpy.ops.wm.read_homefile(use_empty=True)
        be.enable()
    assert e1 <= CY_TOL and e2 <= CY_TOL


def _counts(tree):
    kinds = {}
    for node in tree.nodes:
        key = node.node_tree.name if node.bl_idname == "ShaderNodeGroup" else node.bl_idname
        kinds[key] = kinds.get(key, 0) + 1
    return kinds, len(be_drivers(tree))


def test_light_and_world_defaults(bpy_clean):
    bpy = bpy_clean
    light = bpy.data.lights.new("L", "SPOT")
    s = light.phong
    assert (s.intensity, s.quadratic, s.linear, s.constant, s.edge_exponent, s.diffuse,
            s.specular) == (1.0, 1.0, 0.0, 0.0, 0.0, 1.0, 1.0)
    s.intensity = 2.0
    assert light["phong_intensity"] == 2.0, "stored as a custom property that survives the add-on"
    world = bpy.data.worlds.new("W")
    assert world.phong.ambient_intensity == pytest.approx(0.1)
    assert tuple(world.phong.ambient_color) == (1.0, 1.0, 1.0)
    world.phong.ambient_color = (0.5, 0.25, 1.0)
    assert list(world["phong_ambient_color"]) == [0.5, 0.25, 1.0]
    assert bpy.types.DATA_PT_phong_light.bl_context == "data"
    assert bpy.types.WORLD_PT_phong.bl_context == "world"
    for op in ("apply_material", "relink_lights", "restore_materials", "add_term_passes"):
        assert "UNDO" in getattr(bpy.types, f"PHONG_OT_{op}").bl_options, op


def _lights(kinds, prefix="Phong Rig "):
    """How many of the lights group's light groups (the seeds' model: one per light) *kinds*
    counts, of those whose name starts with *prefix*."""
    return sum(count for name, count in kinds.items() if name.startswith(prefix))


def test_apply_is_idempotent_and_relink_follows_lights(bpy_clean):
    bpy = bpy_clean
    scene, plane, sphere, lights = build_scene(bpy)
    assert bpy.ops.phong.apply_material() == {"FINISHED"}
    n_materials = len(bpy.data.materials)
    tree = lights_tree(plane.active_material)
    first, name = _counts(tree), tree.name
    # one light group per light, one Phong Surface (normal and view once for all), one
    # Phong Ambient, no Phong Shading (its ambient, irradiant and clamp are taken once)
    assert _lights(first[0]) == 3 and first[0]["Phong Surface"] == 1
    assert first[0]["Phong Ambient"] == 1 and "Phong Shading" not in first[0]
    for _ in range(2):
        assert bpy.ops.phong.apply_material() == {"FINISHED"}
        assert bpy.ops.phong.relink_lights() == {"FINISHED"}
    assert len(bpy.data.materials) == n_materials
    again = lights_tree(plane.active_material)
    assert again.name == name and _counts(again) == first
    tree = again
    assert not any(g.name.endswith(".001") for g in bpy.data.node_groups)

    extra = _light(bpy, scene, "Extra", "POINT", (0.0, 0.0, 2.0))
    assert bpy.ops.phong.relink_lights() == {"FINISHED"}
    tree = lights_tree(plane.active_material)  # rebuilt apart and swapped in (two users)
    kinds, n = _counts(tree)
    assert _lights(kinds) == 4 and _lights(kinds, "Phong Rig Point") == 2
    assert n > first[1]
    _assert_drivers_ok(tree)

    extra.hide_set(True)              # hidden in the viewport: F12 renders it, it drives
    lights[1].hide_render = True      # disabled in renders
    assert bpy.ops.phong.relink_lights() == {"FINISHED"}
    tree = lights_tree(plane.active_material)
    assert list(tree["phong_lights"]) == ["Extra", "Point", "Spot"]
    assert _lights(_counts(tree)[0]) == 3

    bpy.data.objects.remove(extra)
    for obj in lights:
        bpy.data.objects.remove(obj)
    assert bpy.ops.phong.relink_lights() == {"FINISHED"}
    tree = lights_tree(plane.active_material)
    kinds, n = _counts(tree)
    assert _lights(kinds) == 0 and kinds["Phong Ambient"] == 1
    assert n == 4, "only the world's ambient intensity and colour remain driven"
    _assert_drivers_ok(tree)


def test_apply_errors_and_slots(bpy_clean):
    bpy = bpy_clean
    scene, plane, sphere, lights = build_scene(bpy)
    before = len(bpy.data.materials)
    for obj in scene.objects:
        obj.select_set(False)
    with pytest.raises(RuntimeError, match="nothing is selected"):
        bpy.ops.phong.apply_material()
    lights[0].select_set(True)
    with pytest.raises(RuntimeError, match="no object with materials"):
        bpy.ops.phong.apply_material()
    assert len(bpy.data.materials) == before and not bpy.data.node_groups, "nothing built"

    # Two slots: both converted, each from its own material.
    keep = bpy.data.materials.new("Keep")
    plane.data.materials.append(keep)
    plane.data.materials.append(bpy.data.materials["Old Principled"])
    plane.select_set(True)            # plus the light: a warning, the mesh is done
    assert bpy.ops.phong.apply_material() == {"FINISHED"}
    assert [s.material.name for s in plane.material_slots] == ["Phong Keep", SPHERE]
    got = plane.material_slots[1].material.node_tree.nodes["phong_object_color"].outputs[0]
    assert tuple(got.default_value) == pytest.approx(SPHERE_COLOR)
    assert bpy.ops.phong.apply_material() == {"FINISHED"}
    assert [s.material.name for s in plane.material_slots] == ["Phong Keep", SPHERE]
    assert not [m for m in bpy.data.materials if m.name.endswith(".001")]

    # No slot at all: one is added.
    mesh = bpy.data.meshes.new("Bare")
    bare = bpy.data.objects.new("Bare", mesh)
    scene.collection.objects.link(bare)
    for obj in scene.objects:
        obj.select_set(obj is bare)
    assert bpy.ops.phong.apply_material() == {"FINISHED"}
    assert [s.material.name for s in bare.material_slots] == [PLANE]


@pytest.mark.eevee
@pytest.mark.slow
def test_lights_drive_phong_materials_eevee(bpy_clean, blender_tmp):
    """Eevee renders the five Phong passes only (each AOV costs Eevee compile time); the
    geometry (P, N, I, id) comes from a Cycles render of the same scene."""
    bpy = bpy_clean
    scene, plane, sphere, lights = build_scene(bpy)
    assert bpy.ops.phong.apply_material() == {"FINISHED"}
    _finish_materials(bpy, plane, sphere)
    bpy.context.view_layer.update()
    out = str(blender_tmp / "materials")
    os.makedirs(out, exist_ok=True)
    geometry, _seconds = render(bpy, scene, os.path.join(out, "eevee_geometry.exr"))
    layer = scene.view_layers[0]
    for name, _kind in AOVS:
        layer.aovs.remove(layer.aovs[name])
    be.configure_engine(scene, "eevee")
    passes, seconds = render(bpy, scene, os.path.join(out, "eevee.exr"))
    world = scene.world
    ident = np.rint(geometry["id"][..., 0]).astype(int)
    edge = np.zeros(ident.shape, dtype=bool)
    P, N, I = (geometry[k][..., :3].astype(np.float64) for k in ("P", "N", "I"))
    expected = {k: np.zeros(P.shape) for k in ("Color",) + TERMS}
    for key, obj in ((1, plane), (2, sphere)):
        m = ident == key
        terms = {}
        expected["Color"][m], edge[m] = reference_color(
            world, lights, _controls(obj.active_material), P[m], N[m], I[m], terms)
        for t in TERMS:
            expected[t][m] = terms[t]
    lines = []
    for name, want in expected.items():
        got = passes[f"Phong {name}"][..., :3].astype(np.float64)
        err = np.abs(got - want).max(axis=-1)[~edge]
        frac = float((err <= EE_TOL).mean())
        lines.append(f"{name} max {err.max():.2e} within {EE_TOL}: {frac:.2%}")
        assert frac >= EE_FRACTION and err.max() <= EE_MAX, (name, lines[-1])
    report(f"[materials eevee, {len(layer.aovs)} AOVs] {seconds:.1f} s: " + "; ".join(lines))
