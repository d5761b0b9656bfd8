#!/usr/bin/env python3
"""Make docs/lights_workflow.png: the artist workflow of README.md, done by a script.

Three ordinary Blender lights (a warm point light, a cool sun, a spot with a soft edge),
three meshes, `bpy.ops.phong.apply_material()`, one Eevee render (Standard view transform).
Run: .venv/bin/python tools/readme_pictures.py
"""

import math
import os
import sys

sys.dont_write_bytecode = True

import phong_nodes  # noqa: E402  (the source tree, linked by tools/phong.sh setup)

ROOT = os.path.dirname(phong_nodes.__file__)


def main():
    import bpy

    phong_nodes.register()
    from phong_nodes.addon import compat
    from phong_nodes.addon.demos import meshes

    scene = bpy.context.scene
    for obj in list(scene.objects):
        bpy.data.objects.remove(obj)
    world = bpy.data.worlds.new("World")
    compat.black_world(world)
    scene.world = world
    world.phong.ambient_intensity = 0.08

    def add(name, data, location, rotation=(0, 0, 0)):
        obj = bpy.data.objects.new(name, data)
        obj.location, obj.rotation_euler = location, rotation
        scene.collection.objects.link(obj)
        return obj

    floor = bpy.data.meshes.new("Floor")
    floor.from_pydata([(-6, -6, 0), (6, -6, 0), (6, 6, 0), (-6, 6, 0)], [], [(0, 1, 2, 3)])
    add("Floor", floor, (0, 0, 0))
    for i, color in enumerate(((1.0, 0.25, 0.09), (0.2, 0.6, 0.25), (0.25, 0.35, 1.0))):
        material = bpy.data.materials.new(f"Ball {i}")  # a user's Principled material
        compat.new_material_tree(material).nodes["Principled BSDF"].inputs[
            "Base Color"].default_value = (*color, 1.0)
        mesh = meshes.uv_sphere(f"Ball {i}", 0.8, 64, 32)
        mesh.materials.append(material)
        add(f"Ball {i}", mesh, ((i - 1) * 2.0, 0, 0.8))

    point = add("Point", bpy.data.lights.new("Point", "POINT"), (-2.5, -2.5, 3.0))
    point.data.color = (1.0, 0.85, 0.7)
    point.data.phong.intensity = 12.0
    sun = add("Sun", bpy.data.lights.new("Sun", "SUN"), (0, 0, 5), (math.radians(50), 0, math.radians(140)))
    sun.data.color = (0.45, 0.55, 1.0)
    sun.data.phong.intensity = 0.35
    spot = add("Spot", bpy.data.lights.new("Spot", "SPOT"), (2.5, -1.5, 4.0), (math.radians(25), 0, math.radians(30)))
    spot.data.spot_size = math.radians(50)
    spot.data.phong.intensity = 14.0
    spot.data.phong.edge_exponent = 20.0

    for obj in scene.objects:
        obj.select_set(obj.type == "MESH")
    bpy.context.view_layer.objects.active = bpy.data.objects["Ball 0"]
    bpy.ops.phong.apply_material()

    camera = add("Camera", bpy.data.cameras.new("Camera"), (0, -9.5, 4.5), (math.radians(68), 0, 0))
    scene.camera = camera
    scene.render.engine = compat.eevee_engine()
    scene.eevee.taa_render_samples = 16
    scene.view_settings.view_transform = "Standard"
    scene.render.resolution_x, scene.render.resolution_y = 640, 320
    compat.set_png(scene.render.image_settings)
    out = os.path.join(ROOT, "docs", "lights_workflow.png")
    scene.render.filepath = out
    bpy.ops.render.render(write_still=True)
    print(out)


if __name__ == "__main__":
    main()
    from phong_nodes.addon import compat

    compat.exit_process(0)
