# SPDX-License-Identifier: GPL-3.0-or-later
"""The World's copies of the lights' transforms (addon/lighting/world_copies.py, issue 38):
on Blender 5.3+, in a scene Eevee renders on the light loop, nothing reads them in Eevee, so
they are parked (no drivers) and a light drag leaves the World alone; an engine that reads
them (Cycles), a render or bake by it, a save, or a reader (a term pass) makes them live.
Before 5.3 nothing changes."""

from __future__ import annotations

import pytest

import blender_env as be
from test_light_loop_render import _check, _expected, _render, _scene


def _modules():
    from phong_nodes.addon.lighting import rig, world_copies  # noqa: PLC0415

    return rig, world_copies


class _WorldSpy:
    """Whether the World was updated by each depsgraph update."""

    def __init__(self, bpy):
        self.bpy = bpy
        self.updates = []

    def __call__(self, _scene, depsgraph):
        self.updates.append(depsgraph.id_type_updated("WORLD"))

    def __enter__(self):
        self.bpy.app.handlers.depsgraph_update_post.insert(0, self)
        return self

    def __exit__(self, *_exc):
        self.bpy.app.handlers.depsgraph_update_post.remove(self)


def _eevee(bpy, scene):
    scene.render.engine = be.compat().eevee_engine()
    bpy.context.view_layer.update()


def _keys(copies, world):
    return [k for k in world.keys() if k.startswith(copies.WORLD_PREFIX)]


@pytest.fixture
def loop_bpy(bpy_clean):
    if not be.compat().HAS_LIGHT_LOOP:
        pytest.skip(f"bpy {be.bpy_release()}: no light loop, Eevee reads the World's copies")
    return bpy_clean


def test_an_eevee_drag_leaves_the_world_alone_and_cycles_makes_the_copies_live(loop_bpy):
    bpy = loop_bpy
    rig, world_copies = _modules()
    scene, _plane, _sphere, lights = _scene(bpy, "Parked", 4)
    world = scene.world
    assert world_copies.is_live(world), "a Cycles scene: its copies follow the lights"
    _eevee(bpy, scene)
    keys = _keys(world_copies, world)
    assert len(keys) == 5 and world_copies.is_live(world), "parked by a drag, not before"
    point = lights[0]
    key = world_copies.world_key(point, "LOCATION")
    with _WorldSpy(bpy) as spy:
        for step in range(4):
            point.location.x += 0.3
            lights[2].rotation_euler.x += 0.05
            bpy.context.view_layer.update()
            if step == 0:
                assert not world_copies.is_live(world), "parked, values kept"
                first = tuple(point.matrix_world.translation)
    assert spy.updates == [True, False, False, False], "the first drag parks them"
    assert tuple(world[key])[:3] == pytest.approx(first), "parked: the first drag's value"
    assert _keys(world_copies, world) == keys

    scene.render.engine = "CYCLES"
    bpy.context.view_layer.update()
    assert world_copies.is_live(world)
    assert _keys(world_copies, world) == keys
    with _WorldSpy(bpy) as spy:
        point.location.y -= 0.5
        bpy.context.view_layer.update()
    assert spy.updates == [True]
    assert tuple(world[key])[:3] == pytest.approx(tuple(point.matrix_world.translation))

    _eevee(bpy, scene)
    assert world_copies.is_live(world)
    point.location.y += 0.5
    bpy.context.view_layer.update()
    assert not world_copies.is_live(world)


def _drag(bpy, light):
    light.location.x += 0.25
    bpy.context.view_layer.update()


def _parked_scene(bpy, name, n_lights):
    """``_scene``'s scene rendered by Eevee after one drag of its last light: parked."""
    _rig, world_copies = _modules()
    scene, plane, sphere, lights = _scene(bpy, name, n_lights)
    _eevee(bpy, scene)
    _drag(bpy, lights[-1])
    assert not world_copies.is_live(scene.world)
    return scene, plane, sphere, lights


def test_a_save_writes_live_copies_and_the_next_drag_parks_them(loop_bpy, blender_tmp):
    bpy = loop_bpy
    _rig, world_copies = _modules()
    scene, _plane, _sphere, lights = _parked_scene(bpy, "Saved", 2)
    written = []

    def probe(*_args):
        written.append(world_copies.is_live(scene.world))

    bpy.app.handlers.save_post.append(probe)
    try:
        bpy.ops.wm.save_as_mainfile(filepath=str(blender_tmp / "saved.blend"), copy=True)
    finally:
        bpy.app.handlers.save_post.remove(probe)
    assert written == [True], "the file has the drivers: Cycles without the extension"
    lights[0].location.x += 0.5
    bpy.context.view_layer.update()
    assert not world_copies.is_live(scene.world)


class _MaterialSpy(_WorldSpy):
    """Whether each depsgraph update re-evaluated a material or a lights group (a light's
    own node tree is no material's)."""

    def __call__(self, _scene, depsgraph):
        types = self.bpy.types
        self.updates.append(any(
            isinstance(u.id, types.Material) or (
                isinstance(u.id, types.NodeTree) and u.id.name.startswith("Phong Lights"))
            for u in depsgraph.updates))


def test_an_eevee_power_drag_leaves_the_materials_alone(loop_bpy):
    """In Eevee (the loop) a light's Power, colour or move re-evaluates no material once its
    lights group's drivers of lights are parked (written down, removed); Cycles gets them all
    back, with the same targets."""
    bpy = loop_bpy
    rig, world_copies = _modules()
    from phong_nodes.addon.lighting import parked_drivers  # noqa: PLC0415

    scene, _plane, _sphere, lights = _scene(bpy, "Power", 3)
    (group,) = rig.groups_of(scene)
    def drivers():
        return sorted((fc.data_path, fc.array_index, fc.driver.type, fc.driver.expression,
                       tuple((v.name, v.type, v.targets[0].id.name, v.targets[0].data_path,
                              v.targets[0].transform_type) for v in fc.driver.variables))
                      for fc in parked_drivers.light_fcurves(group))

    lent = drivers()
    assert lent, "the lights group reads the lights"
    _eevee(bpy, scene)
    with _MaterialSpy(bpy) as spy:
        for step in range(4):
            lights[step % 3].data.energy *= 1.1
            lights[0].data.color = (1.0, 0.9 - 0.1 * step, 0.8)
            lights[1].location.x += 0.1
            bpy.context.view_layer.update()
    assert spy.updates[0], "the first drag parks: the group changes once"
    assert not any(spy.updates[1:]), f"then no material is re-evaluated: {spy.updates}"
    assert parked_drivers.is_parked(group) and not parked_drivers.light_fcurves(group)

    scene.render.engine = "CYCLES"
    bpy.context.view_layer.update()
    assert drivers() == lent and not parked_drivers.is_parked(group)


def test_a_term_pass_keeps_the_copies_live(loop_bpy):
    """A Phong term pass makes Eevee compile the lights group (no loop part): it reads the
    copies, so they stay live in Eevee."""
    bpy = loop_bpy
    rig, world_copies = _modules()
    scene, _plane, _sphere, lights = _scene(bpy, "Passes", 2)
    be.add_aov(scene, rig.PASS_NAMES[0])
    assert bpy.ops.phong.relink_lights() == {"FINISHED"}
    _eevee(bpy, scene)
    assert world_copies.is_live(scene.world)
    lights[0].location.x += 0.5
    bpy.context.view_layer.update()
    assert world_copies.is_live(scene.world)
    key = world_copies.world_key(lights[0], "LOCATION")
    assert tuple(scene.world[key])[:3] == pytest.approx(tuple(lights[0].matrix_world.translation))


@pytest.mark.eevee
@pytest.mark.cycles
@pytest.mark.slow
def test_a_cycles_render_after_an_eevee_drag_sees_the_moved_lights(loop_bpy, blender_tmp):
    """Lights moved while parked: Eevee (the loop) and then Cycles, switched to just before
    its render with the relink handler held (so only ``render_pre`` can make the copies
    live), both match the reference of the lights where they now are."""
    bpy = loop_bpy
    _rig, world_copies = _modules()
    from phong_nodes.addon.lighting import sync  # noqa: PLC0415

    scene, plane, sphere, lights = _parked_scene(bpy, "Parked render", 4)
    lights[0].location = (1.5, -1.0, 1.2)   # far from where the copies were parked
    lights[2].rotation_euler.x += 0.4
    lights[3].location.z += 0.8
    lights[1].data.color = (0.3, 0.9, 0.6)  # the light's data edited while its drivers are parked
    lights[1].data.phong.intensity *= 1.5
    bpy.context.view_layer.update()
    assert not world_copies.is_live(scene.world)
    eevee = _render(bpy, scene, "eevee", str(blender_tmp / "parked_eevee.exr"))
    with sync.paused():
        cycles = _render(bpy, scene, "cycles", str(blender_tmp / "parked_cycles.exr"))
    clamped, unclamped, mask = _expected(scene, {1: (plane, lights), 2: (sphere, lights)},
                                         cycles)
    _check("parked, then Cycles", eevee, cycles, clamped, unclamped, mask)
    assert world_copies.is_live(scene.world)


def test_a_per_vertex_material_makes_the_copies_live(loop_bpy):
    """A Per Vertex group is compiled by Eevee and reads the copies: set on a parked scene,
    they are live again, and a drag keeps them live."""
    bpy = loop_bpy
    rig, world_copies = _modules()
    from phong_nodes.addon.shading import modes  # noqa: PLC0415

    scene, _plane, sphere, lights = _parked_scene(bpy, "Per vertex", 2)
    modes.set_mode(sphere.active_material, modes.VERTEX)
    assert world_copies.is_live(scene.world)
    _drag(bpy, lights[0])
    assert world_copies.is_live(scene.world)
    key = world_copies.world_key(lights[0], "LOCATION")
    assert tuple(scene.world[key])[:3] == pytest.approx(tuple(lights[0].matrix_world.translation))


def test_before_5_3_a_drag_keeps_the_copies_live(bpy_clean):
    """Before 5.3 Eevee reads the copies (5.2's View Layer lookups): never parked."""
    if be.compat().HAS_LIGHT_LOOP:
        pytest.skip("5.3+: see the tests above")
    bpy = bpy_clean
    rig, world_copies = _modules()
    scene, _plane, _sphere, lights = _scene(bpy, "Before 5.3", 2)
    _eevee(bpy, scene)
    assert not world_copies.can_park(scene.world)
    live = world_copies.is_live(scene.world)
    assert live == bool(_keys(world_copies, scene.world)) == (be.compat().VIEW_LAYER_LOOKUPS > 0)
    with _WorldSpy(bpy) as spy:
        lights[0].location.x += 0.5
        bpy.context.view_layer.update()
    assert world_copies.is_live(scene.world) == live
    if live:
        assert spy.updates == [True]
        key = world_copies.world_key(lights[0], "LOCATION")
        assert tuple(scene.world[key])[:3] == pytest.approx(
            tuple(lights[0].matrix_world.translation))
