#!/usr/bin/env python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""Bake Phong Lighting at scale (issue 20): N objects baked to vertex colours, against
Blender's own Combined bake of the same scene with its Principled materials, side by side in
one run.

    .venv/bin/python benchmarks/bake_lighting.py                 # 1,000 objects, 3 repeats
    .venv/bin/python benchmarks/bake_lighting.py --objects 100 --repeats 1

The scene: N UV spheres (16 segments, 8 rings, their own mesh and Principled material each)
in a grid, a point light and a sun, a camera.  Each repeat builds it twice, fresh:

* **Phong**: ``phong.apply_material()`` on every sphere (not timed), then Bake Phong
  Lighting (``addon/baking/lighting.bake``: target vertex, Phong colour, view camera), timed;
* **Blender**: a colour attribute per mesh (not timed), then ``bpy.ops.object.bake(type=
  "COMBINED", target="VERTEX_COLORS")`` on all spheres at once, timed.

Both with Cycles on the CPU at 1 sample (what the Phong bake uses: its colour is exact at
one sample; the Principled bake is noisy at one sample), no denoising.  The order of the
two cases rotates from repeat to repeat.  Writes ``benchmarks/bake_results.json`` and
prints the table row of the README.
"""

from __future__ import annotations

import argparse
import json
import os
import platform
import statistics
import sys
import time

sys.dont_write_bytecode = True

from phong_nodes.benchmarks.measure import remove_scene, rotated, uv_sphere, worker_setup  # noqa: E402

HERE = os.path.dirname(os.path.abspath(__file__))


def build(bpy, n):
    """A fresh scene of *n* spheres with their own mesh and Principled material."""
    scene = bpy.data.scenes.new(f"bake {n} {time.perf_counter_ns()}")
    bpy.context.window.scene = scene
    side = max(1, round(n ** 0.5 + 0.4999))
    spheres = []
    for i in range(n):
        material = bpy.data.materials.new(f"M{i}")
        from phong_nodes.addon import compat  # noqa: PLC0415

        tree = compat.new_material_tree(material)
        tree.nodes["Principled BSDF"].inputs["Base Color"].default_value = (
            0.2 + 0.6 * (i % 7) / 6, 0.5, 0.8 - 0.6 * (i % 5) / 4, 1.0)
        mesh = uv_sphere(f"S{i}", 16)
        mesh.materials.append(material)
        obj = bpy.data.objects.new(f"S{i}", mesh)
        obj.location = (2.5 * (i % side), 2.5 * (i // side), 0.0)
        obj.scale = (0.8, 0.8, 0.8)
        scene.collection.objects.link(obj)
        spheres.append(obj)
    point = bpy.data.objects.new("Point", bpy.data.lights.new("Point", "POINT"))
    point.location = (side, -4.0, 8.0)
    point.data.energy = 2000.0
    point.data.phong.intensity = 60.0
    sun = bpy.data.objects.new("Sun", bpy.data.lights.new("Sun", "SUN"))
    sun.rotation_euler = (0.6, 0.2, 0.3)
    sun.data.phong.intensity = 0.3
    camera = bpy.data.objects.new("Camera", bpy.data.cameras.new("Camera"))
    camera.location = (side * 1.25, -3.0 * side, 2.0 * side)
    camera.rotation_euler = (0.9, 0.0, 0.0)
    for obj in (point, sun, camera):
        scene.collection.objects.link(obj)
    scene.camera = camera
    scene.render.engine = "CYCLES"
    scene.cycles.device = "CPU"
    scene.cycles.samples = 1
    scene.cycles.use_denoising = False
    for obj in scene.objects:
        obj.select_set(obj in spheres)
    bpy.context.view_layer.objects.active = spheres[0]
    return scene, spheres


def phong(bpy, n):
    from phong_nodes.addon.baking import lighting  # noqa: PLC0415

    scene, spheres = build(bpy, n)
    bpy.ops.phong.apply_material()
    lines = []
    t0 = time.perf_counter()
    results, _ = lighting.bake(scene, spheres, lighting.Settings(target="VERTEX"),
                               lambda done, total, name: lines.append(time.perf_counter()))
    seconds = time.perf_counter() - t0
    assert len(results) == n and len(lines) == n
    remove_scene(scene)
    return seconds


def blender(bpy, n):
    scene, spheres = build(bpy, n)
    for obj in spheres:
        attribute = obj.data.color_attributes.new("Bake", "FLOAT_COLOR", "POINT")
        obj.data.color_attributes.active_color = attribute
    t0 = time.perf_counter()
    with bpy.context.temp_override(active_object=spheres[0], object=spheres[0],
                                   selected_objects=spheres, selected_editable_objects=spheres):
        bpy.ops.object.bake(type="COMBINED", target="VERTEX_COLORS", save_mode="INTERNAL")
    seconds = time.perf_counter() - t0
    remove_scene(scene)
    return seconds


def _result(args, bpy, times, load_before, start) -> dict:
    ratios = [p / b for p, b in zip(times["phong"], times["blender"])]
    return {"objects": args.objects, "repeats": len(ratios), "seconds": times,
            "ratio_phong_over_blender": ratios,
            "median": {k: statistics.median(v) for k, v in times.items()},
            "median_ratio": statistics.median(ratios),
            "bpy": ".".join(map(str, bpy.app.version)), "cpus": os.cpu_count(),
            "machine": platform.machine(), "load_before": load_before,
            "load_after": os.getloadavg(), "run_s": time.perf_counter() - start}


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--objects", type=int, default=1000)
    parser.add_argument("--repeats", type=int, default=3)
    parser.add_argument("--out", default=os.path.join(HERE, "bake_results.json"))
    args = parser.parse_args()
    bpy = worker_setup()
    times = {"phong": [], "blender": []}
    load_before = os.getloadavg()
    start = time.perf_counter()
    for r in range(args.repeats):
        for case in rotated(("phong", "blender"), r):
            seconds = (phong if case == "phong" else blender)(bpy, args.objects)
            times[case].append(seconds)
            print(f"repeat {r + 1}: {case} {seconds:.2f} s", flush=True)
        result = _result(args, bpy, times, load_before, start)  # after every repeat
        with open(args.out, "w", encoding="utf-8") as handle:
            json.dump(result, handle, indent=2)
    ratios, med = result["ratio_phong_over_blender"], result["median"]
    row = (f"| 8. Bake to vertex colours, {args.objects:,} spheres: Bake Phong Lighting / "
           f"Blender's Combined bake (Principled) | {result['median_ratio']:.2f} "
           f"({min(ratios):.2f}–{max(ratios):.2f})× | report |  | {med['phong']:.1f} "
           f"({min(times['phong']):.1f}–{max(times['phong']):.1f}) s vs {med['blender']:.1f} "
           f"({min(times['blender']):.1f}–{max(times['blender']):.1f}) s; "
           f"{med['phong'] / args.objects * 1000:.0f} ms per object |")
    print(row)
    sys.stdout.flush()
    os._exit(0)  # skip bpy's clean-up at exit


if __name__ == "__main__":
    main()
