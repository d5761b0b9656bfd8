# SPDX-License-Identifier: GPL-3.0-or-later
"""Phong materials at scale: shared materials stay shared, nothing of the user's is lost,
Light Linking is honoured, lights follow without a click, older files upgrade, every rig
gives the right direction, and Ctrl+Z undoes every operator."""

from __future__ import annotations

import os

import numpy as np
import pytest

import blender_env as be
from phong_scene import (AOVS, _add_probe_aovs, _light, build_scene, compare, input_value,
                            lights_tree, render)

DATA = os.path.join(os.path.dirname(os.path.abspath(__file__)), "data")


def _sphere(bpy, scene, name, location, material=None):
    return be.add_uv_sphere(scene, name, location, 0.6, material, segments=24, rings=12)


def _select(bpy, scene, objects):
    bpy.context.window.scene = scene
    for obj in scene.objects:
        obj.select_set(obj in objects)
    bpy.context.view_layer.objects.active = objects[0]


def _drivers_in_file(bpy):
    trees = [m.node_tree for m in bpy.data.materials if m.node_tree] + list(bpy.data.node_groups)
    return sum(len(t.animation_data.drivers) for t in trees if t.animation_data)


def _principled(bpy, name, color, level=None):
    """A Principled material of base colour *color*; *level*: its Specular IOR Level (0: no
    specular layer, so its Phong version's ambient light sees the base colour itself, Ka =
    Kd; with one, Ka holds what the layer reflects of the World: test_principled_ambient)."""
    material = bpy.data.materials.new(name)
    be.compat().new_material_tree(material)
    node = material.node_tree.nodes["Principled BSDF"]
    node.inputs["Base Color"].default_value = color
    if level is not None:
        node.inputs["Specular IOR Level"].default_value = level
    return material


def test_shared_materials_stay_shared_and_drivers_do_not_grow_with_objects(bpy_clean):
    bpy = bpy_clean
    scene = be.new_scene("Shared", 8, 8)
    shared = _principled(bpy, "Shared", (0.1, 0.5, 0.9, 1.0))
    other = _principled(bpy, "Other", (0.9, 0.2, 0.1, 1.0))
    objects = [_sphere(bpy, scene, f"S{i}", (i, 0, 0), shared) for i in range(3)]
    objects += [_sphere(bpy, scene, f"O{i}", (i, 2, 0), other) for i in range(2)]
    _light(bpy, scene, "Key", "POINT", (0, -3, 3))
    _light(bpy, scene, "Sun", "SUN", (0, 0, 5))
    _select(bpy, scene, objects)
    assert bpy.ops.phong.apply_material() == {"FINISHED"}
    names = {o.name: o.active_material.name for o in objects}
    assert names == {"S0": "Phong Shared", "S1": "Phong Shared", "S2": "Phong Shared",
                     "O0": "Phong Other", "O1": "Phong Other"}
    assert objects[0].active_material is objects[2].active_material
    drivers = _drivers_in_file(bpy)
    assert drivers > 0
    more = [_sphere(bpy, scene, f"M{i}", (i, 4, 0), shared) for i in range(60)]
    _select(bpy, scene, more)
    assert bpy.ops.phong.apply_material() == {"FINISHED"}
    assert {o.active_material.name for o in more} == {"Phong Shared"}
    assert _drivers_in_file(bpy) == drivers, "drivers depend on the lights, not the objects"
    assert len([m for m in bpy.data.materials if m.name.startswith("Phong")]) == 2


def test_original_survives_apply_save_reload_and_restore(bpy_clean, tmp_path):
    bpy = bpy_clean
    scene = be.new_scene("Keep", 8, 8)
    clay = _principled(bpy, "Clay", (0.7, 0.3, 0.1, 1.0))
    image = bpy.data.images.new("Checker", 4, 4)
    textured = _principled(bpy, "Wood", (1.0, 1.0, 1.0, 1.0))
    tree = textured.node_tree
    tex = tree.nodes.new("ShaderNodeTexImage")
    tex.image = image
    mapping = tree.nodes.new("ShaderNodeMapping")
    mapping.inputs["Scale"].default_value = (2.0, 3.0, 1.0)
    tree.links.new(mapping.outputs["Vector"], tex.inputs["Vector"])
    tree.links.new(tex.outputs["Color"], tree.nodes["Principled BSDF"].inputs["Base Color"])
    ball = _sphere(bpy, scene, "Ball", (0, 0, 0), clay)
    box = _sphere(bpy, scene, "Box", (2, 0, 0), textured)
    _light(bpy, scene, "Key", "POINT", (0, -3, 3))
    _select(bpy, scene, [ball, box])
    assert bpy.ops.phong.apply_material() == {"FINISHED"}
    wood = box.active_material
    assert wood.name == "Phong Wood"
    tex_copy = next(n for n in wood.node_tree.nodes if n.bl_idname == "ShaderNodeTexImage")
    assert tex_copy.image is image, "the texture that fed Base Color is kept"
    link = wood.node_tree.nodes["phong_lights"].inputs["Object Color"].links[0]
    assert link.from_node == tex_copy, "and feeds Object Color"
    assert tex_copy.inputs["Vector"].links[0].from_node.inputs["Scale"].default_value[1] == 3.0
    assert not any(n.bl_idname == "ShaderNodeBsdfPrincipled" for n in wood.node_tree.nodes)
    assert clay.users >= 1 and textured.users >= 1, "the sources are kept"

    path = str(tmp_path / "kept.blend")
    bpy.ops.wm.save_as_mainfile(filepath=path)
    bpy.ops.wm.read_homefile(use_empty=True)
    bpy.ops.wm.open_mainfile(filepath=path)
    bpy.data.orphans_purge(do_recursive=True)
    assert "Clay" in bpy.data.materials and "Wood" in bpy.data.materials
    scene = bpy.data.scenes["Keep"]
    bpy.context.window.scene = scene
    ball, box = bpy.data.objects["Ball"], bpy.data.objects["Box"]
    _select(bpy, scene, [ball, box])
    assert bpy.ops.phong.restore_materials() == {"FINISHED"}
    assert ball.active_material.name == "Clay" and box.active_material.name == "Wood"
    node = box.active_material.node_tree.nodes["Principled BSDF"]
    assert node.inputs["Base Color"].links[0].from_node.bl_idname == "ShaderNodeTexImage"
    assert bpy.ops.phong.restore_materials() == {"CANCELLED"}, "nothing left to restore"


def _linking_scene(bpy):
    """Key lights only A (include); Fill lights all but B (exclude); the Sun lights all."""
    scene = be.new_scene("Linking", 48, 16)
    bpy.context.window.scene = scene
    scene.world.phong.ambient_intensity = 0.05
    for name, kind in AOVS:
        be.add_aov(scene, name, kind)
    assert bpy.ops.phong.add_term_passes() == {"FINISHED"}
    be.add_ortho_camera(scene, (0.0, 0.0), 6.0, 2.0)
    spheres = [_sphere(bpy, scene, name, (x, 0.0, 0.0),
                       _principled(bpy, f"M{name}", (0.8, 0.7, 0.6, 1.0)))
               for name, x in (("A", -2.0), ("B", 0.0), ("C", 2.0))]
    key = _light(bpy, scene, "Key", "POINT", (-1.0, -1.0, 2.0))
    key.data.phong.intensity = 4.0
    fill = _light(bpy, scene, "Fill", "POINT", (1.0, -1.0, 2.0))
    fill.data.phong.intensity = 3.0
    fill.data.color = (0.4, 0.6, 1.0)
    sun = _light(bpy, scene, "Sun", "SUN", (0.0, 0.0, 5.0), (0.4, 0.2, 0.0))
    sun.data.phong.intensity = 0.4
    only_a = bpy.data.collections.new("Only A")
    only_a.objects.link(spheres[0])
    key.light_linking.receiver_collection = only_a
    not_b = bpy.data.collections.new("Not B")
    not_b.objects.link(spheres[1])
    not_b.collection_objects[0].light_linking.link_state = "EXCLUDE"
    fill.light_linking.receiver_collection = not_b
    _select(bpy, scene, spheres)
    assert bpy.ops.phong.apply_material() == {"FINISHED"}
    sets = {o.name: list(lights_tree(o.active_material)["phong_lights"]) for o in spheres}
    assert sets == {"A": ["Fill", "Key", "Sun"], "B": ["Sun"], "C": ["Fill", "Sun"]}
    return scene, spheres, (key, fill, sun)


def test_light_linking_include_and_exclude_cycles(bpy_clean, blender_tmp):
    bpy = bpy_clean
    scene, spheres, (key, fill, sun) = _linking_scene(bpy)
    for index, obj in enumerate(spheres, start=1):
        _add_probe_aovs(bpy, obj.active_material, index)
    passes, _seconds = render(bpy, scene, str(blender_tmp / "linking.exr"))
    objects = {1: (spheres[0].active_material, [key, fill, sun]),
               2: (spheres[1].active_material, [sun]),
               3: (spheres[2].active_material, [fill, sun])}
    error = compare(bpy, scene, passes, [], "light linking", objects=objects)
    assert error <= 1e-4


@pytest.mark.slow
@pytest.mark.eevee
def test_light_linking_in_eevee_matches_cycles_on_every_release(bpy_clean, blender_tmp):
    """Eevee has Light Linking only from Blender 4.3, but a Phong material's lights group holds
    only its light set's lights: Eevee 4.2 shows the linked picture all the same. Cycles (checked
    against the reference above) and Eevee agree within 1/255 on every supported release."""
    bpy = bpy_clean
    scene, spheres, _lights = _linking_scene(bpy)
    cycles, _seconds = render(bpy, scene, str(blender_tmp / "linking_cycles.exr"))
    be.configure_engine(scene, "eevee")
    eevee, _seconds = render(bpy, scene, str(blender_tmp / "linking_eevee.exr"))
    a, b = (p["Phong Color"][..., :3].astype(np.float64) for p in (cycles, eevee))
    within = np.abs(a - b).max(axis=-1) <= 1.0 / 255
    be.report(f"[linking eevee] {bpy.app.version_string}: {within.mean():.2%} within 1/255, "
              f"max |Eevee - Cycles| {np.abs(a - b).max():.2e}")
    assert within.mean() >= 0.995
    # the linked lights make a difference the picture shows: B (Sun only) is darker than A and C
    columns = {name: a[8, 8 + 16 * i] for i, name in enumerate("ABC")}
    assert columns["B"].sum() < 0.8 * min(columns["A"].sum(), columns["C"].sum()), columns


def test_lights_follow_without_a_click(bpy_clean, blender_tmp):
    bpy = bpy_clean
    scene, plane, sphere, lights = build_scene(bpy)
    assert bpy.ops.phong.apply_material() == {"FINISHED"}
    _add_probe_aovs(bpy, plane.active_material, 1)
    _add_probe_aovs(bpy, sphere.active_material, 2)
    # a group used by several materials is rebuilt apart and swapped in: ask the material for it
    def tree():
        return lights_tree(plane.active_material)
    extra = _light(bpy, scene, "Extra", "POINT", (-0.5, -0.5, 1.5))
    extra.data.phong.intensity = 0.8
    extra.data.color = (0.2, 1.0, 0.3)
    bpy.context.view_layer.update()  # what Blender's UI does after each change
    assert list(tree()["phong_lights"]) == ["Extra", "Point", "Spot", "Sun"]
    passes, _seconds = render(bpy, scene, str(blender_tmp / "added.exr"))
    compare(bpy, scene, passes, sorted([*lights, extra], key=lambda o: o.name), "light added")
    lights[0].hide_render = True
    bpy.context.view_layer.update()
    assert list(tree()["phong_lights"]) == ["Extra", "Spot", "Sun"]
    bpy.data.objects.remove(extra)
    bpy.context.view_layer.update()
    assert list(tree()["phong_lights"]) == ["Spot", "Sun"]
    area = _light(bpy, scene, "Area", "AREA", (0.3, -0.2, 3.0), (0.2, 0.1, 0.0))
    area.data.energy = 25.0
    bpy.context.view_layer.update()  # an Area light drives Phong as a Lambertian emitter
    assert list(tree()["phong_lights"]) == ["Area", "Spot", "Sun"]
    passes, _seconds = render(bpy, scene, str(blender_tmp / "area.exr"))
    compare(bpy, scene, passes, [area, lights[2], lights[1]], "area light added")


def test_file_of_the_previous_version_upgrades(bpy_clean):
    bpy = bpy_clean
    bpy.ops.wm.open_mainfile(filepath=os.path.join(DATA, "phong_0_1.blend"))
    material = bpy.data.materials["Phong Ball"]
    assert material["phong_nodes_material"] == 1 and material.node_tree.animation_data
    assert bpy.ops.phong.relink_lights() == {"FINISHED"}
    nodes = material.node_tree.nodes
    assert material["phong_nodes_material"] == 5
    assert not [n for n in nodes if n.name.startswith("phong_gen:")]
    strength = nodes["phong_lights"].inputs["Specular Strength"]  # layout 4's control
    assert strength.links[0].from_node.name == "phong_specular_strength"
    assert not (material.node_tree.animation_data and material.node_tree.animation_data.drivers)
    assert nodes["phong_exponent"].outputs[0].default_value == pytest.approx(12.0)
    assert tuple(nodes["phong_specular_color"].outputs[0].default_value)[:3] == \
        pytest.approx((0.5, 0.6, 0.7))
    assert tuple(nodes["phong_object_color"].outputs[0].default_value)[:3] == \
        pytest.approx((0.7, 0.3, 0.1))
    tree = lights_tree(material)
    assert list(tree["phong_lights"]) == ["Key", "Sun"]
    assert all(fc.driver.is_valid for fc in tree.animation_data.drivers)
    bpy.context.view_layer.update()
    key = bpy.data.objects["Key"]
    # the light's position: a World property read by a View Layer attribute (5.2+), or driven
    np.testing.assert_allclose(input_value(tree.nodes["light:Key"].inputs["Position"]),
                               np.array(key.matrix_world)[:3, 3], atol=1e-6)
    # its i0: the fourth component of the same World property (5.2+), or driven
    assert input_value(tree.nodes["light:Key"].inputs["Intensity"]) == pytest.approx(6.0)


@pytest.mark.cycles
def test_mirrored_constrained_and_animated_lights_cycles(bpy_clean, blender_tmp):
    """A spot under a parent with negative scale, a sun tracking an empty, a point light
    keyframed: frames 1 and 10 each show the lights where Blender puts them."""
    bpy = bpy_clean
    scene, plane, sphere, lights = build_scene(bpy)
    point, sun, spot = lights
    mirror = bpy.data.objects.new("Mirror", None)
    scene.collection.objects.link(mirror)
    mirror.scale = (-1.0, 1.0, 1.0)
    mirror.rotation_euler = (0.1, 0.0, 0.3)
    spot.parent = mirror
    spot.location = (1.2, 0.6, 3.0)
    sun.parent = None
    aim = bpy.data.objects.new("Aim", None)
    scene.collection.objects.link(aim)
    aim.location = (0.5, 1.0, -2.0)
    track = sun.constraints.new("DAMPED_TRACK")
    track.target, track.track_axis = aim, "TRACK_NEGATIVE_Z"
    for frame, location in ((1, (1.2, -0.9, 1.6)), (10, (-1.0, 0.8, 1.4))):
        point.location = location
        point.keyframe_insert("location", frame=frame)
    for frame, angle in ((1, 0.0), (10, 1.2)):
        mirror.rotation_euler[2] = angle
        mirror.keyframe_insert("rotation_euler", index=2, frame=frame)
    assert bpy.ops.phong.apply_material() == {"FINISHED"}
    _add_probe_aovs(bpy, plane.active_material, 1)
    _add_probe_aovs(bpy, sphere.active_material, 2)
    assert np.linalg.det(np.array(spot.matrix_world)[:3, :3]) < 0, "a mirrored rig"
    seen = []
    for frame in (1, 10):
        scene.frame_set(frame)
        seen.append(np.array(point.matrix_world)[:3, 3].copy())
        passes, _seconds = render(bpy, scene, str(blender_tmp / f"frame{frame}.exr"))
        compare(bpy, scene, passes, lights, f"mirrored/animated frame {frame}")
    assert np.abs(seen[0] - seen[1]).max() > 1.0, "the point light moved between the frames"


def _state(bpy):
    return {
        "materials": sorted(m.name for m in bpy.data.materials),
        "groups": sorted(g.name for g in bpy.data.node_groups),
        "slots": sorted((o.name, tuple(s.material.name if s.material else "" for s in
                                       o.material_slots)) for o in bpy.data.objects),
        "aovs": sorted(a.name for s in bpy.data.scenes for layer in s.view_layers
                       for a in layer.aovs),
        "drivers": _drivers_in_file(bpy),
    }


def test_ctrl_z_after_each_operator_restores_the_file(bpy_clean):
    bpy = bpy_clean
    scene, plane, sphere, lights = build_scene(bpy)
    steps = [("apply_material", {}), ("add_term_passes", {}), ("relink_lights", {}),
             ("restore_materials", {})]
    bpy.ops.ed.undo_push(message="start")
    for name, kwargs in steps:
        before = _state(bpy)
        assert getattr(bpy.ops.phong, name)("EXEC_DEFAULT", True, **kwargs) == {"FINISHED"}
        after = _state(bpy)
        bpy.ops.ed.undo()
        assert _state(bpy) == before, f"Ctrl+Z after {name}"
        bpy.ops.ed.redo()
        assert _state(bpy) == after, f"Ctrl+Shift+Z after {name}"
        if name == "add_term_passes":
            _light(bpy, bpy.context.scene, "Late", "POINT", (0.0, 0.0, 3.0))
            bpy.ops.ed.undo_push(message="light added")


def test_each_base_colour_reaches_the_render(bpy_clean, blender_tmp):
    """Materials after the first are copies of one template whose Object Color is written
    without Blender's per-value update: the render must still see each one's colour."""
    bpy = bpy_clean
    scene = be.new_scene("Colours", 24, 8)
    bpy.context.window.scene = scene
    scene.world.phong.ambient_intensity = 1.0   # no light, no specular layer: Color = Kd
    colours = [(0.9, 0.1, 0.1, 1.0), (0.1, 0.8, 0.3, 1.0), (0.2, 0.3, 0.9, 1.0)]
    planes = [be.add_uv_plane(scene, f"P{i}", -3.0 + 2.0 * i, -1.0, 2.0,
                              _principled(bpy, f"C{i}", colour, level=0.0))
              for i, colour in enumerate(colours)]
    be.add_ortho_camera(scene, (0.0, 0.0), 6.0, 2.0)
    _select(bpy, scene, planes)
    assert bpy.ops.phong.apply_material() == {"FINISHED"}
    assert bpy.ops.phong.add_term_passes() == {"FINISHED"}
    passes, _seconds = render(bpy, scene, str(blender_tmp / "colours.exr"))
    got = passes["Phong Color"][4, [4, 12, 20], :3]
    np.testing.assert_allclose(got, np.array(colours)[:, :3], atol=1e-6)


def test_a_material_used_in_two_scenes_gets_each_scenes_lights(bpy_clean, blender_tmp):
    """Lights groups are per scene: converting a material in a second scene must not point
    the first scene's Phong materials at the second scene's lights."""
    bpy = bpy_clean
    shared = _principled(bpy, "Shared", (0.8, 0.4, 0.2, 1.0), level=0.0)
    scenes, planes = [], []
    for name, ambient in (("Bright", 1.0), ("Dim", 0.25)):
        scene = be.new_scene(name, 8, 8)
        scene.world.phong.ambient_intensity = ambient  # no light: Color = ambient * colour
        planes.append(be.add_uv_plane(scene, f"{name} plane", -1.0, -1.0, 2.0, shared))
        be.add_ortho_camera(scene, (0.0, 0.0), 2.0, 2.0)
        scenes.append(scene)
    _light(bpy, scenes[1], "Dim key", "POINT", (5.0, 5.0, -5.0))  # behind: lights nothing
    for scene, plane in zip(scenes, planes):
        _select(bpy, scene, [plane])
        assert bpy.ops.phong.apply_material() == {"FINISHED"}
        assert bpy.ops.phong.add_term_passes() == {"FINISHED"}
    bright, dim = (p.active_material for p in planes)
    assert bright is not dim
    assert lights_tree(bright).name == "Phong Lights Bright"
    assert lights_tree(dim).name == "Phong Lights Dim"
    for scene, scale in zip(scenes, (1.0, 0.25)):
        bpy.context.window.scene = scene
        passes, _seconds = render(bpy, scene, str(blender_tmp / f"{scene.name}.exr"))
        np.testing.assert_allclose(passes["Phong Color"][4, 4, :3],
                                   scale * np.array([0.8, 0.4, 0.2]), atol=1e-6)


def test_a_linking_collection_without_phong_objects_is_named_in_a_warning(bpy_clean, capfd):
    bpy = bpy_clean
    scene = be.new_scene("Warn", 8, 8)
    target = _sphere(bpy, scene, "Target", (0, 0, 0), _principled(bpy, "T", (1, 0, 0, 1)))
    bystander = _sphere(bpy, scene, "Bystander", (3, 0, 0))
    collection = bpy.data.collections.new("Only bystander")
    collection.objects.link(bystander)
    key = _light(bpy, scene, "Key", "POINT", (0, -3, 3))
    key.light_linking.receiver_collection = collection
    _select(bpy, scene, [target])
    capfd.readouterr()
    assert bpy.ops.phong.apply_material() == {"FINISHED"}
    out = "".join(capfd.readouterr())
    assert ("Phong: light 'Key' lights only the objects of collection 'Only bystander', and "
            "none of them has a Phong material") in out
    # the target is outside the collection: its light set holds no light
    assert target.active_material.name == "Phong T [no light]"
    assert "Key" not in lights_tree(target.active_material).nodes


def test_a_material_without_nodes_gives_its_viewport_colour(bpy_clean):
    bpy = bpy_clean
    scene = be.new_scene("Flat", 8, 8)
    flat = bpy.data.materials.new("Flat")
    flat.diffuse_color = (0.2, 0.6, 0.3, 1.0)
    if flat.node_tree is not None:          # bpy 5.0 gives new materials a node tree
        flat.node_tree.nodes.clear()
    nodes_before = len(flat.node_tree.nodes) if flat.node_tree else None
    plane = _sphere(bpy, scene, "Plane", (0, 0, 0), flat)
    _light(bpy, scene, "Key", "POINT", (0, -3, 3))
    _select(bpy, scene, [plane])
    assert bpy.ops.phong.apply_material() == {"FINISHED"}
    phong = plane.active_material
    assert phong.name == "Phong Flat" and phong["phong_source"] == "Flat"
    from phong_nodes.addon.lighting import sources  # noqa: PLC0415  (needs bpy)

    assert sources.source_of(phong) == flat and flat.use_fake_user
    colour = phong.node_tree.nodes["phong_object_color"].outputs[0].default_value
    assert tuple(colour) == pytest.approx((0.2, 0.6, 0.3, 1.0))
    assert (len(flat.node_tree.nodes) if flat.node_tree else None) == nodes_before, \
        "the source material is left as it was"


def test_renaming_the_scene_keeps_its_materials_and_lights_group(bpy_clean):
    """Lights groups belong to their scene by an ID pointer, not by its name: after a rename
    a new light still reaches the same materials (no variant copies) through the same group."""
    bpy = bpy_clean
    scene = be.new_scene("Shot", 8, 8)
    ball = _sphere(bpy, scene, "Ball", (0, 0, 0), _principled(bpy, "Clay", (0.7, 0.3, 0.1, 1)))
    _light(bpy, scene, "Key", "POINT", (0, -3, 3))
    _select(bpy, scene, [ball])
    assert bpy.ops.phong.apply_material() == {"FINISHED"}
    material = ball.active_material
    scene.name = "Shot 010"
    _light(bpy, scene, "Fill", "POINT", (3, -3, 3))
    bpy.context.view_layer.update()          # the handler relinks: no click
    assert ball.active_material == material and material.name == "Phong Clay"
    assert [m.name for m in bpy.data.materials if m.name.startswith("Phong")] == ["Phong Clay"]
    tree = lights_tree(material)
    assert tree.name == "Phong Lights Shot 010"
    assert list(tree["phong_lights"]) == ["Fill", "Key"]
    assert len([g for g in bpy.data.node_groups if g.name.startswith("Phong Lights")]) == 1


def test_renaming_a_linked_light_moves_materials_without_copies(bpy_clean):
    """A light set is keyed by its lights' names: when a light is renamed, a material whose
    users all want the renamed set moves to it (no copy), and the stale group goes away."""
    bpy = bpy_clean
    scene = be.new_scene("Linked", 8, 8)
    a = _sphere(bpy, scene, "A", (0, 0, 0), _principled(bpy, "Clay", (0.7, 0.3, 0.1, 1)))
    b = _sphere(bpy, scene, "B", (2, 0, 0), _principled(bpy, "Stone", (0.4, 0.4, 0.4, 1)))
    only_a = bpy.data.collections.new("Only A")
    only_a.objects.link(a)
    key = _light(bpy, scene, "Key", "POINT", (0, -3, 3))
    key.light_linking.receiver_collection = only_a
    sun = _light(bpy, scene, "Sun", "SUN", (0, 0, 5))
    _select(bpy, scene, [a, b])
    assert bpy.ops.phong.apply_material() == {"FINISHED"}
    stone = b.active_material
    assert stone.name == "Phong Stone [Sun]"
    sun.name = "Sky"
    bpy.context.view_layer.update()          # the handler relinks: no click
    assert b.active_material == stone
    assert sorted(m.name for m in bpy.data.materials if m.name.startswith("Phong")) == [
        "Phong Clay", "Phong Stone [Sky]"]
    assert list(lights_tree(stone)["phong_lights"]) == ["Sky"]
    assert sorted(g.name for g in bpy.data.node_groups if g.name.startswith("Phong Lights")) \
        == ["Phong Lights Linked", "Phong Lights Linked [Sky]"]


def test_a_drag_skips_the_lights_signature_and_a_rename_still_relinks(bpy_clean, monkeypatch):
    """Issue 38: an update that only moves a light (its transform, and the World whose
    drivers carry it) cannot change which lights drive the materials, so the relink handler
    skips the lights' fingerprint (from 5.2 on, where the World carries the transforms); a
    light renamed while it moves still relinks (every release)."""
    from phong_nodes.addon.lighting import rig, sync, world_copies  # noqa: PLC0415  (needs bpy)

    bpy = bpy_clean
    scene = be.new_scene("Drag", 8, 8)
    ball = _sphere(bpy, scene, "Ball", (0, 0, 0), _principled(bpy, "Clay", (0.7, 0.3, 0.1, 1)))
    key = _light(bpy, scene, "Key", "POINT", (0, -3, 3))
    sun = _light(bpy, scene, "Sun", "SUN", (0, 0, 5))
    _select(bpy, scene, [ball])
    assert bpy.ops.phong.apply_material() == {"FINISHED"}
    layer = bpy.context.view_layer
    layer.update()
    calls = []
    signature = sync._signature
    monkeypatch.setattr(sync, "_signature", lambda *a: calls.append(a) or signature(*a))
    for step in range(3):
        key.location.x += 0.5
        sun.rotation_euler.x += 0.1
        layer.update()
    through_world = be.compat().VIEW_LAYER_LOOKUPS > 0
    if through_world:  # 5.2+: the lights' transforms reach the materials through the World
        assert calls == []
        world_key = world_copies.world_key(key, "LOCATION")
        assert tuple(scene.world[world_key])[:3] == pytest.approx(
            tuple(key.matrix_world.translation))
    # (before 5.2 the lights group's drivers carry them: there the signature is computed on
    # each of these drags, 3 calls on 4.2.23 and 5.0.1, as before the check)
    calls.clear()
    key.name = "Fill"
    key.location.x += 0.5
    layer.update()
    assert calls
    assert list(lights_tree(ball.active_material)["phong_lights"]) == ["Fill", "Sun"]
    if through_world:
        assert world_copies.world_key(key, "LOCATION") in scene.world.keys()


def test_ambient_object_color_follows_object_color_or_its_own_link(bpy_clean, blender_tmp):
    """The ambient light sees the Object Color (the seeds' model, a source without a specular
    layer) unless the material links its own colour into Ambient Object Color (MTL's Ka):
    exact in Cycles, kept on Relink."""
    bpy = bpy_clean
    scene = be.new_scene("Ka", 16, 8)
    bpy.context.window.scene = scene
    scene.world.phong.ambient_intensity = 0.5
    scene.world.phong.ambient_color = (1.0, 0.5, 0.25)
    planes = [be.add_uv_plane(scene, f"P{i}", -2.0 + 2.0 * i, -1.0, 2.0,
                              _principled(bpy, f"M{i}", (0.9, 0.8, 0.7, 1.0), level=0.0))
              for i in range(2)]
    be.add_ortho_camera(scene, (0.0, 0.0), 4.0, 2.0)
    _select(bpy, scene, planes)
    assert bpy.ops.phong.apply_material() == {"FINISHED"}
    assert bpy.ops.phong.add_term_passes() == {"FINISHED"}
    own = planes[1].active_material
    tree = own.node_tree
    ka = tree.nodes.new("ShaderNodeRGB")
    ka.outputs[0].default_value = (0.2, 0.4, 0.6, 1.0)
    tree.links.new(ka.outputs[0], tree.nodes["phong_lights"].inputs["Ambient Object Color"])
    assert bpy.ops.phong.relink_lights() == {"FINISHED"}
    assert tree.nodes["phong_lights"].inputs["Ambient Object Color"].links[0].from_node == ka
    passes, _seconds = render(bpy, scene, str(blender_tmp / "ka.exr"))
    light = 0.5 * np.array([1.0, 0.5, 0.25])
    np.testing.assert_allclose(passes["Phong Color"][4, 4, :3],
                               light * np.float32([0.9, 0.8, 0.7]), atol=1e-6)
    np.testing.assert_allclose(passes["Phong Color"][4, 12, :3],
                               light * np.float32([0.2, 0.4, 0.6]), atol=1e-6)
    np.testing.assert_allclose(passes["Phong Ambient"][4, 12, :3],
                               light * np.float32([0.2, 0.4, 0.6]), atol=1e-6)


def test_a_layout_2_textured_material_upgrades_keeping_its_texture(bpy_clean, tmp_path):
    """Materials made before Ambient Object Color (layout 2, rig 1) gain it on Relink; the
    links to the group's other sockets, a texture on Object Color included, are kept."""
    bpy = bpy_clean
    scene = be.new_scene("Old", 8, 8)
    image = bpy.data.images.new("checker", 4, 4, alpha=False)
    source = _principled(bpy, "Tiles", (0.5, 0.5, 0.5, 1.0))
    texture = source.node_tree.nodes.new("ShaderNodeTexImage")
    texture.image = image
    bsdf = source.node_tree.nodes["Principled BSDF"]
    source.node_tree.links.new(texture.outputs["Color"], bsdf.inputs["Base Color"])
    ball = _sphere(bpy, scene, "Ball", (0, 0, 0), source)
    _light(bpy, scene, "Key", "POINT", (0, -3, 3))
    _select(bpy, scene, [ball])
    assert bpy.ops.phong.apply_material() == {"FINISHED"}
    material = ball.active_material
    group = lights_tree(material)
    # what layout 2 looked like: no Ambient Object Color, rig version 1
    item = next(i for i in group.interface.items_tree if i.name == "Ambient Object Color")
    group.interface.remove(item)
    group["phong_lights_version"] = 1
    material["phong_nodes_material"] = 2
    node = material.node_tree.nodes["phong_lights"]
    assert "Ambient Object Color" not in node.inputs
    assert bpy.ops.phong.relink_lights() == {"FINISHED"}
    node = material.node_tree.nodes["phong_lights"]
    assert material["phong_nodes_material"] == 5
    feeds = {name: node.inputs[name].links[0].from_node.name
             for name in ("Object Color", "Ambient Object Color", "Specular Color", "Exponent")}
    assert feeds["Object Color"] == feeds["Ambient Object Color"] == texture.name
    assert (feeds["Specular Color"], feeds["Exponent"]) == ("phong_specular_color",
                                                             "phong_exponent")
