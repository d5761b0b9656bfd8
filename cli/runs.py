# SPDX-License-Identifier: GPL-3.0-or-later
"""``phong demo``, ``phong compare`` and ``phong report``: scenes with Phong materials rendered by
Eevee and Cycles (headless, the ``bpy`` module) and checked against the numpy reference.

``demo`` builds every demo scene of ``scenes/*.toml`` (or those named; a path to a .toml file
also works) as an ordinary Blender scene (real lights, Light Linking, materials made by Apply
Phong Material's code) and compares it; ``--save-blend`` keeps each built scene as
``DIR/<scene>/<scene>.blend``.  ``compare`` opens a .blend (or imports an .obj) and compares
every scene of it that has objects with Phong materials (or those named), at the scene's own
resolution unless ``--resolution`` is given.  Each comparison goes into ``DIR/<scene>/``
(pictures, term passes, heatmaps, sheet.png, metrics.json); ``DIR/index.html`` covers every
scene folder in DIR (so shards writing into one DIR merge); a summary table is printed.
``--shard auto`` takes the shard from a scheduler's job array (Slurm, Kubernetes Indexed Jobs;
see ``core.scenes.resolve_shard``).  Each run records the scene folders of the whole run in
``DIR/run.json``; ``report DIR`` rebuilds the index from the finished folders and says which of
those are missing or failed (exit 0 when the run is whole, 1 otherwise).

An imported file without a camera or Viewpoint is framed (``inputs``: "framed: the file has
no camera", a line of the scene's report), and so is a scene of a .blend without any camera
("framed: the scene has no camera"); every scene of a multi-scene .blend is compared; a
comparison whose camera sees Phong surfaces on fewer than 1% of the pixels fails, saying so
(``core.compare.coverage``).

Exit codes: 0 every engine matches the reference (Cycles max |error| <= 1e-4, Eevee within
1/255 on >= 99.5% of pixels) on a picture that shows the scene; 1 some engine does not match,
the camera sees (almost) no Phong surface, or a render failed; 2 bad
arguments, a bad scene file, a missing or unreadable file, or no Phong material (nothing is
written then).
"""

from __future__ import annotations

import os
import sys
import time

from ..core import compare, outputs, report, scenes
from .apply import ApplyFailed, convert_scenes, report_lines
from .inputs import FRAMED_KEY, BadInput, open_scene_file, peer_problem
from .registered import Registered
from .terminal import check_interrupt, terminal



def report_main(args) -> int:
    """``report DIR``: the completeness check of a (sharded) run."""
    out = os.path.abspath(args.dir)
    try:
        state = report.check_run(out)
    except report.RunError as error:
        print(f"phong report: {error}", file=sys.stderr)
        return 2
    outputs.clean_stale(out)  # temporary entries of killed tasks of this host
    if state["kind"] == "bake":  # scene folders with a .glb each: no comparison index
        print(f"phong report: {report.run_text(state)}")
    else:
        index = report.write_index(out)
        results = report.results(out)
        if results:
            print(*summary_table(results), "", sep="\n")
        print(f"phong report: {report.run_text(state)}; report: {index}")
    return 0 if not state["missing"] and not state["failed"] else 1


def run(args, state) -> int:
    """``demo`` or ``compare`` with the parsed *args*; *state* counts done / total scenes."""
    problem = peer_problem(args.peers)
    if problem is not None:
        print(f"phong: {problem}", file=sys.stderr)
        return 2
    with Registered() as registered:
        return _run(args, state, registered)


def _run(args, state, registered) -> int:
    comparing = args.command == "compare"
    try:
        if comparing:
            # bpy must read the file before anything is written
            registered.ensure()
            jobs, every = _file_jobs(args)
        else:
            selected = scenes.load_all(scenes.resolve(args.scenes))
            jobs, every = _demo_jobs(scenes.shard(selected, args.shard), args), [
                d["name"] for d in selected]
    except (scenes.SceneError, BadInput) as error:
        print(f"phong: {error}", file=sys.stderr)
        return 2
    except ApplyFailed as error:   # compare --apply: a conversion raised
        print(f"phong: {error}", file=sys.stderr)
        return 1
    state["total"] = len(jobs)
    out = os.path.abspath(args.out)
    problem = outputs.output_problem(out, refuse_package=False)
    if problem is not None:
        print(f"phong: {problem}", file=sys.stderr)
        return 2
    outputs.clean_stale(out)  # what a killed run left behind
    report.write_run(out, every, args.command)
    check_interrupt()

    say = terminal()
    start = time.perf_counter()
    what = f"of {len(every)} in {args.file}" if comparing else f"of {len(every)}"
    shard = (f" (shard {args.shard}{f' from {args.shard_source}' if args.shard_source else ''})"
             if args.shard else "")
    print(f"phong: {len(jobs)} scene(s) {what}{shard}, engines {', '.join(args.engines)}, "
          f"{f'{args.resolution} px high' if args.resolution else 'own resolution'} -> {out}",
          file=say)
    registered.ensure()
    results, failed = _compare_scenes(jobs, args, out, say, state)
    index = report.write_index(out)
    print("", *summary_table(results), sep="\n", file=say)
    ok = not failed and all(m["ok"] for m in results)
    blind = [m["scene"] for m in results if not m.get("coverage", {}).get("ok", True)]
    off = failed + [m["scene"] for m in results if not m["ok"] and m["scene"] not in blind]
    status = "every engine matches the reference" if ok else "; ".join(
        ([f"NOTHING TO COMPARE ({', '.join(blind)}: the camera sees no Phong surface)"]
         if blind else []) + ([f"MISMATCH or failure ({', '.join(off)})"] if off else []))
    print(f"\n{status}; {len(results)} scene(s) in {time.perf_counter() - start:.1f} s; "
          f"report: {index}", file=say)
    say.flush()
    return 0 if ok else 1


class Job:
    """One scene to compare: *make()* returns the Blender scene; *done(scene, folder, name)*
    runs before its report folder is put in place; *notes*: lines for its report."""

    def __init__(self, name, make, done=None, drop=False, notes=()):
        self.name, self.make, self.done, self.drop = name, make, done, drop
        self.notes = list(notes)


def _demo_jobs(mine, args) -> list:
    def make(data):
        from ..addon.demos import builder  # noqa: PLC0415

        return builder.build(data, args.resolution)

    def save(scene, folder, name):
        import bpy  # noqa: PLC0415

        bpy.data.libraries.write(os.path.join(folder, f"{name}.blend"), {scene},
                                 path_remap="NONE", fake_user=False)

    return [Job(d["name"], lambda d=d: make(d), save if args.save_blend else None, drop=True)
            for d in mine]


def _file_jobs(args):
    """``_scene_jobs`` of args.file; whatever else a file Blender opens makes go wrong while
    its scenes are chosen (exit 2) is one line, never a traceback."""
    try:
        return _scene_jobs(args)
    except (BadInput, ApplyFailed, scenes.SceneError):
        raise
    except Exception as error:  # noqa: BLE001
        raise BadInput(f"{args.file}: its scenes cannot be compared: "
                       f"{type(error).__name__}: {error}") from None


def _scene_jobs(args):
    """The jobs of the scenes of args.file with Phong materials (BadInput: exit 2).  Every
    scene of a multi-scene file is compared, not only the window's; a scene without a camera
    gets one that frames its Phong objects (``framing.add_camera``), said in its notes.
    Without --scenes a scene whose Phong objects cannot be compared (Per Vertex / Per Face
    only) is left out with a line on stderr; a scene named by --scenes must be comparable."""
    import bpy  # noqa: PLC0415

    from ..addon.comparison import engine  # noqa: PLC0415
    from ..addon.scene import describe  # noqa: PLC0415

    names, named = open_scene_file(args.file, args.scenes)
    applied = {}
    if getattr(args, "apply", False):
        # every scene, in every shard alike (so that each names the same folders)
        for name, report in convert_scenes(named or names, args.file):
            print(report_lines(name, report))
            applied[name] = (f"applied: {len(report.converted)} object(s) given Phong "
                             f"materials first (--apply; the file is not written)")
    wanted = named
    if wanted is None:
        wanted = [n for n in names
                  if describe.phong_objects(bpy.data.scenes[n],
                                            describe.view_layer_of(bpy.data.scenes[n]),
                                            instanced=True)]
        if not wanted:
            raise BadInput(f"{args.file}: no scene has an object with a Phong material "
                           "(Apply Phong Material first)")
    comparable, problems = [], []
    for name in wanted:
        try:
            engine.check(bpy.data.scenes[name], camera=False)  # framed below where it has none
        except engine.ComparisonError as error:
            problems.append(str(error))
            continue
        comparable.append(name)
    if named is not None and problems or not comparable:
        raise BadInput(f"{args.file}: {problems[0]}")
    for problem in problems:
        print(f"phong: {os.path.basename(args.file)}: left out: {problem}", file=sys.stderr)
    wanted = comparable
    # of every scene, so that each shard names the same folder for a scene
    folders = outputs.distinct(describe.folder_name(bpy.data.scenes[name]) for name in wanted)
    try:
        mine = scenes.shard(list(zip(wanted, folders)), args.shard)
    except scenes.SceneError as error:
        raise BadInput(str(error)) from None
    jobs = []
    for name, folder in mine:
        scene = bpy.data.scenes[name]
        job = Job(folder, None, notes=([scene[FRAMED_KEY]] if scene.get(FRAMED_KEY) else [])
                  + ([applied[name]] if name in applied else []))
        job.make = lambda n=name, j=job: _file_scene(args.file, bpy.data.scenes[n], j)
        jobs.append(job)
    return jobs, folders


#: The note of a scene of a .blend that had no camera (``_file_scene``).
FRAMED_SCENE = "framed: the scene has no camera"


def _file_scene(file, scene, job):
    """*scene* of a .blend, ready to compare: a scene without a scene camera takes its
    camera object (the first by name) where it has one, else a new camera that frames its
    Phong objects (said on stderr and in *job*'s notes); the file itself is never written."""
    from ..addon.comparison import engine  # noqa: PLC0415
    from ..addon.scene import framing  # noqa: PLC0415

    if scene.camera is not None:
        return scene
    cameras = sorted((o for o in scene.objects if o.type == "CAMERA"), key=lambda o: o.name)
    if cameras:   # the artist's own view, though not set as the scene's camera
        scene.camera = cameras[0]
        said = f"has no scene camera: used its camera object {cameras[0].name!r}"
        job.notes.append(f"camera: the scene sets none; its camera object {cameras[0].name!r}")
    else:
        _layer, objects = engine.check(scene, camera=False)
        framing.add_camera(scene, objects)
        said = "has no camera: added one that frames its Phong objects"
        job.notes.append(FRAMED_SCENE)
    print(f"\nphong: {os.path.basename(file)}: scene {scene.name!r} {said}", file=sys.stderr)
    return scene


def _compare_scenes(jobs, args, out, say, state):
    """Make and compare each job's scene into out/<name>; returns (metrics list, failed names)."""
    from ..addon.comparison import engine  # noqa: PLC0415
    from ..addon.demos import builder  # noqa: PLC0415

    check_interrupt()
    results, failed = [], []
    for number, job in enumerate(jobs, start=1):
        t0 = time.perf_counter()
        print(f"[{number}/{len(jobs)}] {job.name}: build", end="", file=say)

        def progress(fraction, text, t0=t0):
            if fraction < 1.0:  # at 1.0 the scene folder is already in place
                check_interrupt()
            print(f" | {time.perf_counter() - t0:.1f} s: {text}", end="", file=say)

        try:
            scene = job.make()
            metrics = engine.run(scene, os.path.join(out, job.name), engines=args.engines,
                                progress=progress, resolution=args.resolution,
                                peers=args.peers, notes=job.notes,
                                on_folder=None if job.done is None
                                else lambda folder, s=scene: job.done(s, folder, job.name))
            if job.drop:
                builder.remove(scene)
        except Exception as error:  # noqa: BLE001  (one bad scene must not hide the others)
            print(f"\nphong: {job.name}: the comparison failed: {error}", file=sys.stderr)
            failed.append(job.name)
            continue
        for note in metrics.get("notes", []):  # the job's and the comparison's own
            print(f"\n      {note}", end="", file=say)
        print(f"\n      {compare.summary_text(metrics)}", file=say)
        results.append(metrics)
        state["done"] += 1
        check_interrupt()
    return results, failed


def summary_table(results) -> list:
    """The terminal table: one line per scene and pair of pictures; the first two columns
    are as wide as their longest entry."""
    rows = [(m, pair, p) for m in results for pair, p in m["pairs"].items()]
    scene_w = max([16] + [len(m["scene"]) for m, _, _ in rows]) + 2
    pair_w = max([17] + [len(pair) for _, pair, _ in rows]) + 2
    header = (f"{'scene':<{scene_w}}{'pair':<{pair_w}}{'max |d|':>10}{'mean |d|':>10}"
              f"{'PSNR':>8}{'>1/255':>9}  verdict")
    lines = [header, "-" * len(header)]
    for m, pair, p in rows:
        engine = pair.split("-")[0]
        # a peer's verdict is against Cycles, an engine's against the reference
        judged = (pair == f"{engine}-cycles" if engine in compare.PEERS
                  else pair.endswith("reference"))
        v = m["verdict"].get(engine) if judged else None
        mark = "" if v is None else ("OK" if v["ok"] else "FAIL")
        seen = m.get("coverage", {"ok": True})   # metrics.json of 0.x had none
        if v is not None and not seen["ok"]:
            mark = f"FAIL: sees {seen['value']}"
        psnr = "inf" if p["psnr_db"] is None else f"{p['psnr_db']:.1f}"
        lines.append(f"{m['scene']:<{scene_w}}{pair:<{pair_w}}{p['max_abs']:>10.2e}"
                     f"{p['mean_abs']:>10.2e}{psnr:>8}{p['share_over_1_255']:>9.3%}  {mark}")
    return lines
