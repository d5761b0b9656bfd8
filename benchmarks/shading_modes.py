# SPDX-License-Identifier: GPL-3.0-or-later
"""Issue 28 item 5: one depsgraph update after moving a light, 1,000 objects of 482 vertices
(UV spheres, 32 segments, 16 rings, each its own mesh, one shared source material), one point
light: Principled BSDF, Phong Per Pixel, Phong Per Vertex and Phong Per Face.

    .venv/bin/python -m phong_nodes.benchmarks.shading_modes [--objects 1000] [--moves 9]

Each case is built in a fresh file in this one process; the figure is the median over
*moves* light moves of ``view_layer.update()`` (the extension's depsgraph handler included),
after two untimed moves.  Prints one JSON object (seconds, ratios, load average); the lead
merges the figure into benchmarks/results.md.
"""

from __future__ import annotations

import argparse
import json
import os
import statistics
import sys
import time

from .measure import worker_setup


def _build(bpy, case, count):
    bpy.ops.wm.read_homefile(use_empty=True)
    scene = bpy.context.scene
    from phong_nodes.addon import compat  # noqa: PLC0415
    from phong_nodes.addon.scene import meshes  # noqa: PLC0415

    material = bpy.data.materials.new("Shared")
    compat.new_material_tree(material)
    side = int(count ** 0.5 + 0.999)
    objects = []
    for index in range(count):
        mesh = meshes.uv_sphere(f"S{index}", 0.4, 32, 16)
        mesh.materials.append(material)
        obj = bpy.data.objects.new(f"S{index}", mesh)
        obj.location = (index % side, index // side, 0.0)
        scene.collection.objects.link(obj)
        objects.append(obj)
    assert len(objects[0].data.vertices) == 482
    light = bpy.data.objects.new("Lamp", bpy.data.lights.new("Lamp", "POINT"))
    light.location = (side / 2, side / 2, 5.0)
    scene.collection.objects.link(light)
    camera = bpy.data.objects.new("Camera", bpy.data.cameras.new("Camera"))
    camera.location = (side / 2, -side, side)
    scene.collection.objects.link(camera)
    scene.camera = camera
    if case != "principled":
        for obj in scene.objects:
            obj.select_set(obj.type == "MESH")
        bpy.context.view_layer.objects.active = objects[0]
        assert bpy.ops.phong.apply_material() == {"FINISHED"}
        if case != "pixel":
            objects[0].active_material.phong.shading = case.upper()
    bpy.context.view_layer.update()
    return scene, light


def _moves(bpy, light, moves):
    times = []
    for index in range(moves + 2):
        light.location.x += 0.1 if index % 2 else -0.1
        t0 = time.perf_counter()
        bpy.context.view_layer.update()
        times.append(time.perf_counter() - t0)
    return times[2:]


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--objects", type=int, default=1000)
    parser.add_argument("--moves", type=int, default=9)
    args = parser.parse_args(argv)
    bpy = worker_setup()  # the extension registered from the source tree
    load_before = os.getloadavg()
    result = {"objects": args.objects, "vertices_per_object": 482, "moves": args.moves,
              "bpy": bpy.app.version_string, "update_s": {}, "build_s": {}}
    for case in ("principled", "pixel", "vertex", "face"):
        t0 = time.perf_counter()
        _scene, light = _build(bpy, case, args.objects)
        result["build_s"][case] = time.perf_counter() - t0
        times = _moves(bpy, light, args.moves)
        result["update_s"][case] = {"median": statistics.median(times), "min": min(times),
                                    "max": max(times)}
    pixel = result["update_s"]["pixel"]["median"]
    result["ratio_to_pixel"] = {k: v["median"] / pixel for k, v in result["update_s"].items()}
    result["load_average"] = [load_before, os.getloadavg()]
    print(json.dumps(result, indent=1))
    return 0


if __name__ == "__main__":
    sys.exit(main())
