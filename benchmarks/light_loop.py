# SPDX-License-Identifier: GPL-3.0-or-later
"""Issue 38: Phong materials on Eevee's light loop (Blender 5.3+) at 1, 4 and 16 lights, side
by side with Principled and with the lights groups of 5.2 in one run.

    .venv/bin/python -m phong_nodes.benchmarks.light_loop [--objects 1000] [--lights 1 4 16]
        [--repeats 2] [--renders 2] [--out benchmarks/light_loop_results.json]
    .venv/bin/python -m phong_nodes.benchmarks.light_loop --table benchmarks/light_loop_results.json
    .venv/bin/python -m phong_nodes.benchmarks.light_loop --merge benchmarks/light_loop_results.json \
        benchmarks/results.json      # figure 10 of results.md

Two figures, each from the modules that measure it, run one after the other:

* **F12**: ``eevee_materials.run`` (figure 6's artist scene, 1,000 cubes with their own
  materials, 256², Eevee at 1 sample, each case in a process of its own after an untimed
  render, the order of the cases alternating) per number of lights, cases ``principled``,
  ``phong`` (its Eevee side the loop on 5.3+) and ``phong_lights_group`` (the same with the
  lights group in Eevee too: the recipe of 5.2, which the term passes switch to);
* **drag**: ``light_move.run_files`` at the largest number of lights: the scene saved as a
  Principled file and, after Apply, as a Phong file; the update after moving each light in
  turn, each file loaded in a process of its own, *rounds* rounds alternating the order,
  cases ``principled``, ``phong``, ``phong_live`` (the World's copies of the lights'
  transforms kept live, as before ``world_copies``) and ``lights_group`` (the lights groups
  of 5.2).  (Runs before November 2026 used ``run_each``: every case in one process.)

Writes one JSON (every time, the load average before and after each part) and prints the
table of ``table``.  Ratios are within one run; the machine's load is in the JSON.
"""

from __future__ import annotations

import argparse
import json
import os
import statistics
import subprocess
import sys
import time

from .table import publish

CASES = ("principled", "phong", "phong_lights_group")
#: The goals of issue 38 (on 5.3): F12 within 2x Principled at 4 and 16 lights, a drag of any
#: of 16 lights within 1.3x.
F12_GOAL = 2.0
DRAG_GOAL = 1.3


def f12(objects, lights, repeats, renders) -> dict:
    from .eevee_materials import run  # noqa: PLC0415  (no bpy: it starts processes)

    return {str(n): run(objects, n, repeats, list(CASES), renders) for n in lights}


def drag(objects, n_lights, moves, rounds=8, passes=2) -> dict:
    proc = subprocess.run(
        [sys.executable, "-m", "phong_nodes.benchmarks.light_move", "--files", str(rounds),
         "--passes", str(passes), "--objects", str(objects), "--lights", str(n_lights),
         "--moves", str(moves)],
        capture_output=True, text=True)
    text = proc.stdout
    if proc.returncode != 0 or "{" not in text:
        raise RuntimeError(text[-2000:] + proc.stderr[-2000:])
    return json.loads(text[text.index("{"):])


def table(result) -> str:
    """The Markdown table of a run (``run``'s JSON)."""
    lines = ["| lights | Principled | Phong (light loop) | / Principled | lights group of 5.2 "
             "| / Principled | Eevee nodes per material (loop / group) |",
             "|---|---|---|---|---|---|---|"]
    for n, figure in result["f12"].items():
        median = figure["median_s"]
        times = figure["render_s"]

        def cell(case):
            return (f"{median[case]:.2f} s ({min(times[case]):.2f}–{max(times[case]):.2f})"
                    if case in median else "–")

        ratio = figure.get("ratio_to_principled", {})
        nodes = figure.get("eevee_nodes", {})
        lines.append(f"| {n} | {cell('principled')} | {cell('phong')} | "
                     f"**{ratio.get('phong', float('nan')):.2f}×** | "
                     f"{cell('phong_lights_group')} | "
                     f"{ratio.get('phong_lights_group', float('nan')):.2f}× | "
                     f"{nodes.get('phong')} / {nodes.get('phong_lights_group')} |")
    moves = result.get("drag")
    if moves:
        lines += ["", "| a drag of each of "
                  f"{moves['lights']} lights, {moves['objects']:,} objects | median per light "
                  "| / Principled: median | worst light |", "|---|---|---|---|"]
        base = moves["update_s"]["principled"]
        lines.append(f"| Principled | {1000 * statistics.median(base):.2f} ms | 1 | |")
        for design, label in (("phong", "Phong (light loop)"),
                              ("phong_live", "Phong, the World's copies live"),
                              ("lights_group", "lights groups of 5.2"),
                              ("phong_again", "Phong again (drift)")):
            if design not in moves["update_s"]:
                continue
            ratios = moves["ratio_to_principled"][design]
            lines.append(f"| {label} | {1000 * statistics.median(moves['update_s'][design]):.2f}"
                         f" ms | {statistics.median(ratios):.2f}× | {max(ratios):.2f}× |")
    return "\n".join(lines)


def merge(figure, path) -> None:
    """Put *figure* (a run) into the results file *path* as figure 10 (``light_loop``) and
    write the table beside it (results.json -> results.md), as run.py does."""
    from .table import merge_figure  # noqa: PLC0415

    merge_figure(path, "light_loop", figure)


def run(objects, lights, repeats, renders, moves, rounds=8) -> dict:
    started = time.perf_counter()
    out = {"objects": objects, "lights": list(lights), "repeats": repeats, "renders": renders,
           "goals": {"f12": F12_GOAL, "drag": DRAG_GOAL}}
    out["load_average"] = {"start": os.getloadavg()}
    out["f12"] = f12(objects, lights, repeats, renders)
    out["load_average"]["after_f12"] = os.getloadavg()
    out["drag"] = drag(objects, max(lights), moves, rounds)
    out["load_average"]["end"] = os.getloadavg()
    out["bpy"] = out["drag"]["bpy"]
    out["seconds"] = time.perf_counter() - started
    return out


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--objects", type=int, default=1000)
    parser.add_argument("--lights", type=int, nargs="+", default=[1, 4, 16])
    parser.add_argument("--repeats", type=int, default=2)
    parser.add_argument("--renders", type=int, default=2)
    parser.add_argument("--moves", type=int, default=10)
    parser.add_argument("--rounds", type=int, default=8,
                        help="drag: processes per case (light_move --files)")
    parser.add_argument("--drag-only", metavar="RUN_JSON",
                        help="run the drag part again into this run's JSON (its drag_note "
                             "says so)")
    parser.add_argument("--out", default=None, help="write the JSON here")
    parser.add_argument("--table", metavar="JSON", help="only print the table of a run")
    parser.add_argument("--merge", nargs=2, metavar=("RUN_JSON", "RESULTS_JSON"),
                        help="put a run into the results file as figure 10 (and its table)")
    args = parser.parse_args(argv)
    if args.table:
        with open(args.table, encoding="utf-8") as handle:
            print(table(json.load(handle)))
        return 0
    if args.merge:
        with open(args.merge[0], encoding="utf-8") as handle:
            merge(json.load(handle), args.merge[1])
        return 0
    if args.drag_only:
        with open(args.drag_only, encoding="utf-8") as handle:
            result = json.load(handle)
        result["drag"] = drag(args.objects, max(args.lights), args.moves, args.rounds)
        result["drag_note"] = (f"the drag part rerun alone ({time.strftime('%Y-%m-%d')}, "
                               f"light_move --files {args.rounds}, bpy {result['drag']['bpy']})")
        publish(result, args.drag_only, table(result))
        return 0
    result = run(args.objects, args.lights, args.repeats, args.renders, args.moves,
                 args.rounds)
    publish(result, args.out, table(result))
    return 0


if __name__ == "__main__":
    sys.exit(main())
