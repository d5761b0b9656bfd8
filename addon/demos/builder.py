# SPDX-License-Identifier: GPL-3.0-or-later
"""Build a demo scene (a validated dict from ``core/scenes.py``) into a new Blender scene:
an ordinary artist's scene, made by the same code as Apply Phong Material.

* every light of the file is a real Point / Sun / Spot light with its Phong settings
  (``falloff_exponent`` k = 0, 1, 2 is read as γ, β or α = 1, any other k as the light's
  power falloff: i0/d^k exactly);
* a light's ``lights = [...]`` lists of the objects become Blender Light Linking (a
  receiver collection per light that does not reach every object);
* the ambient light is the World's Phong settings;
* each object gets a Principled material of its colour (a checker texture feeding Base
  Color when it has one), converted by :class:`..lighting.sync.Sync` like Apply Phong
  Material does; the Phong controls then take the file's values.  Untextured materials are
  copies of one template, so Eevee compiles one shader per light set, not one per object;
* an object's ``terms`` are values of its controls: Specular Color black without
  "specular", Object Color black without "diffuse", the material's own Ambient Object Color
  (the colour the ambient light sees) black without "ambient", Irradiant black without
  "irradiant".

Moving, recolouring or re-aiming a light then changes the picture, as in any scene.
"""

from __future__ import annotations

import json
import math

import bpy
from mathutils import Vector

from .. import compat
from ..baking import lighting, show
from ..lighting import properties, recipe, rig, writer
from ..lighting import sources as source_materials
from ..lighting import sync as sync_mod
from ..scene import meshes, render
from ..shading import modes as shading_modes
from ..scene.describe import SCENE_FILE_LIGHTS, SCENE_KEY, scene_file

BLACK = (0.0, 0.0, 0.0)


def build(data: dict, resolution: int = 256) -> bpy.types.Scene:
    """A new scene for the scene file *data*; the user's scenes are not touched."""
    scene = bpy.data.scenes.new(data["name"])
    scene[SCENE_KEY] = json.dumps({k: v for k, v in data.items() if k != "path"})
    scene[rig.MODEL_KEY] = data.get("model", rig.MODELS[0])
    render.plain_picture(scene, max(1, round(resolution * data["aspect"])), resolution)
    scene.render.engine = compat.eevee_engine()
    world = bpy.data.worlds.new(f"Phong {data['name']}")
    compat.black_world(world)
    scene.world = world
    properties.write_world(world, data["ambient"]["intensity"], data["ambient"]["color"])
    objects = {o["name"]: _object(scene, o, data["name"]) for o in data["objects"]}
    for light_data in data["lights"]:
        light = _light(scene, light_data)
        reached = [objects[o["name"]] for o in data["objects"]
                   if light_data["name"] in o["lights"]]
        if len(reached) < len(objects):
            _link(light, reached, list(objects.values()))
    _camera(scene, data["camera"], data["name"])

    with sync_mod.session(scene, scene.view_layers[0]) as sync:
        for obj_data in data["objects"]:
            obj = objects[obj_data["name"]]
            (material,) = sync.apply(obj)
            _controls(material, obj_data)
    for obj_data in data["objects"]:  # Per Vertex / Per Face: live (docs/shading_modes.md)
        shading = obj_data["material"].get("shading", "pixel").upper()
        if shading != shading_modes.PIXEL:
            shading_modes.set_mode(objects[obj_data["name"]].active_material, shading)
    for obj_data in data["objects"]:
        if obj_data.get("bake"):
            _bake(scene, objects[obj_data["name"]], obj_data["bake"])
    return scene


def _bake(scene, obj, target: str) -> None:
    """*obj* baked (Bake Phong Lighting, its image packed) and showing its bake."""
    settings = lighting.Settings(target=target.upper(), resolution=256, pack=True)
    show.bake_objects(scene, [obj], settings, display=True)


# -- scene parts -----------------------------------------------------------------------

def _object(scene, obj_data, scene_name):
    name = obj_data["name"]
    size = obj_data["size"]
    if obj_data["shape"] == "sphere":
        segments = obj_data.get("segments", 64)
        mesh = meshes.uv_sphere(f"{scene_name}.{name}", size, segments, max(2, segments // 2),
                                uvs=True)
    else:
        mesh = bpy.data.meshes.new(f"{scene_name}.{name}")
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
    if not obj_data.get("shadows", True):
        compat.set_casts_shadow(obj, False)
    scene.collection.objects.link(obj)
    mesh.materials.append(_source_material(f"{scene_name}.{name}", obj_data["material"]))
    return obj


def _source_material(name, mat):
    """What an artist would have before Apply Phong Material: a Principled BSDF of the
    object colour, with the checker texture on Base Color when the file gives one."""
    material = bpy.data.materials.new(name)
    tree = compat.new_material_tree(material)
    principled = next(n for n in tree.nodes if n.bl_idname == "ShaderNodeBsdfPrincipled")
    principled.inputs["Base Color"].default_value = (*mat["color"], 1.0)
    material.diffuse_color = (*mat["color"], 1.0)
    texture = mat["texture"]
    if texture is not None:
        coords = tree.nodes.new("ShaderNodeTexCoord")
        coords.location = (-700.0, 300.0)
        checker = tree.nodes.new("ShaderNodeTexChecker")
        checker.location = (-450.0, 300.0)
        checker.inputs["Color1"].default_value = (*mat["color"], 1.0)
        checker.inputs["Color2"].default_value = (*texture["color2"], 1.0)
        checker.inputs["Scale"].default_value = texture["scale"]
        tree.links.new(coords.outputs["Object"], checker.inputs["Vector"])
        tree.links.new(checker.outputs["Color"], principled.inputs["Base Color"])
    return material


def _controls(material, obj_data) -> None:
    """The file's values and terms on the Phong controls of *material*."""
    mat, terms = obj_data["material"], set(obj_data["terms"])
    tree = material.node_tree
    lights = tree.nodes[recipe.LIGHTS_NODE]
    color_feed = lights.inputs["Object Color"].links[0].from_socket
    textured = not writer.controlled(material, "Object Color")
    # The ambient light sees the material's own Ambient Object Color control: the model's
    # ambient colour (the object colour; X3D: ambient_intensity × it), or black without the
    # ambient term (the same layout for every object).  Textured: the texture (× X3D's
    # ambient_intensity).
    own_ambient = not (textured and "ambient" in terms)
    colors = {"Specular Color": mat["specular_color"] if "specular" in terms else BLACK,
              "Irradiant Color": mat["irradiant"] if "irradiant" in terms else BLACK}
    if own_ambient:
        colors[recipe.AMBIENT_INPUT] = mat["ambient_color"] if "ambient" in terms else BLACK
    colors["Object Color"] = mat["color"] if "diffuse" in terms else BLACK
    # three.js: MeshLambertMaterial, or no specular term, is specularStrength 0 (a black
    # specular colour alone would keep three.js's Fresnel reflection)
    lambert = mat.get("type") == "lambert" or "specular" not in terms
    controls = writer.write(material, writer.Values(
        colors, exponent=mat["exponent"], blinn=mat["blinn"],
        specular_strength=0.0 if lambert else 1.0), link=False,
        ambient_label="Ambient Object Color")
    if own_ambient:
        ambient = controls[recipe.AMBIENT_INPUT]
    else:
        ambient = color_feed
        if mat.get("ambient_intensity") is not None:
            ambient = _scaled(tree, color_feed, mat["ambient_intensity"])
    tree.links.new(ambient, lights.inputs[recipe.AMBIENT_INPUT])
    if textured and "diffuse" not in terms:
        tree.links.new(controls["Object Color"], lights.inputs["Object Color"])


def _scaled(tree, socket, factor):
    """*socket* (a colour) × *factor*, by a Vector Math Scale node named "ambient_scale"."""
    node = tree.nodes.new("ShaderNodeVectorMath")
    node.name = node.label = "ambient_scale"
    node.operation = "SCALE"
    node.location = (socket.node.location.x + 250.0, socket.node.location.y - 250.0)
    tree.links.new(socket, compat.input_socket(node, "Vector"))
    compat.input_socket(node, "Scale").default_value = float(factor)
    return compat.output_socket(node, "Vector")


def _link(light, reached, everyone) -> None:
    """Blender Light Linking: *light* reaches only the objects *reached* (a receiver
    collection including them, or excluding every object when it reaches none)."""
    collection = bpy.data.collections.new(f"Light Linking for {light.name}")
    members = reached or everyone
    for obj in members:
        collection.objects.link(obj)
    for entry in collection.collection_objects:
        entry.light_linking.link_state = "INCLUDE" if reached else "EXCLUDE"
    light.light_linking.receiver_collection = collection


def _light(scene, light_data):
    kind = SCENE_FILE_LIGHTS[light_data["type"]]
    light = bpy.data.lights.new(light_data["name"], kind)
    light.color = light_data["color"]
    light.use_shadow = bool(light_data.get("shadows", False))  # the seeds' lights cast none
    obj = bpy.data.objects.new(light_data["name"], light)
    if "position" in light_data:
        obj.location = light_data["position"]
    if "direction" in light_data:
        obj.rotation_euler = Vector(light_data["direction"]).to_track_quat("-Z", "Y").to_euler()
    values = {key: light_data[key] for key in properties.LIGHT_KEYS if key in light_data}
    values.setdefault("intensity", 1.0)  # a scene file's light has its own i0, not its watts
    if "falloff" in light_data:  # a falloff_exponent other than 0, 1, 2: i0/d^k
        values["falloff"] = light_data["falloff"]
    if kind == "SPOT":
        light.spot_size = math.radians(2 * light_data["half_angle"])
        light.spot_blend = 0.0
    properties.write_light(light, values)
    scene.collection.objects.link(obj)
    return obj


def _camera(scene, cam_data, name):
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


def remove(scene) -> None:
    """Remove a built scene and the data made for it (objects, meshes, lights, materials and
    their sources, lights groups, light-linking collections, world, camera)."""

    doomed = set()
    for obj in scene.objects:
        doomed.add(obj)
        if obj.data is not None:
            doomed.add(obj.data)
        for slot in obj.material_slots:
            if slot.material is not None:
                doomed.add(slot.material)
                source = source_materials.source_of(slot.material)
                if source is not None:
                    doomed.add(source)
        linking = getattr(obj, "light_linking", None)
        if linking is not None and linking.receiver_collection is not None:
            doomed.add(linking.receiver_collection)
    doomed.update(rig.groups_of(scene))
    if scene.world is not None:
        doomed.add(scene.world)
    bpy.data.scenes.remove(scene)
    bpy.data.batch_remove(list(doomed))
