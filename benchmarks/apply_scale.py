# SPDX-License-Identifier: GPL-3.0-or-later
"""Apply Phong Material against the size of the scene (issue 44 item 5: linear in the number of
objects, 10× the objects within 11× the time).

The artist scene of ``measure.artist_scene`` (cubes, each with its own mesh and its own
Principled material, 4 lights), at 1,000 and 10,000 objects; each case in a process of its own,
the sizes alternating round by round; timed: the operator ``phong.apply_material`` on every
cube (selection and scene building not timed).  Writes ``apply_scale_results.json`` beside
this file (or ``--out``) and prints the ratio of the medians.

    .venv/bin/python -m phong_nodes.benchmarks.apply_scale --rounds 3
"""

from __future__ import annotations

import argparse
import json
import os
import statistics
import subprocess
import sys
import time

HERE = os.path.dirname(os.path.abspath(__file__))
SIZES = (1000, 10000)


def worker(n_objects: int, other: int = 0) -> dict:
    """Seconds of one Apply on *n_objects* cubes (run in a process of its own), and of
    Blender's own slot assignment in the same scene after it (:func:`floor`); *other*: the
    file also holds a second scene of that many cubes of their own materials, which Apply
    does not touch."""
    from . import measure  # noqa: PLC0415  (imports bpy)

    bpy = measure.worker_setup()
    scene, objects, _lights = measure.artist_scene("Apply", n_objects, 4)
    if other:
        measure.artist_scene("Other", other, 4)
    seconds = measure.apply_phong(bpy, scene, objects)
    return {"seconds": seconds, "floor": floor(objects)}


def floor(objects) -> float:
    """Seconds Blender itself takes to put a new material in each of *objects*' one slot (no
    Phong code; the materials made before the clock starts): the part of Apply that no add-on
    can avoid, since every slot assignment walks the file's objects
    (``BKE_objects_materials_sync_length_all``).  Timed in Apply's process, right after it."""
    import bpy  # noqa: PLC0415

    new = [bpy.data.materials.new(f"Floor {i:05d}") for i in range(len(objects))]
    start = time.perf_counter()
    for obj, material in zip(objects, new):
        obj.material_slots[0].material = material
    return time.perf_counter() - start


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--rounds", type=int, default=3)
    parser.add_argument("--out", default=None,
                        help="results file (default apply_scale_results.json beside this file, "
                             "apply_scale_two_scenes_results.json with --other-scene)")
    parser.add_argument("--other-scene", type=int, default=0, metavar="N",
                        help="the file also holds a second scene of N objects (Apply's time "
                             "must grow with what it converts, not with the file)")
    parser.add_argument("--worker", type=int, help=argparse.SUPPRESS)
    args = parser.parse_args(argv)
    if args.out is None:
        args.out = os.path.join(HERE, "apply_scale_two_scenes_results.json" if args.other_scene
                                else "apply_scale_results.json")
    if args.worker:
        print(json.dumps(worker(args.worker, args.other_scene)))
        sys.stdout.flush()
        os._exit(0)  # noqa: SLF001  (bpy's exit is slow with 10,000 objects and not measured)
    times = {n: [] for n in SIZES}
    floors = {n: [] for n in SIZES}
    for round_index in range(args.rounds):
        for n in SIZES:
            run = subprocess.run([sys.executable, "-m", "phong_nodes.benchmarks.apply_scale",
                                  "--worker", str(n), "--other-scene", str(args.other_scene)],
                                 capture_output=True, text=True, check=True)
            measured = json.loads(run.stdout.strip().splitlines()[-1])
            times[n].append(measured["seconds"])
            floors[n].append(measured["floor"])
            print(f"round {round_index + 1}: {n} objects, Apply {measured['seconds']:.2f} s, "
                  f"then Blender's slot assignment alone {measured['floor']:.3f} s", flush=True)
    import bpy  # noqa: PLC0415

    medians = {n: statistics.median(v) for n, v in times.items()}
    floor_medians = {n: statistics.median(v) for n, v in floors.items()}
    ratio = medians[SIZES[1]] / medians[SIZES[0]]
    beyond = {n: statistics.median(a - f for a, f in zip(times[n], floors[n])) for n in SIZES}
    result = {"bpy": bpy.app.version_string, "rounds": args.rounds,
              "other_scene_objects": args.other_scene,
              "load_average": os.getloadavg(),
              "seconds": {str(n): v for n, v in times.items()},
              "median_s": {str(n): m for n, m in medians.items()},
              "ratio_10x_objects": ratio, "goal": 11.0, "met": ratio <= 11.0,
              "blender_slot_assignment_s": {str(n): v for n, v in floors.items()},
              "blender_slot_assignment_median_s": {str(n): m for n, m in floor_medians.items()},
              "blender_slot_assignment_ratio": floor_medians[SIZES[1]] / floor_medians[SIZES[0]],
              "apply_beyond_blender_s": {str(n): b for n, b in beyond.items()},
              "apply_beyond_blender_ratio": beyond[SIZES[1]] / beyond[SIZES[0]]}
    with open(args.out, "w", encoding="utf-8") as handle:
        json.dump(result, handle, indent=2)
        handle.write("\n")
    print(f"Apply: {medians[SIZES[0]]:.2f} s at {SIZES[0]}, {medians[SIZES[1]]:.2f} s at "
          f"{SIZES[1]}: {ratio:.1f}x for 10x the objects (goal 11x: "
          f"{'met' if ratio <= 11.0 else 'missed'}); Blender's own slot assignment "
          f"{floor_medians[SIZES[0]]:.3f} s and {floor_medians[SIZES[1]]:.2f} s "
          f"({result['blender_slot_assignment_ratio']:.0f}x); Apply beyond it "
          f"{result['apply_beyond_blender_ratio']:.1f}x")
    return 0


if __name__ == "__main__":
    sys.exit(main())
