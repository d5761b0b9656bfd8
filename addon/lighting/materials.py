# SPDX-License-Identifier: GPL-3.0-or-later
"""The one Phong material recipe, and converting the user's materials to it.

A Phong material holds, and nothing else:

* the frame **Phong Controls**: Object Color, Specular Color, Exponent, Blinn, Irradiant
  Color (RGB / Value nodes), the material's own values.  A texture that fed the source
  material's Base Color (the whole chain of nodes before it) is kept and feeds Object Color;
* one node of the scene's lights group (``rig.py``) for the light set of its objects; its
  Ambient Object Color is linked from whatever feeds Object Color (the seeds' model), unless
  the material links its own (an MTL ``Ka``);
* the control Opacity (``phong_opacity``, in the frame): at 1 it feeds nothing; below 1
  (``set_opacity``) a Mix Shader of a Transparent BSDF and the group's Shader feeds the
  output, and Eevee blends;
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
  shadows), and the material has no term AOV output.

Materials are converted, not objects: one Phong material per distinct source material
(and light set), so objects that shared a material share its Phong version.  The source
material is kept with a fake user (so it is not purged on save) and named by its Phong
version: ``material["phong_source"]`` its name, ``material["phong_source_key"]`` a token the
source carries too (``source["phong_source_key"]``: the source is found again after a rename);
``restore`` puts it back.  Not an ID pointer: the depsgraph follows those, and each Phong
material would bring its source material and node tree into every update (layout 4
and earlier held a pointer, ``upgrade`` turns it into the name and token).
"""

from __future__ import annotations

import uuid

import bpy
from bpy.app.handlers import persistent

from .. import compat
from . import drivers, node_copy, rig, world_copies
from . import loop as light_loop
from . import shadows

#: Custom property that marks a Phong material; its value is the layout version (1: the
#: layout of version 0.1, every light's nodes and drivers in the material).
MATERIAL_TAG = "phong_nodes_material"
LAYOUT = 5  # 5: the source material named (SOURCE_KEY, SOURCE_TOKEN), not pointed at
SOURCE_KEY = "phong_source"
SOURCE_TOKEN = "phong_source_key"
#: Marks a Phong material made for a slot that had no material.
EMPTY_SOURCE_KEY = "phong_source_empty"
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
#: 1 ``set_opacity`` puts a Mix Shader of a Transparent BSDF and the lights group's Shader
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
#: The nodes of the recipe itself (controls, lights group, output, opacity): what an importer
#: that strips the nodes it replaced must keep.
RECIPE_NODES = frozenset(CONTROLS) | {LIGHTS_NODE, OUTPUT, OPACITY, OPACITY_MIX,
                                      OPACITY_TRANSPARENT, OUTPUT_EEVEE, OPACITY_MIX_EEVEE}
OLD_GENERATED = "phong_gen:"  # prefix of the per-light nodes of layout 1
#: Input of the lights group for the colour the ambient light sees (MTL's Ka).  Linked from
#: whatever feeds Object Color unless the material has its own (layout 3).
AMBIENT_INPUT = "Ambient Object Color"
#: The control node of a material's own Ambient Object Color (made on demand).
AMBIENT_CONTROL = "phong_ambient_color"


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


def is_phong_material(material) -> bool:
    return material is not None and bool(material.get(MATERIAL_TAG)) and material.node_tree is not None


def phong_materials():
    return [m for m in bpy.data.materials if is_phong_material(m) and m.library is None]


def source_of(material, names=None):
    """The material a Phong material was made from (None if unknown or made for no material):
    the material named ``material["phong_source"]`` carrying its token, else the one carrying
    the token under another name (renamed since), else an ID pointer of layout 4 and before.
    *names*: a dict name -> material of ``bpy.data.materials`` (callers that ask for many)."""
    source = material.get(SOURCE_KEY)
    if isinstance(source, bpy.types.Material):
        return source
    token = material.get(SOURCE_TOKEN)
    if not isinstance(token, str) or not token:
        return None
    if not isinstance(source, str):
        named = None
    elif names is not None:
        named = names.get(source)
    else:
        named = bpy.data.materials.get(source)
    if named is not None and named.get(SOURCE_TOKEN) == token and named is not material:
        return named
    return next((m for m in bpy.data.materials if m.get(SOURCE_TOKEN) == token
                 and m is not material and not is_phong_material(m)), None)


def keep_source(material, source) -> None:
    """Name *source* as the source of the Phong *material* and keep it (a fake user)."""
    token = source.get(SOURCE_TOKEN)
    if not isinstance(token, str) or not token:
        token = uuid.uuid4().hex
        source[SOURCE_TOKEN] = token
    if not source.use_fake_user and source.library is None:
        source.use_fake_user = True
    material[SOURCE_KEY] = source.name
    material[SOURCE_TOKEN] = token


def lights_key(material):
    """(scene pointer, light set key) of the lights group *material* uses, or None."""
    node = material.node_tree.nodes.get(LIGHTS_NODE) if material.node_tree else None
    tree = node.node_tree if node is not None else None
    scene = rig.owner(tree) if tree is not None else None
    if scene is None or tree.get(rig.SET_KEY) is None:
        return None
    return (scene.as_pointer(), tree.get(rig.SET_KEY))


# -- what a source material looks like ------------------------------------------------

def _principled(material):
    tree = material.node_tree if material is not None and compat.uses_nodes(material) else None
    if tree is None:
        return None
    output = next((n for n in tree.nodes if n.bl_idname == "ShaderNodeOutputMaterial"
                   and n.is_active_output), None)
    if output is not None and output.inputs["Surface"].is_linked:
        node = output.inputs["Surface"].links[0].from_node
        if node.bl_idname == "ShaderNodeBsdfPrincipled":
            return node
    return next((n for n in tree.nodes if n.bl_idname == "ShaderNodeBsdfPrincipled"), None)


def base_color(material):
    """The base colour of a material (Principled BSDF's, else its viewport colour), or None."""
    if material is None:
        return None
    node = _principled(material)
    if node is not None:
        return tuple(node.inputs["Base Color"].default_value)
    return tuple(material.diffuse_color)


def _unlinked(node, name, default):
    """The value of *node*'s input *name* where nothing feeds it, else *default*."""
    socket = node.inputs.get(name)
    if socket is None or socket.is_linked:
        return default
    return socket.default_value


def source_controls(material) -> dict:
    """{control: value} that a source material gives its Phong version besides the Object
    Color: a Principled BSDF's highlight as the Specular Color (white × 2·Specular IOR
    Level, at most 1, × its Specular Tint: 0 gives a diffuse Phong material, Blender's
    default 0.5 white) and its emission as the Irradiant Color (Emission Color × Strength);
    the defaults for any other material."""
    specular = CONTROLS["phong_specular_color"][2]
    irradiant = CONTROLS["phong_irradiant_color"][2]
    node = _principled(material) if material is not None else None
    if node is not None:
        level = min(1.0, 2.0 * float(_unlinked(node, "Specular IOR Level", 0.5)))
        tint = _unlinked(node, "Specular Tint", (1.0, 1.0, 1.0, 1.0))
        tint = tuple(tint)[:3] if hasattr(tint, "__len__") else (1.0, 1.0, 1.0)
        specular = (*(level * float(t) for t in tint), 1.0)
        strength = float(_unlinked(node, "Emission Strength", 0.0))
        color = tuple(_unlinked(node, "Emission Color", (0.0, 0.0, 0.0, 1.0)))[:3]
        irradiant = (*(max(0.0, strength * float(c)) for c in color), 1.0)
    return {"phong_specular_color": specular, "phong_irradiant_color": irradiant}


def base_color_link(material):
    """The output socket that feeds the Principled Base Color (a texture), or None."""
    node = _principled(material)
    socket = node.inputs.get("Base Color") if node is not None else None
    if socket is not None and socket.is_linked and not socket.links[0].is_muted:
        return socket.links[0].from_socket
    return None


# -- the recipe ------------------------------------------------------------------------

def set_quietly(socket, value) -> None:
    """``socket.default_value = value`` without Blender's per-assignment update, which
    walks every node tree of the file (Apply on 3,000 materials: 1.7 ms per value, growing
    with the file); the tree is tagged once instead."""
    outputs = socket.node.outputs
    if socket.is_output and len(outputs) == 1:
        outputs.foreach_set("default_value", [float(v) for v in value])
    else:
        socket.default_value = value
    socket.id_data.update_tag()


def _controls(tree, base=None) -> dict:
    frame = tree.nodes.get(FRAME)
    if frame is None:
        frame = tree.nodes.new("NodeFrame")
        frame.name = FRAME
        frame.label = "Phong Controls"
        frame.location = (-900.0, 300.0)
    nodes = {}
    for index, (name, (kind, label, default, _target)) in enumerate(CONTROLS.items()):
        node = tree.nodes.get(name)
        if node is None or node.bl_idname != kind:
            if node is not None:
                tree.nodes.remove(node)
            node = tree.nodes.new(kind)
            node.name = name
            node.label = label
            value = default
            if name == "phong_object_color" and base is not None:
                value = (*tuple(base)[:3], 1.0)
            compat.value_output(node).default_value = value
            node.parent = frame
            node.location = (-880.0, 260.0 - 190.0 * index)
        nodes[name] = node
    nodes[OPACITY] = _opacity_node(tree, frame)
    return nodes


def _opacity_node(tree, frame=None):
    """The Opacity control of *tree* (created at 1 when missing)."""
    node = tree.nodes.get(OPACITY)
    if node is not None and node.bl_idname == OPACITY_CONTROL[0]:
        return node
    if node is not None:
        tree.nodes.remove(node)
    node = tree.nodes.new(OPACITY_CONTROL[0])
    node.name = OPACITY
    node.label = OPACITY_CONTROL[1]
    compat.value_output(node).default_value = OPACITY_CONTROL[2]
    frame = frame if frame is not None else tree.nodes.get(FRAME)
    if frame is not None:
        node.parent = frame
    node.location = (-880.0, 260.0 - 190.0 * (len(CONTROLS) + 1))
    return node


def opacity(material) -> float:
    """The opacity of a Phong material (1 when it has no Opacity control)."""
    node = material.node_tree.nodes.get(OPACITY) if material.node_tree else None
    if node is None or node.bl_idname != OPACITY_CONTROL[0]:
        return 1.0
    return float(compat.value_output(node).default_value)


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
    node = _opacity_node(material.node_tree)
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
    map (``OPACITY_MAP``, an imported texture) feeds Fac instead, whatever the value.  The
    EEVEE Material Output of a lights group with the loop part (Blender 5.3+) the same way
    with its Eevee Shader; without the loop part (or in Per Vertex / Per Face shading) it
    is removed."""
    tree = material.node_tree
    lights = tree.nodes.get(LIGHTS_NODE)
    output = tree.nodes.get(OUTPUT)
    if lights is None or output is None:
        return
    value = opacity(material)
    mapped = _opacity_map(tree)
    _term_aovs(tree, lights)
    targets = [(OPACITY_MIX, _shader(tree, lights), output)]
    eevee_output = _eevee_output(tree, lights)
    # With an EEVEE output the first one is Cycles' only: Eevee's inliner then leaves the
    # lights group out (an output of target ALL it would copy whole, and free again: measured
    # 2x the render time of the loop alone at 1,000 materials, bpy 5.3.0)
    target = "ALL" if eevee_output is None else "CYCLES"
    if output.target != target:
        output.target = target
    if eevee_output is not None:
        targets.append((OPACITY_MIX_EEVEE, _eevee_shader(tree, lights), eevee_output))
    elif tree.nodes.get(OPACITY_MIX_EEVEE) is not None:
        tree.nodes.remove(tree.nodes[OPACITY_MIX_EEVEE])
    if value >= 1.0 and mapped is None:
        for name in (OPACITY_MIX, OPACITY_MIX_EEVEE, OPACITY_TRANSPARENT):
            if tree.nodes.get(name) is not None:
                tree.nodes.remove(tree.nodes[name])
        for _mix, source, target in targets:
            tree.links.new(source, target.inputs["Surface"])
        _render_method(material, "DITHERED")
        return
    transparent = named_node(tree, OPACITY_TRANSPARENT, "ShaderNodeBsdfTransparent",
                             (-50.0, 300.0))
    transparent.inputs["Color"].default_value = (1.0, 1.0, 1.0, 1.0)
    fac = mapped if mapped is not None else compat.value_output(tree.nodes[OPACITY])
    for index, (name, source, target) in enumerate(targets):
        mix = named_node(tree, name, "ShaderNodeMixShader", (150.0, 200.0 + 200.0 * index))
        mix.label = "Opacity"
        tree.links.new(fac, compat.input_socket(mix, "Fac"))
        tree.links.new(compat.output_socket(transparent, "BSDF"),
                       compat.input_socket(mix, "Shader"))
        tree.links.new(source, compat.input_socket(mix, "Shader_001"))
        tree.links.new(compat.output_socket(mix, "Shader"), target.inputs["Surface"])
    _render_method(material, "BLENDED")


def _term_aovs(tree, lights, relink=False) -> None:
    """The term AOV outputs of a material: none where it shows the loop in Eevee (they would
    make Eevee evaluate the per-light part: ``loop.py``), else each of AOVS, made when missing
    and linked from the lights group (*relink*: every one of them; Per Vertex / Per Face link
    their own: ``shading/modes.py``)."""
    shows_loop = _eevee_shader(tree, lights) is not None
    for index, (aov_name, socket) in enumerate(AOVS.items()):
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


def _eevee_shader(tree, lights):
    """The lights group's Eevee Shader output when the group has the loop part and the
    material shows it, else None.  Not in Per Vertex / Per Face shading, nor for a material
    that blends (Opacity below 1, an opacity map): the loop's sum cannot be clamped at 1
    (loop.py), and a blend of more than 1 is another picture, where an opaque pixel of more
    than 1 shows as 1 (measured: 2.4 % of test_controls' pixels off by up to 0.25)."""
    emission = tree.nodes.get(SHADING_EMISSION)
    if emission is not None and emission.bl_idname == "ShaderNodeEmission":
        return None
    shadowed = shadows.has_shadows(lights.node_tree)
    if _blends(tree):
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


def _eevee_output(tree, lights):
    """The EEVEE Material Output of *tree*, made when the material shows the loop
    (``_eevee_shader``), removed (None) when it does not."""
    node = tree.nodes.get(OUTPUT_EEVEE)
    if _eevee_shader(tree, lights) is None:
        if node is not None:
            tree.nodes.remove(node)
        return None
    node = named_node(tree, OUTPUT_EEVEE, "ShaderNodeOutputMaterial", (400.0, 300.0))
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
    lights = tree.nodes.get(LIGHTS_NODE)
    if lights is None:
        return True
    aovs = any(tree.nodes.get(f"phong_aov:{name}") is not None for name in AOVS)
    shows = _eevee_shader(tree, lights) is not None
    output = tree.nodes.get(OUTPUT)
    target = output.target if output is not None else None
    if not ((tree.nodes.get(OUTPUT_EEVEE) is not None) == shows and aovs != shows
            and target in (None, "CYCLES" if shows else "ALL")):
        return False
    # each output shows what it should (a group that gained or lost its shadow rays or its
    # loop part keeps its outputs' names: Shader, Eevee Shader, Cycles Shader)
    if shows and _source(tree.nodes[OUTPUT_EEVEE], OPACITY_MIX_EEVEE) != \
            _eevee_shader(tree, lights):
        return False
    return output is None or _source(output, OPACITY_MIX) in (None, _shader(tree, lights))


def _source(output, mix_name):
    """The socket a Material Output shows: what feeds its Surface, or through the opacity
    Mix Shader *mix_name*, what feeds the mix's second shader; None when unlinked or another
    node (Per Vertex / Per Face's emission is ``_shader``'s own)."""
    links = output.inputs["Surface"].links
    if not links:
        return None
    socket = links[0].from_socket
    if socket.node.name == mix_name and socket.node.bl_idname == "ShaderNodeMixShader":
        links = compat.input_socket(socket.node, "Shader_001").links
        socket = links[0].from_socket if links else None
    return socket


def _shader(tree, lights):
    """The shader the material shows: the lights group's, or in Per Vertex / Per Face
    shading (``shading/modes.py``) the Emission of the stored colour."""
    emission = tree.nodes.get(SHADING_EMISSION)
    if emission is not None and emission.bl_idname == "ShaderNodeEmission":
        return compat.output_socket(emission, "Emission")
    if shadows.has_shadows(lights.node_tree) and _eevee_shader(tree, lights) is not None:
        return lights.outputs[shadows.CYCLES_SHADER]  # the output is Cycles' only
    return lights.outputs["Shader"]


#: Pointers of the scenes whose lights groups a material that began to blend makes Eevee
#: compile with more View Layer lookups than ``compat.VIEW_LAYER_LOOKUPS``: the depsgraph
#: handler relinks them (``sync.on_depsgraph_update``), with that budget.
STALE: set = set()


def _blends(tree) -> bool:
    node = tree.nodes.get(OPACITY)
    return _opacity_map(tree) is not None or (
        node is not None and node.bl_idname == OPACITY_CONTROL[0]
        and float(compat.value_output(node).default_value) < 1.0)


def blends(material) -> bool:
    """Whether *material* blends with what is behind it (Opacity below 1, an opacity map)."""
    return material.node_tree is not None and _blends(material.node_tree)


def _opacity_map(tree):
    """The Value output of the opacity map of *tree* (``OPACITY_MAP``), or None."""
    node = tree.nodes.get(OPACITY_MAP)
    if node is None or node.bl_idname != "ShaderNodeMath":
        return None
    return compat.output_socket(node, "Value")


def opacity_in_step(material) -> bool:
    """Whether *material*'s nodes already match the value of its Opacity control (or its
    opacity map)."""
    tree = material.node_tree
    blends = opacity(material) < 1.0 or _opacity_map(tree) is not None
    return ((tree.nodes.get(OPACITY_MIX) is not None) == blends
            and (tree.nodes.get(OPACITY_MIX_EEVEE) is not None)
            == (blends and tree.nodes.get(OUTPUT_EEVEE) is not None))


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
        if (material is not None and material.library is None and is_phong_material(material)
                and not opacity_in_step(material)):
            apply_opacity(material)


def _render_method(material, method) -> None:
    """Eevee's render method (4.2+): Blended blends exactly, Dithered is the default."""
    if getattr(material, "surface_render_method", method) != method:
        material.surface_render_method = method


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


#: Label of a material's own Ambient Object Color control (AMBIENT_CONTROL), as importers make it.
AMBIENT_LABEL = "Ambient Color (Ka)"


def color_control(tree, name, color):
    """The colour control *name* of the recipe (an RGB node of CONTROLS, or the material's own
    AMBIENT_CONTROL, made on demand) set to *color*; what the importers give each colour."""
    label = CONTROLS[name][1] if name in CONTROLS else AMBIENT_LABEL
    return control_node(tree, name, label, color)


def control_node(tree, name, label, color):
    """The RGB control node *name* of *tree* in the Phong Controls frame, created when
    missing, with the colour *color*."""
    before = tree.nodes.get(name)
    node = named_node(tree, name, "ShaderNodeRGB", (-880.0, 260.0 - 190.0 * len(CONTROLS)))
    frame = tree.nodes.get(FRAME)
    if node != before and frame is not None:  # a new control goes into the frame
        node.parent = frame
    node.label = label
    set_quietly(compat.value_output(node), (*tuple(color)[:3], 1.0))
    return node


def _output(tree):
    node = tree.nodes.get(OUTPUT)
    if node is None:
        node = tree.nodes.new("ShaderNodeOutputMaterial")
        node.name = OUTPUT
        node.location = (400.0, 100.0)
    for other in tree.nodes:
        if other.bl_idname == "ShaderNodeOutputMaterial" and other.name != OUTPUT_EEVEE:
            other.is_active_output = other is node
    node.target = "ALL"
    return node


def wire(material, lights_group, object_color=None) -> None:
    """Give *material* the recipe's nodes around *lights_group*; the controls keep their
    values.  *object_color*: an output socket (a texture) to feed Object Color instead of
    the control."""
    tree = material.node_tree
    controls = _controls(tree)
    node = tree.nodes.get(LIGHTS_NODE)
    if node is None:
        node = tree.nodes.new("ShaderNodeGroup")
        node.name = LIGHTS_NODE
        node.location = (-300.0, 100.0)
        node.width = 220.0
    if node.node_tree is not lights_group:
        node.node_tree = lights_group
    node.label = "Phong Lights"
    for control, (_kind, _label, _default, target) in CONTROLS.items():
        if not node.inputs[target].is_linked:
            tree.links.new(compat.value_output(controls[control]), node.inputs[target])
    if object_color is not None:
        tree.links.new(object_color, node.inputs["Object Color"])
    ambient = node.inputs[AMBIENT_INPUT]
    if not ambient.is_linked:  # the seeds' model: the ambient light sees the Object Color
        tree.links.new(node.inputs["Object Color"].links[0].from_socket, ambient)
    tree.links.new(node.outputs["Shader"], _output(tree).inputs["Surface"])
    _term_aovs(tree, node, relink=True)
    apply_opacity(material)
    # the emission that shows the Phong colour is no light for Cycles: the Principled
    # surfaces around a Phong object are lit as they were
    cycles = getattr(material, "cycles", None)
    if getattr(cycles, "emission_sampling", "NONE") != "NONE":
        cycles.emission_sampling = "NONE"
    material[MATERIAL_TAG] = LAYOUT


def new_material(name, lights_group, base=None):
    """A new Phong material around *lights_group* with the Object Color *base*."""
    material = bpy.data.materials.new(name)
    tree = compat.new_material_tree(material)
    tree.nodes.clear()
    _controls(tree, base)
    wire(material, lights_group)
    return material


def from_source(source, name, lights_group, template=None):
    """The Phong version of *source* (a material, or None for an empty slot).

    Without a texture chain on the source's Base Color: a copy of *template* (the same
    layout: Eevee compiles one shader for all of them) with the source's base colour, or a
    new material when there is no template.  With one: the same copy with the chain copied
    in (``node_copy``) feeding Object Color; where the chain cannot be copied (or there is
    no template), a copy of the source whose other nodes are removed, given the recipe's
    nodes (each named: slower in a large file, see ``_textured_from_template``).
    """
    texture = base_color_link(source) if source is not None else None
    if texture is not None:
        material = (_textured_from_template(source, texture, template, name)
                    if template is not None else None)
        if material is None:
            material = _strip_to_texture(source.copy(), texture)
            compat.rename(material, name)
            _controls(material.node_tree, base_color(source))
            wire(material, lights_group, _socket_in_copy(material, texture))
    elif template is not None:
        material = template.copy()
        compat.rename(material, name)
        value = base_color(source)
        default = CONTROLS["phong_object_color"][2]
        set_quietly(compat.value_output(material.node_tree.nodes["phong_object_color"]),
                    default if value is None else (*value[:3], 1.0))
    else:
        material = new_material(name, lights_group, base_color(source))
    nodes = material.node_tree.nodes
    for control, value in source_controls(source).items():
        node = nodes.get(control)
        if node is not None and tuple(compat.value_output(node).default_value) != value:
            set_quietly(compat.value_output(node), value)
    for key in list(material.keys()):
        if key.startswith("phong_") and key != MATERIAL_TAG:
            del material[key]
    if source is None:
        material[EMPTY_SOURCE_KEY] = 1
    else:
        keep_source(material, source)
    return material


def _textured_from_template(source, texture, template, name):
    """A copy of *template* (the recipe's named nodes kept: naming a node walks the whole
    file) with *source*'s texture chain copied in (``node_copy``) feeding Object Color (and
    the ambient light where the template's ambient sees the Object Color control); None
    when the chain cannot be copied faithfully."""
    material = template.copy()
    tree = material.node_tree
    made = node_copy.copy_upstream(source.node_tree, texture.node, tree, (-500.0, 0.0))
    if made is None:
        bpy.data.materials.remove(material)
        return None
    compat.rename(material, name)
    feed = compat.output_socket(made[texture.node.name], texture.identifier)
    control = compat.value_output(tree.nodes["phong_object_color"])
    value = base_color(source)
    set_quietly(control, CONTROLS["phong_object_color"][2] if value is None
                else (*value[:3], 1.0))
    lights = tree.nodes[LIGHTS_NODE]
    tree.links.new(feed, lights.inputs["Object Color"])
    ambient = lights.inputs[AMBIENT_INPUT]
    if ambient.is_linked and ambient.links[0].from_socket == control:
        tree.links.new(feed, ambient)
    return material


def _socket_in_copy(material, socket):
    node = material.node_tree.nodes[socket.node.name]
    return compat.output_socket(node, socket.identifier)


def _strip_to_texture(material, texture_socket):
    """Keep only the nodes upstream of *texture_socket* (by name) in the copy *material*."""
    tree = material.node_tree
    keep = {node.name for node in node_copy.upstream(tree.nodes[texture_socket.node.name])}
    doomed = [n.name for n in tree.nodes if n.name not in keep]
    drivers.remove_node_drivers(tree, doomed)
    for name in doomed:
        tree.nodes.remove(tree.nodes[name])
    return material


def group_links(material, name=LIGHTS_NODE) -> dict:
    """{input name: the output sockets linked to it} of the group node *name*."""
    node = material.node_tree.nodes.get(name) if material.node_tree is not None else None
    if node is None:
        return {}
    return {s.name: [l.from_socket for l in s.links] for s in node.inputs if s.is_linked}


def renew_group_node(material, links=None, name=LIGHTS_NODE) -> bool:
    """Make the group node *name* of *material* again, with the same group, links and input
    values (a file written by a newer Blender: ``compat.file_from_newer_release``), and link
    *links* ({input name: output sockets}: ``group_links`` before) to the inputs that have
    none; returns whether there was a node."""
    tree = material.node_tree
    node = tree.nodes.get(name) if tree is not None else None
    if node is None or node.bl_idname != "ShaderNodeGroup":
        return False
    group, location, width, label = node.node_tree, tuple(node.location), node.width, node.label
    sources = {s.name: [l.from_socket for l in s.links] for s in node.inputs if s.is_linked}
    for input_name, sockets in (links or {}).items():
        sources.setdefault(input_name, sockets)
    values = {s.name: (tuple(s.default_value) if hasattr(s.default_value, "__len__")
                       else s.default_value)
              for s in node.inputs if hasattr(s, "default_value")}
    targets = {s.name: [l.to_socket for l in s.links] for s in node.outputs}
    tree.nodes.remove(node)
    node = tree.nodes.new("ShaderNodeGroup")
    node.name, node.label, node.location, node.width = name, label, location, width
    node.node_tree = group
    for socket in node.inputs:
        if socket.name in values and socket.name not in sources:
            socket.default_value = values[socket.name]
        for source in sources.get(socket.name, ()):
            tree.links.new(source, socket)
    for socket in node.outputs:
        for target in targets.get(socket.name, ()):
            tree.links.new(socket, target)
    return True


def upgrade(material) -> bool:
    """Turn a Phong material of layout 1 (every light's nodes in the material) into the
    recipe: the control nodes and their values stay; returns whether it changed."""
    layout = int(material.get(MATERIAL_TAG, 0))
    if layout >= LAYOUT:
        return False
    source = material.get(SOURCE_KEY)
    if isinstance(source, bpy.types.Material):  # layout <= 4: an ID pointer
        del material[SOURCE_KEY]
        keep_source(material, source)
    if layout >= 4:
        return True
    tree = material.node_tree
    names = [n.name for n in tree.nodes if n.name.startswith(OLD_GENERATED)]
    if tree.animation_data is not None:
        tree.animation_data_clear()
    for name in names:
        tree.nodes.remove(tree.nodes[name])
    for key in ("phong_lights",):
        if key in material.keys():
            del material[key]
    return True


def restore(obj, names=None) -> int:
    """Put back the source materials in the slots of *obj* that hold a Phong material made
    from one; returns how many slots changed.  *names*: as for ``source_of``."""
    changed = 0
    for slot in obj.material_slots:
        material = slot.material
        if not is_phong_material(material):
            continue
        source = source_of(material, names)
        if source is not None:
            slot.material = source
            changed += 1
        elif material.get(EMPTY_SOURCE_KEY):
            slot.material = None
            changed += 1
    return changed


# -- reading a Phong material back (for the exporters) ------------------------------------------

#: The inputs of the lights group that a Phong material's controls feed, and their controls.
FEED_CONTROLS = {target: name for name, (_k, _l, _d, target) in CONTROLS.items()}
FEED_CONTROLS[AMBIENT_INPUT] = AMBIENT_CONTROL


class Feed:
    """What feeds one input of a Phong material's lights group: *value* (a float, or 3
    floats for a colour), the value the material states (its control's, an RGB / Value
    node's, else the socket's own); *other*: the node that feeds the input instead when that
    is not a plain value (a texture, a chain), else None; *texture*: the Image Texture node
    (with an image) when *other* is one, or the importers' colour × map (a Vector Math
    Multiply of an RGB node and an Image Texture: *value* is then that RGB node's colour),
    else None; *socket*: the output socket linked to the input (None when unlinked): two
    inputs fed by the same socket show the same thing (the seeds' Ka = Kd); *chain*: the
    :class:`Chain` that *other* heads (None when *other* is)."""

    __slots__ = ("value", "other", "texture", "socket", "chain")

    def __init__(self, value, other=None, texture=None, socket=None, chain=None):
        self.value, self.other, self.texture = value, other, texture
        self.socket, self.chain = socket, chain

    def __repr__(self):
        return f"Feed({self.value!r}, {getattr(self.other, 'name', None)!r})"


class Chain:
    """The product that a chain of nodes feeding an input makes, as the importers build it:
    Vector Math Multiply and Scale nodes over RGB nodes (*colour*: the product of their
    colours, None without one), an Image Texture with an image (*texture*: the node), a Color
    Attribute (*attribute*: the node), a Scale's factor (*scale*); *unknown*: another node is
    in it (or it is deeper than 8 nodes)."""

    __slots__ = ("colour", "texture", "attribute", "scale", "unknown")

    def __init__(self, socket=None):
        self.colour = self.texture = self.attribute = self.scale = None
        self.unknown = False
        if socket is not None:
            self._walk(socket, 0)

    def _walk(self, source, depth) -> None:
        node = source.node
        kind = node.bl_idname
        if depth > 8:
            self.unknown = True
        elif kind == "ShaderNodeRGB":
            value = _plain_value(compat.value_output(node).default_value)
            self.colour = value if self.colour is None else tuple(
                a * b for a, b in zip(self.colour, value))
        elif kind == "ShaderNodeTexImage" and node.image is not None:
            self.texture = node
        elif kind == "ShaderNodeVertexColor":
            self.attribute = node
        elif kind == "ShaderNodeVectorMath" and node.operation in ("MULTIPLY", "SCALE"):
            identifiers = ("Vector", "Vector_001") if node.operation == "MULTIPLY" else \
                ("Vector",)
            if node.operation == "SCALE":
                self.scale = float(compat.input_socket(node, "Scale").default_value)
            for identifier in identifiers:
                socket = compat.input_socket(node, identifier)
                if socket.is_linked:
                    self._walk(socket.links[0].from_socket, depth + 1)
        else:
            self.unknown = True


def _plain_value(value):
    return tuple(float(v) for v in tuple(value)[:3]) if hasattr(value, "__len__") \
        else float(value)


def feeds(material) -> dict:
    """{input of the lights group: :class:`Feed`} of the Phong material *material*, for every
    input a control feeds (Object Color, Ambient Object Color, Specular Color, Exponent,
    Blinn, Irradiant Color, Specular Strength), and "Opacity": the Opacity control, *other*
    the opacity map (``OPACITY_MAP``) where one feeds the blend.  An Ambient Object Color fed
    by the socket that feeds Object Color (the seeds' model) is Object Color's feed."""
    tree = material.node_tree
    lights = tree.nodes[LIGHTS_NODE]
    out = {}
    for target, control in FEED_CONTROLS.items():
        socket = lights.inputs.get(target)
        if socket is None:
            continue
        node = tree.nodes.get(control)
        stated = _plain_value(compat.value_output(node).default_value) \
            if node is not None and node.bl_idname in compat.VALUE_OUTPUTS else None
        if not socket.is_linked:
            out[target] = Feed(_plain_value(socket.default_value))
            continue
        upstream = socket.links[0].from_node
        if upstream.bl_idname in compat.VALUE_OUTPUTS:
            out[target] = Feed(_plain_value(compat.value_output(upstream).default_value),
                               socket=socket.links[0].from_socket)
            continue
        feed = Feed(stated if stated is not None else _plain_value(socket.default_value),
                    upstream, socket=socket.links[0].from_socket,
                    chain=Chain(socket.links[0].from_socket))
        if upstream.bl_idname == "ShaderNodeTexImage" and upstream.image is not None:
            feed.texture = upstream
        elif upstream.bl_idname == "ShaderNodeVectorMath" and upstream.operation == "MULTIPLY":
            a, b = (compat.input_socket(upstream, k) for k in ("Vector", "Vector_001"))
            if a.is_linked and b.is_linked:
                rgb, image = a.links[0].from_node, b.links[0].from_node
                if rgb.bl_idname == "ShaderNodeRGB" and \
                        image.bl_idname == "ShaderNodeTexImage" and image.image is not None:
                    feed.value = _plain_value(compat.value_output(rgb).default_value)
                    feed.texture = image
        out[target] = feed
    ambient, colour = out.get(AMBIENT_INPUT), out.get("Object Color")
    if ambient is not None and colour is not None and ambient.other is not None and \
            ambient.socket == colour.socket:   # the seeds' model: what feeds Object Color
        out[AMBIENT_INPUT] = Feed(colour.value, colour.other, colour.texture, colour.socket,
                                  colour.chain)
    out["Opacity"] = Feed(opacity(material), tree.nodes.get(OPACITY_MAP))
    return out
