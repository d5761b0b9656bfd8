# SPDX-License-Identifier: GPL-3.0-or-later
"""The analysing half of the benchmarks, without ``bpy``: raw worker results -> figures.

Every figure is a ratio of two measurements taken side by side in one run, summarised over
the repeats as median, min and max (:func:`summary`).  ``table.py`` writes them as Markdown.
"""

from __future__ import annotations

import statistics

#: Goals of issue 10 (lights at scale); the seconds goals hold at 1,000 objects.
MOVE_GOAL = 3.0
SECONDS_GOAL = 2.0
SECONDS_GOAL_OBJECTS = 1000


def summary(values):
    values = [float(v) for v in values]
    return {"median": statistics.median(values), "min": min(values), "max": max(values),
            "values": values}


def ratio_summary(numerators, denominators):
    return summary([a / b for a, b in zip(numerators, denominators)])


def analyse(raw, cfg):
    """Every figure of the table from the raw results of :func:`run.collect`."""
    figures = {
        "node_cost_cycles": node_cost(raw["cycles"]["cycles_times"], cfg),
        "light_scaling_cycles": light_scaling_cycles(raw["cycles"]["cycles_times"], cfg),
        "light_scaling_eevee": light_scaling_eevee(raw["eevee_lights"], cfg),
        "eevee_compile": eevee_compile(raw["eevee_compile"]),
        "quality_per_second": quality(raw["cycles"]["quality"], cfg),
    }
    figures.update(scale(raw["cycles"]["scale"], cfg))
    figures["artist_scale"] = artist_figure(raw["artist"])
    if raw.get("demos"):
        figures["demo_eevee"] = demo_figure(raw["demos"], cfg)
    return figures


def node_cost(t, cfg):
    """1: Cycles render time, Phong with 1 light / the Emission floor."""
    return {
        "what": f"Cycles render, {cfg['grid']}x{cfg['grid']} spheres, 1 light, "
                f"{cfg['cycles_res']}x{cfg['cycles_res']}, {cfg['cycles_spp']} spp: "
                "Phong / Emission floor",
        "ratio": ratio_summary(t["phong:1"], t["emission:1"]),
        "phong_seconds": summary(t["phong:1"]), "floor_seconds": summary(t["emission:1"]),
        "goal": "<= 1.2", "goal_value": 1.2, "goal_kind": "max",
    }


def light_scaling_cycles(t, cfg):
    """2: Cycles render time with N lights / with 1 light."""
    lights = cfg["lights"]
    base = t["phong:1"]
    scaling = {str(n): ratio_summary(t[f"phong:{n}"], base) for n in lights}
    last = lights[-1]
    extra = summary([(a / b - 1) / (last - 1) if last > 1 else 0.0
                     for a, b in zip(t[f"phong:{last}"], base)])
    floor = t["emission:1"]
    # how the part of the render above the Emission floor grows with the lights
    shading = summary([(a - f) / max(b - f, 1e-3)
                       for a, b, f in zip(t[f"phong:{last}"], base, floor)])
    return {
        "what": "Cycles render time with N lights / with 1 light (same grid and size as 1)",
        "ratios": scaling,
        "seconds": {str(n): summary(t[f"phong:{n}"]) for n in lights},
        "extra_light_fraction": extra,
        "shading_growth": shading,
        "goal": "each extra light < 10% of the 1-light render", "goal_value": 0.10,
        "goal_kind": "max",
    }


def light_scaling_eevee(runs, cfg):
    """2: Eevee first render (compile included) with N lights / with 1 light."""
    lights = cfg["lights"]
    first = {n: [run[f"phong:{n}"]["first"] for run in runs] for n in lights}
    second = {n: [run[f"phong:{n}"]["second"] for run in runs] for n in lights}
    return {
        "what": "Eevee first render (material shader compile included, engine shaders already "
                "compiled by a warm-up render) with N lights / with 1 light",
        "ratios": {str(n): ratio_summary(first[n], first[lights[0]]) for n in lights},
        "first_seconds": {str(n): summary(first[n]) for n in lights},
        "second_seconds": {str(n): summary(second[n]) for n in lights},
        "goal": "linear in N", "goal_kind": "info",
    }


def eevee_compile(runs):
    """3: Eevee cold first render, Phong / Principled (*runs*: (material, worker result))."""
    ph = [run for m, run in runs if m == "phong"]
    pr = [run for m, run in runs if m == "principled"]
    ph_first = [run["phong:1"]["first"] for run in ph]
    pr_first = [run["principled:1"]["first"] for run in pr]
    ph_compile = [run["phong:1"]["first"] - run["phong:1"]["second"] for run in ph]
    pr_compile = [run["principled:1"]["first"] - run["principled:1"]["second"] for run in pr]
    cold = [run["warmup_first"] for _m, run in runs]
    return {
        "what": "Eevee first render of the material in a cold-cache process (after a warm-up "
                "render that compiles the engine's own shaders): Phong / Principled BSDF",
        "ratio": ratio_summary(ph_first, pr_first),
        "compile_difference_seconds": summary([a - b for a, b in zip(ph_compile, pr_compile)]),
        "phong_first_seconds": summary(ph_first), "principled_first_seconds": summary(pr_first),
        "phong_compile_seconds": summary(ph_compile),
        "principled_compile_seconds": summary(pr_compile),
        "cold_process_first_render_seconds": summary(cold),
        "goal": "< 1 (Phong compiles faster)", "goal_value": 1.0, "goal_kind": "max_strict",
    }


def quality(q, cfg):
    """4: time of Principled at the noise of 1/255 / time of Phong at 1 spp."""

    def conv(material, key):
        return [rep["converged"][key] for rep in q[material]["repeats"]]

    pr_sec = conv("principled", "seconds")
    ph_one = [rep["one_spp"]["seconds"] for rep in q["phong"]["repeats"]]
    return {
        "what": f"Cycles {cfg['quality_res']}x{cfg['quality_res']}: Principled BSDF at the "
                "sample count whose noise (RMSE against its own "
                f"{cfg['quality_ref_spp']}-spp render, reference noise removed) is below "
                "1/255, time / Phong at 1 spp",
        "ratio": ratio_summary(pr_sec, ph_one),
        "ratio_vs_phong_converged": ratio_summary(pr_sec, conv("phong", "seconds")),
        "principled_spp": summary(conv("principled", "spp")),
        "principled_seconds": summary(pr_sec),
        "principled_reached": all(rep["reached"] for rep in q["principled"]["repeats"]),
        "phong_spp_converged": summary(conv("phong", "spp")),
        "phong_seconds_converged": summary(conv("phong", "seconds")),
        "phong_one_spp_rmse": summary([rep["one_spp"]["rmse"] for rep in q["phong"]["repeats"]]),
        "phong_one_spp_seconds": summary(ph_one),
        "goal": "report", "goal_kind": "info",
    }


def scale(s, cfg):
    """5: first render of many objects, Phong / Emission (shared and own materials)."""
    figures = {}
    figures["scale"] = {
        "what": f"{s['objects']} linked-duplicate spheres sharing one material, 1 light, "
                f"{cfg['scale_res']}x{cfg['scale_res']}, {cfg['scale_spp']} spp, first render "
                "(scene sync included): Phong / Emission",
        "ratio": ratio_summary(s["phong_render"], s["emission_render"]),
        "apply_material_seconds": summary(s["apply_seconds"]),
        "phong_materials": s["phong_materials"],
        "phong_seconds": summary(s["phong_render"]),
        "emission_seconds": summary(s["emission_render"]),
        "goal": "report", "goal_kind": "info",
    }
    if s["distinct_phong_render"]:
        figures["scale_distinct"] = {
            "what": f"{s['objects']} spheres with their own meshes (apply_material makes "
                    f"{s['objects']} materials), first render: Phong / Emission "
                    f"({s['objects']} Emission materials)",
            "ratio": ratio_summary(s["distinct_phong_render"], s["distinct_emission_render"]),
            "apply_material_seconds": summary(s["distinct_apply_seconds"]),
            "phong_seconds": summary(s["distinct_phong_render"]),
            "emission_seconds": summary(s["distinct_emission_render"]),
            "goal": "report", "goal_kind": "info",
        }
    return figures


def artist_figure(runs):
    """6: lights at scale, from the artist workers' results (one per scene size and repeat):
    per size the Phong / Principled ratio of the median update after a light move, the
    seconds of Apply and of Relink after adding a light, and the drivers in the file."""
    med = statistics.median
    by_case = {}
    for run in runs:
        by_case.setdefault((run["objects"], run["lights"]), []).append(run)
    cases = {}
    for (objects, lights), rs in sorted(by_case.items()):
        cases[f"{objects}x{lights}"] = {
            "objects": objects, "lights": lights,
            "phong_materials": rs[0]["phong_materials"],
            "drivers": sorted({r["drivers"] for r in rs}),
            "drivers_after_add": sorted({r["drivers_after_add"] for r in rs}),
            "principled_drivers": sorted({r["principled_drivers"] for r in rs}),
            "move_ratio": ratio_summary([med(r["phong_move"]) for r in rs],
                                        [med(r["principled_move"]) for r in rs]),
            "phong_move_ms": summary([1000 * med(r["phong_move"]) for r in rs]),
            "principled_move_ms": summary([1000 * med(r["principled_move"]) for r in rs]),
            "apply_seconds": summary([r["apply_operator"] + r["apply_update"] for r in rs]),
            "add_light_seconds": summary([r["add_light_update"] for r in rs]),
            "relink_seconds": summary([r["relink_operator"] + r["relink_update"] for r in rs]),
        }
    per_lights = {}
    for case in cases.values():
        per_lights.setdefault(case["lights"], set()).update(case["drivers"])
    return {
        "what": "Lights at scale (issue 10): N cubes with their own meshes and Principled "
                "materials, K lights (point, sun, spot, point, ...); in one process the "
                "Principled scene, then the same scene after Apply Phong Material",
        "cases": cases,
        "drivers_by_lights": {str(k): sorted(v) for k, v in sorted(per_lights.items())},
        "drivers_independent_of_objects": all(len(v) == 1 for v in per_lights.values()),
        "goal": f"move update <= {MOVE_GOAL}x Principled; Relink after adding a light and "
                f"Apply < {SECONDS_GOAL} s at {SECONDS_GOAL_OBJECTS} objects",
        "goal_value": MOVE_GOAL, "goal_kind": "max",
    }


def demo_figure(runs, cfg):
    """7: Eevee first render of each demo scene (cold-cache process, after a warm-up render)
    as built (materials that differ only in values share a layout), and the ratio to the
    same scene with one layout per material."""
    per_scene = {}
    for name in cfg["demo_scenes"]:
        shared = [run[f"{name}:shared"]["first"] for run in runs]
        distinct = [run[f"{name}:distinct"]["first"] for run in runs]
        per_scene[name] = {"shared_first_seconds": summary(shared),
                           "distinct_first_seconds": summary(distinct),
                           "materials": runs[0][f"{name}:distinct"]["materials"],
                           "ratio": ratio_summary(shared, distinct)}
    total_shared = [sum(run[f"{n}:shared"]["first"] for n in cfg["demo_scenes"]) for run in runs]
    total_distinct = [sum(run[f"{n}:distinct"]["first"] for n in cfg["demo_scenes"])
                      for run in runs]
    return {
        "what": "Eevee first render (compile included) of every demo scene as built, / the "
                "same scene with one node layout per material",
        "scenes": per_scene,
        "total_shared_seconds": summary(total_shared),
        "total_distinct_seconds": summary(total_distinct),
        "ratio": ratio_summary(total_shared, total_distinct),
        "goal": "< 1 (shared layouts compile less)", "goal_value": 1.0,
        "goal_kind": "max_strict",
    }
