# SPDX-License-Identifier: GPL-3.0-or-later
"""Apply Phong Material on textured materials against the size of the scene: the texture chain
copied into a copy of the Phong template (``addon/lighting/node_copy.py``) against the former
way (a copy of each source given the recipe's nodes, each named: naming a node walks every ID
of the file), side by side in one run.

N triangles, each with its own mesh and its own Principled material whose Base Color is fed
by a Checker Texture, one point light; each case in a process of its own, round by round;
timed: the operator ``phong.apply_material`` on every object.  Writes
``apply_textured_results.json`` beside this file (or ``--out``).

    .venv/bin/python -m phong_nodes.benchmarks.apply_textured --rounds 1
"""

from __future__ import annotations

import argparse
import json
import os
import statistics
import subprocess
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
SIZES = (500, 2000)
WAYS = ("copy", "former")


def worker(n_objects: int, way: str) -> float:
    """Seconds of one Apply on *n_objects* textured objects, *way* "copy" or "former"."""
    from . import measure  # noqa: PLC0415  (imports bpy)

    bpy = measure.worker_setup()
    from phong_nodes.addon import compat  # noqa: PLC0415

    if way == "former":
        from phong_nodes.addon.lighting import node_copy  # noqa: PLC0415
        node_copy.copy_upstream = lambda *_args, **_kw: None  # every chain: the former way
    scene = bpy.data.scenes.new("Textured")
    objects = []
    for index in range(n_objects):
        mesh = bpy.data.meshes.new(f"mesh {index}")
        mesh.from_pydata([(0, 0, 0), (1, 0, 0), (0, 1, 0)], [], [(0, 1, 2)])
        material = bpy.data.materials.new(f"textured {index:05d}")
        tree = compat.new_material_tree(material)
        principled = next(n for n in tree.nodes if n.bl_idname == "ShaderNodeBsdfPrincipled")
        checker = tree.nodes.new("ShaderNodeTexChecker")
        checker.inputs["Scale"].default_value = 2.0 + index % 7
        tree.links.new(checker.outputs["Color"], principled.inputs["Base Color"])
        mesh.materials.append(material)
        obj = bpy.data.objects.new(f"object {index:05d}", mesh)
        scene.collection.objects.link(obj)
        objects.append(obj)
    light = bpy.data.objects.new("Light", bpy.data.lights.new("Light", "POINT"))
    scene.collection.objects.link(light)
    return measure.apply_phong(bpy, scene, objects)


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--rounds", type=int, default=1)
    parser.add_argument("--out", default=os.path.join(HERE, "apply_textured_results.json"))
    parser.add_argument("--worker", nargs=2, help=argparse.SUPPRESS)
    args = parser.parse_args(argv)
    if args.worker:
        print(json.dumps(worker(int(args.worker[0]), args.worker[1])))
        sys.stdout.flush()
        os._exit(0)  # noqa: SLF001  (bpy's exit is slow with many objects and not measured)
    times = {(n, way): [] for n in SIZES for way in WAYS}
    for round_index in range(args.rounds):
        for n in SIZES:
            for way in WAYS:
                run = subprocess.run([sys.executable, "-m",
                                      "phong_nodes.benchmarks.apply_textured",
                                      "--worker", str(n), way],
                                     capture_output=True, text=True, check=True)
                seconds = json.loads(run.stdout.strip().splitlines()[-1])
                times[(n, way)].append(seconds)
                print(f"round {round_index + 1}: {n} textured objects, {way}: {seconds:.2f} s",
                      flush=True)
    import bpy  # noqa: PLC0415

    medians = {key: statistics.median(v) for key, v in times.items()}
    result = {"bpy": bpy.app.version_string, "rounds": args.rounds,
              "load_average": os.getloadavg(),
              "seconds": {f"{n} {way}": v for (n, way), v in times.items()},
              "median_s": {f"{n} {way}": m for (n, way), m in medians.items()},
              "growth": {way: medians[(SIZES[1], way)] / medians[(SIZES[0], way)]
                         for way in WAYS},
              "former_over_copy": {str(n): medians[(n, "former")] / medians[(n, "copy")]
                                   for n in SIZES}}
    with open(args.out, "w", encoding="utf-8") as handle:
        json.dump(result, handle, indent=2)
        handle.write("\n")
    for way in WAYS:
        print(f"{way}: {medians[(SIZES[0], way)]:.2f} s at {SIZES[0]}, "
              f"{medians[(SIZES[1], way)]:.2f} s at {SIZES[1]} "
              f"({result['growth'][way]:.1f}x for {SIZES[1] // SIZES[0]}x the objects)")
    return 0


if __name__ == "__main__":
    sys.exit(main())
