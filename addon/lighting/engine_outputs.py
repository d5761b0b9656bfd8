# SPDX-License-Identifier: GPL-3.0-or-later
"""What each engine's Material Output of a Phong material shows: the lights group's Shader,
its Eevee Shader (Blender 5.3's light loop, ``loop.py``) or its Cycles Shader (shadow rays,
``shadows.py``), and the term AOV outputs where the material shows no loop.  The opacity blend
in front of the outputs is ``opacity.py``'s."""

from __future__ import annotations

from .. import compat
from . import loop as light_loop
from . import recipe, rig, shadows, world_copies


def add_view_layer_aovs(layer, names) -> list:
    """Add the colour AOVs *names* that *layer* lacks; returns the names added.  The layer's
    Alpha Threshold becomes 0: Cycles then writes the passes (AOVs included) of the first
    surface a ray meets, also when its Opacity is below 0.5 (with the default 0.5 they
    would add up the values of the surfaces behind)."""
    if getattr(layer, "pass_alpha_threshold", 0.0) != 0.0:
        layer.pass_alpha_threshold = 0.0
    have = {aov.name for aov in layer.aovs}
    added = [name for name in names if name not in have]
    for name in added:
        aov = layer.aovs.add()
        aov.name = name
        aov.type = "COLOR"
    return added


def term_aovs(tree, lights, relink=False) -> None:
    """The term AOV outputs of a material: none where it shows the loop in Eevee (they would
    make Eevee evaluate the per-light part: ``loop.py``), else each of ``recipe.AOVS``, made
    when missing and linked from the lights group (*relink*: every one of them; Per Vertex /
    Per Face link their own: ``shading/modes.py``)."""
    shows_loop = eevee_shader(tree, lights) is not None
    for index, (aov_name, socket) in enumerate(recipe.AOVS.items()):
        aov = tree.nodes.get(f"phong_aov:{aov_name}")
        if shows_loop:
            if aov is not None:
                tree.nodes.remove(aov)
            continue
        made = aov is None
        if made:
            aov = tree.nodes.new("ShaderNodeOutputAOV")
            aov.name = f"phong_aov:{aov_name}"
            aov.aov_name = aov_name
            aov.label = aov_name
            aov.location = (400.0, -100.0 - 120.0 * index)
        if made or relink:
            tree.links.new(lights.outputs[socket], aov.inputs["Color"])


def eevee_shader(tree, lights):
    """The lights group's Eevee Shader output when the group has the loop part and the
    material shows it, else None.  Not in Per Vertex / Per Face shading, nor for a material
    that blends (Opacity below 1, an opacity map): the loop's sum cannot be clamped at 1
    (loop.py), and a blend of more than 1 is another picture, where an opaque pixel of more
    than 1 shows as 1 (measured: 2.4 % of test_controls' pixels off by up to 0.25)."""
    emission = tree.nodes.get(recipe.SHADING_EMISSION)
    if emission is not None and emission.bl_idname == "ShaderNodeEmission":
        return None
    shadowed = shadows.has_shadows(lights.node_tree)
    if recipe.tree_blends(tree):
        if (light_loop.has_loop(lights.node_tree)
                and world_copies.listed(lights.node_tree, loop=True)):
            scene = rig.owner(lights.node_tree)  # Eevee compiles its group: at most
            if scene is not None:                # compat.VIEW_LAYER_LOOKUPS (sync.py)
                STALE.add(scene.as_pointer())
        return lights.outputs.get("Shader") if shadowed else None
    if light_loop.has_loop(lights.node_tree):
        return lights.outputs.get(light_loop.EEVEE_SHADER)
    # a group with shadow rays: Eevee must not evaluate its Raycast nodes (shadows.py)
    return lights.outputs.get("Shader") if shadowed else None


def eevee_output(tree, lights):
    """The EEVEE Material Output of *tree*, made when the material shows the loop
    (``eevee_shader``), removed (None) when it does not."""
    node = tree.nodes.get(recipe.OUTPUT_EEVEE)
    if eevee_shader(tree, lights) is None:
        if node is not None:
            tree.nodes.remove(node)
        return None
    node = recipe.named_node(tree, recipe.OUTPUT_EEVEE, "ShaderNodeOutputMaterial", (400.0, 300.0))
    node.label = ("Eevee (light loop, Blender 5.3+)" if light_loop.has_loop(lights.node_tree)
                  else "Eevee (no shadows: Cycles casts them)")
    if node.target != "EEVEE":
        node.target = "EEVEE"
    if not node.is_active_output:
        node.is_active_output = True
    return node


def eevee_in_step(material) -> bool:
    """Whether *material* has the EEVEE Material Output, and no term AOV output, exactly when
    it shows its lights group's loop part in Eevee."""
    tree = material.node_tree
    lights = tree.nodes.get(recipe.LIGHTS_NODE)
    if lights is None:
        return True
    aovs = any(tree.nodes.get(f"phong_aov:{name}") is not None for name in recipe.AOVS)
    shows = eevee_shader(tree, lights) is not None
    output = tree.nodes.get(recipe.OUTPUT)
    target = output.target if output is not None else None
    if not ((tree.nodes.get(recipe.OUTPUT_EEVEE) is not None) == shows and aovs != shows
            and target in (None, "CYCLES" if shows else "ALL")):
        return False
    # each output shows what it should (a group that gained or lost its shadow rays or its
    # loop part keeps its outputs' names: Shader, Eevee Shader, Cycles Shader)
    if shows and _source(tree.nodes[recipe.OUTPUT_EEVEE], recipe.OPACITY_MIX_EEVEE) != \
            eevee_shader(tree, lights):
        return False
    return output is None or _source(output, recipe.OPACITY_MIX) in (None, shader(tree, lights))


def _source(output, mix_name):
    """The socket a Material Output shows: what feeds its Surface, or through the opacity
    Mix Shader *mix_name*, what feeds the mix's second shader; None when unlinked or another
    node (Per Vertex / Per Face's emission is ``shader``'s own)."""
    links = output.inputs["Surface"].links
    if not links:
        return None
    socket = links[0].from_socket
    if socket.node.name == mix_name and socket.node.bl_idname == "ShaderNodeMixShader":
        links = compat.input_socket(socket.node, "Shader_001").links
        socket = links[0].from_socket if links else None
    return socket


def shader(tree, lights):
    """The shader the material shows: the lights group's, or in Per Vertex / Per Face
    shading (``shading/modes.py``) the Emission of the stored colour."""
    emission = tree.nodes.get(recipe.SHADING_EMISSION)
    if emission is not None and emission.bl_idname == "ShaderNodeEmission":
        return compat.output_socket(emission, "Emission")
    if shadows.has_shadows(lights.node_tree) and eevee_shader(tree, lights) is not None:
        return lights.outputs[shadows.CYCLES_SHADER]  # the output is Cycles' only
    return lights.outputs["Shader"]


#: Pointers of the scenes whose lights groups a material that began to blend makes Eevee
#: compile with more View Layer lookups than ``compat.VIEW_LAYER_LOOKUPS``: the depsgraph
#: handler relinks them (``sync.on_depsgraph_update``), with that budget.
STALE: set = set()


def render_method(material, method) -> None:
    """Eevee's render method (4.2+): Blended blends exactly, Dithered is the default."""
    if getattr(material, "surface_render_method", method) != method:
        material.surface_render_method = method
