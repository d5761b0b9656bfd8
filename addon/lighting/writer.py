# SPDX-License-Identifier: GPL-3.0-or-later
"""The one writer of a Phong material: its nodes made around a lights group, and the values
(and texture chains) that importers and the demos hand it.  Only here are the recipe's control
nodes named (``recipe.CONTROLS``); a caller names the lights group's inputs ("Object Color",
"Exponent", ...), the contract's own names.  ``feeds.py`` reads back what this writes."""

from __future__ import annotations

from dataclasses import dataclass, field

import bpy

from .. import compat, loader
from . import engine_outputs, opacity, recipe


def control_nodes(tree, base=None) -> dict:
    """The recipe's control nodes of *tree* in the Phong Controls frame ({name: node}), each
    made at its default where missing (Object Color at *base* when given)."""
    frame = tree.nodes.get(recipe.FRAME)
    if frame is None:
        frame = tree.nodes.new("NodeFrame")
        frame.name = recipe.FRAME
        frame.label = "Phong Controls"
        frame.location = (-900.0, 300.0)
    nodes = {}
    for index, (name, (kind, label, default, target)) in enumerate(
            recipe.CONTROLS.items()):
        before = tree.nodes.get(name)
        node = recipe.named_node(tree, name, kind, (-880.0, 260.0 - 190.0 * index))
        if node != before:  # made now: its label, first value and frame
            node.label = label
            value = default
            if target == "Object Color" and base is not None:
                value = (*tuple(base)[:3], 1.0)
            compat.value_output(node).default_value = value
            node.parent = frame
            node.location = (-880.0, 260.0 - 190.0 * index)
        nodes[name] = node
    nodes[recipe.OPACITY] = opacity.opacity_node(tree, frame)
    return nodes


def color_control(tree, name, color, label=None):
    """The colour control *name* of the recipe (an RGB node of ``recipe.CONTROLS``, or the
    material's own ``recipe.AMBIENT_CONTROL``, made on demand, labelled *label* or
    ``recipe.AMBIENT_LABEL``) set to *color*."""
    if label is None:
        label = recipe.CONTROLS[name][1] if name in recipe.CONTROLS else recipe.AMBIENT_LABEL
    return control_node(tree, name, label, color)


def control_node(tree, name, label, color):
    """The RGB control node *name* of *tree* in the Phong Controls frame, created when
    missing, with the colour *color*."""
    before = tree.nodes.get(name)
    node = recipe.named_node(tree, name, "ShaderNodeRGB",
                             (-880.0, 260.0 - 190.0 * len(recipe.CONTROLS)))
    frame = tree.nodes.get(recipe.FRAME)
    if node != before and frame is not None:  # a new control goes into the frame
        node.parent = frame
    node.label = label
    recipe.set_quietly(compat.value_output(node), (*tuple(color)[:3], 1.0))
    return node


def _output(tree):
    node = recipe.named_node(tree, recipe.OUTPUT, "ShaderNodeOutputMaterial", (400.0, 100.0))
    for other in tree.nodes:
        if other.bl_idname == "ShaderNodeOutputMaterial" and other.name != recipe.OUTPUT_EEVEE:
            other.is_active_output = other is node
    node.target = "ALL"
    return node


def wire(material, lights_group, object_color=None) -> None:
    """Give *material* the recipe's nodes around *lights_group*; the controls keep their
    values.  *object_color*: an output socket (a texture) to feed Object Color instead of
    the control."""
    tree = material.node_tree
    controls = control_nodes(tree)
    node = tree.nodes.get(recipe.LIGHTS_NODE)
    if node is None:
        node = tree.nodes.new("ShaderNodeGroup")
        node.name = recipe.LIGHTS_NODE
        node.location = (-300.0, 100.0)
        node.width = 220.0
    loader.set_group(node, lights_group)  # links kept by name
    node.label = "Phong Lights"
    for control, (_kind, _label, _default, target) in recipe.CONTROLS.items():
        if not node.inputs[target].is_linked:
            tree.links.new(compat.value_output(controls[control]), node.inputs[target])
    if object_color is not None:
        tree.links.new(object_color, node.inputs["Object Color"])
    ambient = node.inputs[recipe.AMBIENT_INPUT]
    if not ambient.is_linked:  # the seeds' model: the ambient light sees the Object Color
        tree.links.new(node.inputs["Object Color"].links[0].from_socket, ambient)
    tree.links.new(node.outputs["Shader"], _output(tree).inputs["Surface"])
    engine_outputs.term_aovs(tree, node, relink=True)
    opacity.apply_opacity(material)
    # the emission that shows the Phong colour is no light for Cycles: the Principled
    # surfaces around a Phong object are lit as they were
    cycles = getattr(material, "cycles", None)
    if getattr(cycles, "emission_sampling", "NONE") != "NONE":
        cycles.emission_sampling = "NONE"
    material[recipe.MATERIAL_TAG] = recipe.LAYOUT


def ambient_is_kd(scale, offset) -> bool:
    """Whether Ka = Kd × *scale* + *offset* is Kd itself (no ambient layer node)."""
    return all(abs(v - 1.0) < 1e-7 for v in scale) and all(abs(v) < 1e-7 for v in offset)


def ambient_layer(material, scale, offset) -> None:
    """Feed the Ambient Object Color of *material* with what feeds its Object Color (Kd)
    × *scale* + *offset* (3 floats each): one Vector Math Multiply Add
    (``recipe.AMBIENT_LAYER``), which follows a texture on Object Color.  Scale 1 and offset
    0 (no specular layer to speak of): no node, Ka is whatever feeds Object Color (the seeds'
    model).  A material with its own Ambient Object Color control is left as it is.  On a
    copy of a material that has the node, linked as here (``sync.Sync.convert``'s templates:
    a node named or a link made walks every node tree of the file), only the values change."""
    tree = material.node_tree
    lights = tree.nodes[recipe.LIGHTS_NODE]
    ambient = lights.inputs[recipe.AMBIENT_INPUT]
    if ambient.is_linked and ambient.links[0].from_node.name == recipe.AMBIENT_CONTROL:
        return
    colour = lights.inputs["Object Color"]
    feed = colour.links[0].from_socket if colour.is_linked else None
    node = tree.nodes.get(recipe.AMBIENT_LAYER)
    if ambient_is_kd(scale, offset):
        if node is not None:
            tree.nodes.remove(node)
        if feed is not None:
            tree.links.new(feed, ambient)
        return
    node = recipe.named_node(tree, recipe.AMBIENT_LAYER, "ShaderNodeVectorMath",
                             (-600.0, -260.0))
    if node.operation != "MULTIPLY_ADD":
        node.operation = "MULTIPLY_ADD"
        node.label = "Ambient: Kd × scale + offset"
    for key, value in (("Vector_001", scale), ("Vector_002", offset)):
        socket = compat.input_socket(node, key)
        if tuple(socket.default_value) != tuple(value):
            recipe.set_quietly(socket, value)
    vector = compat.input_socket(node, "Vector")
    if feed is not None and not (vector.is_linked and vector.links[0].from_socket == feed):
        tree.links.new(feed, vector)
    output = compat.output_socket(node, "Vector")
    if not (ambient.is_linked and ambient.links[0].from_socket == output):
        tree.links.new(output, ambient)


def new_material(name, lights_group, base=None):
    """A new Phong material around *lights_group* with the Object Color *base*."""
    material = bpy.data.materials.new(name)
    tree = compat.new_material_tree(material)
    tree.nodes.clear()
    control_nodes(tree, base)
    wire(material, lights_group)
    return material


# -- values and texture chains: what importers and the demos hand the writer -------------------

#: The lights-group inputs a colour control feeds (their controls are RGB nodes).
COLOR_INPUTS = tuple(target for target, control in recipe.FEED_CONTROLS.items()
                     if control not in recipe.CONTROLS or recipe.CONTROLS[control][0] ==
                     "ShaderNodeRGB")
#: lights-group input of each scalar control -> its field in :class:`Values`.
SCALARS = {"Exponent": "exponent", "Blinn": "blinn", "Specular Strength": "specular_strength"}
#: Node names of a colour × map chain (+ the lights-group input it feeds): the Image Texture
#: and the Vector Math Multiply of the control's colour by it.  The OBJ / MTL importer named
#: them first; the names stay, so that files saved since read the same.
MAP_NODE = "phong_mtl_map:"
TIMES_NODE = "phong_mtl_mul:"


@dataclass
class Values:
    """A Phong material as plain values, what a file or a scene file states.

    *colors*: {lights-group input: RGB} for "Object Color", "Specular Color", "Irradiant
    Color" and "Ambient Object Color" (the material's own ambient colour, MTL's Ka; left out,
    the ambient light sees whatever feeds Object Color), written in their order; *exponent*,
    *blinn*, *specular_strength* (three.js's specularStrength), *opacity*: None leaves the
    control as it is; *maps*: {lights-group input: Blender image (loaded in its colour space
    by the importer)}: the colour × the map feeds the input (:func:`colour_times_map`, in
    the row of the input among *colors*)."""

    colors: dict = field(default_factory=dict)
    exponent: float | None = None
    blinn: float | None = None
    specular_strength: float | None = None
    opacity: float | None = None
    maps: dict = field(default_factory=dict)


def write(material, values: Values, link=True, ambient_label=None) -> dict:
    """Give the Phong material *material* (``new_material``, ``sources.from_source``) the
    *values*; returns {lights-group input: the output socket of its control} for each colour
    written, for the caller's chains (a texture × the colour).  *link*: each colour's control
    feeds its input (what fed it before no longer does); False leaves the links as they are
    (a copy whose Object Color a texture feeds).  *ambient_label*: the label of a new
    Ambient Object Color control (``recipe.AMBIENT_LABEL`` when None).  A colour or map of
    another input is refused (ValueError), before anything is written."""
    unknown = sorted((set(values.colors) | set(values.maps)) - set(COLOR_INPUTS))
    if unknown:
        raise ValueError(f"not a colour input of a Phong material: {', '.join(unknown)} "
                         f"(the colour inputs: {', '.join(COLOR_INPUTS)})")
    tree = material.node_tree
    lights = tree.nodes[recipe.LIGHTS_NODE]
    sockets = {}
    for target, colour in values.colors.items():
        node = color_control(tree, recipe.FEED_CONTROLS[target], colour,
                             ambient_label if target == recipe.AMBIENT_INPUT else None)
        sockets[target] = compat.value_output(node)
        if link:
            tree.links.new(sockets[target], lights.inputs[target])
    for target, name in SCALARS.items():
        value = getattr(values, name)
        if value is not None:
            recipe.set_quietly(control_output(material, target), [float(value)])
    rows = list(values.colors)
    for target, image in values.maps.items():
        colour_times_map(material, target, image,
                         rows.index(target) if target in rows else len(rows))
    if values.opacity is not None:
        opacity.set_opacity(material, values.opacity)
    return sockets


def control_output(material, target):
    """The output socket of the control that feeds the lights-group input *target* of
    *material* ("Object Color", "Exponent", ...; "Ambient Object Color" once written)."""
    return compat.value_output(material.node_tree.nodes[recipe.FEED_CONTROLS[target]])


def controlled(material, target) -> bool:
    """Whether the lights-group input *target* of *material* is fed by its own control (not
    a texture, not a chain)."""
    socket = material.node_tree.nodes[recipe.LIGHTS_NODE].inputs[target]
    control = material.node_tree.nodes.get(recipe.FEED_CONTROLS[target])
    return socket.is_linked and control is not None and \
        socket.links[0].from_node.name == control.name


def colour_times_map(material, target, image, index):
    """Feed the lights-group input *target* with its control's colour × *image* (an Image
    Texture, ``MAP_NODE`` + *target*, labelled "<target> map", in row *index* of the layout)
    by a Vector Math Multiply (``TIMES_NODE`` + *target*): the chain ``feeds.py`` reads back
    as the colour and its texture.  Returns the Image Texture node (its Vector input is the
    caller's: UV map, placement)."""
    tree = material.node_tree
    texture = tree.nodes.get(MAP_NODE + target) or tree.nodes.new("ShaderNodeTexImage")
    texture.name = MAP_NODE + target
    texture.label = f"{target} map"
    texture.image = image
    texture.location = (-1150.0, 200.0 - 300.0 * index)
    multiply = tree.nodes.get(TIMES_NODE + target) or tree.nodes.new("ShaderNodeVectorMath")
    multiply.name = TIMES_NODE + target
    multiply.operation = "MULTIPLY"
    multiply.location = (-600.0, 200.0 - 300.0 * index)
    tree.links.new(control_output(material, target), compat.input_socket(multiply, "Vector"))
    tree.links.new(texture.outputs["Color"], compat.input_socket(multiply, "Vector_001"))
    tree.links.new(multiply.outputs["Vector"],
                   tree.nodes[recipe.LIGHTS_NODE].inputs[target])
    return texture
