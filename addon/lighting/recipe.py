# SPDX-License-Identifier: GPL-3.0-or-later
"""What a Phong material is: the names of its nodes, its controls and their defaults, its tag.

A Phong material holds, and nothing else:

* the frame **Phong Controls**: Object Color, Specular Color, Exponent, Blinn, Irradiant
  Color (RGB / Value nodes), the material's own values.  A texture that fed the source
  material's Base Color (the whole chain of nodes before it) is kept and feeds Object Color;
* one node of the scene's lights group (``rig.py``) for the light set of its objects; its
  Ambient Object Color is linked from whatever feeds Object Color (the seeds' model), unless
  the material links its own (an MTL ``Ka``) or was converted from a Principled BSDF whose
  specular layer reflects the World (one Vector Math node, ``AMBIENT_LAYER``, between them);
* the control Opacity (in the frame): at 1 it feeds nothing; below 1 (``opacity.py``) a Mix
  Shader of a Transparent BSDF and the group's Shader feeds the output, and Eevee blends;
* the Material Output (the group's Shader: an emission of the model's colour) and AOV
  outputs "Phong Color", "Phong Irradiant", "Phong Ambient", "Phong Diffuse",
  "Phong Specular" (add them to the view layer with ``phong.add_term_passes``);
* on Blender 5.3+, when the lights group has the loop part (``loop.py``: no term pass on the
  scene's view layers), a second Material Output of target EEVEE showing the group's Eevee
  Shader (Eevee's light loop) instead of the AOV outputs, which would make Eevee evaluate
  the per-light part; the first one is then what Cycles shows;
* on Blender 5.1+, when the lights group casts shadow rays (``shadows.py``: no term pass on
  the scene's view layers), likewise: the first Material Output (target CYCLES) shows the
  group's Cycles Shader (with shadows) and the EEVEE one its Eevee Shader (the loop) or, where
  the group has no loop part or the material blends, its Shader (no Raycast node: no
  shadows), and the material has no term AOV output (``engine_outputs.py``).

This module names those nodes and reads the material's state; ``writer.py`` is the one writer
of a Phong material (every importer and the demos hand it values), ``feeds.py`` the one reader
(every exporter), ``sources.py`` the link to the material it was made from.
"""

from __future__ import annotations

import bpy

from .. import compat
from . import rig


#: Custom property that marks a Phong material; its value is the layout version (1: the
#: layout of version 0.1, every light's nodes and drivers in the material).
MATERIAL_TAG = "phong_nodes_material"
LAYOUT = 5  # 5: the source material named (sources.py), not pointed at
#: AOV outputs of every Phong material: AOV name -> output of the lights group.
AOVS = {"Phong Color": "Color", "Phong Irradiant": "Irradiant", "Phong Ambient": "Ambient",
        "Phong Diffuse": "Diffuse", "Phong Specular": "Specular"}
AOV_NAME = "Phong Color"

FRAME = "phong_controls"
OUTPUT = "phong_output"
#: The Material Output of target EEVEE (Blender 5.3+, a lights group with the loop part).
OUTPUT_EEVEE = "phong_output_eevee"
LIGHTS_NODE = "phong_lights"
#: control node name -> (node type, label, default, input of the lights group)
CONTROLS = {
    "phong_object_color": ("ShaderNodeRGB", "Object Color", (0.8, 0.8, 0.8, 1.0), "Object Color"),
    "phong_specular_color": ("ShaderNodeRGB", "Specular Color", (1.0, 1.0, 1.0, 1.0),
                             "Specular Color"),
    "phong_exponent": ("ShaderNodeValue", "Exponent", 30.0, "Exponent"),
    "phong_blinn": ("ShaderNodeValue", "Blinn", 0.0, "Blinn"),
    "phong_irradiant_color": ("ShaderNodeRGB", "Irradiant Color", (0.0, 0.0, 0.0, 1.0),
                              "Irradiant Color"),
    # three.js's specularStrength: 1 MeshPhongMaterial, 0 MeshLambertMaterial (layout 4);
    # the seeds' model does not read it
    "phong_specular_strength": ("ShaderNodeValue", "Specular Strength (three.js)", 1.0,
                                "Specular Strength"),
}
#: The Opacity control: not an input of the lights group (opacity is applied in the
#: material, after the Phong colour): (node type, label, default).  At 1 (every material
#: made before it) the node is unlinked and the material is exactly the opaque recipe; below
#: 1 ``opacity.set_opacity`` puts a Mix Shader of a Transparent BSDF and the lights group's Shader
#: before the Material Output (docs/contract.md, "Opacity").
OPACITY = "phong_opacity"
OPACITY_CONTROL = ("ShaderNodeValue", "Opacity", 1.0)
OPACITY_MIX = "phong_opacity_mix"
OPACITY_MIX_EEVEE = "phong_opacity_mix_eevee"
#: The Emission node of Per Vertex / Per Face shading (``shading/modes.py``).
SHADING_EMISSION = "phong_shading_emission"
OPACITY_TRANSPARENT = "phong_opacity_transparent"
#: An opacity map: the Math node that ends an importer's chain of an opacity texture
#: (COLLADA ``<transparent><texture>``, FBX TransparentColor / TransparencyFactor maps).  Its
#: Value output feeds the Mix Shader's Fac in place of the Opacity control, and the material
#: blends whatever the control's value (the value the file states, kept for export).
OPACITY_MAP = "phong_opacity_map"
#: A material converted from a Principled BSDF whose specular layer reflects the World: the
#: Vector Math Multiply Add between what feeds Object Color and the Ambient Object Color,
#: Ka = Kd × scale + offset (``core/specular_albedo.py``; ``writer.ambient_layer``).
AMBIENT_LAYER = "phong_ambient_layer"
#: The nodes of the recipe itself (controls, lights group, output, opacity): what an importer
#: that strips the nodes it replaced must keep.
RECIPE_NODES = frozenset(CONTROLS) | {LIGHTS_NODE, OUTPUT, OPACITY, OPACITY_MIX,
                                      OPACITY_TRANSPARENT, OUTPUT_EEVEE, OPACITY_MIX_EEVEE,
                                      AMBIENT_LAYER}
#: Input of the lights group for the colour the ambient light sees (MTL's Ka).  Linked from
#: whatever feeds Object Color unless the material has its own (layout 3).
AMBIENT_INPUT = "Ambient Object Color"
#: The control node of a material's own Ambient Object Color (made on demand).
AMBIENT_CONTROL = "phong_ambient_color"
#: Label of a material's own Ambient Object Color control (AMBIENT_CONTROL), as importers make it.
AMBIENT_LABEL = "Ambient Color (Ka)"
#: lights-group input -> the control that feeds it: the names the writer and the reader share
#: (a caller names the input, never the control node).
FEED_CONTROLS = {target: name for name, (_k, _l, _d, target) in CONTROLS.items()}
FEED_CONTROLS[AMBIENT_INPUT] = AMBIENT_CONTROL


def default(target):
    """The default value of the control that feeds the lights-group input *target*."""
    return CONTROLS[FEED_CONTROLS[target]][2]


def is_phong_material(material) -> bool:
    return material is not None and bool(material.get(MATERIAL_TAG)) and material.node_tree is not None


def phong_materials():
    return [m for m in bpy.data.materials if is_phong_material(m) and m.library is None]


def lights_key(material):
    """(scene pointer, light set key) of the lights group *material* uses, or None."""
    node = material.node_tree.nodes.get(LIGHTS_NODE) if material.node_tree else None
    tree = node.node_tree if node is not None else None
    scene = rig.owner(tree) if tree is not None else None
    if scene is None or tree.get(rig.SET_KEY) is None:
        return None
    return (scene.as_pointer(), tree.get(rig.SET_KEY))


def lights_scene(material):
    """The pointer of the scene whose lights group the Phong *material* uses; None for
    another material or one whose group belongs to no scene."""
    key = lights_key(material) if is_phong_material(material) else None
    return key[0] if key is not None else None


def blinn_constant(material):
    """*material*'s Blinn where it is a constant, else None: the lights node's Blinn input
    fed by the Blinn control (or by nothing), whose value no keyframe or driver changes; a
    Blinn from any other node, or animated, may take any value (``rig.highlight_for``)."""
    tree = material.node_tree
    node = tree.nodes.get(LIGHTS_NODE) if tree is not None else None
    socket = node.inputs.get("Blinn") if node is not None else None
    if socket is None:
        return None
    if socket.is_linked:
        source = socket.links[0].from_node
        if source.name != FEED_CONTROLS["Blinn"] or source.bl_idname != CONTROLS[
                source.name][0] or source.mute:
            return None
        socket, path = compat.value_output(source), f'nodes["{source.name}"]'
    else:
        path = f'nodes["{LIGHTS_NODE}"].inputs'
    animated = compat.animated_paths(tree)
    if animated is None or any(p.startswith(path) for p in animated):
        return None
    return float(socket.default_value)


def set_quietly(socket, value) -> None:
    """``socket.default_value = value`` without Blender's per-assignment update, which
    walks every node tree of the file (Apply on 3,000 materials: 1.7 ms per value, growing
    with the file); the tree is tagged once instead.  An output of a node of one output (an
    RGB or Value node) or a vector or colour input; any other socket is assigned."""
    outputs = socket.node.outputs
    if socket.is_output and len(outputs) == 1:
        outputs.foreach_set("default_value", [float(v) for v in value])
    elif hasattr(socket.default_value, "foreach_set"):  # a vector or colour input
        socket.default_value.foreach_set([float(v) for v in value])
    else:
        socket.default_value = value
    socket.id_data.update_tag()


def named_node(tree, name, bl_idname, location):
    """The node *name* of *tree*, of type *bl_idname*: the one there, else a new one at
    *location* (a node of another type under that name is replaced)."""
    node = tree.nodes.get(name)
    if node is None or node.bl_idname != bl_idname:
        if node is not None:
            tree.nodes.remove(node)
        node = tree.nodes.new(bl_idname)
        node.name = name
        node.location = location
    return node


def opacity(material) -> float:
    """The opacity of a Phong material (1 when it has no Opacity control)."""
    node = material.node_tree.nodes.get(OPACITY) if material.node_tree else None
    if node is None or node.bl_idname != OPACITY_CONTROL[0]:
        return 1.0
    return float(compat.value_output(node).default_value)


def tree_blends(tree) -> bool:
    node = tree.nodes.get(OPACITY)
    return opacity_map(tree) is not None or (
        node is not None and node.bl_idname == OPACITY_CONTROL[0]
        and float(compat.value_output(node).default_value) < 1.0)


def blends(material) -> bool:
    """Whether *material* blends with what is behind it (Opacity below 1, an opacity map)."""
    return material.node_tree is not None and tree_blends(material.node_tree)


def read_nodes(materials, kinds):
    """(node, material name) for each node of a type in *kinds* (bl_idnames) that
    *materials* read: in their trees and the node groups those use, not muted, an output
    linked."""
    seen = set()
    trees = [(m.node_tree, m.name) for m in materials if m is not None and m.node_tree]
    while trees:
        tree, owner = trees.pop(0)
        if tree.as_pointer() in seen:
            continue
        seen.add(tree.as_pointer())
        for node in tree.nodes:
            if node.bl_idname == "ShaderNodeGroup" and node.node_tree is not None:
                trees.append((node.node_tree, owner))
            if node.bl_idname in kinds and not node.mute \
                    and any(out.is_linked for out in node.outputs):
                yield node, owner


def missing_images(materials) -> list:
    """The images *materials* read (``read_nodes``' Image Texture nodes) that are not there,
    each worded once: "'name' (its path)" for an image of source File that is not packed and
    has no file at its path (relative to its library's file where it comes from one), "no
    image in 'node' of 'material'" for a node without one.  Blender's engines differ there:
    Cycles shows a missing image magenta, Eevee black."""
    import os  # noqa: PLC0415

    found = {}
    for node, owner in read_nodes(materials, ("ShaderNodeTexImage",)):
        image = node.image
        if image is None:
            found.setdefault(f"no image in {node.name!r} of {owner!r}", None)
            continue
        if image.source != "FILE" or image.packed_file is not None:
            continue
        path = bpy.path.abspath(image.filepath, library=image.library) if image.filepath \
            else ""
        if not path or not os.path.isfile(path):
            found.setdefault(f"{image.name!r} ({image.filepath or 'no path'})", None)
    return list(found)


def unnamed_attributes(materials) -> list:
    """"'node' of 'material'" for each Attribute node of type Geometry with no name that
    *materials* read (``read_nodes``): Cycles reads nothing there (0), Eevee the mesh's
    active colour attribute (glTF-Blender-IO's 24_vertex_color_and_factor.blend, bpy 5.3.0)."""
    return [f"{node.name!r} of {owner!r}"
            for node, owner in read_nodes(materials, ("ShaderNodeAttribute",))
            if node.attribute_type == "GEOMETRY" and not node.attribute_name.strip()]


def opacity_map(tree):
    """The Value output of the opacity map of *tree* (``OPACITY_MAP``), or None."""
    node = tree.nodes.get(OPACITY_MAP)
    if node is None or node.bl_idname != "ShaderNodeMath":
        return None
    return compat.output_socket(node, "Value")
