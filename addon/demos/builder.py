# SPDX-License-Identifier: GPL-3.0-or-later
"""Build a demo scene (a validated dict from ``scenes.py``) into a new Blender scene.

One material per scene, shared by all its objects: the per-object values (colours,
exponent, Blinn, which terms and which lights apply) are object custom properties read
through Attribute nodes, so Eevee compiles one shader per scene instead of one per object.
The lights' values are group-node inputs of that material.  Blender light objects are
added too (so the scene reads well in the viewport) but do not light anything: the
materials are pure Phong emission.

AOV outputs (position, normal, incoming, object colour, object index) feed the numpy
reference of the comparison bake; they are muted for Eevee renders (each AOV costs
shader compile time there).
"""

from __future__ import annotations

import json
import math

import bpy

from .. import compat, loader
from ..lighting import properties
from . import meshes, render

#: Custom property on a built scene: the scene dict (JSON) it was built from.
SCENE_KEY = "phong_demo"
#: AOVs written by every demo material: name -> (type, what)
AOVS = {
    "phong_P": ("COLOR", "position"),
    "phong_N": ("COLOR", "normal"),
    "phong_I": ("COLOR", "incoming"),
    "phong_color": ("COLOR", "object colour"),
    "phong_index": ("VALUE", "object index"),
}
#: UV sphere resolution (segments, rings).
SPHERE_SEGMENTS = (64, 32)
AOV_LAYER = "Phong AOVs"
PICTURE_LAYER = "Phong Picture"


def build(scene_dict: dict, resolution: int = 128) -> bpy.types.Scene:
    """A new scene for *scene_dict*; the user's scenes are not touched."""
    loader.load_all()
    data = scene_dict
    scene = bpy.data.scenes.new(f"Phong {data['name']}")
    scene[SCENE_KEY] = json.dumps(data)
    render.plain_picture(scene, max(1, round(resolution * data["aspect"])), resolution)
    _black_world(scene, data["name"])
    # The scene's ambient light as the Phong world settings (issue 3's custom properties).
    properties.write_world(scene.world, data["ambient"]["intensity"], data["ambient"]["color"])
    _view_layers(scene)

    material = _material(data)
    for index, obj_data in enumerate(data["objects"], start=1):
        obj = _object(scene, obj_data, data)
        obj.data.materials.append(material)
        _object_props(obj, obj_data, data, index)
    for light_data in data["lights"]:
        _light(scene, light_data)
    _camera(scene, data["camera"], data["name"])
    return scene


def scene_dict(scene) -> dict | None:
    text = scene.get(SCENE_KEY)
    return json.loads(text) if text else None


# -- scene parts -----------------------------------------------------------------

def _black_world(scene, name):
    world = bpy.data.worlds.new(f"Phong {name}")
    compat.black_world(world)
    scene.world = world


def _view_layers(scene):
    """Two view layers: the picture (no AOVs, for Eevee) and the AOVs (for Cycles)."""
    picture = scene.view_layers[0]
    picture.name = PICTURE_LAYER
    aov_layer = scene.view_layers.new(AOV_LAYER)
    for name, (kind, _what) in AOVS.items():
        aov = aov_layer.aovs.add()
        aov.name = name
        aov.type = kind
    aov_layer.use = False


def _object(scene, obj_data, data):
    name = obj_data["name"]
    size = obj_data["size"]
    if obj_data["shape"] == "sphere":
        mesh = meshes.uv_sphere(f"{data['name']}.{name}", size, *SPHERE_SEGMENTS)
    else:
        mesh = bpy.data.meshes.new(f"{data['name']}.{name}")
        verts = [(-size, -size, 0.0), (size, -size, 0.0), (size, size, 0.0), (-size, size, 0.0)]
        mesh.from_pydata(verts, [], [(0, 1, 2, 3)])
        uv = mesh.uv_layers.new(name="UVMap")
        for loop in mesh.loops:
            x, y, _z = verts[loop.vertex_index]
            uv.data[loop.index].uv = ((x / size + 1) / 2, (y / size + 1) / 2)
    mesh.update()
    obj = bpy.data.objects.new(name, mesh)
    obj.location = obj_data["location"]
    obj.rotation_euler = [math.radians(a) for a in obj_data["rotation"]]
    scene.collection.objects.link(obj)
    return obj


def _object_props(obj, obj_data, data, index):
    """The per-object values the shared material reads (Attribute nodes, type Object).

    Packed four floats to an attribute: Eevee reads at most 8 object attributes per
    material (GPU_MAX_UNIFORM_ATTR), the rest silently read 0.
    """
    mat = obj_data["material"]
    terms = set(obj_data["terms"])
    tex = mat["texture"]
    irradiant = list(mat["irradiant"]) if "irradiant" in terms else [0.0, 0.0, 0.0]
    ambient = data["ambient"]["intensity"] if "ambient" in terms else 0.0
    obj["phong_index"] = float(index)
    obj["phong_color"] = [*mat["color"], mat["exponent"]]
    obj["phong_specular_color"] = [*mat["specular_color"], mat["blinn"]]
    obj["phong_irradiant"] = [*irradiant, ambient]
    # Not textured: both checker colours are the object colour.
    obj["phong_color2"] = [*(tex["color2"] if tex else mat["color"]),
                           tex["scale"] if tex else 1.0]
    lights = data["lights"]
    for pack in range(max(1, math.ceil(len(lights) / 4))):
        dif, spe = [0.0] * 4, [0.0] * 4
        for j, light in enumerate(lights[4 * pack:4 * pack + 4]):
            on = light["name"] in obj_data["lights"]
            dif[j] = light["diffuse"] if on and "diffuse" in terms else 0.0
            spe[j] = light["specular"] if on and "specular" in terms else 0.0
        obj[f"phong_diffuse_{pack}"] = dif
        obj[f"phong_specular_{pack}"] = spe


def _light(scene, light_data):
    kind = {"point": "POINT", "directional": "SUN", "spot": "SPOT"}[light_data["type"]]
    light = bpy.data.lights.new(light_data["name"], kind)
    light.color = [min(c, 1.0) for c in light_data["color"]]
    if hasattr(light, "use_shadow"):
        light.use_shadow = False
    obj = bpy.data.objects.new(light_data["name"], light)
    if "position" in light_data:
        obj.location = light_data["position"]
    if "direction" in light_data:
        from mathutils import Vector

        obj.rotation_euler = Vector(light_data["direction"]).to_track_quat("-Z", "Y").to_euler()
    if kind == "SPOT":
        light.spot_size = math.radians(2 * light_data["half_angle"])
        light.spot_blend = 0.0
    # Phong settings, readable by the Phong panels.
    properties.write_light(light, {key: light_data[key] for key in properties.LIGHT_KEYS
                                   if key in light_data})
    obj.visible_camera = False
    scene.collection.objects.link(obj)
    return obj


def _camera(scene, cam_data, name):
    from mathutils import Vector

    cam = bpy.data.cameras.new(f"Phong {name}")
    cam.type = "ORTHO" if cam_data["type"] == "orthographic" else "PERSP"
    cam.lens = cam_data["lens"]
    cam.ortho_scale = cam_data["ortho_scale"]
    cam.sensor_fit = "AUTO"
    cam.clip_start, cam.clip_end = 0.05, 200.0
    obj = bpy.data.objects.new(f"Phong {name} camera", cam)
    obj.location = cam_data["location"]
    direction = Vector(cam_data["look_at"]) - Vector(cam_data["location"])
    obj.rotation_euler = direction.to_track_quat("-Z", "Y").to_euler()
    scene.collection.objects.link(obj)
    scene.camera = obj


# -- the material -------------------------------------------------------------------

class _Tree:
    def __init__(self, tree):
        self.tree = tree
        self.attrs = {}

    def node(self, kind, x, y, **props):
        node = self.tree.nodes.new(kind)
        node.location = (x, y)
        for key, value in props.items():
            setattr(node, key, value)
        return node

    def group(self, name, x, y):
        node = self.node("ShaderNodeGroup", x, y)
        node.node_tree, _status = loader.ensure_group(name)
        node.width = 200
        return node

    def attr(self, name, vector=False, component=None):
        """Output socket of an Object attribute node: Color (vector), Fac, or one
        component 0-3 of a packed 4-float attribute (x, y, z through Separate XYZ, alpha)."""
        if name not in self.attrs:
            node = self.node("ShaderNodeAttribute", -1400, 600 - 140 * len(self.attrs),
                             attribute_type="OBJECT", attribute_name=name, label=name)
            self.attrs[name] = node
        node = self.attrs[name]
        if component == 3:
            return node.outputs["Alpha"]
        if component is not None:
            key = "sep:" + name
            if key not in self.attrs:
                self.attrs[key] = self.node("ShaderNodeSeparateXYZ", node.location.x + 200,
                                            node.location.y)
                self.link(node.outputs["Vector"], self.attrs[key].inputs[0])
            return self.attrs[key].outputs[component]
        return node.outputs["Color" if vector else "Fac"]

    def link(self, a, b):
        self.tree.links.new(a, b)


def _material(data) -> bpy.types.Material:
    material = bpy.data.materials.new(f"Phong {data['name']}")
    t = _Tree(compat.new_material_tree(material))
    t.tree.nodes.clear()
    color = t.attr("phong_color", vector=True)
    if any(o["material"]["texture"] for o in data["objects"]):
        coords = t.node("ShaderNodeTexCoord", -1400, -600)
        checker = t.node("ShaderNodeTexChecker", -1150, -500)
        t.link(coords.outputs["Object"], checker.inputs["Vector"])
        t.link(color, checker.inputs["Color1"])
        t.link(t.attr("phong_color2", vector=True), checker.inputs["Color2"])
        t.link(t.attr("phong_color2", component=3), checker.inputs["Scale"])
        color = checker.outputs["Color"]

    shadings = []
    lights = data["lights"] or [None]
    for k, light in enumerate(lights):
        y = 400 - 700 * k
        shading = t.group("Phong Shading", -300, y)
        light_vector, intensity = _light_nodes(t, light, -700, y)
        if light is None:
            shading.inputs["Light Intensity"].default_value = 0.0
            shading.inputs["Diffuse Strength"].default_value = 0.0
            shading.inputs["Specular Strength"].default_value = 0.0
        else:
            t.link(light_vector, shading.inputs["Light Vector"])
            t.link(intensity, shading.inputs["Light Intensity"])
            shading.inputs["Light Color"].default_value = (*light["color"], 1.0)
            pack, comp = divmod(k, 4)
            t.link(t.attr(f"phong_diffuse_{pack}", component=comp),
                   shading.inputs["Diffuse Strength"])
            t.link(t.attr(f"phong_specular_{pack}", component=comp),
                   shading.inputs["Specular Strength"])
        t.link(color, shading.inputs["Object Color"])
        t.link(t.attr("phong_specular_color", vector=True), shading.inputs["Specular Color"])
        t.link(t.attr("phong_color", component=3), shading.inputs["Exponent"])
        t.link(t.attr("phong_specular_color", component=3), shading.inputs["Blinn"])
        if k == 0:  # ambient and irradiant counted once
            t.link(t.attr("phong_irradiant", vector=True), shading.inputs["Irradiant Color"])
            t.link(t.attr("phong_irradiant", component=3), shading.inputs["Ambient Intensity"])
            shading.inputs["Ambient Color"].default_value = (*data["ambient"]["color"], 1.0)
        else:
            shading.inputs["Irradiant Color"].default_value = (0.0, 0.0, 0.0, 1.0)
            shading.inputs["Ambient Intensity"].default_value = 0.0
        shadings.append(shading)

    out = t.node("ShaderNodeOutputMaterial", 700, 0)
    if len(shadings) == 1:
        t.link(shadings[0].outputs["Shader"], out.inputs["Surface"])
        final = shadings[0].outputs["Color"]
    else:
        final = shadings[0].outputs["Color"]
        for k, shading in enumerate(shadings[1:], start=1):
            add = t.group("Phong Color Add", 50 + 60 * k, 300 - 200 * k)
            t.link(final, add.inputs["A"])
            t.link(shading.outputs["Color"], add.inputs["B"])
            final = add.outputs["Color"]
        emission = t.node("ShaderNodeEmission", 450, 0)
        emission.inputs["Strength"].default_value = 1.0
        t.link(final, emission.inputs["Color"])
        t.link(emission.outputs["Emission"], out.inputs["Surface"])

    reroute = t.node("NodeReroute", 300, -400)
    reroute.name = "phong_color_out"
    t.link(color, reroute.inputs[0])
    geometry = t.node("ShaderNodeNewGeometry", 300, -500)
    geometry.name = "phong_geometry"
    index = t.attr("phong_index").node
    index.name = "phong_index_attr"
    _add_aovs(t.tree)
    return material


def _light_nodes(t, light, x, y):
    """(Light Vector, Intensity) output sockets for one light (None: no light)."""
    if light is None:
        return None, None
    kind = light["type"]
    if kind == "directional":
        node = t.group("Phong Directional Light", x, y)
        node.inputs["Direction"].default_value = light["direction"]
        node.inputs["Intensity"].default_value = light["intensity"]
        return node.outputs["Light Vector"], node.outputs["Intensity"]
    name = "Phong Point Light" if kind == "point" else "Phong Spot Light"
    node = t.group(name, x, y)
    node.inputs["Position"].default_value = light["position"]
    node.inputs["Intensity"].default_value = light["intensity"]
    for key in ("quadratic", "linear", "constant"):
        node.inputs[key.capitalize()].default_value = light[key]
    if kind == "spot":
        node.inputs["Direction"].default_value = light["direction"]
        node.inputs["Half Angle"].default_value = math.radians(light["half_angle"])
        node.inputs["Edge Exponent"].default_value = light["edge_exponent"]
    if kind == "point" and "falloff_exponent" in light:
        falloff = t.group("Phong Power Falloff", x + 100, y - 250)
        t.link(node.outputs["Distance"], falloff.inputs["Distance"])
        falloff.inputs["Intensity"].default_value = light["intensity"]
        falloff.inputs["Exponent"].default_value = light["falloff_exponent"]
        return node.outputs["Light Vector"], falloff.outputs["Intensity"]
    return node.outputs["Light Vector"], node.outputs["Intensity"]


def _add_aovs(tree):
    geometry = tree.nodes["phong_geometry"].outputs
    sources = {"phong_P": geometry["Position"], "phong_N": geometry["Normal"],
               "phong_I": geometry["Incoming"],
               "phong_color": tree.nodes["phong_color_out"].outputs[0],
               "phong_index": tree.nodes["phong_index_attr"].outputs["Fac"]}
    for i, (name, (kind, _what)) in enumerate(AOVS.items()):
        aov = tree.nodes.new("ShaderNodeOutputAOV")
        aov.location = (700, -300 - 120 * i)
        aov.label = f"AOV {name}"
        aov.aov_name = name
        tree.links.new(sources[name], aov.inputs["Value" if kind == "VALUE" else "Color"])


def set_aov_outputs(scene, enabled: bool):
    """Add (Cycles) or remove (Eevee) the AOV outputs of the scene's demo materials.

    Muting is not enough: Eevee still compiles muted AOV outputs, which costs about a
    minute per material on software GL against under two seconds without them.
    """
    materials = {slot.material for obj in scene.objects
                 for slot in getattr(obj, "material_slots", ()) if slot.material}
    for material in materials:
        tree = material.node_tree
        if tree is None or "phong_geometry" not in tree.nodes:
            continue
        aovs = [n for n in tree.nodes if n.bl_idname == "ShaderNodeOutputAOV"]
        if enabled and not aovs:
            _add_aovs(tree)
        elif not enabled:
            for node in aovs:
                tree.nodes.remove(node)
