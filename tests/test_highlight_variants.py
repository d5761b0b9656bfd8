# SPDX-License-Identifier: GPL-3.0-or-later
"""Before Blender 5.3 a Phong material uses the lights group of its highlight
(``lighting/rig.py``, ``highlight_for``): Phong's alone where its Blinn is the constant 0,
Blinn-Phong's alone where it is the constant 1, the blend of both otherwise (a value between,
a Blinn linked from another node, keyframed or driven).  A user who changes the Blinn gets
the group of the new value without a click (the depsgraph handler), a file of an earlier
layout gets them on load, and the picture stays the reference's.  On 5.3 the Switch does
this inside the one lights group: every material uses it whatever its Blinn."""

from __future__ import annotations

import os

import pytest

import blender_env as be

DATA = os.path.join(os.path.dirname(os.path.abspath(__file__)), "data")


def _library():
    from phong_nodes.node_groups import library  # noqa: PLC0415

    return library


def _variants() -> bool:
    return _library().SWITCH_FEATURE not in be.compat().NODE_FEATURES


def _scene(bpy, blinns):
    """A scene with a point light, a sun and one sphere per Blinn of *blinns*, Apply Phong
    Material given, each Blinn then set on its control as a user sets it."""
    scene = be.new_scene("Highlights", 48, 32)
    bpy.context.window.scene = scene
    be.add_ortho_camera(scene, (0.0, 0.0), 3.6 * len(blinns) / 2.0, 2.4)
    balls = [be.add_uv_sphere(scene, f"Ball {i}", (1.25 * i - 0.625 * (len(blinns) - 1), 0, 0),
                              0.55, bpy.data.materials.new(f"Clay {i}"), segments=24, rings=12)
             for i in range(len(blinns))]
    for name, kind, location in (("Point", "POINT", (0.8, -1.0, 2.5)),
                                 ("Sun", "SUN", (0.0, 0.0, 3.0))):
        light = bpy.data.objects.new(name, bpy.data.lights.new(name, kind))
        light.location = location
        light.rotation_euler = (0.4, -0.3, 0.0)
        scene.collection.objects.link(light)
    be.apply_phong(scene, balls)
    for ball, blinn in zip(balls, blinns):
        _blinn_control(ball.active_material).outputs[0].default_value = blinn
        ball.active_material.node_tree.nodes["phong_exponent"].outputs[0].default_value = 12.0
    bpy.context.view_layer.update()  # what Blender's UI does after each change
    return scene, [ball.active_material for ball in balls]


def _blinn_control(material):
    return material.node_tree.nodes["phong_blinn"]


def _group(material):
    return material.node_tree.nodes["phong_lights"].node_tree


def _highlight(material) -> str:
    from phong_nodes.addon.lighting import rig  # noqa: PLC0415

    return rig.highlight_of(_group(material))


def _light_groups(material) -> set:
    return {n.node_tree.name for n in _group(material).nodes if n.name.startswith("light:")}


def test_each_material_uses_the_lights_group_of_its_blinn(bpy_clean):
    bpy = bpy_clean
    library = _library()
    scene, (phong, blinn, blend) = _scene(bpy, (0.0, 1.0, 0.4))
    from phong_nodes.addon.lighting import rig  # noqa: PLC0415

    if not _variants():  # 5.3: the Switch inside the one group
        assert _group(phong) is _group(blinn) is _group(blend)
        assert _highlight(phong) == library.BLEND and len(rig.groups_of(scene)) == 1
        return
    assert [_highlight(m) for m in (phong, blinn, blend)] == [library.PHONG, library.BLINN,
                                                              library.BLEND]
    assert len({_group(m) for m in (phong, blinn, blend)}) == 3 == len(rig.groups_of(scene))
    assert _group(phong).name == "Phong Lights Highlights"  # the usual one keeps its name
    assert _light_groups(phong) == {"Phong Rig Point (Phong highlight)",
                                    "Phong Rig Sun (Phong highlight)"} or \
        _light_groups(phong) == {"Phong Rig Point with Shadow (Phong highlight)",
                                 "Phong Rig Sun with Shadow (Phong highlight)"}
    assert all("(Blinn-Phong highlight)" in name for name in _light_groups(blinn))
    assert not any("highlight)" in name for name in _light_groups(blend))


def test_a_blinn_changed_linked_keyframed_or_driven_gets_its_group_without_a_click(bpy_clean):
    bpy = bpy_clean
    library = _library()
    if not _variants():
        pytest.skip("Blender 5.3+: one lights group whatever the Blinn (its Switch)")
    from phong_nodes.addon.lighting import rig  # noqa: PLC0415

    scene, (material,) = _scene(bpy, (0.0,))
    control = _blinn_control(material)
    steps = []
    for value, want in ((0.5, library.BLEND), (1.0, library.BLINN), (0.0, library.PHONG)):
        control.outputs[0].default_value = value
        bpy.context.view_layer.update()
        steps.append((value, _highlight(material), want))
    assert all(got == want for _value, got, want in steps), steps
    assert len(rig.groups_of(scene)) == 1, "the groups no material uses are gone"

    tree = material.node_tree
    control.outputs[0].keyframe_insert("default_value", frame=1)
    bpy.context.view_layer.update()
    assert _highlight(material) == library.BLEND, "a keyframed Blinn may take any value"
    tree.animation_data_clear()
    bpy.context.view_layer.update()
    assert _highlight(material) == library.PHONG

    driver = control.outputs[0].driver_add("default_value").driver
    driver.expression = "0.0"
    bpy.context.view_layer.update()
    assert _highlight(material) == library.BLEND, "a driven Blinn may take any value"
    control.outputs[0].driver_remove("default_value")
    # Blender's Delete Driver tags the material for an update; driver_remove from a script
    # does not on 4.2 (a blend left in place is still exact: it only costs nodes)
    material.update_tag()
    bpy.context.view_layer.update()
    assert _highlight(material) == library.PHONG

    lights = tree.nodes["phong_lights"]
    math = tree.nodes.new("ShaderNodeMath")  # a Blinn from a texture, a chain: any value
    tree.links.new(math.outputs[0], lights.inputs["Blinn"])
    bpy.context.view_layer.update()
    assert _highlight(material) == library.BLEND
    tree.links.new(control.outputs[0], lights.inputs["Blinn"])
    bpy.context.view_layer.update()
    assert _highlight(material) == library.PHONG


@pytest.mark.cycles
@pytest.mark.eevee
def test_the_three_highlights_render_the_reference(bpy_clean, tmp_path):
    bpy = bpy_clean
    from phong_nodes.addon.comparison import engine  # noqa: PLC0415

    scene, materials = _scene(bpy, (0.0, 1.0, 0.4))
    groups = sorted({_highlight(m) for m in materials})
    metrics = engine.run(scene, str(tmp_path / "report"))
    pairs = metrics["pairs"]
    cycles_max = pairs["cycles-reference"]["max_abs"]
    eevee_share = 1.0 - pairs["eevee-reference"]["share_over_1_255"]
    be.report(f"[highlights {be.bpy_release()}] groups {groups}: Cycles max {cycles_max:.2e}, "
              f"Eevee {eevee_share:.3%} within 1/255")
    assert cycles_max <= 1e-4, metrics["verdict"]
    assert eevee_share >= 0.995, metrics["verdict"]


def test_a_file_of_the_former_layout_gets_the_highlights_on_load(bpy_clean):
    """A file saved before the variants (every material on the blend): each material on the
    group of its Blinn once opened (the Enamel's Blinn is 1, the others' 0)."""
    bpy = bpy_clean
    library = _library()
    from phong_nodes.addon.lighting import recipe, rig  # noqa: PLC0415

    bpy.ops.wm.open_mainfile(filepath=os.path.join(DATA, "upgrade", "phong_4.2.23.blend"))
    phong = {m.name: m for m in bpy.data.materials if recipe.is_phong_material(m)}
    got = {name: _highlight(m) for name, m in phong.items()}
    if not _variants():
        assert set(got.values()) == {library.BLEND}, got
        return
    assert got == {name: library.BLINN if name == "Phong Enamel" else library.PHONG
                   for name in phong}, got
    scene = bpy.data.scenes["Upgrade"]
    assert all(t[rig.VERSION_KEY] == rig.RIG_VERSION for t in rig.groups_of(scene))
