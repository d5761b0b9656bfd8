# Makes tests/data/phong_0_1.blend with Phong Nodes 0.1 (commit 397e1e1) on the bpy it runs on.
import sys, bpy, addon_utils
out = sys.argv[1]
bpy.ops.wm.read_factory_settings(use_empty=True)
addon_utils.enable("phong_nodes", default_set=True)
scene = bpy.context.scene
world = bpy.data.worlds.new("World"); scene.world = world
mesh = bpy.data.meshes.new("Ball")
import bmesh
bm = bmesh.new(); bmesh.ops.create_uvsphere(bm, u_segments=32, v_segments=16, radius=1.0); bm.to_mesh(mesh); bm.free()
ball = bpy.data.objects.new("Ball", mesh); scene.collection.objects.link(ball)
clay = bpy.data.materials.new("Clay"); clay.use_nodes = True
clay.node_tree.nodes["Principled BSDF"].inputs["Base Color"].default_value = (0.7, 0.3, 0.1, 1.0)
mesh.materials.append(clay)
for name, kind, loc in (("Key", "POINT", (2.0, -2.0, 3.0)), ("Sun", "SUN", (0.0, 0.0, 5.0))):
    data = bpy.data.lights.new(name, kind)
    obj = bpy.data.objects.new(name, data); obj.location = loc; scene.collection.objects.link(obj)
bpy.data.lights["Key"].phong.intensity = 6.0
for o in bpy.context.view_layer.objects: o.select_set(o.name == "Ball")
bpy.context.view_layer.objects.active = ball
assert bpy.ops.phong.apply_material() == {"FINISHED"}, "apply"
mat = ball.active_material
print("material", mat.name, mat.get("phong_nodes_material"), len(mat.node_tree.animation_data.drivers))
nodes = mat.node_tree.nodes
nodes["phong_exponent"].outputs[0].default_value = 12.0
nodes["phong_specular_color"].outputs[0].default_value = (0.5, 0.6, 0.7, 1.0)
bpy.ops.wm.save_as_mainfile(filepath=out, compress=True)
print("saved", out, bpy.app.version_string)
