#!/usr/bin/env python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""Phong Nodes benchmarks: what Phong shading costs (issue 5).

    .venv/bin/python benchmarks/run.py            # full run, ~10 min on a 2-core CPU
    .venv/bin/python benchmarks/run.py --quick    # tiny sizes, for the smoke test

Writes ``benchmarks/results.json`` and ``benchmarks/results.md`` (the Markdown table it also
prints).  Every figure is a ratio of two renders (or builds) measured side by side in the
same run; each is given as the median over the repeats and the spread (min-max).

This process never imports ``bpy``: it starts worker processes (``--worker``) of itself.
The Cycles figures come from one warm worker; every Eevee figure that includes shader
compilation comes from its own worker whose Mesa and Blender shader caches point to a fresh
empty folder (MESA_SHADER_CACHE_DIR, XDG_CACHE_HOME), so compiles are really cold.
"""

from __future__ import annotations

import argparse
import json
import math
import os
import platform
import shutil
import statistics
import subprocess
import sys
import tempfile
import time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
HERE = os.path.join(ROOT, "benchmarks")
RESULT_TAG = "BENCH-RESULT:"
SCHEMA = 1

#: Sizes of the full run (documented in results.md) and of --quick (smoke test).
FULL = {
    "repeats": 3,
    "cycles_res": 512, "cycles_spp": 16, "grid": 5, "segments": 32,
    "lights": [1, 2, 4, 8, 16],
    "quality_res": 64, "quality_ref_spp": 4096, "quality_max_spp": 4096,
    "scale_objects": 1000, "scale_res": 512, "scale_spp": 4, "scale_segments": 16,
    "eevee_res": 256, "eevee_samples": 4, "eevee_grid": 3,
}
QUICK = {
    "repeats": 3,
    "cycles_res": 32, "cycles_spp": 1, "grid": 2, "segments": 8,
    "lights": [1, 2],
    "quality_res": 16, "quality_ref_spp": 64, "quality_max_spp": 64,
    "scale_objects": 20, "scale_res": 32, "scale_spp": 1, "scale_segments": 8,
    "eevee_res": 32, "eevee_samples": 1, "eevee_grid": 1,
}
THRESHOLD = 1.0 / 255.0
OBJECT_COLOR = (1.0, 0.246, 0.091)  # the demo's 0xFF8855, linear


# =========================================================================== statistics

def summary(values):
    values = [float(v) for v in values]
    return {"median": statistics.median(values), "min": min(values), "max": max(values),
            "values": values}


def ratio_summary(numerators, denominators):
    return summary([a / b for a, b in zip(numerators, denominators)])


# =========================================================================== workers (bpy)

def _bpy():
    import bpy  # noqa: PLC0415

    return bpy


def worker_setup():
    """Import bpy (with a throw-away user folder) and register the extension from source."""
    os.environ.setdefault("BLENDER_USER_RESOURCES", tempfile.mkdtemp(prefix="phong_bench_res_"))
    bpy = _bpy()
    sys.path.insert(0, os.path.join(ROOT, "tools"))
    import phong  # noqa: PLC0415  (tools/phong.py)

    extension = phong.import_extension()
    extension.register()
    return bpy


def uv_sphere(name, segments):
    from phong_nodes.addon import demo  # noqa: PLC0415

    mesh = _bpy().data.meshes.new(name)
    demo._uv_sphere(mesh, segments=segments, rings=max(segments // 2, 3))
    return mesh


def build_scene(name, *, res, grid, n_lights, material, segments=32, shared_mesh=False,
                n_objects=None, select=True):
    """Spheres on a grid in front of an orthographic camera, lit by *n_lights* point lights.

    material: 'phong' (apply_material; timed), 'emission' (the floor: Emission of the object
    colour, strength 1), 'principled' (Principled BSDF of that colour, lit by the lights).
    Each object has its own mesh and material unless *shared_mesh* (linked duplicates: one
    mesh, one material).  Returns (scene, apply_material seconds or None).
    """
    bpy = _bpy()
    from phong_nodes.addon import properties  # noqa: PLC0415

    scene = bpy.data.scenes.new(name)
    scene.render.resolution_x = scene.render.resolution_y = res
    scene.render.resolution_percentage = 100
    scene.view_settings.view_transform = "Standard"
    scene.render.film_transparent = False
    world = bpy.data.worlds.new(name)
    world.color = (0.0, 0.0, 0.0)
    background = world.node_tree.nodes.get("Background") if world.node_tree else None
    if background is not None:
        background.inputs["Color"].default_value = (0.0, 0.0, 0.0, 1.0)
        background.inputs["Strength"].default_value = 0.0
    scene.world = world

    count = n_objects if n_objects is not None else grid * grid
    cols = max(1, math.ceil(math.sqrt(count)))
    rows = math.ceil(count / cols)
    spacing = 2.2
    objects = []
    shared = uv_sphere(f"{name} sphere", segments) if shared_mesh else None
    for index in range(count):
        mesh = shared if shared_mesh else uv_sphere(f"{name} sphere {index}", segments)
        obj = bpy.data.objects.new(f"{name} {index:04d}", mesh)
        obj.location = ((index % cols - (cols - 1) / 2) * spacing, 0.0,
                        (index // cols - (rows - 1) / 2) * spacing)
        scene.collection.objects.link(obj)
        objects.append(obj)

    camera = bpy.data.objects.new(f"{name} camera", bpy.data.cameras.new(f"{name} camera"))
    camera.data.type = "ORTHO"
    camera.data.ortho_scale = max(cols, rows) * spacing
    camera.data.clip_end = 1000.0
    camera.location = (0.0, -20.0, 0.0)
    camera.rotation_euler = (math.pi / 2, 0.0, 0.0)
    scene.collection.objects.link(camera)
    scene.camera = camera

    extent = max(cols, rows) * spacing / 2
    for k in range(n_lights):
        angle = 2 * math.pi * (k + 0.125) / n_lights
        data = bpy.data.lights.new(f"{name} light {k}", "POINT")
        data.energy = 4000.0 * extent * extent / 16 / n_lights  # Principled: similar exposure
        data.shadow_soft_size = 0.25
        properties.ensure_light_props(data)
        data["phong_intensity"] = 2.0 * (extent + 4) ** 2 / n_lights
        light = bpy.data.objects.new(f"{name} light {k}", data)
        light.location = (extent * math.cos(angle), -6.0, extent * math.sin(angle) + 2.0)
        scene.collection.objects.link(light)

    build_seconds = None
    if material == "phong":
        view_layer = scene.view_layers[0]
        for obj in objects:
            obj.select_set(True, view_layer=view_layer)
        start = time.perf_counter()
        with bpy.context.temp_override(scene=scene, view_layer=view_layer,
                                       selected_objects=objects):
            result = bpy.ops.phong.apply_material()
        build_seconds = time.perf_counter() - start
        if result != {"FINISHED"}:
            raise RuntimeError(f"apply_material returned {result}")
        for mat in {slot.material for obj in objects for slot in obj.material_slots}:
            mat.node_tree.nodes["phong_object_color"].outputs[0].default_value = (*OBJECT_COLOR, 1)
    else:
        mats = {}
        for obj in objects:
            key = obj.data.name
            if key not in mats:
                mats[key] = simple_material(f"{name} {material} {len(mats)}", material)
                obj.data.materials.append(mats[key])
    return scene, build_seconds


def simple_material(name, kind):
    bpy = _bpy()
    from phong_nodes.addon import compat  # noqa: PLC0415

    mat = bpy.data.materials.new(name)
    tree = compat.new_material_tree(mat)
    tree.nodes.clear()
    out = tree.nodes.new("ShaderNodeOutputMaterial")
    if kind == "emission":
        node = tree.nodes.new("ShaderNodeEmission")
        node.inputs["Color"].default_value = (*OBJECT_COLOR, 1.0)
        node.inputs["Strength"].default_value = 1.0
        tree.links.new(node.outputs["Emission"], out.inputs["Surface"])
    elif kind == "principled":
        node = tree.nodes.new("ShaderNodeBsdfPrincipled")
        node.inputs["Base Color"].default_value = (*OBJECT_COLOR, 1.0)
        node.inputs["Roughness"].default_value = 0.3
        tree.links.new(node.outputs["BSDF"], out.inputs["Surface"])
    else:
        raise ValueError(kind)
    return mat


def set_cycles(scene, samples, seed=0):
    scene.render.engine = "CYCLES"
    cycles = scene.cycles
    cycles.device = "CPU"
    cycles.samples = samples
    cycles.use_adaptive_sampling = False
    cycles.use_denoising = False
    cycles.seed = seed
    cycles.use_animated_seed = False


def set_eevee(scene, samples):
    from phong_nodes.addon import compat  # noqa: PLC0415

    scene.render.engine = compat.eevee_engine()
    scene.eevee.taa_render_samples = samples


def render(scene, path=None):
    """Render *scene* (PNG 16-bit to *path* when given); returns the wall-clock seconds."""
    bpy = _bpy()
    from phong_nodes.addon import compat  # noqa: PLC0415

    if path is not None:
        compat.set_png(scene.render.image_settings)
        scene.render.image_settings.color_depth = "16"
        scene.render.filepath = path
    start = time.perf_counter()
    with bpy.context.temp_override(scene=scene):
        bpy.ops.render.render(write_still=path is not None, scene=scene.name)
    return time.perf_counter() - start


def read_image(path):
    import numpy as np  # noqa: PLC0415
    import OpenImageIO as oiio  # noqa: PLC0415

    buf = oiio.ImageBuf(path)
    return np.asarray(buf.get_pixels(oiio.FLOAT), dtype=np.float64)[..., :3]


def rmse(a, b):
    import numpy as np  # noqa: PLC0415

    return float(np.sqrt(np.mean((a - b) ** 2)))


def remove_scene(scene):
    bpy = _bpy()
    objects = list(scene.collection.objects)
    meshes = {o.data for o in objects if o.type == "MESH"}
    lights = {o.data for o in objects if o.type == "LIGHT"}
    materials = {m for me in meshes for m in me.materials if m is not None}
    world = scene.world
    bpy.data.scenes.remove(scene)
    for obj in objects:
        bpy.data.objects.remove(obj)
    for block, coll in ((meshes, bpy.data.meshes), (lights, bpy.data.lights),
                        (materials, bpy.data.materials)):
        for item in block:
            coll.remove(item)
    if world is not None:
        bpy.data.worlds.remove(world)


def rotated(items, r):
    """Order of the cases in repeat *r*: rotated so that no case always runs first."""
    r %= len(items)
    return list(items[r:]) + list(items[:r])


# --------------------------------------------------------------------- Cycles worker

def worker_cycles(cfg):
    """Figures 1, 2 (Cycles), 4 and 5 in one warm process."""
    out = {}
    reps = cfg["repeats"]

    # warm-up: loads the Cycles kernels once
    scene, _ = build_scene("warm", res=16, grid=1, n_lights=1, material="emission", segments=8)
    set_cycles(scene, 1)
    render(scene)
    remove_scene(scene)

    # 1 + 2: node cost and light scaling, same sphere grid
    cases = [("emission", 1)] + [("phong", n) for n in cfg["lights"]]
    scenes = {}
    builds = {}
    for material, n in cases:
        scene, build = build_scene(f"{material} {n}", res=cfg["cycles_res"], grid=cfg["grid"],
                                   n_lights=n, material=material, segments=cfg["segments"])
        set_cycles(scene, cfg["cycles_spp"])
        scenes[(material, n)] = scene
        builds[(material, n)] = build
        render(scene)  # first render: syncs the scene (not timed)
    times = {case: [] for case in cases}
    for r in range(reps):
        for case in rotated(cases, r):
            times[case].append(render(scenes[case]))
    for scene in scenes.values():
        remove_scene(scene)
    out["cycles_times"] = {f"{m}:{n}": t for (m, n), t in times.items()}
    out["apply_material_seconds"] = {f"{m}:{n}": b for (m, n), b in builds.items() if b}

    # 4: quality per second at a small resolution
    out["quality"] = quality(cfg)

    # 5: scale, one material shared by linked duplicates
    out["scale"] = scale(cfg)
    return out


def quality(cfg):
    tmp = tempfile.mkdtemp(prefix="phong_bench_q_")
    res = cfg["quality_res"]
    result = {}
    try:
        for material in ("principled", "phong"):
            scene, _ = build_scene(f"q {material}", res=res, grid=cfg["grid"], n_lights=1,
                                   material=material, segments=cfg["segments"])
            ref_path = os.path.join(tmp, f"{material}_ref.png")
            set_cycles(scene, cfg["quality_ref_spp"], seed=1000)
            ref_seconds = render(scene, ref_path)
            ref = read_image(ref_path)
            repeats = []
            for r in range(cfg["repeats"]):
                curve = []
                samples = 1
                found = None
                while samples <= cfg["quality_max_spp"]:
                    path = os.path.join(tmp, f"{material}_{r}_{samples}.png")
                    set_cycles(scene, samples, seed=r + 1)
                    seconds = render(scene, path)
                    error = rmse(read_image(path), ref)
                    curve.append({"spp": samples, "rmse": error, "seconds": seconds})
                    if error < THRESHOLD:
                        found = curve[-1]
                        break
                    samples *= 2
                one = curve[0]
                repeats.append({"curve": curve, "converged": found, "one_spp": one})
            result[material] = {"reference_spp": cfg["quality_ref_spp"],
                                "reference_seconds": ref_seconds,
                                "mean_value": float(ref.mean()), "repeats": repeats}
            remove_scene(scene)
    finally:
        shutil.rmtree(tmp, ignore_errors=True)
    return result


def scale(cfg):
    n = cfg["scale_objects"]
    builds, phong_t, emission_t = [], [], []
    for r in range(cfg["repeats"]):
        pairs = {}
        for material in ("phong", "emission"):
            scene, build = build_scene(f"s{r} {material}", res=cfg["scale_res"], grid=0,
                                       n_lights=1, material=material, n_objects=n,
                                       segments=cfg["scale_segments"], shared_mesh=True)
            set_cycles(scene, cfg["scale_spp"])
            if build is not None:
                builds.append(build)
            pairs[material] = scene
        for material in rotated(["phong", "emission"], r):
            seconds = render(pairs[material])  # first render of the scene: sync included
            (phong_t if material == "phong" else emission_t).append(seconds)
        materials = {s.material for o in pairs["phong"].collection.objects
                     for s in o.material_slots}
        for scene in pairs.values():
            remove_scene(scene)
    return {"objects": n, "phong_materials": len(materials), "apply_seconds": builds,
            "phong_render": phong_t, "emission_render": emission_t}


# --------------------------------------------------------------------- Eevee worker

def worker_eevee(cfg, cases):
    """One cold process: warm the engine with the Emission floor, then time the first
    (compile included) and second render of each case (material, n_lights)."""
    out = {}
    scene, _ = build_scene("ewarm", res=cfg["eevee_res"], grid=cfg["eevee_grid"], n_lights=1,
                           material="emission", segments=cfg["segments"])
    set_eevee(scene, cfg["eevee_samples"])
    out["warmup_first"] = render(scene)
    out["warmup_second"] = render(scene)
    remove_scene(scene)
    for material, n in cases:
        scene, _ = build_scene(f"e {material} {n}", res=cfg["eevee_res"], grid=cfg["eevee_grid"],
                               n_lights=n, material=material, segments=cfg["segments"])
        set_eevee(scene, cfg["eevee_samples"])
        first = render(scene)
        second = render(scene)
        out[f"{material}:{n}"] = {"first": first, "second": second}
        remove_scene(scene)
    return out


def worker_main(name, params):
    cfg = params["cfg"]
    worker_setup()
    if name == "cycles":
        result = worker_cycles(cfg)
    elif name == "eevee":
        result = worker_eevee(cfg, [tuple(c) for c in params["cases"]])
    else:
        raise SystemExit(f"unknown worker {name}")
    print(RESULT_TAG + json.dumps(result), flush=True)
    sys.stdout.flush()
    os._exit(0)  # skip bpy's clean-up at exit (slow, and it can crash after Eevee)


# =========================================================================== orchestrator

def run_worker(name, params, cold_cache=False, log=print):
    env = dict(os.environ)
    tmp = tempfile.mkdtemp(prefix="phong_bench_w_")
    env["BLENDER_USER_RESOURCES"] = os.path.join(tmp, "user")
    if cold_cache:
        env["MESA_SHADER_CACHE_DIR"] = os.path.join(tmp, "mesa")
        env["XDG_CACHE_HOME"] = os.path.join(tmp, "cache")  # Blender's gl-shader-cache too
    start = time.perf_counter()
    try:
        proc = subprocess.run([sys.executable, os.path.abspath(__file__), "--worker", name,
                               "--params", json.dumps(params)], env=env, cwd=ROOT,
                              capture_output=True, text=True)
    finally:
        shutil.rmtree(tmp, ignore_errors=True)
    for line in proc.stdout.splitlines():
        if line.startswith(RESULT_TAG):
            log(f"  worker {name}: {time.perf_counter() - start:.1f} s")
            return json.loads(line[len(RESULT_TAG):])
    raise RuntimeError(f"worker {name} failed (exit {proc.returncode}):\n"
                       f"{proc.stdout[-3000:]}\n{proc.stderr[-3000:]}")


def load_average():
    try:
        return list(os.getloadavg())
    except OSError:
        return None


def collect(cfg, log=print):
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
                "eevee", {"cfg": cfg, "cases": [[material, 1]]}, cold_cache=True, log=log)))

    log("Eevee light scaling (figure 2)...")
    light_runs = []
    cases = [["phong", n] for n in cfg["lights"]]
    for r in range(reps):
        light_runs.append(run_worker("eevee", {"cfg": cfg, "cases": rotated(cases, r)},
                                     cold_cache=True, log=log))

    load_after = load_average()
    return {"cycles": cyc, "eevee_compile": compile_runs, "eevee_lights": light_runs,
            "load_before": load_before, "load_after": load_after,
            "total_seconds": time.perf_counter() - started}


def analyse(raw, cfg):
    figures = {}
    cyc = raw["cycles"]
    t = cyc["cycles_times"]
    lights = cfg["lights"]

    # 1
    figures["node_cost_cycles"] = {
        "what": f"Cycles render, {cfg['grid']}x{cfg['grid']} spheres, 1 light, "
                f"{cfg['cycles_res']}x{cfg['cycles_res']}, {cfg['cycles_spp']} spp: "
                "Phong / Emission floor",
        "ratio": ratio_summary(t["phong:1"], t["emission:1"]),
        "phong_seconds": summary(t["phong:1"]), "floor_seconds": summary(t["emission:1"]),
        "goal": "<= 1.2", "goal_value": 1.2, "goal_kind": "max",
    }

    # 2 Cycles
    base = t["phong:1"]
    scaling = {str(n): ratio_summary(t[f"phong:{n}"], base) for n in lights}
    last = lights[-1]
    extra = summary([(a / b - 1) / (last - 1) if last > 1 else 0.0
                     for a, b in zip(t[f"phong:{last}"], base)])
    floor = t["emission:1"]
    shading = summary([(a - f) / (b - f) if b > f else float("nan")
                       for a, b, f in zip(t[f"phong:{last}"], base, floor)])
    figures["light_scaling_cycles"] = {
        "what": "Cycles render time with N lights / with 1 light (same grid and size as 1)",
        "ratios": scaling,
        "seconds": {str(n): summary(t[f"phong:{n}"]) for n in lights},
        "extra_light_fraction": extra,
        "shading_time_ratio": shading,
        "goal": "each extra light < 10% of the 1-light render", "goal_value": 0.10,
        "goal_kind": "max",
    }

    # 2 Eevee
    first = {n: [run[f"phong:{n}"]["first"] for run in raw["eevee_lights"]] for n in lights}
    second = {n: [run[f"phong:{n}"]["second"] for run in raw["eevee_lights"]] for n in lights}
    figures["light_scaling_eevee"] = {
        "what": "Eevee first render (material shader compile included, engine shaders already "
                "compiled by a warm-up render) with N lights / with 1 light",
        "ratios": {str(n): ratio_summary(first[n], first[lights[0]]) for n in lights},
        "first_seconds": {str(n): summary(first[n]) for n in lights},
        "second_seconds": {str(n): summary(second[n]) for n in lights},
        "goal": "linear in N", "goal_kind": "info",
    }

    # 3
    ph = [run for m, run in raw["eevee_compile"] if m == "phong"]
    pr = [run for m, run in raw["eevee_compile"] if m == "principled"]
    ph_first = [run["phong:1"]["first"] for run in ph]
    pr_first = [run["principled:1"]["first"] for run in pr]
    ph_compile = [run["phong:1"]["first"] - run["phong:1"]["second"] for run in ph]
    pr_compile = [run["principled:1"]["first"] - run["principled:1"]["second"] for run in pr]
    cold = [run["warmup_first"] for _m, run in raw["eevee_compile"]]
    figures["eevee_compile"] = {
        "what": "Eevee first render of the material in a cold-cache process (after a warm-up "
                "render that compiles the engine's own shaders): Phong / Principled BSDF",
        "ratio": ratio_summary(ph_first, pr_first),
        "compile_ratio": ratio_summary([max(x, 1e-3) for x in ph_compile],
                                       [max(x, 1e-3) for x in pr_compile]),
        "phong_first_seconds": summary(ph_first), "principled_first_seconds": summary(pr_first),
        "phong_compile_seconds": summary(ph_compile),
        "principled_compile_seconds": summary(pr_compile),
        "cold_process_first_render_seconds": summary(cold),
        "goal": "< 1 (Phong compiles faster)", "goal_value": 1.0, "goal_kind": "max_strict",
    }

    # 4
    q = cyc["quality"]

    def conv(material, key):
        return [rep["converged"][key] if rep["converged"] else float("nan")
                for rep in q[material]["repeats"]]

    pr_sec, ph_one = conv("principled", "seconds"), [rep["one_spp"]["seconds"]
                                                    for rep in q["phong"]["repeats"]]
    figures["quality_per_second"] = {
        "what": f"Cycles {cfg['quality_res']}x{cfg['quality_res']}: Principled BSDF at the "
                f"sample count whose RMSE against its own {cfg['quality_ref_spp']}-spp render "
                "is below 1/255, time / Phong at 1 spp",
        "ratio": ratio_summary(pr_sec, ph_one),
        "ratio_vs_phong_converged": ratio_summary(pr_sec, conv("phong", "seconds")),
        "principled_spp": summary(conv("principled", "spp")),
        "principled_seconds": summary(pr_sec),
        "phong_spp_converged": summary(conv("phong", "spp")),
        "phong_one_spp_rmse": summary([rep["one_spp"]["rmse"] for rep in q["phong"]["repeats"]]),
        "phong_one_spp_seconds": summary(ph_one),
        "curves": {m: [rep["curve"] for rep in q[m]["repeats"]] for m in q},
        "goal": "report", "goal_kind": "info",
    }

    # 5
    s = cyc["scale"]
    figures["scale"] = {
        "what": f"{s['objects']} linked-duplicate spheres sharing one material, 1 light, "
                f"{cfg['scale_res']}x{cfg['scale_res']}, {cfg['scale_spp']} spp, first render "
                "(scene sync included): Phong / Emission",
        "ratio": ratio_summary(s["phong_render"], s["emission_render"]),
        "apply_material_seconds": summary(s["apply_seconds"]),
        "phong_materials": s["phong_materials"],
        "phong_seconds": summary(s["phong_render"]), "emission_seconds": summary(s["emission_render"]),
        "goal": "report", "goal_kind": "info",
    }
    return figures


def fmt(s, digits=2, unit=""):
    return (f"{s['median']:.{digits}f}{unit} ({s['min']:.{digits}f}–{s['max']:.{digits}f})")


def verdict(value, goal_value, kind):
    if kind == "max":
        ok = value <= goal_value
    elif kind == "max_strict":
        ok = value < goal_value
    else:
        return ""
    if ok:
        return "met"
    return f"missed by {value / goal_value:.1f}×" if goal_value else "missed"


def markdown(figures, meta):
    f = figures
    rows = []
    n1 = f["node_cost_cycles"]
    rows.append(("1. Node cost, Cycles: Phong / Emission floor", fmt(n1["ratio"]) + "×",
                 "≤ 1.2×", verdict(n1["ratio"]["median"], 1.2, "max"),
                 f"{fmt(n1['phong_seconds'])} s vs {fmt(n1['floor_seconds'])} s"))
    ls = f["light_scaling_cycles"]
    lights = list(ls["ratios"])
    rows.append(("2. Lights, Cycles: N lights / 1 light",
                 ", ".join(f"{n}: {ls['ratios'][n]['median']:.2f}×" for n in lights),
                 "linear", "", "spread: " + ", ".join(
                     f"{n}: {ls['ratios'][n]['min']:.2f}–{ls['ratios'][n]['max']:.2f}"
                     for n in lights)))
    rows.append(("2. Lights, Cycles: cost of one extra light / 1-light render",
                 fmt(ls["extra_light_fraction"], 3), "< 0.10",
                 verdict(ls["extra_light_fraction"]["median"], 0.10, "max"),
                 f"from {lights[-1]} lights; shading part (time − floor) grows "
                 f"{ls['shading_time_ratio']['median']:.1f}× for {lights[-1]}× the lights"))
    le = f["light_scaling_eevee"]
    rows.append(("2. Lights, Eevee first render (compile incl.): N / 1",
                 ", ".join(f"{n}: {le['ratios'][n]['median']:.2f}×" for n in le["ratios"]),
                 "linear", "", "first render s: " + ", ".join(
                     f"{n}: {le['first_seconds'][n]['median']:.1f}" for n in le["ratios"])))
    ec = f["eevee_compile"]
    rows.append(("3. Eevee cold first render: Phong / Principled", fmt(ec["ratio"]) + "×",
                 "< 1×", verdict(ec["ratio"]["median"], 1.0, "max_strict"),
                 f"{fmt(ec['phong_first_seconds'], 1)} s vs "
                 f"{fmt(ec['principled_first_seconds'], 1)} s; compile part "
                 f"{fmt(ec['compile_ratio'])}×; engine warm-up "
                 f"{ec['cold_process_first_render_seconds']['median']:.1f} s"))
    qs = f["quality_per_second"]
    rows.append(("4. Same RMSE < 1/255: Principled time / Phong 1 spp time",
                 fmt(qs["ratio"], 1) + "×", "report", "",
                 f"Principled needs {qs['principled_spp']['median']:.0f} spp "
                 f"({fmt(qs['principled_seconds'])} s); Phong 1 spp RMSE "
                 f"{qs['phong_one_spp_rmse']['median'] * 255:.2f}/255, reaches < 1/255 at "
                 f"{qs['phong_spp_converged']['median']:.0f} spp "
                 f"(ratio then {qs['ratio_vs_phong_converged']['median']:.1f}×)"))
    sc = f["scale"]
    rows.append((f"5. {sc['phong_materials']} material, "
                 f"{meta['config']['scale_objects']} objects: Phong / Emission render",
                 fmt(sc["ratio"]) + "×", "report", "",
                 f"apply_material {fmt(sc['apply_material_seconds'], 3)} s"))
    lines = ["| figure | median (min–max) | goal | verdict | detail |",
             "|---|---|---|---|---|"]
    lines += ["| " + " | ".join(r) + " |" for r in rows]
    cfg = meta["config"]
    lines.append("")
    lines.append(f"{meta['repeats']} repeats; load average {meta['load_before']} before, "
                 f"{meta['load_after']} after; {meta['cpu_count']} CPUs; bpy {meta['bpy']}; "
                 f"run took {meta['total_seconds']:.0f} s.")
    lines.append(f"Sizes: Cycles {cfg['cycles_res']}² at {cfg['cycles_spp']} spp, "
                 f"{cfg['grid']}×{cfg['grid']} UV spheres ({cfg['segments']} segments); "
                 f"quality at {cfg['quality_res']}², reference {cfg['quality_ref_spp']} spp; "
                 f"Eevee {cfg['eevee_res']}², {cfg['eevee_samples']} samples, "
                 f"{cfg['eevee_grid']}×{cfg['eevee_grid']} spheres; scale "
                 f"{cfg['scale_objects']} objects at {cfg['scale_res']}², {cfg['scale_spp']} spp.")
    return "\n".join(lines)


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
    parser.add_argument("--md", default=None, help="Markdown file (default: next to --out)")
    parser.add_argument("--worker", help=argparse.SUPPRESS)
    parser.add_argument("--params", help=argparse.SUPPRESS)
    args = parser.parse_args(argv)
    if args.worker:
        worker_main(args.worker, json.loads(args.params))
        return 0
    cfg = dict(QUICK if args.quick else FULL)
    if args.repeats:
        cfg["repeats"] = args.repeats
    if cfg["repeats"] < 1:
        parser.error("--repeats must be at least 1")
    md_path = args.md or os.path.join(os.path.dirname(os.path.abspath(args.out)), "results.md")

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
