"""Make tests/data/phong_0_2.blend with the previous release's code (rig 3, layout 4)."""
import os, sys, math, tempfile
os.environ.setdefault("BLENDER_USER_RESOURCES", tempfile.mkdtemp())
import bpy
import phong_nodes
print("code from", phong_nodes.__file__)
phong_nodes.register()
from phong_nodes.addon import compat
bpy.ops.wm.read_homefile(use_empty=True)
scene = bpy.context.scene
scene.name = "Old"
scene.world = bpy.data.worlds.new("Old World")
scene.world.phong.ambient_intensity = 0.1
scene.world.phong.ambient_color = (1.0, 0.9, 0.8)
clay = bpy.data.materials.new("Clay")
compat.new_material_tree(clay)
clay.node_tree.nodes["Principled BSDF"].inputs["Base Color"].default_value = (0.7, 0.3, 0.1, 1.0)
mesh = bpy.data.meshes.new("Ball")
import bmesh
bm = bmesh.new(); bmesh.ops.create_uvsphere(bm, u_segments=24, v_segments=12, radius=1.0); bm.to_mesh(mesh); bm.free()
for p in mesh.polygons: p.use_smooth = True
mesh.materials.append(clay)
ball = bpy.data.objects.new("Ball", mesh); scene.collection.objects.link(ball)
def light(name, kind, loc, rot):
    o = bpy.data.objects.new(name, bpy.data.lights.new(name, kind)); o.location = loc; o.rotation_euler = rot
    scene.collection.objects.link(o); return o
key = light("Key", "POINT", (1.5, -1.0, 2.0), (0, 0, 0)); key.data.phong.intensity = 3.0; key.data.color = (1.0, 0.9, 0.7)
sun = light("Sun", "SUN", (0, 0, 3), (0.4, -0.3, 0.2)); sun.data.phong.intensity = 0.4
spot = light("Spot", "SPOT", (-1.5, 0.5, 2.5), (0.3, -0.4, 0.2)); spot.data.spot_size = math.radians(60); spot.data.phong.intensity = 2.0
cam = bpy.data.objects.new("Camera", bpy.data.cameras.new("Camera")); cam.location = (0, -6, 2); cam.rotation_euler = (math.radians(75), 0, 0)
scene.collection.objects.link(cam); scene.camera = cam
ball.select_set(True); bpy.context.view_layer.objects.active = ball
assert bpy.ops.phong.apply_material() == {"FINISHED"}
m = ball.active_material
print(m.name, m["phong_nodes_material"], m["phong_source"], m.node_tree.nodes["phong_lights"].node_tree["phong_lights_version"])
bpy.ops.wm.save_as_mainfile(filepath=sys.argv[-1], compress=True)
