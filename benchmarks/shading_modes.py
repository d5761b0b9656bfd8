# SPDX-License-Identifier: GPL-3.0-or-later
"""Issue 28 item 5: one depsgraph update after moving a light, 1,000 objects of 482 vertices
(UV spheres, 32 segments, 16 rings, each its own mesh, one shared source material), one point
light: Principled BSDF, Phong Per Pixel, Phong Per Vertex and Phong Per Face.

    .venv/bin/python -m phong_nodes.benchmarks.shading_modes [--objects 1000] [--moves 9]
        [--repeats 3] [--merge benchmarks/results.json]

Each case is built in a fresh file in this one process; a run's figure is the median over
*moves* light moves of ``view_layer.update()`` (the extension's depsgraph handler included),
after two untimed moves; ratios are taken run by run (side by side).  Prints one JSON object
(seconds, ratios, load average); ``--merge`` writes it into the results file as figure 8 and
regenerates the table beside it (``results.md``).
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


def _stats(values):
    return {"median": statistics.median(values), "min": min(values), "max": max(values),
            "values": list(values)}


def merge(figure, path) -> None:
    """Put *figure* into the results file *path* as figure 8 (``shading_modes``) and write the
    table beside it (results.json -> results.md), as run.py does."""
    from .table import merge_figure  # noqa: PLC0415

    merge_figure(path, "shading_modes", figure)


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--objects", type=int, default=1000)
    parser.add_argument("--moves", type=int, default=9)
    parser.add_argument("--repeats", type=int, default=1,
                        help="runs of the four cases (their order rotates); the figure is the "
                             "median over the runs")
    parser.add_argument("--merge", metavar="RESULTS_JSON",
                        help="write the figure into this results file (figure 8) and its table")
    args = parser.parse_args(argv)
    bpy = worker_setup()  # the extension registered from the source tree
    load_before = os.getloadavg()
    cases = ["principled", "pixel", "vertex", "face"]
    medians = {case: [] for case in cases}
    build = {case: [] for case in cases}
    for repeat in range(args.repeats):
        order = cases[repeat % len(cases):] + cases[:repeat % len(cases)]
        for case in order:
            t0 = time.perf_counter()
            _scene, light = _build(bpy, case, args.objects)
            build[case].append(time.perf_counter() - t0)
            medians[case].append(statistics.median(_moves(bpy, light, args.moves)))
    result = {"what": "one depsgraph update after moving the light: Per Vertex / Per Face "
                      "against Per Pixel (and Principled), same process",
              "objects": args.objects, "vertices_per_object": 482, "moves": args.moves,
              "repeats": args.repeats, "bpy": bpy.app.version_string, "goal_value": 3.0,
              "update_s": {c: _stats(v) for c, v in medians.items()},
              "build_s": {c: _stats(v) for c, v in build.items()},
              "ratio_to_pixel": {c: _stats([m / p for m, p in zip(medians[c], medians["pixel"])])
                                 for c in cases},
              "load_average": [load_before, os.getloadavg()], "cpu_count": os.cpu_count()}
    print(json.dumps(result, indent=1))
    if args.merge:
        merge(result, args.merge)
    return 0


if __name__ == "__main__":
    sys.exit(main())
