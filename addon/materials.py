# SPDX-License-Identifier: GPL-3.0-or-later
"""Phong materials driven by the scene's Blender lights.

``bpy.ops.phong.apply_material()`` gives every selected mesh object its own material
"Phong <object>" and ``bpy.ops.phong.relink_lights()`` brings every Phong material of the
file up to date with the lights of the current scene.  Layout of a Phong material:

* the frame **Phong Controls** holds the material's own settings, once: Object Color,
  Specular Color, Exponent, Blinn, Irradiant Color (RGB / Value nodes linked to every
  Phong Shading).  These nodes are kept, with the user's values, when the material is
  rebuilt;
* per supported light (Point, Sun, Spot; visible and renderable), a light-model group
  (Phong Point / Directional / Spot Light) and a Phong Shading, driven by the light
  (drivers without Python, see ``drivers.py``);
* the shadings are summed with Phong Color Add; ambient (from the World) and irradiant are
  counted once, on the first Phong Shading (the others get Ambient Intensity 0 and a black
  Irradiant Color);
* the sum goes to the Material Output as an emission of strength 1 (the Shader output of
  the Phong Shading when there is one light) and to an AOV output named "Phong Color".

With no supported light the material holds a single Phong Shading with Light Intensity 0:
the picture is ambient + irradiant, which is black when the World's Phong ambient is 0 and
the irradiant colour is black (seed 004 slide 43: no light at all gives black; the ambient
light is a light, seed 000 §3.3).
"""

from __future__ import annotations

import bpy

from ..node_groups import loader
from . import compat, drivers, properties

#: Custom property that marks a material made by apply_material.
MATERIAL_TAG = "phong_nodes_material"
#: Name of the AOV output that carries the summed Phong colour.
AOV_NAME = "Phong Color"
SUPPORTED = {"POINT": "Phong Point Light", "SUN": "Phong Directional Light",
             "SPOT": "Phong Spot Light"}

GEN = "phong_gen:"          # prefix of the nodes rebuilt on every relink
FRAME = "phong_controls"
OUTPUT = "phong_output"
#: control node name -> (node type, label, default, Phong Shading input)
CONTROLS = {
    "phong_object_color": ("ShaderNodeRGB", "Object Color", (0.8, 0.8, 0.8, 1.0), "Object Color"),
    "phong_specular_color": ("ShaderNodeRGB", "Specular Color", (1.0, 1.0, 1.0, 1.0),
                             "Specular Color"),
    "phong_exponent": ("ShaderNodeValue", "Exponent", 30.0, "Exponent"),
    "phong_blinn": ("ShaderNodeValue", "Blinn", 0.0, "Blinn"),
    "phong_irradiant_color": ("ShaderNodeRGB", "Irradiant Color", (0.0, 0.0, 0.0, 1.0),
                              "Irradiant Color"),
}
IRRADIANT = "phong_irradiant_color"


# -- lights ---------------------------------------------------------------------

def scene_lights(scene, view_layer=None):
    """(supported, unsupported) light objects of *scene* that render, sorted by name.

    A light counts when it is not disabled in renders and is visible in the view layer
    (not hidden, not in an excluded or hidden collection).
    """
    view_layer = view_layer or scene.view_layers[0]
    supported, unsupported = [], []
    for obj in sorted(scene.objects, key=lambda o: o.name):
        if obj.type != "LIGHT" or obj.hide_render:
            continue
        try:
            visible = obj.visible_get(view_layer=view_layer)
        except (TypeError, RuntimeError):
            visible = not obj.hide_get()
        if not visible:
            continue
        (supported if obj.data.type in SUPPORTED else unsupported).append(obj)
    return supported, unsupported


# -- material -------------------------------------------------------------------

def is_phong_material(material) -> bool:
    return material is not None and bool(material.get(MATERIAL_TAG)) and material.node_tree is not None


def principled_color(material):
    """The base colour a material had (Principled BSDF, else its viewport colour), or None."""
    if material is None:
        return None
    tree = material.node_tree if compat.uses_nodes(material) else None
    if tree is not None:
        for node in tree.nodes:
            if node.bl_idname == "ShaderNodeBsdfPrincipled":
                socket = node.inputs.get("Base Color")
                if socket is not None and not socket.is_linked:
                    return tuple(socket.default_value)
    return tuple(material.diffuse_color)


def new_material(name, base_color=None):
    material = bpy.data.materials.new(name)
    material[MATERIAL_TAG] = 1
    tree = compat.new_material_tree(material)
    tree.nodes.clear()
    _ensure_controls(tree, base_color)
    return material


def _ensure_controls(tree, base_color=None):
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
            if name == "phong_object_color" and base_color is not None:
                value = (*tuple(base_color)[:3], 1.0)
            node.outputs[0].default_value = value
            node.parent = frame
            node.location = (-880.0, 260.0 - 190.0 * index)
        nodes[name] = node
    return nodes


def _clear_generated(tree):
    names = [n.name for n in tree.nodes if n.name.startswith(GEN)]
    drivers.remove_node_drivers(tree, names)
    for name in names:
        tree.nodes.remove(tree.nodes[name])


def _light_node(tree, obj, location):
    light = obj.data
    properties.ensure_light_props(light)
    group_name = SUPPORTED[light.type]
    group, _status = loader.ensure_group(group_name)
    node = tree.nodes.new("ShaderNodeGroup")
    node.node_tree = group
    node.name = f"{GEN}light:{obj.name}"
    node.label = f"{group_name.removeprefix('Phong ')}: {obj.name}"
    node.location = location
    inputs = node.inputs
    if light.type in ("POINT", "SPOT"):
        drivers.world_location(inputs["Position"], obj)
        for attr in ("quadratic", "linear", "constant"):
            key = properties.LIGHT_KEYS[attr][0]
            drivers.prop(inputs[attr.capitalize()], None, "LIGHT", light, f'["{key}"]')
    if light.type in ("SUN", "SPOT"):
        drivers.world_minus_z(inputs["Direction"], obj)
    if light.type == "SPOT":
        drivers.prop(inputs["Half Angle"], None, "LIGHT", light, "spot_size", scale=0.5)
        key = properties.LIGHT_KEYS["edge_exponent"][0]
        drivers.prop(inputs["Edge Exponent"], None, "LIGHT", light, f'["{key}"]')
    key = properties.LIGHT_KEYS["intensity"][0]
    drivers.prop(inputs["Intensity"], None, "LIGHT", light, f'["{key}"]')
    return node


def _shading_node(tree, name, label, location, controls, first):
    group, _status = loader.ensure_group("Phong Shading")
    node = tree.nodes.new("ShaderNodeGroup")
    node.node_tree = group
    node.name = name
    node.label = label
    node.location = location
    for control, (_k, _l, _d, target) in CONTROLS.items():
        if control == IRRADIANT and not first:
            node.inputs[target].default_value = (0.0, 0.0, 0.0, 1.0)
            continue
        tree.links.new(controls[control].outputs[0], node.inputs[target])
    return node


def _drive_ambient(node, world):
    if world is None:
        key, default = properties.AMBIENT_INTENSITY
        node.inputs["Ambient Intensity"].default_value = default
        node.inputs["Ambient Color"].default_value = (*properties.AMBIENT_COLOR[1], 1.0)
        return
    properties.ensure_world_props(world)
    drivers.prop(node.inputs["Ambient Intensity"], None, "WORLD", world,
                 f'["{properties.AMBIENT_INTENSITY[0]}"]')
    drivers.color(node.inputs["Ambient Color"], "WORLD", world, f'["{properties.AMBIENT_COLOR[0]}"]')


def _output_node(tree):
    node = tree.nodes.get(OUTPUT)
    if node is None:
        node = tree.nodes.new("ShaderNodeOutputMaterial")
        node.name = OUTPUT
        node.location = (900.0, 0.0)
    for other in tree.nodes:
        if other.bl_idname == "ShaderNodeOutputMaterial":
            other.is_active_output = other is node
    node.target = "ALL"
    return node


def rebuild(material, lights, world):
    """(Re)build the light part of a Phong material for *lights* (supported light objects)."""
    tree = material.node_tree
    controls = _ensure_controls(tree)
    _clear_generated(tree)
    y = 300.0
    colors = []
    for index, obj in enumerate(lights):
        light_node = _light_node(tree, obj, (-400.0, y))
        shading = _shading_node(tree, f"{GEN}shading:{obj.name}", f"Phong Shading: {obj.name}",
                                (-100.0, y), controls, first=index == 0)
        tree.links.new(light_node.outputs["Light Vector"], shading.inputs["Light Vector"])
        tree.links.new(light_node.outputs["Intensity"], shading.inputs["Light Intensity"])
        drivers.color(shading.inputs["Light Color"], "LIGHT", obj.data, "color")
        for attr, socket in (("diffuse", "Diffuse Strength"), ("specular", "Specular Strength")):
            key = properties.LIGHT_KEYS[attr][0]
            drivers.prop(shading.inputs[socket], None, "LIGHT", obj.data, f'["{key}"]')
        if index == 0:
            _drive_ambient(shading, world)
        else:
            shading.inputs["Ambient Intensity"].default_value = 0.0
        colors.append(shading)
        y -= 520.0
    if not lights:
        shading = _shading_node(tree, f"{GEN}shading:ambient", "Phong Shading: ambient only",
                                (-100.0, y), controls, first=True)
        shading.inputs["Light Intensity"].default_value = 0.0
        _drive_ambient(shading, world)
        colors.append(shading)

    # Sum: Phong Color Add chain.
    color_out = colors[0].outputs["Color"]
    add_group = None
    for index, shading in enumerate(colors[1:], start=1):
        if add_group is None:
            add_group, _status = loader.ensure_group("Phong Color Add")
        add = tree.nodes.new("ShaderNodeGroup")
        add.node_tree = add_group
        add.name = f"{GEN}add:{index}"
        add.label = "Phong Color Add"
        add.location = (250.0 + 180.0 * (index - 1), 300.0 - 200.0 * index)
        tree.links.new(color_out, add.inputs["A"])
        tree.links.new(shading.outputs["Color"], add.inputs["B"])
        color_out = add.outputs["Color"]

    output = _output_node(tree)
    if len(colors) == 1:
        shader_out = colors[0].outputs["Shader"]
    else:
        emission = tree.nodes.new("ShaderNodeEmission")
        emission.name = f"{GEN}emission"
        emission.label = "Phong Emission"
        emission.location = (output.location.x - 200.0, output.location.y)
        emission.inputs["Strength"].default_value = 1.0
        tree.links.new(color_out, emission.inputs["Color"])
        shader_out = emission.outputs["Emission"]
    tree.links.new(shader_out, output.inputs["Surface"])
    aov = tree.nodes.new("ShaderNodeOutputAOV")
    aov.name = f"{GEN}aov"
    aov.label = AOV_NAME
    aov.aov_name = AOV_NAME
    aov.location = (output.location.x, output.location.y - 200.0)
    tree.links.new(color_out, aov.inputs["Color"])
    material["phong_lights"] = [obj.name for obj in lights]
    return material


def _copy_material(template, name, base_color):
    """A new Phong material like *template* (same lights, drivers copied with the node tree)
    with the Object Color of *base_color*.

    Copying instead of building node by node matters with many objects: every node rename
    (``node.name = ...``) makes Blender fix the animation paths of every ID in the file, so
    building the N-th material cost time proportional to the drivers of the N-1 before it.
    """
    material = template.copy()
    material.name = name
    _kind, _label, default, _target = CONTROLS["phong_object_color"]
    value = default if base_color is None else (*tuple(base_color)[:3], 1.0)
    material.node_tree.nodes["phong_object_color"].outputs[0].default_value = value
    return material


def apply_to_object(obj, lights, world, rebuilt=None, templates=None):
    """Give *obj* its Phong material (created, or updated when it has one); returns it.

    An object that already has a Phong material in a slot keeps it (updated).  Otherwise a
    new material "Phong <object>" replaces the material of the active slot (a slot is added
    when the object has none); the other slots are left as they were.

    *rebuilt* (a set, shared by the calls of one operator run) holds the materials already
    built for these lights: objects that share a material (linked duplicates, a shared
    mesh) rebuild it once, not once per object.  *templates* (a dict, shared likewise):
    the first new material is built node by node, the next ones are copies of it.
    """
    for slot in obj.material_slots:
        if is_phong_material(slot.material):
            material = slot.material
            if rebuilt is not None:
                if material.as_pointer() in rebuilt:
                    return material
                rebuilt.add(material.as_pointer())
            return rebuild(material, lights, world)
    active = obj.active_material if obj.material_slots else None
    template = templates.get("new") if templates is not None else None
    if template is not None:
        material = _copy_material(template, f"Phong {obj.name}", principled_color(active))
    else:
        material = new_material(f"Phong {obj.name}", principled_color(active))
    if not obj.material_slots:
        obj.data.materials.append(material)
    else:
        obj.material_slots[obj.active_material_index].material = material
    if rebuilt is not None:
        rebuilt.add(material.as_pointer())
    if template is not None:
        return material
    rebuild(material, lights, world)
    if templates is not None:
        templates["new"] = material
    return material


def phong_materials():
    return [m for m in bpy.data.materials if is_phong_material(m) and m.library is None]


def _warn_unsupported(op, unsupported):
    if unsupported:
        names = ", ".join(f"{o.name} ({o.data.type.title()})" for o in unsupported)
        op.report({"WARNING"}, f"Phong: unsupported light type ignored: {names}; "
                               "only Point, Sun and Spot lights drive Phong materials")


# -- operators ------------------------------------------------------------------

class PHONG_OT_apply_material(bpy.types.Operator):
    """Give the selected mesh objects a Phong material driven by the scene's Point, Sun and Spot lights"""

    bl_idname = "phong.apply_material"
    bl_label = "Apply Phong Material"
    bl_options = {"REGISTER", "UNDO"}

    def execute(self, context):
        selected = list(context.selected_objects or [])
        meshes = [o for o in selected if o.type == "MESH" and o.library is None
                  and o.data.library is None]
        others = [o for o in selected if o not in meshes]
        if not meshes:
            what = (f"no mesh among the selected objects ({', '.join(o.name for o in others)})"
                    if others else "nothing is selected")
            self.report({"ERROR"}, f"Apply Phong Material: {what}; select mesh objects")
            return {"CANCELLED"}
        if others:
            self.report({"WARNING"}, "Apply Phong Material: skipped (not editable meshes): "
                        + ", ".join(o.name for o in others))
        lights, unsupported = scene_lights(context.scene, context.view_layer)
        _warn_unsupported(self, unsupported)
        world = context.scene.world
        rebuilt, templates = set(), {}
        done = list(dict.fromkeys(apply_to_object(obj, lights, world, rebuilt, templates).name
                                  for obj in meshes))
        if not lights:
            self.report({"WARNING"}, "Phong: the scene has no Point, Sun or Spot light; "
                                     "the materials show ambient and irradiant only")
        self.report({"INFO"}, f"Phong materials: {', '.join(done)} "
                              f"({len(lights)} light{'s' if len(lights) != 1 else ''})")
        return {"FINISHED"}


class PHONG_OT_relink_lights(bpy.types.Operator):
    """Bring every Phong material of the file up to date with the lights of the current scene"""

    bl_idname = "phong.relink_lights"
    bl_label = "Relink Phong Lights"
    bl_options = {"REGISTER", "UNDO"}

    def execute(self, context):
        materials = phong_materials()
        lights, unsupported = scene_lights(context.scene, context.view_layer)
        _warn_unsupported(self, unsupported)
        for material in materials:
            rebuild(material, lights, context.scene.world)
        self.report({"INFO"}, f"Phong: {len(materials)} material(s) relinked to "
                              f"{len(lights)} light(s)")
        return {"FINISHED"}


classes = (PHONG_OT_apply_material, PHONG_OT_relink_lights)


register, unregister = bpy.utils.register_classes_factory(classes)
