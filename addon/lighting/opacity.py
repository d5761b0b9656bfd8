# SPDX-License-Identifier: GPL-3.0-or-later
"""A Phong material's Opacity: its control, its value set and followed, and the Mix Shader of
a Transparent BSDF that blends it in front of each Material Output (docs/contract.md,
"Opacity")."""

from __future__ import annotations

import bpy
from bpy.app.handlers import persistent

from .. import compat
from . import engine_outputs, recipe


def opacity_node(tree, frame=None):
    """The Opacity control of *tree* (created at 1 when missing)."""
    node = tree.nodes.get(recipe.OPACITY)
    if node is not None and node.bl_idname == recipe.OPACITY_CONTROL[0]:
        return node
    if node is not None:
        tree.nodes.remove(node)
    node = tree.nodes.new(recipe.OPACITY_CONTROL[0])
    node.name = recipe.OPACITY
    node.label = recipe.OPACITY_CONTROL[1]
    compat.value_output(node).default_value = recipe.OPACITY_CONTROL[2]
    frame = frame if frame is not None else tree.nodes.get(recipe.FRAME)
    if frame is not None:
        node.parent = frame
    node.location = (-880.0, 260.0 - 190.0 * (len(recipe.CONTROLS) + 1))
    return node


def set_opacity(material, value) -> float:
    """Set the opacity of the Phong material *material* (clamped to [0, 1]) and switch its
    transparency on (below 1) or off (at 1); returns the value set.  The pixel becomes
    opacity × Phong colour + (1 − opacity) × what is behind, in Cycles and Eevee alike
    (docs/contract.md, "Opacity"); the AOVs keep the Phong values."""
    try:
        value = float(value)
    except (TypeError, ValueError):
        raise ValueError(f"opacity must be a number, not {value!r}") from None
    if value != value:
        raise ValueError("opacity must be a number, not NaN")
    value = min(max(value, 0.0), 1.0)
    node = opacity_node(material.node_tree)
    control = compat.value_output(node)
    if float(control.default_value) != value:
        control.default_value = value
    apply_opacity(material)
    return value


def apply_opacity(material) -> None:
    """The nodes and Eevee settings of *material* for the value of its Opacity control:
    below 1 a Mix Shader (Fac = Opacity) of a Transparent BSDF and the lights group's
    Shader feeds the output and Eevee blends (render method Blended); at 1 the lights
    group's Shader feeds the output directly, as in every opaque Phong material.  An opacity
    map (``recipe.OPACITY_MAP``, an imported texture) feeds Fac instead, whatever the value.  The
    EEVEE Material Output of a lights group with the loop part (Blender 5.3+) the same way
    with its Eevee Shader; without the loop part (or in Per Vertex / Per Face shading) it
    is removed."""
    tree = material.node_tree
    lights = tree.nodes.get(recipe.LIGHTS_NODE)
    output = tree.nodes.get(recipe.OUTPUT)
    if lights is None or output is None:
        return
    value = recipe.opacity(material)
    mapped = recipe.opacity_map(tree)
    engine_outputs.term_aovs(tree, lights)
    targets = [(recipe.OPACITY_MIX, engine_outputs.shader(tree, lights), output)]
    eevee_output = engine_outputs.eevee_output(tree, lights)
    # With an EEVEE output the first one is Cycles' only: Eevee's inliner then leaves the
    # lights group out (an output of target ALL it would copy whole, and free again: measured
    # 2x the render time of the loop alone at 1,000 materials, bpy 5.3.0)
    target = "ALL" if eevee_output is None else "CYCLES"
    if output.target != target:
        output.target = target
    if eevee_output is not None:
        targets.append((recipe.OPACITY_MIX_EEVEE, engine_outputs.eevee_shader(tree, lights),
                        eevee_output))
    elif tree.nodes.get(recipe.OPACITY_MIX_EEVEE) is not None:
        tree.nodes.remove(tree.nodes[recipe.OPACITY_MIX_EEVEE])
    if value >= 1.0 and mapped is None:
        for name in (recipe.OPACITY_MIX, recipe.OPACITY_MIX_EEVEE, recipe.OPACITY_TRANSPARENT):
            if tree.nodes.get(name) is not None:
                tree.nodes.remove(tree.nodes[name])
        for _mix, source, target in targets:
            tree.links.new(source, target.inputs["Surface"])
        engine_outputs.render_method(material, "DITHERED")
        return
    transparent = recipe.named_node(tree, recipe.OPACITY_TRANSPARENT, "ShaderNodeBsdfTransparent",
                             (-50.0, 300.0))
    transparent.inputs["Color"].default_value = (1.0, 1.0, 1.0, 1.0)
    fac = mapped if mapped is not None else compat.value_output(tree.nodes[recipe.OPACITY])
    for index, (name, source, target) in enumerate(targets):
        mix = recipe.named_node(tree, name, "ShaderNodeMixShader", (150.0, 200.0 + 200.0 * index))
        mix.label = "Opacity"
        tree.links.new(fac, compat.input_socket(mix, "Fac"))
        tree.links.new(compat.output_socket(transparent, "BSDF"),
                       compat.input_socket(mix, "Shader"))
        tree.links.new(source, compat.input_socket(mix, "Shader_001"))
        tree.links.new(compat.output_socket(mix, "Shader"), target.inputs["Surface"])
    engine_outputs.render_method(material, "BLENDED")


def opacity_in_step(material) -> bool:
    """Whether *material*'s nodes already match the value of its Opacity control (or its
    opacity map)."""
    tree = material.node_tree
    blends = recipe.opacity(material) < 1.0 or recipe.opacity_map(tree) is not None
    return ((tree.nodes.get(recipe.OPACITY_MIX) is not None) == blends
            and (tree.nodes.get(recipe.OPACITY_MIX_EEVEE) is not None)
            == (blends and tree.nodes.get(recipe.OUTPUT_EEVEE) is not None))


@persistent
def follow_opacity(_scene, depsgraph=None) -> None:
    """After an edit of the Opacity control node in the node editor: the materials of the
    active object (the ones the node editor and the panel show) get the nodes of their
    Opacity.  Only those are looked at, so a light move in a file of thousands of Phong
    materials costs nothing here; scripts set ``material.phong.opacity`` or call
    :func:`set_opacity`, and Relink brings every material in line."""
    if depsgraph is None or not (depsgraph.id_type_updated("MATERIAL")
                                 or depsgraph.id_type_updated("NODETREE")):
        return
    layer = getattr(bpy.context, "view_layer", None)
    obj = layer.objects.active if layer is not None else None
    if obj is None or not hasattr(obj, "material_slots"):
        return
    for slot in obj.material_slots:
        material = slot.material
        if (material is not None and material.library is None
                and recipe.is_phong_material(material)
                and not opacity_in_step(material)):
            apply_opacity(material)
