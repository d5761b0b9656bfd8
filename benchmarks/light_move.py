# SPDX-License-Identifier: GPL-3.0-or-later
"""Issue 30: one depsgraph update after moving (and turning) a light, Principled against Phong
with the lights' transforms as World properties read by View Layer attributes (this version)
and against the design before it (drivers on the lights group's sockets, ``phong_source`` an
ID pointer), side by side in one process.

    .venv/bin/python -m phong_nodes.benchmarks.light_move [--objects 1000] [--lights 4] [--moves 21]
    .venv/bin/python -m phong_nodes.benchmarks.light_move --eevee 4 8 16 [--repeats 1]

The scene is figure 6's artist scene (``measure.artist_scene``: cubes with their own mesh and
Principled material, lights cycling point, sun, spot, point).  In one process: the Principled
scene; then Apply Phong Material (this version); then the same file turned into the previous
design (every group rebuilt with no View Layer lookup, ``compat.VIEW_LAYER_LOOKUPS = 0``,
which is the previous rig exactly, and each Phong material given back its ``phong_source`` ID
pointer); then this version again (Relink), to see the drift of the machine.  Each figure is
the median of *moves* updates after two untimed ones; "move" moves the first light (a point
light), "turn" rotates the third (a spot).  Prints one JSON object (seconds, ratios to
Principled, relink seconds, load average).

``--each``: the update after moving each light in turn (a point or spot moved, a sun turned),
Principled, this version and, on Blender 5.3+, the lights groups of 5.2 (no light loop, so
at most ``compat.VIEW_LAYER_LOOKUPS`` transforms from the World: the lights beyond are
driven in the group) side by side in one process (``run_each``; issue 38).

``--parts PASSES``: what a drag costs beyond Principled, part by part, in one process after
Apply (``run_parts``): Principled, Phong, Phong without the World's update, without the
extension's handlers and without both, the cases alternating per block of *moves* updates
of one light.

``--files ROUNDS``: the drag as a user meets it (issue 38): the artist scene saved as a
Principled file and, after Apply, as a Phong file; each round loads each file in a process
of its own (the extension registered in both, the order alternating) and times *moves*
updates of each light in turn, every light *passes* times (``--passes``); per light, the
median of all its updates over the rounds.  Also "phong_live": the Phong file with the
World's copies of the lights' transforms kept live (``world_copies``: what a drag cost
before they were parked), and on 5.3+ "lights_group": the Phong file relinked without the
light loop (the lights groups of 5.2, at most ``compat.VIEW_LAYER_LOOKUPS`` transforms from
the World).  A process's own speed varies by up to 2.7x from one process to the next on
this machine (the same file, medians of 2.1 to 5.5 ms), hence the rounds.

``--power``: the update after a drag step of each light's Power slider (up or down a tenth),
Principled, then Phong with every light's i0 following its Power, then Principled again, in
one process (``run_power``); ratios to the lower Principled median per light.

``--eevee``: Eevee's first render (shader compile included, after the engine's warm-up) of
3x3 spheres with 4, 8 and 16 point lights, this version against the previous rig, each in a
process of its own with empty shader caches.
"""

from __future__ import annotations

import argparse
import functools
import json
import os
import statistics
import sys
import time

from .measure import apply_phong, artist_scene, worker_setup
from .table import publish


def _timed(view_layer, change, moves, untimed=2) -> list:
    """The seconds of *moves* updates, each after ``change(index)``, after *untimed* ones."""
    times = []
    for index in range(moves + untimed):
        change(index)
        t0 = time.perf_counter()
        view_layer.update()
        times.append(time.perf_counter() - t0)
    return times[untimed:]


def _updates(bpy, view_layer, change, moves):
    return statistics.median(_timed(view_layer, change, moves))


def _nudge(light, index) -> None:
    """A drag step of *light*: a point or spot moved, a sun turned, back and forth."""
    if light.data.type == "SUN":
        light.rotation_euler.x += 0.05 if index % 2 == 0 else -0.05
    else:
        light.location.x += 0.25 if index % 2 == 0 else -0.25


def _measure(bpy, view_layer, lights, moves):
    point, spot = lights[0], lights[min(2, len(lights) - 1)]

    def move(index):
        point.location.x += 0.25 if index % 2 == 0 else -0.25

    def turn(index):
        spot.rotation_euler.x += 0.05 if index % 2 == 0 else -0.05

    return {"move": _updates(bpy, view_layer, move, moves),
            "turn": _updates(bpy, view_layer, turn, moves)}


def _relink(bpy, scene, view_layer):
    with bpy.context.temp_override(scene=scene, view_layer=view_layer):
        t0 = time.perf_counter()
        result = bpy.ops.phong.relink_lights()
        view_layer.update()
        if result != {"FINISHED"}:
            raise RuntimeError(f"relink_lights returned {result}")
    return time.perf_counter() - t0


def _artist(bpy, name, objects, n_lights):
    """``artist_scene`` shown in the window and evaluated once (untimed): (scene, its cubes,
    its lights, its view layer)."""
    scene, meshes, lights = artist_scene(name, objects, n_lights)
    bpy.context.window.scene = scene
    view_layer = scene.view_layers[0]
    view_layer.update()
    return scene, meshes, lights, view_layer


def run(objects: int, n_lights: int, moves: int) -> dict:
    bpy = worker_setup()
    from phong_nodes.addon import compat  # noqa: PLC0415
    from phong_nodes.addon.lighting import opacity, recipe, sources  # noqa: PLC0415

    load_before = os.getloadavg()
    scene, meshes, lights, view_layer = _artist(bpy, "light_move", objects, n_lights)
    out = {"objects": objects, "lights": n_lights, "moves": moves,
           "bpy": bpy.app.version_string, "update_s": {}, "relink_s": {}}
    out["update_s"]["principled"] = _measure(bpy, view_layer, lights, moves)
    for obj in meshes:  # the operator and its update timed, as a user waits for them
        obj.select_set(True, view_layer=view_layer)
    with bpy.context.temp_override(scene=scene, view_layer=view_layer, selected_objects=meshes):
        t0 = time.perf_counter()
        assert bpy.ops.phong.apply_material() == {"FINISHED"}
        view_layer.update()
        out["apply_s"] = time.perf_counter() - t0
    out["update_s"]["world_attributes"] = _measure(bpy, view_layer, lights, moves)
    out["relink_s"]["world_attributes"] = _relink(bpy, scene, view_layer)

    saved = compat.VIEW_LAYER_LOOKUPS
    compat.VIEW_LAYER_LOOKUPS = 0  # the previous rig: every transform driven in the group
    try:
        out["relink_s"]["previous"] = _relink(bpy, scene, view_layer)
        for material in recipe.phong_materials():  # and the source as an ID pointer
            material[sources.SOURCE_KEY] = sources.source_of(material)
        view_layer.update()
        out["update_s"]["previous"] = _measure(bpy, view_layer, lights, moves)
        for material in recipe.phong_materials():
            material[sources.SOURCE_KEY] = material[sources.SOURCE_KEY].name
    finally:
        compat.VIEW_LAYER_LOOKUPS = saved
    _relink(bpy, scene, view_layer)
    out["update_s"]["world_attributes_again"] = _measure(bpy, view_layer, lights, moves)
    base = out["update_s"]["principled"]
    out["ratio_to_principled"] = {
        case: {k: v / base[k] for k, v in figures.items()}
        for case, figures in out["update_s"].items()}
    out["load_average"] = [load_before, os.getloadavg()]
    return out


def _each(view_layer, lights, moves):
    """Per light: the median update after moving it (a sun: turning it)."""
    return [_updates(None, view_layer, functools.partial(_nudge, light), moves)
            for light in lights]


def run_each(objects: int, n_lights: int, moves: int) -> dict:
    """Issue 38: the update after moving each of *n_lights* lights, Principled, this version
    ("phong") and on 5.3+ the lights groups of 5.2 ("lights_group"), then this version
    again (the drift), in one process; ratios to Principled per light."""
    bpy = worker_setup()
    from phong_nodes.addon.lighting import loop, rig, sync  # noqa: PLC0415

    load_before = os.getloadavg()
    scene, meshes, lights, view_layer = _artist(bpy, "light_each", objects, n_lights)
    out = {"objects": objects, "lights": n_lights, "moves": moves,
           "bpy": bpy.app.version_string, "kinds": [o.data.type for o in lights],
           "update_s": {}}
    out["update_s"]["principled"] = _each(view_layer, lights, moves)
    apply_phong(bpy, scene, meshes)
    view_layer.update()
    group = meshes[0].material_slots[0].material.node_tree.nodes["phong_lights"].node_tree
    out["loop"] = loop.has_loop(group)
    out["update_s"]["phong"] = _each(view_layer, lights, moves)
    designs = ["phong"]
    if out["loop"]:
        wants = rig.wants_loop
        rig.wants_loop = lambda _scene: False
        try:
            sync.relink_scene(scene, view_layer)
            view_layer.update()
            out["update_s"]["lights_group"] = _each(view_layer, lights, moves)
            designs.append("lights_group")
        finally:
            rig.wants_loop = wants
        sync.relink_scene(scene, view_layer)
        view_layer.update()
        out["update_s"]["phong_again"] = _each(view_layer, lights, moves)
        designs.append("phong_again")
    base = out["update_s"]["principled"]
    out["ratio_to_principled"] = {
        design: [t / b for t, b in zip(out["update_s"][design], base)] for design in designs}
    out["worst_ratio"] = {design: max(ratios)
                          for design, ratios in out["ratio_to_principled"].items()}
    out["load_average"] = [load_before, os.getloadavg()]
    return out


def _power_step(light, index) -> None:
    """A drag step of *light*'s Power slider: up and down by a tenth."""
    light.data.energy *= 1.1 if index % 2 == 0 else 1.0 / 1.1


def run_power(objects: int, n_lights: int, moves: int) -> dict:
    """The update after a drag step of each light's Power slider, Principled against Phong
    (every light's i0 following its Power: ``properties.FROM_POWER_KEY``), then Principled
    again (the drift), in one process; ratios to Principled per light."""
    bpy = worker_setup()
    from phong_nodes.addon.lighting import properties  # noqa: PLC0415

    load_before = os.getloadavg()
    scene, meshes, lights, view_layer = _artist(bpy, "light_power", objects, n_lights)
    for light in lights:
        light.data[properties.FROM_POWER_KEY] = 1

    def each():
        return [_updates(None, view_layer, functools.partial(_power_step, light), moves)
                for light in lights]

    out = {"objects": objects, "lights": n_lights, "moves": moves,
           "bpy": bpy.app.version_string, "kinds": [o.data.type for o in lights],
           "update_s": {"principled": each()}}
    originals = [[slot.material for slot in obj.material_slots] for obj in meshes]
    apply_phong(bpy, scene, meshes)
    view_layer.update()
    assert all(properties.from_power(o.data) for o in lights)
    out["update_s"]["phong"] = each()
    for obj, slots in zip(meshes, originals):
        for slot, material in zip(obj.material_slots, slots):
            slot.material = material
    view_layer.update()
    out["update_s"]["principled_again"] = each()
    base = [min(a, b) for a, b in zip(out["update_s"]["principled"],
                                      out["update_s"]["principled_again"])]
    out["ratio_to_principled"] = [t / b for t, b in zip(out["update_s"]["phong"], base)]
    out["worst_ratio"] = max(out["ratio_to_principled"])
    out["goal"] = 1.3
    out["load_average"] = [load_before, os.getloadavg()]
    return out


def _block(view_layer, light, moves):
    """*moves* timed updates after moving *light* (a sun: turning it), after 3 untimed."""
    return _timed(view_layer, functools.partial(_nudge, light), moves, untimed=3)


#: ``run_parts``' cases: (materials, the World's drivers of the lights' transforms, the
#: extension's depsgraph handlers of the lights).
PARTS = {"principled": ("principled", False, False), "phong": ("phong", True, True),
         "phong_no_world": ("phong", False, True), "phong_no_handlers": ("phong", True, False),
         "phong_neither": ("phong", False, False)}


def run_parts(objects: int, n_lights: int, moves: int, passes: int) -> dict:
    """Issue 38: what a light drag costs in a Phong scene beyond Principled, in one process
    after Apply, the cases alternating per block of *moves* updates of one light (every
    light, *passes* times): Principled (the cubes given back their Principled materials, the
    World's drivers of the lights' transforms removed: nothing of Phong updates), Phong as
    Apply leaves it, Phong without the World's drivers (the World no longer updates on a
    drag; Cycles would then render stale transforms), without the extension's depsgraph
    handlers of the lights (``sync.on_depsgraph_update``, ``loop.follow_lights``,
    ``opacity.follow_opacity``), and without both.  Also Principled before Apply
    ("principled_fresh": what ``run_each`` compares with) and the handlers' own time."""
    bpy = worker_setup()
    from phong_nodes.addon.lighting import loop, opacity, recipe, sources, sync, world_copies  # noqa: PLC0415

    load_before = os.getloadavg()
    scene, meshes, lights, view_layer = _artist(bpy, "light_parts", objects, n_lights)
    fresh = [[] for _ in lights]
    for _pass in range(passes):
        for index, light in enumerate(lights):
            fresh[index] += _block(view_layer, light, moves)
    originals = [[slot.material for slot in obj.material_slots] for obj in meshes]
    apply_phong(bpy, scene, meshes)
    view_layer.update()
    phong = [[slot.material for slot in obj.material_slots] for obj in meshes]
    world = scene.world
    keys = [(key, obj, kind) for obj in lights for kind in ("LOCATION", "AXIS", "UNIT_AXIS")
            if (key := world_copies.world_key(obj, kind)) in world.keys()]
    handlers = bpy.app.handlers.depsgraph_update_post
    ours = [h for h in handlers
            if h in (opacity.follow_opacity, loop.follow_lights, sync.on_depsgraph_update)]
    state = {"materials": "phong", "world": True, "handlers": True}

    def case(name):
        wanted_materials, world_on, handlers_on = PARTS[name]
        if state["materials"] != wanted_materials:
            for obj, slots in zip(meshes, originals if wanted_materials == "principled"
                                  else phong):
                for slot, material in zip(obj.material_slots, slots):
                    slot.material = material
        if state["world"] != world_on:
            if world_on:
                for key, obj, kind in keys:
                    world_copies.write(world, key, obj, kind)
            else:
                for fcurve in list(world.animation_data.drivers):
                    world.animation_data.drivers.remove(fcurve)
        if state["handlers"] != handlers_on:
            for handler in ours:
                (handlers.append if handlers_on else handlers.remove)(handler)
        state.update(materials=wanted_materials, world=world_on, handlers=handlers_on)
        view_layer.update()

    names = list(PARTS)
    times = {name: [[] for _ in lights] for name in names}
    for number in range(passes):
        for index, light in enumerate(lights):
            for name in names if (number * len(lights) + index) % 2 == 0 else names[::-1]:
                case(name)
                times[name][index] += _block(view_layer, light, moves)
    case("phong")
    spent = {h.__name__: [] for h in ours}

    def timed(handler):
        def run_handler(*args):
            t0 = time.perf_counter()
            handler(*args)
            spent[handler.__name__].append(time.perf_counter() - t0)
        return run_handler

    for handler in ours:
        handlers[handlers.index(handler)] = timed(handler)
    for light in lights:
        _block(view_layer, light, moves)
    per_light = {name: [statistics.median(t) for t in times[name]] for name in names}
    per_light["principled_fresh"] = [statistics.median(t) for t in fresh]
    base = per_light["principled"]
    return {"objects": objects, "lights": n_lights, "moves": moves, "passes": passes,
            "bpy": bpy.app.version_string, "update_s": per_light,
            "median_s": {name: statistics.median(v) for name, v in per_light.items()},
            "ratio_to_principled": {name: [t / b for t, b in zip(v, base)]
                                    for name, v in per_light.items()},
            "median_ratio": {name: statistics.median(t / b for t, b in zip(v, base))
                             for name, v in per_light.items()},
            "handler_s": {name: statistics.median(v) for name, v in spent.items() if v},
            "load_average": [load_before, os.getloadavg()]}


#: ``run_files``' cases: (file, the World's copies kept live, the light loop).
FILE_CASES = {"principled": ("principled", False, True), "phong": ("phong", False, True),
              "phong_live": ("phong", True, True), "lights_group": ("phong", True, False)}


def files_build(folder: str, objects: int, n_lights: int) -> dict:
    """The artist scene saved as ``principled.blend``, and after Apply as ``phong.blend``
    (Eevee, the file's render engine, as Blender makes a new scene); returns this bpy's
    version and whether it has the light loop."""
    bpy = worker_setup()
    from phong_nodes.addon import compat  # noqa: PLC0415

    scene, meshes, _lights, view_layer = _artist(bpy, "light_files", objects, n_lights)
    for other in [s for s in bpy.data.scenes if s != scene]:
        bpy.data.scenes.remove(other)
    bpy.ops.wm.save_as_mainfile(filepath=os.path.join(folder, "principled.blend"))
    apply_phong(bpy, scene, meshes)
    view_layer.update()
    bpy.ops.wm.save_as_mainfile(filepath=os.path.join(folder, "phong.blend"))
    return {"bpy": bpy.app.version_string, "loop": compat.HAS_LIGHT_LOOP}


def files_worker(folder: str, case: str, moves: int, passes: int) -> dict:
    """One process: load the case's file, then *passes* times each light's block of *moves*
    updates; returns every update's seconds per light (lights by name)."""
    bpy = worker_setup()
    from phong_nodes.addon.lighting import loop as light_loop  # noqa: PLC0415
    from phong_nodes.addon.lighting import rig, world_copies  # noqa: PLC0415

    name, live, loop = FILE_CASES[case]
    if live:  # the copies stay live: every drag updates the World, as before issue 38
        world_copies.can_park = lambda _world: False
    if not loop:  # loading relinks the file's groups without it (sync.upgrade_on_load)
        rig.wants_loop = lambda _scene: False
    bpy.ops.wm.open_mainfile(filepath=os.path.join(folder, f"{name}.blend"))
    scene = bpy.data.scenes["light_files"]
    view_layer = scene.view_layers[0]
    if not loop and any(light_loop.has_loop(t) for t in rig.groups_of(scene)):
        raise RuntimeError("the lights groups kept the loop part after loading")
    if live:
        world_copies.make_live(scene.world)
    view_layer.update()
    lights = sorted((o for o in scene.objects if o.type == "LIGHT"), key=lambda o: o.name)
    times = [[] for _ in lights]
    for _pass in range(passes):
        for index, light in enumerate(lights):
            times[index] += _block(view_layer, light, moves)
    return {"case": case, "lights": [o.name for o in lights], "update_s": times,
            "world_live": world_copies.is_live(scene.world) if scene.world else None}


def run_files(objects: int, n_lights: int, moves: int, passes: int, rounds: int) -> dict:
    """Issue 38's drag goal as a user meets it: see ``--files`` above."""
    import subprocess  # noqa: PLC0415
    import tempfile  # noqa: PLC0415

    load_before = os.getloadavg()
    folder = tempfile.mkdtemp(prefix="phong_light_files_")

    def child(*args):
        proc = subprocess.run([sys.executable, "-m", "phong_nodes.benchmarks.light_move",
                               *args], capture_output=True, text=True)
        lines = [x for x in proc.stdout.splitlines() if x.startswith("FILES ")]
        if proc.returncode != 0 or not lines:
            raise RuntimeError(proc.stdout[-2000:] + proc.stderr[-2000:])
        return json.loads(lines[-1][6:])

    built = child("--files-build", folder, str(objects), str(n_lights))
    names = [c for c in FILE_CASES if c != "lights_group" or built["loop"]]
    samples = {case: [[] for _ in range(n_lights)] for case in names}
    worlds = {}
    process_s = {case: [] for case in names}
    for number in range(rounds):
        for case in names if number % 2 == 0 else names[::-1]:
            result = child("--files-worker", folder, case, str(moves), str(passes))
            worlds[case] = result["world_live"]
            process_s[case].append(statistics.median(
                [t for times in result["update_s"] for t in times]))
            for index, times in enumerate(result["update_s"]):
                samples[case][index] += times
    per_light = {case: [statistics.median(t) for t in v] for case, v in samples.items()}
    base = per_light["principled"]
    ratios = {case: [t / b for t, b in zip(v, base)] for case, v in per_light.items()}
    return {"objects": objects, "lights": n_lights, "moves": moves, "passes": passes,
            "rounds": rounds, "bpy": built["bpy"], "method": "files", "update_s": per_light,
            "median_s": {case: statistics.median(v) for case, v in per_light.items()},
            "ratio_to_principled": ratios,
            "median_ratio": {case: statistics.median(v) for case, v in ratios.items()},
            "worst_ratio": {case: max(v) for case, v in ratios.items()},
            "process_median_s": process_s, "world_copies_live": worlds,
            "load_average": [load_before, os.getloadavg()]}


def eevee_first(n_lights: int, design: str) -> dict:
    """One cold process (run by ``eevee``): Eevee's engine warmed up by the Emission scene,
    then the first render (shader compile included) and a second render of 3x3 spheres with
    *n_lights* point lights in *design* ("world_attributes" or "previous")."""
    worker_setup()
    from phong_nodes.addon import compat  # noqa: PLC0415

    from .measure import build_scene, remove_scene, render, set_eevee  # noqa: PLC0415

    if design == "previous":
        compat.VIEW_LAYER_LOOKUPS = 0
    elif design.startswith("lookups="):  # a budget other than the release's, to compare
        compat.VIEW_LAYER_LOOKUPS = int(design.split("=")[1])
    warm, _ = build_scene("ewarm", res=64, grid=3, n_lights=1, material="emission", segments=16)
    set_eevee(warm, 1)
    render(warm)
    remove_scene(warm)
    scene, _ = build_scene(f"e {n_lights}", res=64, grid=3, n_lights=n_lights, material="phong",
                           segments=16)
    set_eevee(scene, 1)
    return {"first": render(scene), "second": render(scene)}


def eevee(lights, repeats) -> dict:
    """Eevee's cold first render per number of lights, both designs, each in a process of
    its own with empty shader caches (as ``run.py`` does); the order alternates."""
    import subprocess  # noqa: PLC0415
    import tempfile  # noqa: PLC0415

    out = {}
    for repeat in range(repeats):
        for n in lights:
            designs = ("world_attributes", "previous")
            for design in designs if repeat % 2 == 0 else designs[::-1]:
                tmp = tempfile.mkdtemp(prefix="phong_light_move_")
                env = dict(os.environ, BLENDER_USER_RESOURCES=os.path.join(tmp, "user"),
                           MESA_SHADER_CACHE_DIR=os.path.join(tmp, "mesa"),
                           XDG_CACHE_HOME=os.path.join(tmp, "cache"))
                proc = subprocess.run(
                    [sys.executable, "-m", "phong_nodes.benchmarks.light_move",
                     "--eevee-worker", str(n), design], env=env, capture_output=True, text=True)
                line = [x for x in proc.stdout.splitlines() if x.startswith("EEVEE ")]
                if proc.returncode != 0 or not line:
                    raise RuntimeError(proc.stderr[-2000:])
                out.setdefault(f"{design}:{n}", []).append(json.loads(line[-1][6:]))
    return out


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--objects", type=int, default=1000)
    parser.add_argument("--lights", type=int, default=4)
    parser.add_argument("--moves", type=int, default=21)
    parser.add_argument("--eevee", type=int, nargs="*", metavar="LIGHTS",
                        help="instead: Eevee's cold first render with these numbers of lights")
    parser.add_argument("--repeats", type=int, default=1)
    parser.add_argument("--each", action="store_true",
                        help="instead: the update after moving each light (issue 38)")
    parser.add_argument("--parts", type=int, metavar="PASSES",
                        help="instead: the parts of a drag's cost, the cases alternating "
                             "per block of --moves updates, every light PASSES times")
    parser.add_argument("--files", type=int, metavar="ROUNDS",
                        help="instead: each light's drag in saved files, each case in a "
                             "process of its own, ROUNDS rounds")
    parser.add_argument("--passes", type=int, default=4,
                        help="--files: each light's block of --moves updates, PASSES times "
                             "per process")
    parser.add_argument("--power", action="store_true",
                        help="the update after a drag step of each light's Power slider")
    parser.add_argument("--out", help="--parts, --files, --power: also write the JSON here")
    parser.add_argument("--files-build", nargs=3, help=argparse.SUPPRESS)
    parser.add_argument("--files-worker", nargs=4, help=argparse.SUPPRESS)
    parser.add_argument("--eevee-worker", nargs=2, help=argparse.SUPPRESS)
    args = parser.parse_args(argv)
    if args.eevee_worker:
        print("EEVEE " + json.dumps(eevee_first(int(args.eevee_worker[0]),
                                                args.eevee_worker[1])))
        return 0
    if args.files_build:
        folder, objects, n_lights = args.files_build
        print("FILES " + json.dumps(files_build(folder, int(objects), int(n_lights))),
              flush=True)
        os._exit(0)
    if args.files_worker:
        folder, case, moves, passes = args.files_worker
        print("FILES " + json.dumps(files_worker(folder, case, int(moves), int(passes))),
              flush=True)
        sys.stderr.flush()
        os._exit(0)
    if args.files:
        result = run_files(args.objects, args.lights, args.moves, args.passes, args.files)
        publish(result, args.out, json.dumps(result, indent=1))
        return 0
    if args.parts or args.power:
        result = (run_parts(args.objects, args.lights, args.moves, args.parts) if args.parts
                  else run_power(args.objects, args.lights, args.moves))
        publish(result, args.out, json.dumps(result, indent=1))
        sys.stderr.flush()
        os._exit(0)
    if args.each:
        print(json.dumps(run_each(args.objects, args.lights, args.moves), indent=1), flush=True)
        sys.stderr.flush()
        os._exit(0)
    if args.eevee is not None:
        print(json.dumps(eevee(args.eevee or [4, 8, 16], args.repeats), indent=1))
        return 0
    print(json.dumps(run(args.objects, args.lights, args.moves), indent=1), flush=True)
    sys.stderr.flush()
    os._exit(0)  # bpy 4.2's clean-up at interpreter exit crashed after this run (signal 11)


if __name__ == "__main__":
    sys.exit(main())
