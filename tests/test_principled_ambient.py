# SPDX-License-Identifier: GPL-3.0-or-later
"""A Principled surface under a uniform World keeps its brightness through Apply: the Phong
ambient colour Ka of a converted Principled material is what Cycles shows of it, its diffuse
base under the specular layer plus that layer (``core/specular_albedo.py``).

The check: spheres under a World of one colour and no light, seen by an orthographic camera,
rendered by Cycles with their Principled materials (many samples), then after Apply.  An
orthographic camera's pixel centres on a sphere sample its view directions cosine-weighted,
the average Ka stands for, so the mean over a sphere's pixels of the Principled picture is
the Phong picture's (World colour × Ka).  The spheres do not see each other (their diffuse,
glossy and shadow ray visibility off): each sees the whole World.  Specular IOR Level 0 and
non-Principled sources keep Ka = Kd (no node)."""

from __future__ import annotations

import numpy as np

import blender_env as be

SIZE = 96
WORLD = (0.6, 0.45, 0.3)
SAMPLES = 256
#: Measured (bpy 5.3.0, 256 samples, 5,860 pixels a sphere): Phong within 0.0-1.0% of Cycles,
#: Phong a little brighter at the dark and the plain-GGX spheres (the tables' interpolation,
#: within 1.3e-3 of Ka, and Cycles' own tabulated albedo estimate that attenuates the base):
#: 1.5% of the colour, + 1e-4 for the noise of a black sphere.
RELATIVE, ABSOLUTE = 0.015, 1e-4
#: the spheres: (name, Roughness, Specular IOR Level, Metallic, distribution, base colour)
SPHERES = [
    ("rough_half_blue", 0.5, 0.5, 0.0, "MULTI_GGX", (0.02, 0.05, 0.3)),
    ("rough_half_grey", 0.5, 0.5, 0.0, "MULTI_GGX", (0.5, 0.5, 0.5)),
    ("rough_one_red", 1.0, 0.5, 0.0, "MULTI_GGX", (0.6, 0.05, 0.02)),
    ("rough_one_black", 1.0, 0.5, 0.0, "MULTI_GGX", (0.0, 0.0, 0.0)),
    ("ggx_half_dark", 0.5, 0.5, 0.0, "GGX", (0.01, 0.02, 0.1)),
    ("level_one", 0.5, 1.0, 0.0, "MULTI_GGX", (0.1, 0.3, 0.1)),
    ("metal_gold", 0.5, 0.5, 1.0, "MULTI_GGX", (0.9, 0.6, 0.2)),
    ("level_zero", 0.5, 0.0, 0.0, "MULTI_GGX", (0.3, 0.2, 0.6)),
]


def _principled(bpy, name, roughness, level, metallic, distribution, color):
    material = bpy.data.materials.new(name)
    be.compat().new_material_tree(material)
    node = material.node_tree.nodes["Principled BSDF"]
    node.distribution = distribution
    node.inputs["Base Color"].default_value = (*color, 1.0)
    node.inputs["Roughness"].default_value = roughness
    node.inputs["IOR"].default_value = 1.5
    node.inputs["Specular IOR Level"].default_value = level
    node.inputs["Metallic"].default_value = metallic
    return material


def _scene(bpy):
    scene = be.new_scene("Ambient", SIZE * 4, SIZE * 2, "cycles")
    bpy.context.window.scene = scene
    background = be.compat().new_material_tree(scene.world).nodes["Background"]  # 4.x: use_nodes
    background.inputs["Color"].default_value = (*WORLD, 1.0)
    background.inputs["Strength"].default_value = 1.0
    scene.cycles.samples = SAMPLES
    be.add_ortho_camera(scene, (0.0, 0.0), 8.0, 4.0)
    spheres = []
    for index, (name, *values) in enumerate(SPHERES):
        x, y = -3.0 + 2.0 * (index % 4), 1.0 - 2.0 * (index // 4)
        sphere = be.add_uv_sphere(scene, name, (x, y, 0.0), 0.9,
                                  _principled(bpy, name, *values), 96, 48)
        sphere.pass_index = index + 1
        for attr in ("visible_diffuse", "visible_glossy", "visible_transmission",
                     "visible_shadow", "visible_volume_scatter"):
            setattr(sphere, attr, False)
        spheres.append(sphere)
    scene.view_layers[0].use_pass_object_index = True
    return scene, spheres


def _render(scene, path):
    be.render_exr(scene, path)
    passes = be.read_multilayer_exr(path)
    name = "Object Index" if "Object Index" in passes else "IndexOB"
    return (passes["Combined"][..., :3].astype(np.float64),
            np.rint(passes[name][..., 0]).astype(int))


def test_principled_ambient_is_what_cycles_shows_under_a_uniform_world(bpy_clean, tmp_path):
    bpy = bpy_clean
    from phong_nodes.addon.lighting import recipe  # noqa: PLC0415  (needs bpy)

    scene, spheres = _scene(bpy)
    before, index = _render(scene, str(tmp_path / "principled.exr"))
    be.apply_phong(scene, spheres)
    after, index_after = _render(scene, str(tmp_path / "phong.exr"))
    assert (index == index_after).all()
    for number, (name, *_values, color) in enumerate(SPHERES, start=1):
        pixels = index == number
        cycles = before[pixels].mean(axis=0)
        phong = after[pixels].mean(axis=0)
        kd = np.array(color) * np.array(WORLD)
        be.report(f"{name}: {int(pixels.sum())} px, Cycles {np.round(cycles, 5).tolist()}, "
                  f"Phong {np.round(phong, 5).tolist()}, Kd×World {np.round(kd, 5).tolist()}, "
                  f"ratio {np.round(phong / np.maximum(cycles, 1e-9), 4).tolist()}")
        assert np.all(np.abs(phong - cycles) <= RELATIVE * cycles + ABSOLUTE), name
        if name not in ("level_zero", "metal_gold"):  # the check can fail: Ka = Kd would
            assert np.any(np.abs(kd - cycles) > 3 * (RELATIVE * cycles + ABSOLUTE)), name
    materials = {s.name: s.material_slots[0].material for s in spheres}
    for name, material in materials.items():
        layer = material.node_tree.nodes.get(recipe.AMBIENT_LAYER)
        lights = material.node_tree.nodes[recipe.LIGHTS_NODE]
        feed = lights.inputs[recipe.AMBIENT_INPUT].links[0].from_socket
        if name == "level_zero":  # no specular layer, no metal: Ka = Kd, no node
            assert layer is None
            assert feed == lights.inputs["Object Color"].links[0].from_socket
        else:
            assert layer is not None and feed.node == layer, name


def test_ambient_stays_object_color_without_a_specular_layer(bpy_clean):
    """A Diffuse BSDF source and a Principled one with Specular IOR Level 0 keep Ka = Kd (the
    Ambient Object Color linked from Object Color's control, no node between); a textured
    Roughness is read at its socket's value and named in one report line."""
    bpy = bpy_clean
    scene = be.new_scene("Plain", 8, 8, "cycles")
    bpy.context.window.scene = scene
    diffuse = bpy.data.materials.new("Matte")
    tree = be.compat().new_material_tree(diffuse)
    tree.nodes.clear()
    bsdf = tree.nodes.new("ShaderNodeBsdfDiffuse")
    output = tree.nodes.new("ShaderNodeOutputMaterial")
    tree.links.new(bsdf.outputs["BSDF"], output.inputs["Surface"])
    flat = _principled(bpy, "Flat", 0.5, 0.0, 0.0, "MULTI_GGX", (0.2, 0.3, 0.4))
    textured = _principled(bpy, "Scratched", 0.5, 0.5, 0.0, "MULTI_GGX", (0.2, 0.3, 0.4))
    noise = textured.node_tree.nodes.new("ShaderNodeTexNoise")
    textured.node_tree.links.new(noise.outputs["Fac"],
                                 textured.node_tree.nodes["Principled BSDF"].inputs["Roughness"])
    objects = []
    for index, material in enumerate((diffuse, flat, textured)):
        obj = be.add_quad(scene, material.name, index, 0, index + 1, 1)
        obj.data.materials.append(material)
        objects.append(obj)
    from phong_nodes.addon.lighting import convert, recipe  # noqa: PLC0415  (needs bpy)

    report = convert.apply(scene, objects)
    for obj in objects[:2]:
        material = obj.material_slots[0].material
        lights = material.node_tree.nodes[recipe.LIGHTS_NODE]
        assert material.node_tree.nodes.get(recipe.AMBIENT_LAYER) is None, obj.name
        assert lights.inputs[recipe.AMBIENT_INPUT].links[0].from_socket == \
            lights.inputs["Object Color"].links[0].from_socket, obj.name
    assert objects[2].material_slots[0].material.node_tree.nodes.get(recipe.AMBIENT_LAYER)
    lines = [line for line in report.notes if line.startswith("Ambient colour")]
    assert len(lines) == 1 and "'Scratched'" in lines[0] and "Roughness" in lines[0], lines


def test_the_ambient_layer_comes_with_the_template_copy(bpy_clean, monkeypatch):
    """Apply makes the ambient layer's node once per light set, not once per material (a node
    named or a link made walks every node tree of the file, as the values' assignment did
    before ``recipe.set_quietly`` wrote them: Apply at 10,000 Principled materials took
    140 s): the other materials are copies that carry it, each with its own scale and
    offset, read back as its own Ka."""
    bpy = bpy_clean
    from phong_nodes.addon.lighting import convert, feeds, recipe  # noqa: PLC0415
    from phong_nodes.addon.lighting import sources as source_materials

    scene = be.new_scene("Layers", 8, 8, "cycles")
    bpy.context.window.scene = scene
    made = []
    real = recipe.named_node
    monkeypatch.setattr(recipe, "named_node", lambda tree, name, *args: (
        made.append(name) if tree.nodes.get(name) is None else None) or real(tree, name, *args))
    # the first material converted (by name) has no layer: the layered ones still share one
    spheres = [("a plain one", 0.5, 0.0, 0.0, "MULTI_GGX", (0.3, 0.2, 0.6)), *SPHERES]
    objects = []
    for index, (name, *values) in enumerate(spheres):
        obj = be.add_quad(scene, name, index, 0, index + 1, 1)
        obj.data.materials.append(_principled(bpy, name, *values[:-1], values[-1]))
        objects.append(obj)
    convert.apply(scene, objects)
    assert made.count(recipe.AMBIENT_LAYER) == 1, made
    for obj, (name, *values) in zip(objects, spheres):
        material = obj.material_slots[0].material
        (scale, offset), _linked = source_materials.ambient_terms(
            source_materials.source_of(material))
        kd = np.array(values[-1])
        ka = feeds.feeds(material)[recipe.AMBIENT_INPUT].value
        assert np.allclose(np.array(ka)[:3], kd * scale + offset, atol=1e-6), name
        assert (material.node_tree.nodes.get(recipe.AMBIENT_LAYER) is None) == \
            (name in ("level_zero", "a plain one")), name
