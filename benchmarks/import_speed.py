# SPDX-License-Identifier: GPL-3.0-or-later
"""Issue 35 item 4: import speed of the Phong importers against Blender's own, side by side.

    .venv/bin/python -m phong_nodes.benchmarks.import_speed [--repeats 3]
        [--folder out/import_speed] [--blender42 .venv-bpy4.2.23/bin/python]
        [--merge benchmarks/results.json] [--uv-maps]

One file of 520,192 triangles: 8 UV spheres (256 segments, 128 rings, triangulated: 65,024
triangles each, smooth: corner normals; no UV map, as the issue's file), each with its own Principled material, written by Blender
4.2's own exporters (OBJ + MTL, binary FBX 7.4, COLLADA 1.4.1) into *folder* (made once, by
a child process of bpy 4.2.23: ``--make``; never committed).  Then, in this process (the
default release), each case into a fresh empty file (``read_homefile(use_empty=True)``),
the cases of a repeat in rotating order:

* OBJ: ``phong.import_obj`` against Blender's ``wm.obj_import``;
* FBX: ``phong.import_fbx`` against Blender's ``import_scene.fbx``;
* COLLADA: ``phong.import_collada`` here, and then, in a second process of bpy 4.2.23 (Python
  3.11: ``--time-collada42``), Blender 4.2's own C++ ``wm.collada_import`` of the same file,
  into a fresh empty file each time, the same number of repeats.

``--uv-maps`` gives the spheres their UV maps (files in ``out/import_speed_uv``; not the
issue's file: its figure is without).  Times are wall-clock seconds of the operator call (``time.perf_counter``); the figure is the
median over the repeats, a ratio the median of ours over the median of Blender's.  Prints one
JSON object (seconds, ratios, load average before and after); ``--merge`` writes it into the
results file as ``import_speed`` and regenerates the table beside it (``results.md``).
"""

from __future__ import annotations

import argparse
import json
import os
import statistics
import subprocess
import sys
import time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
SPHERES = 8
SEGMENTS, RINGS = 256, 128
#: triangles of one triangulated UV sphere: two fans of SEGMENTS at the poles, two per quad
TRIANGLES = SPHERES * (2 * SEGMENTS + 2 * SEGMENTS * (RINGS - 2))
GOALS = {"obj": 1.5, "fbx": 1.5, "collada": 2.0}
FILES = {"obj": "spheres.obj", "fbx": "spheres.fbx", "collada": "spheres.dae"}


# -- run in bpy 4.2.23 (--make, --time-collada42) ------------------------------------------------

def make(folder, uv_maps=False) -> None:
    """The three files, by Blender 4.2's own exporters (*uv_maps*: each sphere with its UV
    map, which the COLLADA exporter writes per corner: 3.1 M more numbers to read)."""
    import bpy  # noqa: PLC0415  (first: bmesh is a module of bpy's)
    import bmesh  # noqa: PLC0415

    if bpy.app.version[:2] != (4, 2):
        raise SystemExit(f"--make needs bpy 4.2 (its COLLADA exporter), not {bpy.app.version_string}")
    os.makedirs(folder, exist_ok=True)
    bpy.ops.wm.read_homefile(use_empty=True)
    scene = bpy.context.scene
    for index in range(SPHERES):
        mesh = bpy.data.meshes.new(f"Sphere{index}")
        bm = bmesh.new()
        if uv_maps:
            bm.loops.layers.uv.new("UVMap")
        bmesh.ops.create_uvsphere(bm, u_segments=SEGMENTS, v_segments=RINGS, radius=1.0,
                                  calc_uvs=True)
        bmesh.ops.triangulate(bm, faces=bm.faces[:])
        bm.to_mesh(mesh)
        bm.free()
        mesh.shade_smooth()
        material = bpy.data.materials.new(f"Material{index}")
        material.use_nodes = True
        principled = material.node_tree.nodes["Principled BSDF"]
        principled.inputs["Base Color"].default_value = (0.1 * index + 0.1, 0.5, 0.9 - 0.1 * index, 1)
        mesh.materials.append(material)
        obj = bpy.data.objects.new(f"Sphere{index}", mesh)
        obj.location = (3.0 * (index % 4), 3.0 * (index // 4), 0.0)
        scene.collection.objects.link(obj)
    assert sum(len(m.polygons) for m in bpy.data.meshes) == TRIANGLES
    bpy.ops.wm.obj_export(filepath=os.path.join(folder, FILES["obj"]), export_materials=True)
    bpy.ops.export_scene.fbx(filepath=os.path.join(folder, FILES["fbx"]))
    bpy.ops.wm.collada_export(filepath=os.path.join(folder, FILES["collada"]))


def time_collada42(path, repeats) -> list:
    """Seconds of Blender 4.2's own COLLADA importer on *path*, each into an empty file."""
    import bpy  # noqa: PLC0415

    times = []
    for _ in range(repeats):
        bpy.ops.wm.read_homefile(use_empty=True)
        t0 = time.perf_counter()
        bpy.ops.wm.collada_import(filepath=path)
        times.append(time.perf_counter() - t0)
        assert sum(len(o.data.polygons) for o in bpy.data.objects if o.type == "MESH") == TRIANGLES
    return times


# -- run in the default release ------------------------------------------------------------------

def _ours(bpy, kind, path):
    op = {"obj": bpy.ops.phong.import_obj, "fbx": bpy.ops.phong.import_fbx,
          "collada": bpy.ops.phong.import_collada}[kind]
    return op(filepath=path)


def _blenders(bpy, kind, path):
    if kind == "obj":
        return bpy.ops.wm.obj_import(filepath=path)
    return bpy.ops.import_scene.fbx(filepath=path)


def _timed(bpy, call, kind, path):
    bpy.ops.wm.read_homefile(use_empty=True)
    t0 = time.perf_counter()
    result = call(bpy, kind, path)
    seconds = time.perf_counter() - t0
    assert result == {"FINISHED"}, (kind, result)
    triangles = sum(len(o.data.polygons) for o in bpy.data.objects if o.type == "MESH")
    assert triangles == TRIANGLES, (kind, triangles)
    return seconds


def _stats(values):
    return {"median": statistics.median(values), "min": min(values), "max": max(values),
            "values": list(values)}


def merge(figure, path) -> None:
    """Put *figure* into the results file *path* as ``import_speed`` and write the table
    beside it (results.json -> results.md), as run.py does."""
    from .table import merge_figure  # noqa: PLC0415

    merge_figure(path, "import_speed", figure)


def _child(python, *args) -> str:
    done = subprocess.run([python, "-m", "phong_nodes.benchmarks.import_speed", *args],
                          capture_output=True, text=True, check=False, cwd=ROOT)
    if done.returncode != 0:
        raise SystemExit(f"{python} {' '.join(args)} failed:\n{done.stderr[-3000:]}")
    return done.stdout


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeats", type=int, default=3)
    parser.add_argument("--folder", default=os.path.join(ROOT, "out", "import_speed"))
    parser.add_argument("--blender42", default=os.path.join(ROOT, ".venv-bpy4.2.23", "bin", "python"),
                        help="the Python of bpy 4.2.23 (PHONG_BPY=4.2.23 bash tools/phong.sh setup)")
    parser.add_argument("--merge", metavar="RESULTS_JSON")
    parser.add_argument("--make", action="store_true", help=argparse.SUPPRESS)
    parser.add_argument("--time-collada42", action="store_true", help=argparse.SUPPRESS)
    parser.add_argument("--only", default="obj,fbx,collada", help="formats to time")
    parser.add_argument("--uv-maps", action="store_true",
                        help="spheres with UV maps (another folder: out/import_speed_uv)")
    args = parser.parse_args(argv)
    folder = os.path.abspath(args.folder)
    if args.uv_maps and args.folder == parser.get_default("folder"):
        folder += "_uv"
    if args.make:
        make(folder, args.uv_maps)
        return 0
    if args.time_collada42:
        print(json.dumps(time_collada42(os.path.join(folder, FILES["collada"]), args.repeats)))
        return 0
    if not os.path.isfile(args.blender42):
        raise SystemExit(f"{args.blender42} not found: make it with "
                         "`PHONG_BPY=4.2.23 bash tools/phong.sh setup`")
    if not all(os.path.isfile(os.path.join(folder, f)) for f in FILES.values()):
        _child(args.blender42, "--make", "--folder", folder, *(["--uv-maps"] if args.uv_maps
                                                                  else []))
    from .measure import worker_setup  # noqa: PLC0415

    bpy = worker_setup()
    from io_scene_fbx import import_fbx  # noqa: F401,PLC0415  (loaded before timing)

    kinds = [k for k in ("obj", "fbx", "collada") if k in args.only.split(",")]
    load_before = os.getloadavg()
    ours = {k: [] for k in kinds}
    blenders = {k: [] for k in kinds if k != "collada"}
    for repeat in range(args.repeats):
        order = kinds[repeat % len(kinds):] + kinds[:repeat % len(kinds)]
        for kind in order:
            path = os.path.join(folder, FILES[kind])
            pair = [("ours", _ours)] + ([("blender", _blenders)] if kind != "collada" else [])
            if repeat % 2:
                pair.reverse()
            for who, call in pair:
                (ours if who == "ours" else blenders)[kind].append(_timed(bpy, call, kind, path))
    if "collada" in kinds:
        blenders["collada"] = json.loads(_child(args.blender42, "--time-collada42",
                                                "--folder", folder,
                                                "--repeats", str(args.repeats)))
    result = {"what": "import of one file of 520,192 triangles in 8 objects and 8 materials "
                      "written by Blender 4.2's exporters: the Phong importer / Blender's own "
                      "(OBJ, FBX: same process, default release; COLLADA: Blender 4.2.23's C++ "
                      "importer in a second process, one after the other)",
              "triangles": TRIANGLES, "objects": SPHERES, "repeats": args.repeats,
              "uv_maps": args.uv_maps,
              "bpy": bpy.app.version_string, "blender_collada": "4.2.23",
              "goal_value": GOALS,
              "ours_s": {k: _stats(v) for k, v in ours.items()},
              "blender_s": {k: _stats(v) for k, v in blenders.items()},
              "ratio": {k: statistics.median(ours[k]) / statistics.median(blenders[k])
                        for k in kinds},
              "load_average": [load_before, os.getloadavg()], "cpu_count": os.cpu_count(),
              "file_bytes": {k: os.path.getsize(os.path.join(folder, FILES[k])) for k in kinds}}
    print(json.dumps(result, indent=1))
    if args.merge:
        merge(result, args.merge)
    return 0


if __name__ == "__main__":
    sys.exit(main())
