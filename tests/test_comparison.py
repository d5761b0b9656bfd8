# SPDX-License-Identifier: GPL-3.0-or-later
"""Demo scenes as artist scenes, and the comparison on any scene with Phong materials
(build_demo_scene, compare_scene, ``phong compare``)."""

import json
import math
import os
import re
import subprocess

import numpy as np
import pytest

import blender_env as be

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def _layout(material):
    """The node layout of a material (what Eevee compiles a shader for): node types and
    names, links, and the lights group's identity left out (values are not layout)."""
    tree = material.node_tree
    nodes = sorted((n.name, n.bl_idname) for n in tree.nodes)
    links = sorted((l.from_node.name, l.from_socket.identifier, l.to_node.name,
                    l.to_socket.identifier) for l in tree.links)
    return nodes, links


def _base(name):
    """A name without Blender's ".001" (demo scenes built into one file share names)."""
    return re.sub(r"\.\d{3}$", "", name)


def _reach(light):
    """Names of the objects a light reaches under Light Linking (None: every object)."""
    collection = light.light_linking.receiver_collection
    if collection is None:
        return None
    states = {_base(obj.name): entry.light_linking.link_state
              for entry, obj in zip(collection.collection_objects, collection.objects)}
    return states


@pytest.mark.slow
def test_every_scene_builds_as_an_artist_scene(bpy_clean):
    bpy = bpy_clean
    from phong_nodes.addon.baking import lighting  # noqa: PLC0415
    from phong_nodes.addon.lighting import sources  # noqa: PLC0415
    from phong_nodes.addon.lighting import recipe as phong_recipe
    from phong_nodes.core import scenes  # noqa: PLC0415
    mine = bpy.data.scenes[0]
    mine_objects = len(mine.objects)
    kinds = {"point": "POINT", "directional": "SUN", "spot": "SPOT"}
    for name in scenes.available():
        before = set(bpy.data.scenes)
        assert bpy.ops.phong.build_demo_scene(name=name, resolution=16) == {"FINISHED"}
        (scene,) = set(bpy.data.scenes) - before
        data = scenes.load(os.path.join(scenes.SCENES_DIR, f"{name}.toml"))
        meshes = {_base(o.name): o for o in scene.objects if o.type == "MESH"}
        lights = {_base(o.name): o for o in scene.objects if o.type == "LIGHT"}
        assert sorted(meshes) == sorted(o["name"] for o in data["objects"]), name
        # real lights with the file's Phong settings
        for light_data in data["lights"]:
            light = lights[light_data["name"]]
            assert light.data.type == kinds[light_data["type"]]
            assert light.data.phong.intensity == pytest.approx(light_data["intensity"])
            assert light.data.phong.quadratic == pytest.approx(light_data.get("quadratic", 1))
            assert tuple(light.data.color) == pytest.approx(light_data["color"])
            # Cast Shadow as the file says (the seeds' scenes: off, their figures have none)
            assert light.data.use_shadow == light_data["shadows"], (name, light.name)
            reach = _reach(light)
            wanted = {o["name"] for o in data["objects"] if light_data["name"] in o["lights"]}
            if wanted == set(meshes):
                assert reach is None, f"{name}: {light.name} reaches every object"
            elif wanted:
                assert reach == {n: "INCLUDE" for n in wanted}, f"{name}: {light.name}"
            else:
                assert set(reach.values()) == {"EXCLUDE"}
        # Phong materials made by Apply's code from a Principled original, one per object
        layouts = {}
        for obj_data in data["objects"]:
            obj = meshes[obj_data["name"]]
            material = obj.active_material
            if obj_data["bake"]:  # shown baked; its Phong material is kept
                assert material.name == f"Phong Bake {obj.name}", name
                material = lighting.phong_material(obj, 0)
            assert phong_recipe.is_phong_material(material), name
            assert sources.source_of(material) is not None, "the original is kept"
            nodes = material.node_tree.nodes
            exponent = nodes["phong_exponent"].outputs[0].default_value
            assert exponent == pytest.approx(obj_data["material"]["exponent"])
            if obj_data["material"]["shading"] != "pixel":  # its own nodes (test_shading_modes)
                assert material["phong_shading"] == obj_data["material"]["shading"].upper()
            elif obj_data["material"]["texture"] is None:
                group = nodes[phong_recipe.LIGHTS_NODE].node_tree.name
                layouts.setdefault(group, set()).add(repr(_layout(material)))
        assert all(len(v) == 1 for v in layouts.values()), \
            f"{name}: untextured materials of one light set share one layout (one shader)"
        assert scene.world.phong.ambient_intensity == pytest.approx(data["ambient"]["intensity"])
        assert scene.camera is not None
        assert scene.render.resolution_y == 16
        assert scene.render.resolution_x == max(1, round(16 * data["aspect"]))
    assert len(mine.objects) == mine_objects, "the user's scene is untouched"


def test_terms_become_control_values(bpy_clean):
    """four_terms: each object's terms are values of its controls, not another recipe."""
    bpy = bpy_clean
    bpy.ops.phong.build_demo_scene(name="four_terms", resolution=16)
    scene = bpy.data.scenes["four_terms"]

    def value(obj, node):
        return tuple(scene.objects[obj].active_material.node_tree.nodes[node].outputs[0]
                     .default_value)[:3]

    black = (0.0, 0.0, 0.0)
    assert value("ambient", "phong_object_color") == black  # no diffuse
    assert value("ambient", "phong_specular_color") == black
    assert value("ambient", "phong_ambient_color") != black
    assert value("diffuse", "phong_ambient_color") == black
    assert value("diffuse", "phong_object_color") != black
    assert value("specular", "phong_specular_color") != black
    assert value("specular", "phong_object_color") == black
    assert value("all", "phong_ambient_color") == value("all", "phong_object_color")


def _read_png(path):
    import OpenImageIO as oiio  # noqa: PLC0415

    image = oiio.ImageBuf(str(path))
    return np.asarray(image.get_pixels(oiio.FLOAT))


@pytest.mark.slow
@pytest.mark.cycles
def test_moving_a_light_of_a_demo_changes_the_picture_and_still_matches(bpy_clean, tmp_path):
    bpy = bpy_clean
    from phong_nodes.addon.comparison import engine  # noqa: PLC0415
    bpy.ops.phong.build_demo_scene(name="two_lights", resolution=24)
    scene = bpy.data.scenes["two_lights"]
    first = engine.run(scene, str(tmp_path / "before"), engines=("cycles",))
    assert first["ok"], first["verdict"]
    scene.objects["green"].location = (-1.0, -4.0, 2.5)
    scene.objects["green"].data.color = (0.2, 0.4, 1.0)
    second = engine.run(scene, str(tmp_path / "after"), engines=("cycles",))
    assert second["ok"], second["verdict"]
    before = _read_png(tmp_path / "before" / "cycles.png")
    after = _read_png(tmp_path / "after" / "cycles.png")
    assert np.abs(before - after).max() > 0.1, "the moved, recoloured light shows"
    green = next(l for l in second["parameters"]["lights"] if l["name"] == "green")
    assert green["position"] == pytest.approx([-1.0, -4.0, 2.5])


def _hand_made_scene(bpy):
    """Three spheres, a spot parented to a rotated empty, a sun, a point light linked to one
    sphere only, a checker texture on one object colour; artist settings everywhere."""
    from mathutils import Vector  # noqa: PLC0415
    scene = bpy.data.scenes.new("By hand")
    bpy.context.window.scene = scene
    scene.render.resolution_x, scene.render.resolution_y = 48, 32
    scene.render.engine = "CYCLES"
    scene.cycles.samples = 64
    scene.view_settings.view_transform = "Filmic" if "Filmic" in [
        i.identifier for i in scene.view_settings.bl_rna.properties["view_transform"]
        .enum_items] else "Standard"
    world = bpy.data.worlds.new("By hand")
    be.compat().black_world(world)
    scene.world = world
    world.phong.ambient_intensity = 0.12
    spheres = []
    for index, (x, color) in enumerate(((-2.2, (0.8, 0.2, 0.1)), (0.0, (0.2, 0.7, 0.3)),
                                        (2.2, (0.3, 0.4, 0.9)))):
        material = bpy.data.materials.new(f"Paint {index}")
        tree = be.compat().new_material_tree(material)
        principled = tree.nodes["Principled BSDF"]
        principled.inputs["Base Color"].default_value = (*color, 1.0)
        if index == 2:
            checker = tree.nodes.new("ShaderNodeTexChecker")
            checker.inputs["Scale"].default_value = 3.0
            tree.links.new(checker.outputs["Color"], principled.inputs["Base Color"])
        spheres.append(be.add_uv_sphere(scene, f"Ball {index}", (x, 0.0, 0.0), 1.0, material,
                                        segments=32, rings=16))
    camera = bpy.data.objects.new("Camera", bpy.data.cameras.new("Camera"))
    scene.collection.objects.link(camera)
    camera.location = (0.0, -9.0, 2.0)
    camera.rotation_euler = (Vector((0, 0, 0)) - camera.location).to_track_quat("-Z", "Y").to_euler()
    scene.camera = camera

    def light(name, kind, location):
        obj = bpy.data.objects.new(name, bpy.data.lights.new(name, kind))
        scene.collection.objects.link(obj)
        obj.location = location
        return obj

    sun = light("Sun", "SUN", (0, 0, 5))
    sun.rotation_euler = (0.6, 0.3, 0.0)
    sun.data.phong.intensity = 0.5
    pivot = bpy.data.objects.new("Pivot", None)
    scene.collection.objects.link(pivot)
    pivot.location = (0.0, -2.0, 3.0)
    pivot.rotation_euler = (0.4, 0.0, 0.3)
    spot = light("Spot", "SPOT", (0.5, 0.0, 1.0))
    spot.parent = pivot
    spot.data.spot_size = math.radians(60.0)
    spot.data.phong.intensity = 4.0
    spot.data.phong.edge_exponent = 3.0
    point = light("Point", "POINT", (2.0, -2.5, 1.5))
    point.data.color = (1.0, 0.6, 0.2)
    point.data.phong.intensity = 6.0
    receivers = bpy.data.collections.new("Point receivers")
    receivers.objects.link(spheres[2])
    point.light_linking.receiver_collection = receivers
    for obj in scene.objects:
        obj.select_set(obj in spheres)
    assert bpy.ops.phong.apply_material() == {"FINISHED"}
    return scene


def _settings(scene):
    layer = scene.view_layers[0]
    return (scene.render.engine, scene.cycles.samples, scene.render.resolution_x,
            scene.view_settings.view_transform, scene.render.filepath,
            scene.render.image_settings.file_format, [a.name for a in layer.aovs],
            [o.pass_index for o in scene.objects])


@pytest.mark.slow
@pytest.mark.cycles
@pytest.mark.eevee
def test_a_scene_made_by_hand_compares_ok_by_operator_and_cli(bpy_clean, tmp_path):
    bpy = bpy_clean
    from phong_nodes.addon.lighting import sources  # noqa: PLC0415
    from phong_nodes.addon.lighting import recipe as phong_recipe
    scene = _hand_made_scene(bpy)
    settings = _settings(scene)
    groups = {m.name: m.node_tree.nodes[phong_recipe.LIGHTS_NODE].node_tree.name
              for m in phong_recipe.phong_materials()}
    assert len(set(groups.values())) == 2, "the point light's link makes a second light set"
    with bpy.context.temp_override(scene=scene):
        assert bpy.ops.phong.compare_scene(directory=str(tmp_path / "op")) == {"FINISHED"}
        # the old name runs the same operator, for scripts written for 0.3
        assert bpy.ops.phong.bake_comparison(directory=str(tmp_path / "op-old")) == {"FINISHED"}
        assert (tmp_path / "op-old").is_dir()
    metrics = json.loads((tmp_path / "op" / "By_hand" / "metrics.json").read_text())
    assert metrics["ok"], metrics["verdict"]
    assert metrics["resolution"] == [48, 32], "the scene's own size"
    assert metrics["pairs"]["cycles-reference"]["max_abs"] <= 1e-4
    assert max(t["max_abs"] for t in metrics["terms"].values()) <= 1e-4
    assert metrics["pixels"]["compared"] > 300
    spot = next(l for l in metrics["parameters"]["lights"] if l["name"] == "Spot")
    assert spot["position"] != pytest.approx([0.5, 0.0, 1.0]), "the parent's transform counts"
    # everything the comparison changed is back
    assert _settings(scene) == settings
    assert {m.name: m.node_tree.nodes[phong_recipe.LIGHTS_NODE].node_tree.name
            for m in phong_recipe.phong_materials()} == groups
    assert not [g for g in bpy.data.node_groups if g.name.endswith("(probe)")]
    assert not [f for f in os.listdir(tmp_path / "op") if f.startswith(".")]

    path = tmp_path / "by_hand.blend"
    bpy.ops.wm.save_as_mainfile(filepath=str(path), copy=True)
    env = dict(os.environ, BLENDER_USER_RESOURCES=str(tmp_path / "user"))
    result = subprocess.run(["bash", os.path.join(ROOT, "tools", "phong.sh"), "compare",
                             str(path), "--out", str(tmp_path / "cli"), "--engines", "cycles"],
                            capture_output=True, text=True, env=env, timeout=300)
    assert result.returncode == 0, result.stdout[-3000:] + result.stderr[-3000:]
    cli = json.loads((tmp_path / "cli" / "By_hand" / "metrics.json").read_text())
    assert cli["ok"] and cli["resolution"] == [48, 32]
    assert cli["pairs"]["cycles-reference"]["max_abs"] == pytest.approx(
        metrics["pairs"]["cycles-reference"]["max_abs"], abs=1e-6)
    assert (tmp_path / "cli" / "index.html").exists()


@pytest.mark.slow
@pytest.mark.cycles
def test_a_stale_lights_group_is_a_mismatch(bpy_clean, tmp_path):
    """The reference reads the lights, not the lights groups: a group that does not follow
    its light (its intensity driver muted) shows as a mismatch, so the comparison checks the recipe."""
    bpy = bpy_clean
    from phong_nodes.addon.comparison import engine  # noqa: PLC0415
    from phong_nodes.addon.lighting import rig  # noqa: PLC0415
    bpy.ops.phong.build_demo_scene(name="lambert_vs_phong", resolution=16)
    scene = bpy.data.scenes["lambert_vs_phong"]
    (group,) = [g for g in rig.groups_of(scene)]
    # a light's i0 is driven in the group, or in its World copy's fourth component (5.2+)
    drivers = [*group.animation_data.drivers,
               *(scene.world.animation_data.drivers if scene.world.animation_data else ())]
    fcurve = next(f for f in drivers
                  if f.data_path.startswith(('nodes["light:', '["phong_light_'))
                  and f.driver.variables[0].targets[0].data_path == '["phong_intensity"]')
    light = fcurve.driver.variables[0].targets[0].id
    fcurve.mute = True
    light.phong.intensity = 3.0 * light.phong.intensity + 0.5
    metrics = engine.run(scene, str(tmp_path / "stale"), engines=("cycles",))
    assert not metrics["ok"]
    assert metrics["pairs"]["cycles-reference"]["max_abs"] > 1e-2


@pytest.mark.cycles
def test_interrupted_bake_leaves_nothing_and_puts_the_scene_back(bpy_clean, tmp_path,
                                                                   monkeypatch):
    bpy = bpy_clean
    from phong_nodes.addon.comparison import engine
    from phong_nodes.addon.demos import builder  # noqa: PLC0415
    from phong_nodes.core import report, scenes  # noqa: PLC0415
    data = scenes.load(os.path.join(scenes.SCENES_DIR, "lambert_vs_phong.toml"))
    scene = builder.build(data, 12)
    groups = sorted(g.name for g in bpy.data.node_groups)

    def boom(*_args, **_kwargs):
        raise KeyboardInterrupt

    monkeypatch.setattr(report, "write_scene", boom)
    (tmp_path / "lambert_vs_phong").mkdir()
    (tmp_path / "lambert_vs_phong" / "metrics.json").write_text("{}")  # an older comparison
    with pytest.raises(KeyboardInterrupt):
        engine.run(scene, str(tmp_path / "lambert_vs_phong"), engines=("cycles",))
    assert sorted(os.listdir(tmp_path)) == ["lambert_vs_phong"]
    assert os.listdir(tmp_path / "lambert_vs_phong") == ["metrics.json"], "old comparison kept whole"
    assert sorted(g.name for g in bpy.data.node_groups) == groups, "probe groups removed"
    assert scene.render.engine != "CYCLES" and len(scene.view_layers[0].aovs) == 0
    builder.remove(scene)
    assert "lambert_vs_phong" not in bpy.data.scenes


@pytest.mark.slow
@pytest.mark.cycles
def test_the_operator_reports_a_camera_that_sees_nothing_as_an_error(bpy_clean, tmp_path):
    """Compare Phong Scene on a scene whose camera looks away from every Phong object: an
    error report saying why and what to do (bpy.ops raises it), the report folder written
    and failed; the same scene framed compares OK."""
    bpy = bpy_clean
    from phong_nodes.addon.interchange import x3d_import  # noqa: PLC0415
    from phong_nodes.addon.scene import framing  # noqa: PLC0415
    path = tmp_path / "away.wrl"
    path.write_text("#VRML V2.0 utf8\n"
                    "Viewpoint { position 0 0 10 orientation 0 1 0 3.14159 }\n"
                    "Shape { appearance Appearance { material Material { "
                    "diffuseColor 0.8 0.3 0.2 } } geometry Box { size 0.24 0.12 0.1 } }\n")
    scene = bpy.data.scenes.new("Away")
    bpy.context.window.scene = scene
    scene.render.resolution_x, scene.render.resolution_y = 32, 24
    with bpy.context.temp_override(scene=scene):
        x3d_import.import_file(bpy.context, str(path))
        assert not scene.camera.get(x3d_import.DEFAULT_VIEWPOINT_KEY), "the file's Viewpoint"
        with pytest.raises(RuntimeError, match=r"Compare Phong Scene: 'Away': the camera sees "
                           r"0 of 768 pixels of Phong surfaces .*frame the scene"):
            bpy.ops.phong.compare_scene(directory=str(tmp_path / "op"), engines={"CYCLES"})
    metrics = json.loads((tmp_path / "op" / "Away" / "metrics.json").read_text())
    assert not metrics["ok"] and metrics["coverage"]["pixels"] == 0
    assert framing.frame(scene, scene.camera, framing.visible_meshes(scene))
    with bpy.context.temp_override(scene=scene):
        assert bpy.ops.phong.compare_scene(directory=str(tmp_path / "op"),
                                           engines={"CYCLES"}) == {"FINISHED"}
    metrics = json.loads((tmp_path / "op" / "Away" / "metrics.json").read_text())
    assert metrics["ok"] and metrics["coverage"]["pixels"] > 0.2 * 768


def test_bake_refuses_a_scene_without_phong_materials(bpy_clean, tmp_path):
    bpy = bpy_clean
    scene = bpy.data.scenes.new("Plain")
    bpy.context.window.scene = scene
    material = bpy.data.materials.new("Plain")
    be.add_uv_sphere(scene, "Ball", (0, 0, 0), 1.0, material, segments=8, rings=4)
    with bpy.context.temp_override(scene=scene), pytest.raises(
            RuntimeError, match="scene 'Plain' has no object with a Phong material"):
        bpy.ops.phong.compare_scene(directory=str(tmp_path / "out"))
    assert not (tmp_path / "out").exists()


@pytest.mark.cycles
def test_the_operator_compares_a_scene_without_a_camera_and_leaves_it_so(bpy_clean, tmp_path):
    """Compare Phong Scene on a scene with no camera at all: compared from a camera that
    frames its Phong objects, which is gone afterwards (no object, no camera data, the scene
    still without a camera); a scene with a camera object that is not its scene camera is
    compared from that object and keeps no scene camera either."""
    bpy = bpy_clean
    scene = be.new_scene("No camera", 32, 24)
    bpy.context.window.scene = scene
    scene.world.phong.ambient_intensity = 1.0
    material = bpy.data.materials.new("Clay")
    be.add_uv_sphere(scene, "Ball", (0.0, 0.0, 0.0), 1.0, material, segments=16, rings=8)
    be.apply_phong(scene, [bpy.data.objects["Ball"]])
    before = (len(bpy.data.objects), len(bpy.data.cameras))
    with bpy.context.temp_override(scene=scene):
        assert bpy.ops.phong.compare_scene(directory=str(tmp_path / "op"),
                                           engines={"CYCLES"}) == {"FINISHED"}
    metrics = json.loads((tmp_path / "op" / "No_camera" / "metrics.json").read_text())
    assert metrics["ok"] and metrics["coverage"]["pixels"] > 0.1 * 768
    assert scene.camera is None and (len(bpy.data.objects), len(bpy.data.cameras)) == before
    be.add_ortho_camera(scene, (0.0, 0.0), 3.0, 3.0)
    camera, scene.camera = scene.camera, None
    with bpy.context.temp_override(scene=scene):
        assert bpy.ops.phong.compare_scene(directory=str(tmp_path / "op2"),
                                           engines={"CYCLES"}) == {"FINISHED"}
    assert scene.camera is None and camera.name in bpy.data.objects


@pytest.mark.slow
@pytest.mark.cycles
@pytest.mark.eevee
def test_compare_names_flat_polygons_that_are_not_planar(bpy_clean, tmp_path, capfd):
    """A flat quad lifted at one corner by 0.3 (its two triangles turn about 6° from its own
    normal) beside a planar one: Compare Phong Scene says, when it compares Eevee, that the
    warped object has 1 flat polygon that is not planar (Eevee shades it with one normal,
    Cycles each triangle with its own), in its reports and the report's notes; shaded smooth
    or compared with Cycles alone, it says nothing of it."""
    bpy = bpy_clean
    scene = be.new_scene("Warped", 32, 24)
    bpy.context.window.scene = scene
    scene.world.phong.ambient_intensity = 0.2
    material = be.plain_source("Card")
    made = []
    for name, x, lift in (("Bent card", -1.1, 0.3), ("Flat card", 1.1, 0.0)):
        mesh = bpy.data.meshes.new(name)
        mesh.from_pydata([(x - 1, -1, 0), (x + 1, -1, 0), (x + 1, 1, lift), (x - 1, 1, 0)], [],
                         [(0, 1, 2, 3)])
        mesh.materials.append(material)
        obj = bpy.data.objects.new(name, mesh)
        scene.collection.objects.link(obj)
        made.append(obj)
    sun = bpy.data.objects.new("Sun", bpy.data.lights.new("Sun", "SUN"))
    scene.collection.objects.link(sun)
    sun.rotation_euler = (0.4, 0.3, 0.0)
    be.add_persp_camera(scene, (0.0, -4.0, 6.0), (0.0, 0.0, 0.0), lens=30.0)
    with bpy.context.temp_override(scene=scene, view_layer=scene.view_layers[0]):
        be.apply_phong(scene, made)

    def compare(folder, engines):
        capfd.readouterr()
        with bpy.context.temp_override(scene=scene):
            assert bpy.ops.phong.compare_scene(directory=str(tmp_path / folder),
                                               engines=engines) == {"FINISHED"}
        said = "".join(capfd.readouterr())
        notes = json.loads((tmp_path / folder / "Warped" / "metrics.json").read_text()).get(
            "notes", [])
        return said, [n for n in notes if "not planar" in n]

    said, notes = compare("both", {"CYCLES", "EEVEE"})
    assert len(notes) == 1 and notes[0].startswith("'Bent card': 1 flat polygon(s) not planar")
    assert "'Warped': 'Bent card': 1 flat polygon(s) not planar" in said
    said, notes = compare("cycles", {"CYCLES"})
    assert not notes and "not planar" not in said
    made[0].data.polygons[0].use_smooth = True
    said, notes = compare("smooth", {"CYCLES", "EEVEE"})
    assert not notes and "not planar" not in said
