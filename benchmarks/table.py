# SPDX-License-Identifier: GPL-3.0-or-later
"""The table of the benchmarks, without ``bpy``: figures (``analyse.py``) -> Markdown."""

from __future__ import annotations

import json
import os
import statistics

from .analyse import MOVE_GOAL, SECONDS_GOAL, SECONDS_GOAL_OBJECTS


def merge_figure(path, name, figure) -> None:
    """Put *figure* into the results file *path* (results.json) under *name* and write the
    table beside it (results.md), as run.py does: what ``--merge`` of a benchmark that run.py
    does not run writes."""
    with open(path, encoding="utf-8") as handle:
        data = json.load(handle)
    data["figures"][name] = figure
    with open(path, "w", encoding="utf-8") as handle:
        json.dump(data, handle, indent=1)
        handle.write("\n")
    with open(os.path.splitext(path)[0] + ".md", "w", encoding="utf-8") as handle:
        handle.write(markdown(data["figures"], data["meta"]) + "\n")


def publish(result, out, text) -> None:
    """What a benchmark's command line ends with: *result* written as JSON to *out* (a path,
    or None: not written), then *text* (its table, or the JSON itself) printed."""
    if out:
        with open(out, "w", encoding="utf-8") as handle:
            json.dump(result, handle, indent=1)
            handle.write("\n")
    print(text, flush=True)


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


def rows(figures, meta):
    """One row per figure and case: (figure, median (min–max), goal, verdict, detail)."""
    return [*cycles_rows(figures), *eevee_rows(figures), *quality_rows(figures),
            *scale_rows(figures, meta["config"]["scale_objects"]),
            *artist_rows(figures["artist_scale"]), *demo_rows(figures.get("demo_eevee")),
            *shading_rows(figures.get("shading_modes")), *import_rows(figures.get("import_speed")),
            *loop_rows(figures.get("light_loop"))]


def markdown(figures, meta):
    """The table (one row per figure and case) and two lines on the run and its sizes."""
    lines = ["| figure | median (min–max) | goal | verdict | detail |",
             "|---|---|---|---|---|"]
    lines += ["| " + " | ".join(r) + " |" for r in rows(figures, meta)]
    return "\n".join(lines + [""] + footer(meta))


def side_by_side(runs):
    """Two or more runs ({label: (figures, meta)}) in one table: each figure's median (min–max)
    and verdict per run, in the order of the first run's rows."""
    tables = {label: {r[0]: r for r in rows(figures, meta)} for label, (figures, meta) in runs.items()}
    labels = list(tables)
    lines = ["| figure | " + " | ".join(labels) + " |", "|---" * (len(labels) + 1) + "|"]
    for name in tables[labels[0]]:
        cells = []
        for label in labels:
            row = tables[label].get(name)
            cells.append("–" if row is None else row[1] + (f" ({row[3]})" if row[3] else ""))
        lines.append(f"| {name} | " + " | ".join(cells) + " |")
    lines.append("")
    for label, (_figures, meta) in runs.items():
        lines.append(f"{label}: " + " ".join(footer(meta)[:1]))
    return "\n".join(lines)


def cycles_rows(f):
    """Figures 1 and 2 (Cycles)."""
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
                 f"{ls['shading_growth']['median']:.1f}× for {lights[-1]}× the lights"))
    return rows


def eevee_rows(f):
    """Figures 2 (Eevee) and 3."""
    rows = []
    le = f["light_scaling_eevee"]
    rows.append(("2. Lights, Eevee first render (compile incl.): N / 1",
                 ", ".join(f"{n}: {le['ratios'][n]['median']:.2f}×" for n in le["ratios"]),
                 "linear", "", "first render s: " + ", ".join(
                     f"{n}: {le['first_seconds'][n]['median']:.1f}" for n in le["ratios"])))
    ec = f["eevee_compile"]
    rows.append(("3. Eevee cold first render: Phong / Principled", fmt(ec["ratio"]) + "×",
                 "< 1×", verdict(ec["ratio"]["median"], 1.0, "max_strict"),
                 f"{fmt(ec['phong_first_seconds'], 1)} s vs "
                 f"{fmt(ec['principled_first_seconds'], 1)} s; first − second render "
                 f"(compile): {fmt(ec['phong_compile_seconds'], 1)} s vs "
                 f"{fmt(ec['principled_compile_seconds'], 1)} s; engine warm-up "
                 f"{ec['cold_process_first_render_seconds']['median']:.1f} s"))
    return rows


def quality_rows(f):
    """Figure 4."""
    qs = f["quality_per_second"]
    return [("4. Same RMSE < 1/255: Principled time / Phong 1 spp time",
             fmt(qs["ratio"], 1) + "×", "report", "",
             f"Principled needs {qs['principled_spp']['median']:.0f} spp "
             f"({fmt(qs['principled_seconds'])} s); Phong 1 spp RMSE "
             f"{qs['phong_one_spp_rmse']['median'] * 255:.2f}/255, reaches < 1/255 at "
             f"{qs['phong_spp_converged']['median']:.0f} spp "
             f"(ratio then {qs['ratio_vs_phong_converged']['median']:.1f}×)")]


def scale_rows(f, n_obj):
    """Figure 5."""
    rows = []
    sc = f["scale"]
    rows.append((f"5. {n_obj} linked duplicates, 1 shared material: Phong / Emission render",
                 fmt(sc["ratio"]) + "×", "report", "",
                 f"{fmt(sc['phong_seconds'])} s vs {fmt(sc['emission_seconds'])} s"))
    if "scale_distinct" in f:
        sd = f["scale_distinct"]
        rows.append((f"5. {n_obj} objects, {n_obj} materials: Phong / Emission render",
                     fmt(sd["ratio"]) + "×", "report", "",
                     f"{fmt(sd['phong_seconds'])} s vs {fmt(sd['emission_seconds'])} s; "
                     f"apply_material {fmt(sd['apply_material_seconds'])} s"))
    return rows


def footer(meta):
    """The run (repeats, load, machine, duration) and its sizes."""
    cfg = meta["config"]
    lines = []
    lines.append(f"{meta['repeats']} repeats; load average {meta['load_before']} before, "
                 f"{meta['load_after']} after; {meta['cpu_count']} CPUs; bpy {meta['bpy']}; "
                 f"run took {meta['total_seconds']:.0f} s.")
    lines.append(f"Sizes: Cycles {cfg['cycles_res']}² at {cfg['cycles_spp']} spp, "
                 f"{cfg['grid']}×{cfg['grid']} UV spheres ({cfg['segments']} segments); "
                 f"quality at {cfg['quality_res']}², reference {cfg['quality_ref_spp']} spp; "
                 f"Eevee {cfg['eevee_res']}², {cfg['eevee_samples']} samples, "
                 f"{cfg['eevee_grid']}×{cfg['eevee_grid']} spheres; scale "
                 f"{cfg['scale_objects']} objects at {cfg['scale_res']}², {cfg['scale_spp']} spp; "
                 f"lights at scale: {', '.join(f'{n:,}' for n in cfg['artist_objects'])} cubes "
                 f"(own mesh and Principled material each), "
                 f"{' and '.join(str(k) for k in cfg['artist_lights'])} lights, "
                 f"median of {cfg['scale_moves']} light moves.")
    return lines


def artist_rows(figure):
    """Table rows of figure 6."""
    rows = []
    for case in figure["cases"].values():
        n, k = case["objects"], case["lights"]
        where = f"6. {n:,} objects, {k} lights"
        timed_goal = n <= SECONDS_GOAL_OBJECTS
        goal = f"< {SECONDS_GOAL:.0f} s" if timed_goal else "report"
        rows.append((f"{where}: one update after moving a light, Phong / Principled",
                     fmt(case["move_ratio"], 1) + "×", f"≤ {MOVE_GOAL:.0f}×",
                     verdict(case["move_ratio"]["median"], MOVE_GOAL, "max"),
                     f"{fmt(case['phong_move_ms'], 1)} ms vs "
                     f"{fmt(case['principled_move_ms'], 1)} ms"))
        rows.append((f"{where}: Relink Phong Lights after adding a light",
                     fmt(case["relink_seconds"]) + " s", goal,
                     verdict(case["relink_seconds"]["median"], SECONDS_GOAL, "max_strict")
                     if timed_goal else "",
                     f"without a click (depsgraph handler, next update): "
                     f"{fmt(case['add_light_seconds'])} s"))
        rows.append((f"{where}: Apply Phong Material",
                     fmt(case["apply_seconds"]) + " s", goal,
                     verdict(case["apply_seconds"]["median"], SECONDS_GOAL, "max_strict")
                     if timed_goal else "",
                     f"{case['phong_materials']:,} Phong materials"))
    drivers = figure["drivers_by_lights"]
    rows.append(("6. Drivers in the file after Apply (Principled scene: 0)",
                 "; ".join(f"{k} lights: {', '.join(str(d) for d in v)}"
                           for k, v in drivers.items()),
                 "independent of the objects",
                 "met" if figure["drivers_independent_of_objects"] else "missed",
                 "the same count at every object count; one light more adds "
                 + ", ".join(sorted({str(c["drivers_after_add"][0] - c["drivers"][0])
                                     for c in figure["cases"].values()}))))
    return rows


def demo_rows(figure):
    """Table rows of figure 7 (absent in results of older runs)."""
    if figure is None:
        return []
    detail = "; ".join(f"{name} {fmt(c['shared_first_seconds'])} s vs "
                       f"{fmt(c['distinct_first_seconds'])} s ({c['materials']} materials)"
                       for name, c in figure["scenes"].items())
    return [("7. Demo scenes, Eevee first render: as built / one layout per material",
             fmt(figure["ratio"]) + "×", "< 1×",
             verdict(figure["ratio"]["median"], figure["goal_value"], figure["goal_kind"]),
             f"all scenes {fmt(figure['total_shared_seconds'])} s vs "
             f"{fmt(figure['total_distinct_seconds'])} s; {detail}")]


def shading_rows(figure):
    """Table rows of figure 8 (issue 28; ``shading_modes.py --merge``)."""
    if figure is None:
        return []
    ms = {case: {k: stats[k] * 1000.0 for k in ("median", "min", "max")}
          for case, stats in figure["update_s"].items()}
    where = (f"8. {figure['objects']:,} objects of {figure['vertices_per_object']} vertices, "
             f"1 light: one update after moving it")
    rows = []
    for case, label in (("vertex", "Per Vertex"), ("face", "Per Face")):
        ratio = figure["ratio_to_pixel"][case]
        rows.append((f"{where}, {label} / Per Pixel", fmt(ratio, 2) + "×",
                     f"≤ {figure['goal_value']:.0f}×",
                     verdict(ratio["median"], figure["goal_value"], "max"),
                     f"{fmt(ms[case], 2)} ms vs Per Pixel {fmt(ms['pixel'], 2)} ms, Principled "
                     f"{fmt(ms['principled'], 2)} ms; {figure['repeats']} runs of "
                     f"{figure['moves']} moves, bpy {figure['bpy']}"))
    return rows


def import_rows(figure):
    """Table rows of figure 9 (issue 35; ``import_speed.py --merge``)."""
    if figure is None:
        return []
    rows = []
    theirs = {"obj": f"Blender {figure['bpy']}'s OBJ importer",
              "fbx": f"Blender {figure['bpy']}'s FBX importer",
              "collada": f"Blender {figure['blender_collada']}'s COLLADA importer (own process)"}
    load = figure["load_average"]
    for kind, ratio in figure["ratio"].items():
        goal = figure["goal_value"][kind]
        rows.append((f"9. Import of {figure['triangles']:,} triangles in {figure['objects']} "
                     f"objects, {kind.upper() if kind != 'collada' else 'COLLADA'}: "
                     "Phong / Blender's", f"{ratio:.2f}×", f"≤ {goal:g}×",
                     verdict(ratio, goal, "max"),
                     f"{fmt(figure['ours_s'][kind])} s vs {fmt(figure['blender_s'][kind])} s "
                     f"({theirs[kind]}); median of {figure['repeats']}, bpy {figure['bpy']}, "
                     f"load {load[0][0]:.2f} before, {load[1][0]:.2f} after"))
    return rows


def loop_rows(figure):
    """Table rows of figure 10 (issue 38; ``light_loop.py --merge``): an Eevee F12 of 1,000
    own-material cubes per number of lights, and a drag of each light, on Blender 5.3's light
    loop."""
    if figure is None:
        return []
    rows = []
    goal_f12, goal_drag = figure["goals"]["f12"], figure["goals"]["drag"]
    for n, f12 in figure["f12"].items():
        median, times = f12["median_s"], f12["render_s"]
        ratio = f12["ratio_to_principled"]["phong"]
        goal = f"≤ {goal_f12:g}×" if int(n) > 1 else "–"
        rows.append((
            f"10. Eevee F12 of {figure['objects']:,} own-material cubes, {n} light"
            f"{'s' if int(n) > 1 else ''}: Phong (light loop) / Principled", f"{ratio:.2f}×",
            goal, verdict(ratio, goal_f12, "max") if int(n) > 1 else "",
            f"{median['phong']:.2f} s ({min(times['phong']):.2f}–{max(times['phong']):.2f}) vs "
            f"{median['principled']:.2f} s ({min(times['principled']):.2f}–"
            f"{max(times['principled']):.2f}); the lights group of 5.2 "
            f"{f12['ratio_to_principled']['phong_lights_group']:.2f}×; "
            f"{len(times['phong'])} renders, bpy {f12['bpy']}"))
    drag = figure.get("drag")
    if drag:
        worst = drag["worst_ratio"]
        ratios = drag["ratio_to_principled"]["phong"]
        method = (f"each file in its own process, {drag['rounds']} rounds of {drag['passes']}"
                  f" x {drag['moves']} moves per light"
                  if drag.get("method") == "files" else f"median of {drag['moves']} moves each")
        others = "; ".join(f"{label}: worst {worst[key]:.2f}×"
                           for key, label in (("phong_live", "the World's copies live"),
                                              ("lights_group", "the lights groups of 5.2"),
                                              ("phong_again", "again (drift)"))
                           if key in worst)
        of_medians = (statistics.median(drag["update_s"]["phong"])
                      / statistics.median(drag["update_s"]["principled"]))
        rows.append((
            f"10. Drag of each of {drag['lights']} lights, {drag['objects']:,} objects: Phong "
            "(light loop) / Principled, worst light", f"{worst['phong']:.2f}×",
            f"≤ {goal_drag:g}×", verdict(worst["phong"], goal_drag, "max"),
            f"median of the lights {statistics.median(ratios):.2f}×, ratio of their medians "
            f"{of_medians:.2f}×; {others}; {method}, bpy {drag['bpy']}"))
    return rows
