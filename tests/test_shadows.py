# SPDX-License-Identifier: GPL-3.0-or-later
"""Shadows (issue 43).

* Nothing else loses its shadows: on Blender 5.3 the lights that drive Phong materials get a
  custom influence distance for Eevee's light loop (``compat.LOOP_LIGHT_DISTANCE``); from
  5,000 m on Eevee drops those lights' shadows for every material.  A Principled scene keeps
  its Eevee shadows after Apply Phong Material ran on another object of it.
"""

from __future__ import annotations

import math

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
    for obj in scene.objects:
        obj.select_set(obj is other)
    bpy.context.view_layer.objects.active = other
    assert bpy.ops.phong.apply_material() == {"FINISHED"}
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
