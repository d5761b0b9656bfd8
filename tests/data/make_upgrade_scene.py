"""Make tests/data/upgrade/phong_<bpy>.blend: a Phong scene as a user makes it, saved by the
Blender release this runs on (the upgrade path of issue 42; tests/test_upgrade.py opens each
file on the newest release, and the newest's file on the LTS before it).

Run with each release's environment, from the repository root:
    PHONG_BPY=4.2.23 bash tools/phong.sh setup
    .venv-bpy4.2.23/bin/python tests/data/make_upgrade_scene.py tests/data/upgrade/phong_4.2.23.blend

What it holds (every control set away from its default, so that a control landing on the wrong
input of the lights group shows): a floor, a smooth sphere with a Phong highlight, a cube with a
Blinn material, a smooth sphere shaded Per Vertex; a point light with the quadratic falloff
(α, β, γ = 0.6, 0.3, 0.2), a point light with the power falloff (k = 1.5), a spot under a
turned and scaled empty with an edge exponent of 4, a sun; the World's Phong ambient; a
perspective camera, 64 x 48 pixels.  Everything made through the extension's public operators
and properties (Apply Phong Material, material.phong.shading, light.phong.*).
"""
import math
import os
import sys
import tempfile

os.environ.setdefault("BLENDER_USER_RESOURCES", tempfile.mkdtemp())

import bpy  # noqa: E402
import bmesh  # noqa: E402  (after bpy)

import phong_nodes  # noqa: E402

phong_nodes.register()
from phong_nodes.addon import compat  # noqa: E402

bpy.ops.wm.read_homefile(use_empty=True)
scene = bpy.context.scene
scene.name = "Upgrade"
scene.render.resolution_x, scene.render.resolution_y = 64, 48
scene.render.resolution_percentage = 100
scene.world = bpy.data.worlds.new("Upgrade World")
scene.world.phong.ambient_intensity = 0.15
scene.world.phong.ambient_color = (0.9, 0.95, 1.0)


def principled(name, color):
    """A Principled source of base colour *color* with Specular IOR Level 0: no specular
    layer, so its Phong version's ambient light sees the Object Color itself (Ka = Kd), as
    Apply made every Phong material of the files saved here; its Specular Color is set below."""
    material = bpy.data.materials.new(name)
    compat.new_material_tree(material)
    node = material.node_tree.nodes["Principled BSDF"]
    node.inputs["Base Color"].default_value = color
    node.inputs["Specular IOR Level"].default_value = 0.0
    return material


def mesh_object(name, build, material, location=(0.0, 0.0, 0.0), smooth=False):
    mesh = bpy.data.meshes.new(name)
    bm = bmesh.new()
    build(bm)
    bm.to_mesh(mesh)
    bm.free()
    for polygon in mesh.polygons:
        polygon.use_smooth = smooth
    mesh.materials.append(material)
    obj = bpy.data.objects.new(name, mesh)
    obj.location = location
    scene.collection.objects.link(obj)
    return obj


floor = mesh_object("Floor", lambda bm: bmesh.ops.create_grid(bm, x_segments=4, y_segments=4,
                                                                 size=3.0),
                    principled("Floor Paint", (0.5, 0.55, 0.6, 1.0)))
ball = mesh_object("Ball", lambda bm: bmesh.ops.create_uvsphere(bm, u_segments=32, v_segments=16,
                                                                 radius=0.7),
                   principled("Clay", (0.7, 0.3, 0.1, 1.0)), (-1.0, 0.2, 0.7), smooth=True)
cube = mesh_object("Cube", lambda bm: bmesh.ops.create_cube(bm, size=0.9),
                   principled("Enamel", (0.1, 0.35, 0.8, 1.0)), (1.1, 0.6, 0.45))
cube.rotation_euler = (0.0, 0.0, math.radians(30.0))
bead = mesh_object("Bead", lambda bm: bmesh.ops.create_uvsphere(bm, u_segments=24, v_segments=12,
                                                                 radius=0.45),
                   principled("Jade", (0.2, 0.7, 0.4, 1.0)), (0.3, -1.0, 0.45), smooth=True)


def light(name, kind, location, rotation=(0.0, 0.0, 0.0), color=(1.0, 1.0, 1.0)):
    obj = bpy.data.objects.new(name, bpy.data.lights.new(name, kind))
    obj.location, obj.rotation_euler = location, rotation
    obj.data.color = color
    scene.collection.objects.link(obj)
    return obj


key = light("Key", "POINT", (2.0, -2.0, 3.0), color=(1.0, 0.92, 0.8))
key.data.phong.intensity = 9.0
key.data.phong.quadratic, key.data.phong.linear, key.data.phong.constant = 0.6, 0.3, 0.2
fill = light("Fill", "POINT", (-2.5, -1.5, 2.0), color=(0.7, 0.8, 1.0))
fill.data.phong.intensity = 3.0
fill.data.phong.falloff = "POWER"
fill.data.phong.power_k = 1.5
rig = bpy.data.objects.new("Spot Rig", None)
rig.location = (0.0, 2.5, 2.0)
rig.rotation_euler = (math.radians(-35.0), 0.0, math.radians(10.0))
rig.scale = (1.5, 1.5, 1.5)
scene.collection.objects.link(rig)
spot = light("Spot", "SPOT", (0.0, 0.0, 0.0), color=(1.0, 0.85, 0.9))
spot.parent = rig
spot.data.spot_size = math.radians(70.0)
spot.data.phong.intensity = 6.0
spot.data.phong.edge_exponent = 4.0
sun = light("Sun", "SUN", (0.0, 0.0, 5.0), (math.radians(40.0), math.radians(-20.0), 0.3))
sun.data.phong.intensity = 0.35

camera = bpy.data.objects.new("Camera", bpy.data.cameras.new("Camera"))
camera.location = (0.0, -6.5, 4.2)
camera.rotation_euler = (math.radians(58.0), 0.0, 0.0)
scene.collection.objects.link(camera)
scene.camera = camera

for obj in (floor, ball, cube, bead):
    obj.select_set(True)
bpy.context.view_layer.objects.active = ball
assert bpy.ops.phong.apply_material() == {"FINISHED"}


def control(material, name, value):
    node = material.node_tree.nodes[name]
    socket = node.outputs[0]
    socket.default_value = value


clay, enamel, jade = (o.active_material for o in (ball, cube, bead))
control(clay, "phong_specular_color", (0.9, 0.8, 0.6, 1.0))
control(clay, "phong_exponent", 24.0)
control(clay, "phong_irradiant_color", (0.03, 0.0, 0.02, 1.0))
control(enamel, "phong_blinn", 1.0)
control(enamel, "phong_exponent", 60.0)
control(enamel, "phong_specular_color", (0.6, 0.7, 1.0, 1.0))
control(jade, "phong_exponent", 12.0)
control(jade, "phong_specular_color", (1.0, 1.0, 1.0, 1.0))
control(floor.active_material, "phong_specular_color", (1.0, 1.0, 1.0, 1.0))
jade.phong.shading = "VERTEX"
assert bpy.ops.phong.relink_lights() == {"FINISHED"}
print("saved by bpy", bpy.app.version_string, "materials",
      sorted(m.name for m in bpy.data.materials))
bpy.ops.wm.save_as_mainfile(filepath=os.path.abspath(sys.argv[-1]), compress=True)
sys.stdout.flush()
os._exit(0)  # bpy 4.5.15 can hang in its exit after a save
