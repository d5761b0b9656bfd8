# SPDX-License-Identifier: GPL-3.0-or-later
"""Issue 45 item 4: File ▸ Export ▸ FBX with Phong Materials against Blender's own exporter.

    .venv/bin/python -m phong_nodes.benchmarks.fbx_export_speed [--repeats 3] [--spheres 16]
        [--folder out/fbx_export_speed]

A scene of *spheres* UV spheres (256 segments, 128 rings, triangulated: 65,024 triangles each;
16: 1,040,384 triangles), each with its own Phong material (Apply Phong Material), lit by a
point light, a spot and a sun.  In this process, the two calls alternating (the first of a
repeat swaps each time): ``phong.export_fbx`` (Blender's exporter, then the Phong parts
rewritten, ``core/fbx/write.py``, and the file renamed into place) and Blender's own
``export_scene.fbx`` of the same scene, same options (the defaults).  Times are wall-clock
seconds of the operator call (``time.perf_counter``); the figure is the median over the
repeats, the ratio ours / Blender's (goal: 1.3).  Prints one JSON object (with the load
average before and after: the machine may be shared).
"""

from __future__ import annotations

import argparse
import json
import os
import statistics
import time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
SEGMENTS, RINGS = 256, 128
PER_SPHERE = 2 * SEGMENTS + 2 * SEGMENTS * (RINGS - 2)
GOAL = 1.3


def build(bpy, spheres) -> None:
    import bmesh  # noqa: PLC0415

    bpy.ops.wm.read_homefile(use_empty=True)
    scene = bpy.context.scene
    for index in range(spheres):
        mesh = bpy.data.meshes.new(f"Sphere{index}")
        bm = bmesh.new()
        bmesh.ops.create_uvsphere(bm, u_segments=SEGMENTS, v_segments=RINGS, radius=1.0)
        bmesh.ops.triangulate(bm, faces=bm.faces[:])
        bm.to_mesh(mesh)
        bm.free()
        mesh.materials.append(bpy.data.materials.new(f"Clay{index}"))
        obj = bpy.data.objects.new(f"Sphere{index}", mesh)
        obj.location = (3.0 * (index % 4), 3.0 * (index // 4), 0.0)
        scene.collection.objects.link(obj)
        obj.select_set(True)
        bpy.context.view_layer.objects.active = obj
    for name, kind in (("Bulb", "POINT"), ("Beam", "SPOT"), ("Sky", "SUN")):
        scene.collection.objects.link(bpy.data.objects.new(name, bpy.data.lights.new(name, kind)))
    assert bpy.ops.phong.apply_material() == {"FINISHED"}
    for obj in scene.objects:
        obj.select_set(False)


def _stats(values):
    return {"median": statistics.median(values), "min": min(values), "max": max(values),
            "values": list(values)}


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeats", type=int, default=3)
    parser.add_argument("--spheres", type=int, default=16)
    parser.add_argument("--folder", default=os.path.join(ROOT, "out", "fbx_export_speed"))
    args = parser.parse_args(argv)
    folder = os.path.abspath(args.folder)
    os.makedirs(folder, exist_ok=True)
    from .measure import worker_setup  # noqa: PLC0415

    bpy = worker_setup()
    build(bpy, args.spheres)
    calls = {"ours": lambda path: bpy.ops.phong.export_fbx(filepath=path),
             "blender": lambda path: bpy.ops.export_scene.fbx(filepath=path)}
    calls["blender"](os.path.join(folder, "warm.fbx"))   # the add-on loaded before timing
    load_before = os.getloadavg()
    times = {"ours": [], "blender": []}
    for repeat in range(args.repeats):
        order = ["ours", "blender"] if repeat % 2 == 0 else ["blender", "ours"]
        for who in order:
            path = os.path.join(folder, f"{who}.fbx")
            start = time.perf_counter()
            assert calls[who](path) == {"FINISHED"}
            times[who].append(time.perf_counter() - start)
    ours, blender = (statistics.median(times[k]) for k in ("ours", "blender"))
    result = {"what": "export of a scene of Phong materials: phong.export_fbx / Blender's "
                      "export_scene.fbx, same process, default options",
              "triangles": PER_SPHERE * args.spheres, "objects": args.spheres,
              "repeats": args.repeats, "bpy": bpy.app.version_string, "goal_value": GOAL,
              "ours_s": _stats(times["ours"]), "blender_s": _stats(times["blender"]),
              "ratio": ours / blender,
              "bytes": {k: os.path.getsize(os.path.join(folder, f"{k}.fbx")) for k in times},
              "load_before": load_before, "load_after": os.getloadavg()}
    print(json.dumps(result, indent=1))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
