# SPDX-License-Identifier: GPL-3.0-or-later
"""Apply Phong Material on textured materials: the texture chain is copied into a copy of the
Phong template (``addon/lighting/node_copy.py``: no node of the recipe is named again, which
walked the whole file per name), and the picture is the one of the former way (a copy of the
source given the recipe's nodes), pixel for pixel in Cycles."""

from __future__ import annotations

import numpy as np
import pytest

import blender_env as be


def _principled(material):
    return next(n for n in material.node_tree.nodes if n.bl_idname == "ShaderNodeBsdfPrincipled")


def _chains(bpy):
    """Principled materials whose Base Color is fed by chains of various nodes."""
    out = []

    def material(name):
        m = bpy.data.materials.new(name)
        be.compat().new_material_tree(m)
        return m, m.node_tree

    m, t = material("mapped checker")
    coords, mapping = t.nodes.new("ShaderNodeTexCoord"), t.nodes.new("ShaderNodeMapping")
    checker = t.nodes.new("ShaderNodeTexChecker")
    mapping.inputs["Rotation"].default_value = (0.0, 0.0, 0.4)
    mapping.inputs["Scale"].default_value = (1.5, 0.7, 1.0)
    checker.inputs["Scale"].default_value = 7.0
    checker.inputs["Color1"].default_value = (0.9, 0.3, 0.1, 1.0)
    t.links.new(coords.outputs["UV"], mapping.inputs["Vector"])
    t.links.new(mapping.outputs["Vector"], checker.inputs["Vector"])
    t.links.new(checker.outputs["Color"], _principled(m).inputs["Base Color"])
    out.append(m)

    m, t = material("image")
    image = bpy.data.images.new("pattern", 8, 8)
    image.pixels.foreach_set(np.random.default_rng(3).uniform(0, 1, 8 * 8 * 4).astype(np.float32))
    uvmap, tex = t.nodes.new("ShaderNodeUVMap"), t.nodes.new("ShaderNodeTexImage")
    uvmap.uv_map = "UVMap"
    tex.image, tex.interpolation, tex.extension = image, "Closest", "EXTEND"
    t.links.new(uvmap.outputs["UV"], tex.inputs["Vector"])
    t.links.new(tex.outputs["Color"], _principled(m).inputs["Base Color"])
    out.append(m)

    m, t = material("ramp")
    gradient, ramp = t.nodes.new("ShaderNodeTexGradient"), t.nodes.new("ShaderNodeValToRGB")
    ramp.color_ramp.interpolation = "CONSTANT"
    ramp.color_ramp.elements[0].color = (0.1, 0.2, 0.8, 1.0)
    ramp.color_ramp.elements.new(0.4).color = (0.9, 0.8, 0.1, 1.0)
    ramp.color_ramp.elements[-1].position = 0.75
    t.links.new(gradient.outputs["Fac"], ramp.inputs["Fac"])
    t.links.new(ramp.outputs["Color"], _principled(m).inputs["Base Color"])
    out.append(m)

    m, t = material("curves and mix")
    checker, curves = t.nodes.new("ShaderNodeTexChecker"), t.nodes.new("ShaderNodeRGBCurve")
    curves.mapping.curves[3].points[0].location = (0.0, 0.25)
    curves.mapping.curves[3].points.new(0.5, 0.8)
    curves.mapping.update()
    mix = t.nodes.new("ShaderNodeMix")
    mix.data_type, mix.blend_type = "RGBA", "MULTIPLY"
    mix.inputs["Factor"].default_value = 0.7
    mix.inputs["B"].default_value = (0.4, 0.9, 0.6, 1.0)
    t.links.new(checker.outputs["Color"], curves.inputs["Color"])
    t.links.new(curves.outputs["Color"], mix.inputs["A"])
    t.links.new(mix.outputs["Result"], _principled(m).inputs["Base Color"])
    out.append(m)
    return out


def _render(scene, path):
    be.render_exr(scene, path)
    return be.read_multilayer_exr(path)["Combined"][..., :3]


@pytest.mark.cycles
def test_textured_materials_are_copies_of_the_template_with_the_same_picture(bpy_clean,
                                                                            blender_tmp,
                                                                            monkeypatch):
    bpy = bpy_clean
    from phong_nodes.addon.lighting import node_copy, recipe  # noqa: PLC0415
    from phong_nodes.addon.lighting import sources as source_materials
    copied = []
    real = node_copy.copy_upstream
    monkeypatch.setattr(node_copy, "copy_upstream",
                        lambda *args, **kw: copied.append(real(*args, **kw)) or copied[-1])
    scene = be.new_scene("Textured", 96, 24, "cycles")
    bpy.context.window.scene = scene
    be.add_ortho_camera(scene, (4.0, 0.5), 8.0, 2.0)
    sources = _chains(bpy)
    planes = [be.add_uv_plane(scene, s.name, 2.0 * i + 0.1, 0.1, 1.8, s)
              for i, s in enumerate(sources)]
    light = bpy.data.objects.new("Key", bpy.data.lights.new("Key", "POINT"))
    light.location = (4.0, -1.0, 3.0)
    light.data.phong.intensity = 1.0  # its own i0, not its watts'
    scene.collection.objects.link(light)
    scene.world.phong.ambient_intensity = 0.1  # the black World gives no ambient light
    be.apply_phong(scene, planes)
    fast = [p.material_slots[0].material for p in planes]
    assert len(copied) == 4 and None not in copied  # every chain copied into the template
    # the chains were copied, not the sources: no scratch template is left behind
    assert not [m for m in bpy.data.materials if m.name.startswith("Phong template")]
    for phong, source in zip(fast, sources):
        assert source_materials.source_of(phong) is source and phong.name == f"Phong {source.name}"
        assert len(phong.node_tree.nodes) == len(fast[0].node_tree.nodes) - \
            len(node_copy.upstream(source_materials.base_color_link(sources[0]).node)) + \
            len(node_copy.upstream(source_materials.base_color_link(source).node))
    picture = _render(scene, str(blender_tmp / "fast.exr"))
    # the former way: a copy of each source given the recipe's nodes
    group = fast[0].node_tree.nodes[recipe.LIGHTS_NODE].node_tree
    for plane, source in zip(planes, sources):
        plane.material_slots[0].material = source_materials.from_source(source, "former", group)
    former = _render(scene, str(blender_tmp / "former.exr"))
    lit = picture.max(axis=-1) > 0.02
    assert lit.mean() > 0.5
    per_plane = [np.abs(picture - former)[:, 24 * i + 2:24 * i + 22].max() for i in range(4)]
    be.report(f"[textured apply] fast vs former, per chain max |Δ| "
              f"{', '.join(f'{d:.1e}' for d in per_plane)}")
    assert max(per_plane) <= 1e-6, per_plane
    # each plane shows its texture: the four pictures differ from each other
    assert min(np.abs(picture[:, 2:22] - picture[:, 24 * i + 2:24 * i + 22]).max()
               for i in range(1, 4)) > 0.05


def test_a_chain_the_copy_cannot_reproduce_is_left_whole(bpy_clean, monkeypatch):
    """A node with a nested setting the copy does not know (here: a Color Ramp, made
    unknown) is not copied: nothing is left in the target, and Apply takes the former way,
    the source's own nodes kept."""
    bpy = bpy_clean
    from phong_nodes.addon.lighting import node_copy, recipe  # noqa: PLC0415
    from phong_nodes.addon.lighting import sources as source_materials
    ramp_source = _chains(bpy)[2]
    target = bpy.data.materials.new("target")
    be.compat().new_material_tree(target)
    before = len(target.node_tree.nodes)
    link = source_materials.base_color_link(ramp_source)
    assert node_copy.copy_upstream(ramp_source.node_tree, link.node, target.node_tree) is not None
    assert len(target.node_tree.nodes) == before + 2
    monkeypatch.setattr(node_copy, "_NESTED", node_copy._NESTED - {"ColorRamp"})
    assert node_copy.copy_upstream(ramp_source.node_tree, link.node, target.node_tree) is None
    assert len(target.node_tree.nodes) == before + 2
    scene = be.new_scene("Fallback", 8, 8, "cycles")
    bpy.context.window.scene = scene
    plane = be.add_uv_plane(scene, "ramp", 0.0, 0.0, 1.0, ramp_source)
    light = bpy.data.objects.new("Key", bpy.data.lights.new("Key", "POINT"))
    scene.collection.objects.link(light)
    plane.select_set(True)
    bpy.context.view_layer.objects.active = plane
    assert bpy.ops.phong.apply_material() == {"FINISHED"}
    phong = plane.material_slots[0].material
    ramp = next(n for n in phong.node_tree.nodes if n.bl_idname == "ShaderNodeValToRGB")
    assert ramp.name == link.node.name  # the source's node, kept by the copy of the source
    assert [round(e.position, 4) for e in ramp.color_ramp.elements] == [0.0, 0.4, 0.75]
