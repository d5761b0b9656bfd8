# SPDX-License-Identifier: GPL-3.0-or-later
"""Time to a finished picture: Cycles F12 at Blender's default render settings, Phong against
Principled, in one run.

    .venv/bin/python -m phong_nodes.benchmarks.finished_picture [--objects 1000] [--res 128]
        [--lights 4 16] [--repeats 2] [--out benchmarks/finished_picture_results.json]
    .venv/bin/python -m phong_nodes.benchmarks.finished_picture --table \
        benchmarks/finished_picture_results.json

The fixed-sample figures of ``shadow_speed.py`` give both materials the same number of samples.
A user does not: Blender's defaults render until every pixel's noise is under the adaptive
threshold (0.01, at most 4,096 samples) and then denoise (OpenImageDenoise).  Phong's shading
has no noise of its own (its lights are evaluated, not sampled; only the pixel filter and the
edges vary from sample to sample), so a Phong picture is finished after far fewer samples than
a Principled one lit by the same lights.  This measures that, on the same scene as
``shadow_speed.py`` (``measure.artist_scene`` with every light casting shadows, a floor, the
orthographic camera from above): each case (``principled``, ``phong`` after Apply Phong
Material) in a process of its own, one untimed 1-sample render first (kernels loaded), then
one timed render with the scene's defaults left as Blender makes them (only the device is set:
CPU).  Per render: the wall-clock seconds, the seconds until Cycles' first sample (the sync:
scene, shaders, BVH) and the samples per pixel Cycles spent (its Debug Sample Count pass: mean
and maximum over the pixels).  The order of the cases alternates from repeat to repeat.
"""

from __future__ import annotations

import argparse
import json
import os
import statistics
import subprocess
import sys
import tempfile
import time

from .table import publish

CASES = ("principled", "phong")


def _sample_counts(path):
    """(mean, max) of the Debug Sample Count pass of the multilayer EXR at *path*: fractions of
    the scene's samples (Cycles writes a pixel's samples divided by them)."""
    import numpy as np  # noqa: PLC0415
    import OpenImageIO as oiio  # noqa: PLC0415

    found = []
    for subimage in range(oiio.ImageInput.open(path).spec().get_int_attribute("oiio:subimages", 1)
                          or 1):
        buf = oiio.ImageBuf(path, subimage, 0)
        names = list(buf.spec().channelnames)
        found.append(names)
        for column, name in enumerate(names):
            if "sample count" in name.lower():
                counts = np.asarray(buf.get_pixels(oiio.FLOAT), dtype=np.float64)[..., column]
                return float(counts.mean()), float(counts.max())
    raise RuntimeError(f"no Debug Sample Count pass in {path}: {found}")


def worker(case, objects, n_lights, res) -> dict:
    """One process, one case: the scene built, one untimed 1-sample render, then one render at
    Blender's default Cycles settings (adaptive sampling, denoising) on the CPU."""
    os.environ["PHONG_BENCH_SHADOWS"] = "1"
    from .eevee_materials import _camera  # noqa: PLC0415
    from .measure import apply_phong, artist_scene, worker_setup  # noqa: PLC0415
    from phong_nodes.addon import compat  # noqa: PLC0415

    bpy = worker_setup()
    scene, meshes, _lights = artist_scene(case, objects, n_lights)
    bpy.context.window.scene = scene
    _camera(bpy, scene, objects)
    scene.render.resolution_x = scene.render.resolution_y = res
    scene.render.engine = "CYCLES"
    cycles = scene.cycles
    cycles.device = "CPU"
    defaults = {name: getattr(cycles, name) for name in
                ("samples", "use_adaptive_sampling", "adaptive_threshold",
                 "adaptive_min_samples", "use_denoising", "denoiser", "time_limit")}
    if case == "phong":
        apply_phong(bpy, scene, meshes)
    scene.view_layers[0].cycles.pass_debug_sample_count = True
    compat.set_multilayer_exr(scene.render.image_settings)
    stamps = []
    bpy.app.handlers.render_stats.append(lambda text: stamps.append((time.perf_counter(), text)))
    with tempfile.TemporaryDirectory() as folder:
        cycles.samples = 1
        with bpy.context.temp_override(scene=scene):
            bpy.ops.render.render(scene=scene.name)
        cycles.samples = defaults["samples"]
        stamps.clear()
        scene.render.filepath = os.path.join(folder, "finished.exr")
        start = time.perf_counter()
        with bpy.context.temp_override(scene=scene):
            bpy.ops.render.render(write_still=True, scene=scene.name)
        seconds = time.perf_counter() - start
        mean, most = (defaults["samples"] * x for x in _sample_counts(scene.render.filepath))
    first = next((t for t, text in stamps if "Sample 0/" in text or "Sample 1/" in text), None)
    return {"render_s": seconds, "sync_s": None if first is None else first - start,
            "mean_samples": mean, "max_samples": most, "defaults": defaults,
            "bpy": bpy.app.version_string}


def figure(objects, n_lights, res, repeats) -> dict:
    out = {"lights": n_lights, "runs": {case: [] for case in CASES},
           "load_average": [os.getloadavg()]}
    for repeat in range(repeats):
        for case in CASES if repeat % 2 == 0 else CASES[::-1]:
            args = [sys.executable, "-m", "phong_nodes.benchmarks.finished_picture",
                    "--worker", case, str(objects), str(n_lights), str(res)]
            proc = subprocess.run(args, capture_output=True, text=True)
            line = [x for x in proc.stdout.splitlines() if x.startswith("RESULT ")]
            if proc.returncode != 0 or not line:
                raise RuntimeError(proc.stdout[-2000:] + proc.stderr[-2000:])
            result = json.loads(line[-1][7:])
            out["bpy"], out["defaults"] = result.pop("bpy"), result.pop("defaults")
            out["runs"][case].append(result)
            out["load_average"].append(os.getloadavg())
    median = {case: statistics.median(r["render_s"] for r in runs)
              for case, runs in out["runs"].items()}
    out["median_s"] = median
    out["ratio_to_principled"] = median["phong"] / median["principled"]
    return out


def run(objects, res, lights, repeats) -> dict:
    started = time.perf_counter()
    out = {"objects": objects, "res": res, "repeats": repeats, "figures": []}
    for n_lights in lights:
        out["figures"].append(figure(objects, n_lights, res, repeats))
        out["bpy"] = out["figures"][-1]["bpy"]
    out["seconds"] = time.perf_counter() - started
    return out


def _median(runs, key) -> float:
    return statistics.median(r[key] for r in runs)


def table(result) -> str:
    """The Markdown table of a run (``run``'s JSON)."""
    lines = ["| Cycles F12, Blender's defaults | Principled | Phong | Phong / Principled | "
             "samples per pixel, mean (max): Principled | Phong |",
             "|---|---|---|---|---|---|"]
    for fig in result["figures"]:
        runs = fig["runs"]
        cells = []
        for case in CASES:
            times = [r["render_s"] for r in runs[case]]
            cells.append(f"{statistics.median(times):.2f} s "
                         f"({min(times):.2f}–{max(times):.2f})")
        samples = [f"{_median(runs[c], 'mean_samples'):.0f} ({_median(runs[c], 'max_samples'):.0f})"
                   for c in CASES]
        lines.append(f"| {fig['lights']} lights | {cells[0]} | {cells[1]} | "
                     f"**{fig['ratio_to_principled']:.2f}×** | {samples[0]} | {samples[1]} |")
    return "\n".join(lines)


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--objects", type=int, default=1000)
    parser.add_argument("--res", type=int, default=128)
    parser.add_argument("--lights", type=int, nargs="+", default=[4, 16])
    parser.add_argument("--repeats", type=int, default=2)
    parser.add_argument("--out", help="write the JSON here")
    parser.add_argument("--table", metavar="JSON", help="only print the table of a run")
    parser.add_argument("--worker", nargs=4, help=argparse.SUPPRESS)
    args = parser.parse_args(argv)
    if args.worker:
        case, objects, n_lights, res = args.worker
        result = worker(case, int(objects), int(n_lights), int(res))
        print("RESULT " + json.dumps(result), flush=True)
        os._exit(0)  # skip bpy's clean-up at exit (slow)
    if args.table:
        with open(args.table, encoding="utf-8") as handle:
            print(table(json.load(handle)))
        return 0
    result = run(args.objects, args.res, args.lights, args.repeats)
    publish(result, args.out, table(result))
    return 0


if __name__ == "__main__":
    sys.exit(main())
