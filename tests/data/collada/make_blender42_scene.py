# SPDX-License-Identifier: GPL-3.0-or-later
"""Makes tests/data/collada/blender42_scene.dae with Blender 4.2's own COLLADA exporter:

    .venv-bpy4.2.23/bin/python tests/data/collada/make_blender42_scene.py tests/data/collada/blender42_scene.dae
"""

import math
import sys

import bpy

out = sys.argv[-1]
bpy.ops.wm.read_factory_settings(use_empty=True)
scene = bpy.context.scene
mesh = bpy.data.meshes.new("Tile")
mesh.from_pydata([(-1, -1, 0), (1, -1, 0), (1, 1, 0), (-1, 1, 0)], [], [(0, 1, 2, 3)])
tile = bpy.data.objects.new("Tile", mesh); scene.collection.objects.link(tile)
mat = bpy.data.materials.new("Glazed tile"); mat.use_nodes = True
bsdf = mat.node_tree.nodes["Principled BSDF"]
bsdf.inputs["Base Color"].default_value = (0.1, 0.3, 0.6, 1.0)
mesh.materials.append(mat)
spot = bpy.data.objects.new("Spot", bpy.data.lights.new("Spot", "SPOT")); scene.collection.objects.link(spot)
spot.location = (0, 0, 3); spot.data.spot_size = math.radians(60.0); spot.data.spot_blend = 0.25
spot.data.color = (1.0, 0.9, 0.8)
point = bpy.data.objects.new("Bulb", bpy.data.lights.new("Bulb", "POINT")); scene.collection.objects.link(point)
point.location = (1, 2, 3)
sun = bpy.data.objects.new("Sun", bpy.data.lights.new("Sun", "SUN")); scene.collection.objects.link(sun)
sun.rotation_euler = (0.3, 0.2, 0.0)
cam = bpy.data.objects.new("Camera", bpy.data.cameras.new("Camera")); scene.collection.objects.link(cam)
cam.location = (0, -6, 4); cam.rotation_euler = (math.radians(55), 0, 0)
print(bpy.ops.wm.collada_export(filepath=out))
