# SPDX-License-Identifier: GPL-3.0-or-later
"""Issue 43 item 8: the speed of Phong shadows, Principled against Phong with every light
casting shadows on both sides, in one run.

    .venv/bin/python -m phong_nodes.benchmarks.shadow_speed [--objects 1000] [--res 128]
        [--repeats 2] [--renders 1] [--rounds 2] [--out benchmarks/shadow_speed_results.json]
    .venv/bin/python -m phong_nodes.benchmarks.shadow_speed --table \
        benchmarks/shadow_speed_results.json

The scene is figure 6's artist scene (``measure.artist_scene``: cubes with their own mesh and
Principled material, lights cycling point, sun, spot, point) with ``measure.SHADOWS_ENV`` set:
every light casts shadows and the cubes stand on a floor with its own material, seen from
above by ``eevee_materials``' orthographic camera at ``--res``².  Figures, each case
(``principled``, ``phong``: after Apply Phong Material) built and rendered in a process of its
own after one untimed render, the order of the cases alternating from repeat to repeat:

* **Cycles F12** (CPU, no denoising, no adaptive sampling) at 4 lights / 16 samples and 16
  lights / 64 samples (the goals: 1.6× and 2×), and 16 lights / 16 samples (the figure of
  the issue before shadows); per render also the seconds until Cycles starts its first
  sample (``sync_s``: Blender's render depsgraph, Cycles' sync of the scene, its shader
  compile, kernels, BVH, lights) and from there to the end (``samples_s``), from the
  ``render_stats`` messages;
* **Eevee F12** (1 sample) at 4 and 16 lights (goal 2×; on 5.3 the light loop);
* **drag**: ``light_loop.drag`` (``light_move --files``) at 16 lights, same scene (goal 1.3×).

Writes one JSON (every time, the load averages) and prints the table of ``table``.
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

CASES = ("principled", "phong")
#: (engine, lights, samples) of each F12 figure, and its goal (None: reported only).
FIGURES = (("cycles", 4, 16, 1.6), ("cycles", 16, 64, 2.0), ("cycles", 16, 16, None),
           ("eevee", 4, 1, 2.0), ("eevee", 16, 1, 2.0))
DRAG_GOAL = 1.3


def worker(engine, case, objects, n_lights, samples, res, renders, variant="") -> dict:
    """One process, one case: the scene built, rendered once untimed, then *renders* timed
    renders; *variant*: ablations of the Phong materials while looking for the constant
    (``noemission``: Cycles' emission sampling off; ``noeevee``: the EEVEE Material Outputs
    removed; ``ungrouped``: the lights group's nested groups replaced by their nodes;
    ``noblinn``: ``_without_blinn``; ``persistent``: Cycles' Persistent Data on;
    ``castoff``: the lights' Cast Shadow off; ``extratrees``: 1,000 unused materials more
    in the file (Eevee: each material's shader walks the file's node trees, see
    benchmarks/README.md); ``move``: the first light
    moved before each timed render; ``shared``:
    every object given the first object's material; ``chain<K>``: every material replaced by
    ``_chain_materials``' K math nodes and a Raycast node per light, Phong-free; ``blend``:
    the lights group's light groups written as before 5.3 (no Switch on the Blinn); joined by
    "+")."""
    os.environ["PHONG_BENCH_SHADOWS"] = "1"
    from .eevee_materials import _camera  # noqa: PLC0415
    from .measure import (apply_phong, artist_scene, render, set_cycles,  # noqa: PLC0415
                          set_eevee, worker_setup)

    bpy = worker_setup()
    scene, meshes, _lights = artist_scene(case, objects, n_lights)
    bpy.context.window.scene = scene
    _camera(bpy, scene, objects)
    scene.render.resolution_x = scene.render.resolution_y = res
    if engine == "cycles":
        set_cycles(scene, samples)
    else:
        set_eevee(scene, samples)
    if case == "phong":
        apply_phong(bpy, scene, meshes)
    materials = {slot.material for obj in meshes for slot in obj.material_slots}
    for part in filter(None, variant.split("+")):
        if part == "noemission":
            for material in materials:
                material.cycles.emission_sampling = "NONE"
        elif part == "noeevee":
            for material in materials:
                tree = material.node_tree
                for node in [n for n in tree.nodes if n.bl_idname == "ShaderNodeOutputMaterial"
                             and n.target == "EEVEE"]:
                    tree.nodes.remove(node)
        elif part == "ungrouped":  # the lights group's nested groups replaced by their nodes
            from .eevee_materials import ungroup_all  # noqa: PLC0415

            tree = meshes[0].material_slots[0].material.node_tree
            ungroup_all(tree.nodes["phong_lights"].node_tree)
        elif part == "noblinn":  # every material's Blinn is 0: the Blinn branch unlinked
            for group in _light_groups(meshes):
                _without_blinn(group)
        elif part == "persistent":  # Render > Performance > Persistent Data (the user's)
            scene.render.use_persistent_data = True
        elif part == "castoff":  # the lights' Cast Shadow off (Principled's too: not the goal)
            for light in _lights:
                light.data.use_shadow = False
        elif part == "move":  # each timed render after a move of the first light
            pass
        elif part == "extratrees":  # 1,000 more node trees in the file (unused materials)
            for index in range(1000):
                bpy.data.materials.new(f"Extra {index:04d}").use_fake_user = True
        elif part == "blend":  # the light groups as releases before 5.3 write them
            from phong_nodes.addon import loader  # noqa: PLC0415
            from phong_nodes.node_groups import library  # noqa: PLC0415

            for group in _light_groups(meshes):
                loader._write(group, library.RIG_GROUPS[group.name])
        elif part == "nosources":  # the kept source materials removed (one tree a material)
            for material in [m for m in bpy.data.materials if m.use_fake_user
                             and m not in materials]:
                bpy.data.materials.remove(material)
        elif part == "nocontrols":  # each material's controls folded into its group node
            _fold_controls(materials)
        elif part == "extranodes":  # 8 more nodes in each material, linked to nothing
            for material in materials:
                for _ in range(8):
                    material.node_tree.nodes.new("ShaderNodeValue")
        elif part.startswith("chain"):  # chain<K>: a Cycles node budget (no Phong nodes)
            _chain_materials(bpy, materials, int(part[5:]), len(_lights))
        elif part == "shared":
            for obj in meshes:
                obj.material_slots[0].material = meshes[0].material_slots[0].material
        else:
            raise ValueError(f"unknown variant {part}")
    scene.view_layers[0].update()
    stamps = []

    def stats(text):
        stamps.append((time.perf_counter(), text))

    bpy.app.handlers.render_stats.append(stats)
    render(scene)
    out = {"render_s": [], "sync_s": [], "samples_s": [], "cpu_s": []}
    for index in range(renders):
        if "move" in variant.split("+"):
            _lights[0].location.x += 0.5 if index % 2 == 0 else -0.5
            scene.view_layers[0].update()
        stamps.clear()
        start, cpu = time.perf_counter(), time.process_time()
        out["render_s"].append(render(scene))
        out["cpu_s"].append(time.process_time() - cpu)
        first = next((t for t, text in stamps if "Sample 0/" in text), None)
        if first is not None:
            out["sync_s"].append(first - start)
            out["samples_s"].append(out["render_s"][-1] - (first - start))
    out["bpy"] = bpy.app.version_string
    return out


def _chain_materials(bpy, materials, k, rays) -> None:
    """Ablation: each of *materials* made Emission ← one shared node group of *k* Math nodes
    (a chain of multiply-adds of the shaded point's X, distinct constants: neither Blender's
    inliner nor Cycles folds or merges them) times *rays* Raycast nodes' Is Hit (5.1+), with
    the material's own colour as the group's input.  What Cycles pays per material and per
    node, free of Phong's design: the node budget of a goal (benchmarks/README.md)."""
    group = bpy.data.node_groups.new(f"Budget chain {k}", "ShaderNodeTree")
    group.interface.new_socket("Color", in_out="INPUT", socket_type="NodeSocketColor")
    group.interface.new_socket("Color", in_out="OUTPUT", socket_type="NodeSocketColor")
    nodes, links = group.nodes, group.links
    group_in, group_out = nodes.new("NodeGroupInput"), nodes.new("NodeGroupOutput")
    separate = nodes.new("ShaderNodeSeparateXYZ")
    geometry = nodes.new("ShaderNodeNewGeometry")
    links.new(geometry.outputs["Position"], separate.inputs[0])
    value = separate.outputs["X"]
    for index in range(k):
        node = nodes.new("ShaderNodeMath")
        node.operation = "MULTIPLY_ADD"
        links.new(value, node.inputs[0])
        node.inputs[1].default_value = 0.999 - 1e-4 * index
        node.inputs[2].default_value = 1e-3 * (index + 1)
        value = node.outputs[0]
    for index in range(rays if hasattr(bpy.types, "ShaderNodeRaycast") else 0):
        ray = nodes.new("ShaderNodeRaycast")
        ray.inputs["Length"].default_value = 1.0 + index
        hit = nodes.new("ShaderNodeMath")
        hit.operation = "MULTIPLY"
        links.new(value, hit.inputs[0])
        links.new(ray.outputs["Is Hit"], hit.inputs[1])
        value = hit.outputs[0]
    scale = nodes.new("ShaderNodeVectorMath")
    scale.operation = "SCALE"
    links.new(group_in.outputs[0], scale.inputs[0])
    links.new(value, scale.inputs["Scale"])
    links.new(scale.outputs[0], group_out.inputs[0])
    for material in materials:
        tree = material.node_tree
        color = next((n.inputs["Object Color"].default_value[:] for n in tree.nodes
                      if n.bl_idname == "ShaderNodeGroup" and "Object Color" in n.inputs),
                     (0.8, 0.8, 0.8, 1.0))
        tree.nodes.clear()
        node = tree.nodes.new("ShaderNodeGroup")
        node.node_tree = group
        node.inputs[0].default_value = color
        emission = tree.nodes.new("ShaderNodeEmission")
        output = tree.nodes.new("ShaderNodeOutputMaterial")
        tree.links.new(node.outputs[0], emission.inputs["Color"])
        tree.links.new(emission.outputs[0], output.inputs["Surface"])


def _fold_controls(materials) -> None:
    """Each material's control nodes (Value, RGB) removed, the lights group node's inputs
    they fed set to their values, the frame removed: the same picture, 8 nodes fewer a
    material."""
    for material in materials:
        tree = material.node_tree
        for node in [n for n in tree.nodes if n.bl_idname in ("ShaderNodeValue", "ShaderNodeRGB")]:
            value = node.outputs[0].default_value
            for link in list(node.outputs[0].links):
                target = link.to_socket
                tree.links.remove(link)
                target.default_value = value if node.bl_idname == "ShaderNodeValue" \
                    else tuple(value)[:len(target.default_value)]
            tree.nodes.remove(node)
        for node in [n for n in tree.nodes if n.bl_idname == "NodeFrame"]:
            tree.nodes.remove(node)


def _light_groups(meshes) -> list:
    """The light groups (one a light: ``library.rig_light_group``) of the lights group of
    the first of *meshes*' material."""
    tree = meshes[0].material_slots[0].material.node_tree.nodes["phong_lights"].node_tree
    return list({n.node_tree for n in tree.nodes if n.name.startswith("light:")})


def _without_blinn(tree) -> None:
    """Ablation (same picture where Blinn is 0): in a light group, the highlight blend
    (1 - Blinn)·Phong + Blinn·Blinn-Phong replaced by its first product, so that Blender's
    inliner never reaches the Blinn-Phong branch (what a Switch on a constant Blinn gives)."""
    group_in = next(n for n in tree.nodes if n.bl_idname == "NodeGroupInput")
    blinn = group_in.outputs["Blinn"]
    for link in list(blinn.links):
        product = link.to_node
        if product.bl_idname != "ShaderNodeMath" or product.operation != "MULTIPLY":
            continue
        for out_link in list(product.outputs[0].links):
            add = out_link.to_node
            if add.bl_idname != "ShaderNodeMath" or add.operation != "ADD":
                continue
            other = next(s for s in add.inputs[:2] if s.is_linked
                         and s.links[0].from_node != product).links[0].from_socket
            for target in [l.to_socket for l in add.outputs[0].links]:
                tree.links.new(other, target)
            return
    raise RuntimeError("no Blinn blend found")


def f12(engine, objects, n_lights, samples, res, repeats, renders, cases=CASES,
        variant="") -> dict:
    out = {"engine": engine, "lights": n_lights, "samples": samples, "render_s": {},
           "sync_s": {}, "samples_s": {}, "load_average": [os.getloadavg()]}
    for repeat in range(repeats):
        for case in cases if repeat % 2 == 0 else cases[::-1]:
            args = [sys.executable, "-m", "phong_nodes.benchmarks.shadow_speed", "--worker",
                    engine, case, str(objects), str(n_lights), str(samples), str(res),
                    str(renders)]
            if variant and case != "principled":
                args.append(variant)
            proc = subprocess.run(args, capture_output=True, text=True)
            line = [x for x in proc.stdout.splitlines() if x.startswith("RESULT ")]
            if proc.returncode != 0 or not line:
                raise RuntimeError(proc.stdout[-2000:] + proc.stderr[-2000:])
            result = json.loads(line[-1][7:])
            out["bpy"] = result["bpy"]
            for key in ("render_s", "sync_s", "samples_s"):
                out[key].setdefault(case, []).extend(result[key])
            out["load_average"].append(os.getloadavg())
    out["median_s"] = {c: statistics.median(t) for c, t in out["render_s"].items()}
    out["median_sync_s"] = {c: statistics.median(t) for c, t in out["sync_s"].items() if t}
    if "principled" in out["median_s"]:
        base = out["median_s"]["principled"]
        out["ratio_to_principled"] = {c: t / base for c, t in out["median_s"].items()}
    return out


def run(objects, res, repeats, renders, rounds, moves, figures=FIGURES, drag=True) -> dict:
    started = time.perf_counter()
    os.environ["PHONG_BENCH_SHADOWS"] = "1"  # the drag's children build the same scene
    out = {"objects": objects, "res": res, "repeats": repeats, "renders": renders,
           "load_average": {"start": os.getloadavg()}, "f12": []}
    for engine, n_lights, samples, goal in figures:
        figure = f12(engine, objects, n_lights, samples, res, repeats, renders)
        figure["goal"] = goal
        out["f12"].append(figure)
        out["bpy"] = figure["bpy"]
    out["load_average"]["after_f12"] = os.getloadavg()
    if drag:
        from .light_loop import drag as light_drag  # noqa: PLC0415

        out["drag"] = light_drag(objects, 16, moves, rounds)
        out["drag"]["goal"] = DRAG_GOAL
    out["load_average"]["end"] = os.getloadavg()
    out["seconds"] = time.perf_counter() - started
    return out


def _cell(times) -> str:
    return f"{statistics.median(times):.2f} s ({min(times):.2f}–{max(times):.2f})"


def table(result) -> str:
    """The Markdown table of a run (``run``'s JSON)."""
    lines = ["| F12 | Principled | Phong | Phong / Principled | goal | Phong until the first "
             "sample (Principled) |", "|---|---|---|---|---|---|"]
    for figure in result["f12"]:
        times = figure["render_s"]
        what = (f"Cycles, {figure['lights']} lights, {figure['samples']} samples"
                if figure["engine"] == "cycles" else f"Eevee, {figure['lights']} lights")
        ratio = figure["ratio_to_principled"]["phong"]
        goal = figure.get("goal")
        verdict = "–" if goal is None else f"{goal}×: {'met' if ratio <= goal else 'missed'}"
        sync = figure.get("median_sync_s", {})
        sync_cell = (f"{sync['phong']:.2f} s ({sync['principled']:.2f} s)"
                     if "phong" in sync and "principled" in sync else "–")
        lines.append(f"| {what} | {_cell(times['principled'])} | {_cell(times['phong'])} | "
                     f"**{ratio:.2f}×** | {verdict} | {sync_cell} |")
    moves = result.get("drag")
    if moves:
        lines += ["", f"| a drag of each of {moves['lights']} lights | median per light "
                  "| / Principled: median | worst light |", "|---|---|---|---|"]
        lines.append(f"| Principled | {1000 * moves['median_s']['principled']:.2f} ms | 1 | |")
        for design, label in (("phong", "Phong (light loop)"),
                              ("phong_live", "Phong, the World's copies live"),
                              ("lights_group", "lights groups of 5.2")):
            if design in moves["median_s"]:
                lines.append(f"| {label} | {1000 * moves['median_s'][design]:.2f} ms | "
                             f"{moves['median_ratio'][design]:.2f}× | "
                             f"{moves['worst_ratio'][design]:.2f}× |")
    return "\n".join(lines)


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--objects", type=int, default=1000)
    parser.add_argument("--res", type=int, default=128)
    parser.add_argument("--repeats", type=int, default=2)
    parser.add_argument("--renders", type=int, default=1, help="timed renders per process")
    parser.add_argument("--rounds", type=int, default=2, help="drag: processes per case")
    parser.add_argument("--moves", type=int, default=10)
    parser.add_argument("--only", help="engine,lights,samples of one F12 figure (no drag)")
    parser.add_argument("--variant", default="", help="ablation of the Phong case (worker)")
    parser.add_argument("--out", help="write the JSON here")
    parser.add_argument("--table", metavar="JSON", help="only print the table of a run")
    parser.add_argument("--worker", nargs="+", help=argparse.SUPPRESS)
    args = parser.parse_args(argv)
    if args.worker:
        engine, case, objects, n_lights, samples, res, renders, *variant = args.worker
        result = worker(engine, case, int(objects), int(n_lights), int(samples), int(res),
                        int(renders), variant[0] if variant else "")
        print("RESULT " + json.dumps(result), flush=True)
        os._exit(0)  # skip bpy's clean-up at exit (slow, and it can crash after Eevee)
    if args.table:
        with open(args.table, encoding="utf-8") as handle:
            print(table(json.load(handle)))
        return 0
    if args.only:
        engine, n_lights, samples = args.only.split(",")
        figure = f12(engine, args.objects, int(n_lights), int(samples), args.res,
                     args.repeats, args.renders, variant=args.variant)
        figure["variant"] = args.variant
        publish(figure, args.out, json.dumps(figure, indent=1))
        return 0
    result = run(args.objects, args.res, args.repeats, args.renders, args.rounds, args.moves)
    publish(result, args.out, table(result))
    return 0


if __name__ == "__main__":
    sys.exit(main())
