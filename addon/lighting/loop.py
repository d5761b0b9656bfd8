# SPDX-License-Identifier: GPL-3.0-or-later
"""The Eevee side of Phong materials on Blender 5.3+: Eevee's light loop.

Blender 5.3's Eevee runs the nodes upstream of a Light Accumulation node that read the
current light (Light Evaluation, Attribute of type Light, Vector Transform's Light space) once
per light of the scene and sums what Light Accumulation takes.  A lights group of such a
release (``rig.build`` with ``loop``) holds, beside its per-light nodes (what Cycles renders),
this part, which does not depend on the lights at all:

* Light Evaluation (the unit vector toward the light and the distance), a Vector Transform of
  (0, 0, 1) from Light to World space (the light's axis) and one Attribute node of type Light
  per packed setting of the model (``library.LOOP_MODELS``: a few numeric custom properties
  ``phong_eevee_<model>_<name>`` of the light's data that ``write_parameters`` keeps in step
  with its Phong settings, colour, type, spot size and Blender's Diffuse / Specular factors);
* the nodes of the model's loop group (``Phong Loop Light``, ``three.js Loop Light``:
  node_groups/library.py), written into the lights group itself (``loader.NodeWriter``): a
  group node inside the loop gets no light (measured on 5.3.0: Light Accumulation then adds
  0), and Light Accumulation, every colour of which is linked from outside the loop (a colour
  left unlinked there is compiled into the shader: one shader per material);
* Emission(irradiant + ambient) added to it: the group's output "Eevee Shader", which the
  material's second Material Output (target EEVEE) shows (``engine_outputs.py``).

So a light added, removed, retyped, relinked or moved changes nothing of the material for
Eevee, and every material has the same few nodes whatever the number of lights.  What Light
Accumulation cannot do: clamp the sum (Eevee's pixel is irradiant + ambient + Σ lights, not
min(…, 1): the same picture on screen with the Standard view transform, more than 1 in the
render's values), take a colour outside [0, 1], or undo a Blender Diffuse / Specular factor of
0 (docs/contract.md, "Eevee's light loop").

Nothing here runs before 5.3 (``compat.HAS_LIGHT_LOOP``).
"""

from __future__ import annotations

import math

import bpy
from bpy.app.handlers import persistent

from ...node_groups.expr import input_
from ...node_groups.library import LOOP_MODELS, LOOP_PREFIX, definition, loop_parameters
from .. import compat, loader
from . import properties

#: The output of a lights group that the material's EEVEE Material Output shows (on 5.3+).
EEVEE_SHADER = "Eevee Shader"
#: Custom property of a lights group whose Eevee Shader is the light loop: the fingerprint of
#: the model's loop group it was written from (a changed formula relinks on load).
LOOP_KEY = "phong_lights_loop"
#: Labels of the loop part's nodes in a lights group (their names are Blender's).
NODE_PREFIX = "loop:"
#: The loop group's inputs that Blender's light nodes feed.
LIGHT_VECTOR, DISTANCE, AXIS = "Light Vector", "Distance", "Light Axis"
ACCUMULATE = {"Diffuse": ("Diffuse Light", "Diffuse Color"),
              "Glossy": ("Glossy Light", "Glossy Color"),
              "Transmission": ("Transmission Light", "Transmission Color")}


def supports(model: str) -> bool:
    """Whether this Blender runs *model*'s Eevee side on the light loop."""
    return compat.HAS_LIGHT_LOOP and model in LOOP_MODELS


def stamp(model: str) -> str:
    """What ``LOOP_KEY`` holds in a lights group of *model* with the loop part."""
    return definition(LOOP_MODELS[model].group).fingerprint


def has_loop(tree) -> bool:
    """Whether the lights group *tree* has the loop part (its Eevee Shader is the loop)."""
    return tree is not None and compat.HAS_LIGHT_LOOP and bool(tree.get(LOOP_KEY))


# -- the light's packed settings ------------------------------------------------------------

def write_parameters(light) -> bool:
    """Write the loop's packed settings of *light* (a Light) for every model, and give a
    point or spot light the influence distance of a Phong light (Eevee leaves out a light
    beyond it, and drops every material's shadows of a light whose distance is much more:
    ``compat.LOOP_LIGHT_DISTANCE``, set exactly, lowered too); only what differs is written
    (arrays in place: no ID property freed, which is safe inside a depsgraph handler).
    Returns whether anything changed."""
    if not compat.HAS_LIGHT_LOOP or light.library is not None:
        return False
    values = properties.light_values(light)
    changed = False
    for model in LOOP_MODELS:
        for key, value in loop_parameters(model, values).items():
            current = light.get(key)
            if isinstance(value, float):
                if not isinstance(current, float) or current != value:
                    light[key] = value
                    changed = True
            elif (current is not None and not isinstance(current, (str, float, int))
                  and len(current) == len(value)):
                if tuple(current) != value:
                    for index, item in enumerate(value):
                        current[index] = item
                    changed = True
            else:
                light[key] = list(value)
                changed = True
    if light.type in ("POINT", "SPOT", "AREA"):
        if not light.use_custom_distance:
            light.use_custom_distance = True
            changed = True
        if light.cutoff_distance != compat.LOOP_LIGHT_DISTANCE:  # not beyond: shadows go
            light.cutoff_distance = compat.LOOP_LIGHT_DISTANCE
            changed = True
    return changed


def is_phong_light(light) -> bool:
    """Whether *light* carries Phong settings (a light that drives, or drove, Phong
    materials: ``properties.ensure_light_props`` wrote them)."""
    return properties.LIGHT_KEYS["intensity"][0] in light.keys()


@persistent
def follow_lights(_scene, depsgraph=None) -> None:
    """After an edit of a light's data (a Phong setting written through ``light.phong``, by a
    script with ``update_tag()``, its colour, Power, type, spot size, Blender's Diffuse /
    Specular factor): its packed settings again.  Every Phong light of the file is looked at
    (``write_parameters`` writes only what differs), not the depsgraph's updates: a Power
    drag updates the World's copies and with them thousands of IDs, which walking
    ``depsgraph.updates`` took 10 ms of each update at 1,000 objects.  A light move or a
    material edit costs one check."""
    if depsgraph is None or not compat.HAS_LIGHT_LOOP or not depsgraph.id_type_updated("LIGHT"):
        return
    for light in bpy.data.lights:
        if light.library is None and is_phong_light(light):
            write_parameters(light)


# -- the loop part of a lights group ---------------------------------------------------------

def _node(tree, kind, name, location):
    """A new node labelled ``NODE_PREFIX + name`` (named by Blender: see ``shadows._node``)."""
    node = tree.nodes.new(kind)
    node.label = NODE_PREFIX + name
    node.location = location
    return node


def build(tree, model, group_in, group_out, irradiant, ambient, surface=None,
          shadows=False) -> None:
    """Add the loop part of *model* to the lights group *tree* (being built: *group_in*,
    *group_out* its Group Input and Output): its Eevee Shader output = Emission(*irradiant*
    + *ambient*) + Light Accumulation of the model's loop group.  *surface*: a Phong Surface
    node of the group (the unit normal and view vector), else its nodes are written.
    *shadows*: each light's Light inputs of Light Accumulation times its Shadow Raycast
    (Softness 0: the light's shadow map at the shaded point; 1 where the light casts no
    shadow), Eevee's side of the shadow rays (``shadows.py``)."""
    spec = LOOP_MODELS[model]
    x, y = -900.0, 1400.0
    if surface is None:  # written flat: the group keeps the group nodes of its model
        unit = _write(tree, definition("Phong Surface"), {}, group_in, (x - 300.0, y + 600.0))
    else:
        unit = {name: surface.outputs[name] for name in ("Normal", "View Vector")}
    evaluation = _node(tree, "ShaderNodeLightEvaluation", "evaluation", (x, y))
    axis = _node(tree, "ShaderNodeVectorTransform", "axis", (x, y - 220.0))
    axis.vector_type, axis.convert_from, axis.convert_to = "VECTOR", "LIGHT", "WORLD"
    compat.input_socket(axis, "Vector").default_value = (0.0, 0.0, 1.0)
    sources = {LIGHT_VECTOR: compat.output_socket(evaluation, "Direction"),
               DISTANCE: compat.output_socket(evaluation, "Distance"),
               AXIS: compat.output_socket(axis, "Vector"),
               "Normal": unit["Normal"], "View Vector": unit["View Vector"]}
    for row, parameter in enumerate(spec.parameters):
        attribute = _node(tree, "ShaderNodeAttribute", parameter.name,
                          (x + 250.0, y - 200.0 * row))
        attribute.attribute_type = "LIGHT"
        attribute.attribute_name = parameter.key(model)
        for output, target in (("Vector", parameter.vector), ("Alpha", parameter.alpha),
                               ("Fac", parameter.factor)):
            if target is not None:
                sources[target] = compat.output_socket(attribute, output)
        if parameter.components:
            separate = _node(tree, "ShaderNodeSeparateXYZ", parameter.name + ":xyz",
                             (x + 420.0, y - 200.0 * row))
            tree.links.new(compat.output_socket(attribute, "Vector"),
                           compat.input_socket(separate, "Vector"))
            for output, target in zip(("X", "Y", "Z"), parameter.components):
                sources[target] = compat.output_socket(separate, output)
    light = _write(tree, definition(spec.group), sources, group_in, (x + 500.0, y))
    accumulation = _node(tree, "ShaderNodeLightAccumulation", "accumulation", (x + 900.0, y))
    shadow = None
    if shadows:
        shadow = _node(tree, "ShaderNodeShadowRaycast", "shadow", (x + 700.0, y + 200.0))
        compat.input_socket(shadow, "Softness").default_value = 0.0
    for row, (slot, (light_input, color_input)) in enumerate(ACCUMULATE.items()):
        if slot in spec.slots:
            light_output, color_output = spec.slots[slot]
            source = light[light_output]
            if shadow is not None and slot not in spec.unshadowed:
                lit = _node(tree, "ShaderNodeVectorMath", f"shadow:{slot}",
                            (x + 750.0, y - 150.0 * row))
                lit.operation = "MULTIPLY"
                tree.links.new(source, compat.input_socket(lit, "Vector"))
                tree.links.new(compat.output_socket(shadow, "Color"),
                               compat.input_socket(lit, "Vector_001"))
                source = compat.output_socket(lit, "Vector")
            tree.links.new(source, compat.input_socket(accumulation, light_input))
            tree.links.new(light[color_output], compat.input_socket(accumulation, color_input))
        else:  # linked from outside the loop too (see the module's docstring)
            tree.links.new(group_in.outputs["Irradiant Color"],
                           compat.input_socket(accumulation, color_input))
    base = _node(tree, "ShaderNodeVectorMath", "base", (x + 900.0, y + 300.0))
    base.operation = "ADD"
    tree.links.new(irradiant, compat.input_socket(base, "Vector"))
    tree.links.new(ambient, compat.input_socket(base, "Vector_001"))
    emission = _node(tree, "ShaderNodeEmission", "emission", (x + 1100.0, y + 300.0))
    compat.input_socket(emission, "Strength").default_value = 1.0
    tree.links.new(compat.output_socket(base, "Vector"), compat.input_socket(emission, "Color"))
    add = _node(tree, "ShaderNodeAddShader", "add", (x + 1300.0, y + 150.0))
    tree.links.new(compat.output_socket(emission, "Emission"), compat.input_socket(add, "Shader"))
    tree.links.new(compat.output_socket(accumulation, "Shader"),
                   compat.input_socket(add, "Shader_001"))
    tree.links.new(compat.output_socket(add, "Shader"), group_out.inputs[EEVEE_SHADER])
    tree[LOOP_KEY] = stamp(model)


def _write(tree, group, sources, group_in, origin) -> dict:
    """The nodes of the library group *group* written into *tree*, its inputs read from
    *sources* ({input name: socket}) or else *group_in*'s output of the same name; returns
    {output name: socket}.  Placed from *origin*."""
    writer = loader.NodeWriter(tree, group_in)
    for socket in group.inputs:
        source = sources.get(socket.name)
        if source is None and socket.name in group_in.outputs:
            source = group_in.outputs[socket.name]
        if source is None:
            raise KeyError(f"{group.name}: no source for its input {socket.name!r}")
        key = input_(socket.name, socket.kind).key
        writer.sockets[key] = source
        writer.depth[key] = 0
    before = set(tree.nodes.keys())
    outputs = {}
    for name, expression in group.expressions.items():
        outputs[name] = writer.socket(expression)
        if outputs[name] is None:
            raise ValueError(f"{group.name}: output {name!r} is a constant")
    for node in tree.nodes:
        if node.name not in before:
            node.location = (origin[0] + node.location.x, origin[1] + node.location.y)
            node.label = NODE_PREFIX + (node.label or node.name)
    return outputs


__all__ = ["EEVEE_SHADER", "LOOP_KEY", "LOOP_PREFIX", "build", "follow_lights", "has_loop",
           "supports", "write_parameters"]
