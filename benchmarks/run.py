#!/usr/bin/env python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""Phong Nodes benchmarks: what Phong shading costs (issue 5).

    .venv/bin/python benchmarks/run.py            # full run, ~6 min on a 2-core CPU
    .venv/bin/python benchmarks/run.py --quick    # tiny sizes, for the smoke test

Writes ``benchmarks/results.json`` and ``benchmarks/results.md`` (the Markdown table it also
prints).  Every figure is a ratio of two renders (or builds) measured side by side in the
same run; each is given as the median over the repeats and the spread (min-max).

Three modules, by what they need:

* ``measure.py`` (imports ``bpy``): the worker processes this script starts.  The Cycles
  figures come from one warm worker; every Eevee figure that includes shader compilation
  comes from its own worker whose Mesa and Blender shader caches point to a fresh empty
  folder (MESA_SHADER_CACHE_DIR, XDG_CACHE_HOME), so compiles are really cold; each size
  of the lights-at-scale figure has its own worker;
* ``analyse.py`` (pure): raw results -> figures (medians, spreads, ratios, goals);
* ``table.py`` (pure): figures -> the Markdown table.

This process never imports ``bpy``.
"""

from __future__ import annotations

import argparse
import json
import os
import platform
import shutil
import subprocess
import sys
import tempfile
import time

from phong_nodes.benchmarks.analyse import analyse
from phong_nodes.benchmarks.measure import rotated
from phong_nodes.benchmarks.table import markdown

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
HERE = os.path.join(ROOT, "benchmarks")
SCHEMA = 1

#: Sizes of the full run (documented in results.md) and of --quick (smoke test).
FULL = {
    "repeats": 3,
    "cycles_res": 512, "cycles_spp": 8, "grid": 5, "segments": 32,
    "lights": [1, 2, 4, 8, 16],
    "quality_res": 48, "quality_ref_spp": 4096, "quality_max_spp": 8192,
    "quality_probe_spp": [1, 16, 64],
    "scale_objects": 1000, "scale_res": 512, "scale_spp": 4, "scale_segments": 16,
    "scale_distinct": True,
    "artist_objects": [1000, 10000], "artist_lights": [4, 16], "scale_moves": 9,
    "eevee_res": 256, "eevee_samples": 4, "eevee_grid": 3, "eevee_cold": True,
    "demo_scenes": ["color_product", "exponents", "four_terms", "lambert_vs_phong",
                    "point_falloff", "spot_edges", "textured", "two_lights"],
}
QUICK = {
    "repeats": 3,
    "cycles_res": 32, "cycles_spp": 1, "grid": 2, "segments": 8,
    "lights": [1, 2],
    "quality_res": 16, "quality_ref_spp": 64, "quality_max_spp": 64,
    "quality_probe_spp": [1, 4],
    "scale_objects": 20, "scale_res": 32, "scale_spp": 1, "scale_segments": 8,
    "scale_distinct": True,
    "artist_objects": [6, 12], "artist_lights": [2, 4], "scale_moves": 3,
    "eevee_res": 32, "eevee_samples": 1, "eevee_grid": 1, "eevee_cold": False,
    "demo_scenes": ["exponents", "two_lights"],
}


def run_worker(name, params, cold_cache=False, log=print):
    """Run worker *name* of ``measure.py`` in a process of its own; returns its result."""
    env = dict(os.environ)
    tmp = tempfile.mkdtemp(prefix="phong_bench_w_")
    env["BLENDER_USER_RESOURCES"] = os.path.join(tmp, "user")
    if cold_cache:
        env["MESA_SHADER_CACHE_DIR"] = os.path.join(tmp, "mesa")
        env["XDG_CACHE_HOME"] = os.path.join(tmp, "cache")  # Blender's gl-shader-cache too
    params = {**params, "result_path": os.path.join(tmp, "result.json")}
    start = time.perf_counter()
    try:
        proc = subprocess.run([sys.executable, "-m", "phong_nodes.benchmarks.measure", name,
                               json.dumps(params)], env=env, cwd=ROOT,
                              capture_output=True, text=True)
        if proc.returncode == 0 and os.path.exists(params["result_path"]):
            with open(params["result_path"]) as fh:
                result = json.load(fh)
            log(f"  worker {name}: {time.perf_counter() - start:.1f} s")
            return result
    finally:
        shutil.rmtree(tmp, ignore_errors=True)
    raise RuntimeError(f"worker {name} failed (exit {proc.returncode}):\n"
                       f"{proc.stdout[-3000:]}\n{proc.stderr[-3000:]}")


def load_average():
    try:
        return list(os.getloadavg())
    except OSError:
        return None


def collect(cfg, log=print):
    """Every measurement of the run (raw seconds and counts from the workers)."""
    reps = cfg["repeats"]
    started = time.perf_counter()
    load_before = load_average()
    log(f"load average before: {load_before}")

    log("Cycles (figures 1, 2, 4, 5)...")
    cyc = run_worker("cycles", {"cfg": cfg}, log=log)

    log("Eevee compile, Phong vs Principled (figure 3)...")
    compile_runs = []
    for r in range(reps):
        for material in rotated(["phong", "principled"], r):
            compile_runs.append((material, run_worker(
                "eevee", {"cfg": cfg, "cases": [[material, 1]]}, cold_cache=cfg["eevee_cold"],
                log=log)))

    log("Eevee light scaling (figure 2)...")
    light_runs = []
    cases = [["phong", n] for n in cfg["lights"]]
    for r in range(reps):
        light_runs.append(run_worker("eevee", {"cfg": cfg, "cases": rotated(cases, r)},
                                     cold_cache=cfg["eevee_cold"], log=log))

    log("Lights at scale: artist scenes, Principled then Phong (figure 6)...")
    cases = [[n, k] for n in cfg["artist_objects"] for k in cfg["artist_lights"]]
    artist_runs = []
    for r in range(reps):
        for case in rotated(cases, r):
            artist_runs.append(run_worker("artist", {"cfg": cfg, "case": case}, log=log))

    log("Demo scenes, Eevee first render: shared layouts vs one per material (figure 7)...")
    names = cfg["demo_scenes"]
    demo_runs = [run_worker("demos", {"cfg": cfg, "names": rotated(names, r)},
                            cold_cache=cfg["eevee_cold"], log=log) for r in range(reps)]

    load_after = load_average()
    return {"cycles": cyc, "eevee_compile": compile_runs, "eevee_lights": light_runs,
            "artist": artist_runs, "demos": demo_runs,
            "load_before": load_before, "load_after": load_after,
            "total_seconds": time.perf_counter() - started}


def bpy_version():
    try:
        out = subprocess.run([sys.executable, "-c", "import bpy; print(bpy.app.version_string)"],
                             capture_output=True, text=True, timeout=120,
                             env={**os.environ, "BLENDER_USER_RESOURCES": tempfile.gettempdir()})
        return out.stdout.strip().splitlines()[-1]
    except Exception:  # noqa: BLE001
        return "unknown"


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--quick", action="store_true", help="tiny sizes (smoke test)")
    parser.add_argument("--repeats", type=int, help="repeats per figure (default 3)")
    parser.add_argument("--out", default=os.path.join(HERE, "results.json"))
    parser.add_argument("--md", default=None,
                        help="Markdown file (default: --out with .md for .json)")
    args = parser.parse_args(argv)
    cfg = dict(QUICK if args.quick else FULL)
    if args.repeats:
        cfg["repeats"] = args.repeats
    if cfg["repeats"] < 1:
        parser.error("--repeats must be at least 1")
    # the table beside the figures, named after them (results.json -> results.md)
    md_path = args.md or os.path.splitext(os.path.abspath(args.out))[0] + ".md"

    raw = collect(cfg, log=lambda m: print(m, file=sys.stderr, flush=True))
    meta = {"schema": SCHEMA, "date": time.strftime("%Y-%m-%d %H:%M:%S"),
            "quick": bool(args.quick), "repeats": cfg["repeats"], "config": cfg,
            "load_before": raw["load_before"], "load_after": raw["load_after"],
            "cpu_count": os.cpu_count(), "machine": platform.platform(),
            "python": platform.python_version(), "bpy": bpy_version(),
            "total_seconds": raw["total_seconds"]}
    figures = analyse(raw, cfg)
    table = markdown(figures, meta)
    result = {"meta": meta, "figures": figures, "raw": raw}
    os.makedirs(os.path.dirname(os.path.abspath(args.out)), exist_ok=True)
    with open(args.out, "w") as fh:
        json.dump(result, fh, indent=1, allow_nan=True)
    with open(md_path, "w") as fh:
        fh.write(table + "\n")
    print(table)
    return 0


if __name__ == "__main__":
    sys.exit(main())

