#!/usr/bin/env python3
"""Make the README's pictures by script (Eevee, Standard view transform).

* docs/lights_workflow.png: three ordinary Blender lights (a warm point light, a cool sun, a
  spot with a soft edge), three meshes, `bpy.ops.phong.apply_material()`;
* docs/sheet_two_lights.png, docs/sheet_exponents.png: the comparison sheets of two demo
  scenes, built as live scenes by `bpy.ops.phong.build_demo_scene()` and compared by
  `bpy.ops.phong.compare_scene()` (256 px high);
* docs/sheet_threejs_phong_lab.png: the seeds' three.js Phong lab in the three.js model,
  compared with three.js itself in headless Chromium (`peers={'THREEJS'}`);
* docs/obj_import.png: an OBJ/MTL file of four spheres with classic materials of the OpenGL
  material table (brass, jade, ruby, chrome: Ka, Kd, Ks, Ns), written here and imported by
  `bpy.ops.phong.import_obj()`, lit by a point light and the ambient light.

* docs/phong_vs_gouraud.png: the demo scene phong_vs_gouraud (its right sphere baked to
  vertex colours by Bake Phong Lighting), Eevee;
* docs/gltf_check.png: that scene exported by `bpy.ops.phong.export_gltf()` (the left sphere
  baked to a 256 px image, the right one keeping its vertex bake) and checked: three.js's GLTFLoader in headless Chromium beside Cycles rendering the bake.

Run: .venv/bin/python tools/readme_pictures.py  (only the three.js sheet: ... threejs; only
the baking pictures: ... baking)
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
    from phong_nodes.addon.scene import meshes

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
    render_png(scene, "lights_workflow.png", 640, 320)


def render_png(scene, name, width, height):
    """Eevee, 16 samples, Standard view transform: docs/<name>."""
    import bpy

    from phong_nodes.addon import compat

    scene.render.engine = compat.eevee_engine()
    scene.eevee.taa_render_samples = 16
    scene.view_settings.view_transform = "Standard"
    scene.render.resolution_x, scene.render.resolution_y = width, height
    compat.set_png(scene.render.image_settings)
    out = os.path.join(ROOT, "docs", name)
    scene.render.filepath = out
    bpy.ops.render.render(write_still=True)
    print(out)


#: name -> (Ka, Kd, Ks, shininess as a fraction of 128): the classic OpenGL material table.
CLASSIC = {
    "brass": ((0.329412, 0.223529, 0.027451), (0.780392, 0.568627, 0.113725),
              (0.992157, 0.941176, 0.807843), 0.21794872),
    "jade": ((0.135, 0.2225, 0.1575), (0.54, 0.89, 0.63), (0.316228, 0.316228, 0.316228), 0.1),
    "ruby": ((0.1745, 0.01175, 0.01175), (0.61424, 0.04136, 0.04136),
             (0.727811, 0.626959, 0.626959), 0.6),
    "chrome": ((0.25, 0.25, 0.25), (0.4, 0.4, 0.4), (0.774597, 0.774597, 0.774597), 0.6),
}


def _sphere_obj(lines, offset, centre, radius=0.9, rings=24, segments=48):
    """OBJ lines (Y up) of a UV sphere; returns the next vertex offset."""
    first = offset
    for ring in range(rings + 1):
        theta = math.pi * ring / rings
        for seg in range(segments):
            phi = 2 * math.pi * seg / segments
            n = (math.sin(theta) * math.cos(phi), math.cos(theta), math.sin(theta) * math.sin(phi))
            lines.append("v " + " ".join(f"{c + radius * d:.6f}" for c, d in zip(centre, n)))
            lines.append("vn " + " ".join(f"{d:.6f}" for d in n))
    for ring in range(rings):
        for seg in range(segments):
            a = first + ring * segments + seg
            b = first + ring * segments + (seg + 1) % segments
            c, d = b + segments, a + segments
            lines.append(f"f {a}//{a} {b}//{b} {c}//{c} {d}//{d}")  # outward
    return first + (rings + 1) * segments


def obj_import_picture():
    import tempfile

    import bpy

    from phong_nodes.addon import compat

    bpy.ops.wm.read_homefile(use_empty=True)
    scene = bpy.context.scene
    world = bpy.data.worlds.new("World")
    compat.black_world(world)
    scene.world = world
    world.phong.ambient_intensity = 1.0
    folder = tempfile.mkdtemp(prefix="phong_classic_")
    mtl_lines = ["# The classic OpenGL material table: Ka, Kd, Ks, Ns = 128 * shininess"]
    obj_lines = ["# Four spheres, one per classic material", "mtllib classic.mtl"]
    offset = 1
    for index, (name, (ka, kd, ks, shininess)) in enumerate(CLASSIC.items()):
        mtl_lines += [f"newmtl {name}", "Ka " + " ".join(map(str, ka)),
                      "Kd " + " ".join(map(str, kd)), "Ks " + " ".join(map(str, ks)),
                      f"Ns {128 * shininess:.4f}", "illum 2"]
        obj_lines += [f"o {name}", f"usemtl {name}"]
        offset = _sphere_obj(obj_lines, offset, ((index - 1.5) * 2.1, 0.0, 0.0))
    with open(os.path.join(folder, "classic.mtl"), "w") as fh:
        fh.write("\n".join(mtl_lines) + "\n")
    with open(os.path.join(folder, "classic.obj"), "w") as fh:
        fh.write("\n".join(obj_lines) + "\n")
    light = bpy.data.objects.new("Key", bpy.data.lights.new("Key", "POINT"))
    light.location = (-3.0, -6.0, 5.0)
    light.data.phong.intensity = 55.0
    scene.collection.objects.link(light)
    assert bpy.ops.phong.import_obj(filepath=os.path.join(folder, "classic.obj")) == {"FINISHED"}
    camera = bpy.data.objects.new("Camera", bpy.data.cameras.new("Camera"))
    camera.data.type = "ORTHO"
    camera.data.ortho_scale = 8.8
    camera.location, camera.rotation_euler = (0, -10, 0), (math.pi / 2, 0, 0)
    scene.collection.objects.link(camera)
    scene.camera = camera
    render_png(scene, "obj_import.png", 640, 180)


def sheets(names=(("two_lights", set()), ("exponents", set()),
                  ("threejs_phong_lab", {"THREEJS"}))):
    import shutil
    import tempfile

    import bpy

    folder = tempfile.mkdtemp(prefix="phong_sheets_")
    for name, peers in names:
        bpy.ops.wm.read_homefile(use_empty=True)
        assert bpy.ops.phong.build_demo_scene(name=name, resolution=256) == {"FINISHED"}
        with bpy.context.temp_override(scene=bpy.data.scenes[name]):
            assert bpy.ops.phong.compare_scene(directory=folder, peers=peers) == {"FINISHED"}
        out = os.path.join(ROOT, "docs", f"sheet_{name}.png")
        shutil.copyfile(os.path.join(folder, name, "sheet.png"), out)
        print(out)
    shutil.rmtree(folder)


def baking_pictures():
    import shutil
    import tempfile

    import bpy

    from phong_nodes.addon.baking import check

    bpy.ops.wm.read_homefile(use_empty=True)
    assert bpy.ops.phong.build_demo_scene(name="phong_vs_gouraud", resolution=320) == {"FINISHED"}
    scene = bpy.data.scenes["phong_vs_gouraud"]
    bpy.context.window.scene = scene
    render_png(scene, "phong_vs_gouraud.png", 640, 320)
    folder = tempfile.mkdtemp(prefix="phong_gltf_")
    glb = os.path.join(folder, "phong_vs_gouraud.glb")
    bpy.ops.object.select_all(action="DESELECT")
    # the left sphere baked to an image, the right one keeps its vertex bake (Gouraud)
    assert bpy.ops.phong.export_gltf(filepath=glb, target="IMAGE", resolution=256,
                                     rebake=False) == {"FINISHED"}
    objects = [o for o in scene.objects if o.type == "MESH"]
    result = check.check(scene, objects, glb, os.path.join(folder, "check"), 256)
    out = os.path.join(ROOT, "docs", "gltf_check.png")
    shutil.copyfile(os.path.join(folder, "check", "sheet.png"), out)
    print(out, result["verdict"])
    shutil.rmtree(folder)


if __name__ == "__main__":
    try:
        if sys.argv[1:] == ["baking"]:
            phong_nodes.register()
            baking_pictures()
        elif sys.argv[1:] == ["threejs"]:
            phong_nodes.register()
            sheets((("threejs_phong_lab", {"THREEJS"}),))
        else:
            main()
            obj_import_picture()
            sheets()
            baking_pictures()
    finally:
        # registered by hand, not as an add-on: bpy 4.2 crashes at exit while it stays so
        phong_nodes.unregister()
    from phong_nodes.addon import compat

    compat.leave_if_exit_crashes(0)  # the glTF pictures: bpy 4.2's exit would crash
