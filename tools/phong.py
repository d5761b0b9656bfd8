#!/usr/bin/env python3
"""Headless command of Phong Nodes (runs on the ``bpy`` module): scenes with Phong materials
rendered by Eevee and Cycles and checked against the numpy reference of the formulas.

    python tools/phong.py [--scenes a,b|all] [--engines cycles,eevee] [--resolution N]
                          [--out DIR] [--shard i/n] [--save-blend]
    python tools/phong.py compare FILE.blend [--scenes a,b] [--engines cycles,eevee]
                          [--resolution N] [--out DIR] [--shard i/n]
    python tools/phong.py report DIR

    python tools/phong.py bake FILE.blend --target image|vertex [options]   (phong_bake.py)

The first form builds every demo scene of ``scenes/*.toml`` (or those named; a path to a
.toml file also works) as an ordinary Blender scene (real lights, Light Linking, materials
made by Apply Phong Material's code) and compares it; ``--save-blend`` keeps each built scene
as ``DIR/<scene>/<scene>.blend``.  ``compare`` opens a .blend and compares every scene of it
that has objects with Phong materials (or those named), at the scene's own resolution unless
``--resolution`` is given.  Each comparison goes into ``DIR/<scene>/`` (pictures, term
passes, heatmaps, sheet.png, metrics.json); ``DIR/index.html`` covers every scene folder in
DIR (so shards writing into one DIR merge); a summary table is printed.  ``--shard auto``
takes the shard from a scheduler's job array (Slurm, Kubernetes Indexed Jobs; see
``core.scenes.resolve_shard``).  Each run records the scene folders of the whole run in
``DIR/run.json``; ``report DIR`` rebuilds the index from the finished folders and says which
of those are missing or failed (exit 0 when the run is whole, 1 otherwise).

Exit codes: 0 every engine matches the reference (Cycles max |error| <= 1e-4, Eevee within
1/255 on >= 99.5% of pixels); 1 some engine does not match, or a render failed; 2 bad
arguments, a bad scene file, a missing or unreadable .blend, or no Phong material (nothing
is written then).
"""

from __future__ import annotations

import argparse
import os
import signal
import sys
import time

sys.dont_write_bytecode = True  # write nothing outside --out (no __pycache__ in the source tree)

# The extension's pure packages (no bpy): `tools/phong.sh setup` makes the source tree
# importable as `phong_nodes` in the virtual environment.
from cli_input import (BadInput, open_blend, parse_peers, parse_shard,  # noqa: E402
                       peer_problem)
from phong_nodes.core import compare, outputs, report, scenes  # noqa: E402

DEFAULT_RESOLUTION = 256


class Interrupted(KeyboardInterrupt):
    """Ctrl+C (SIGINT) or SIGTERM: stop at the next step, keep only finished scene folders."""

    def __init__(self, signum: int):
        super().__init__(signum)
        self.signum = signum


_PENDING = []


def _on_signal(signum, _frame):
    # Only note it: raising here could land inside a Blender callback, which would print a
    # traceback and swallow it.  check_interrupt() raises at the next step.
    _PENDING.append(signum)


def check_interrupt() -> None:
    if _PENDING:
        raise Interrupted(_PENDING[0])


def parse_args(argv):
    compare_mode = bool(argv) and argv[0] == "compare"
    if compare_mode:
        parser = argparse.ArgumentParser(
            prog="phong compare", description="Compare every scene of a .blend that has "
            "Phong materials with the numpy reference of the formulas.")
        parser.add_argument("file", help="the .blend file")
        parser.add_argument("--scenes", default=None,
                            help="comma-separated scene names of the file (default: every "
                                 "scene with Phong materials)")
        resolution_help = "picture height in pixels (default: each scene's own size)"
        default_out = "out/compare"
    else:
        parser = argparse.ArgumentParser(prog="phong", description=__doc__.split("\n\n")[0])
        parser.add_argument("--scenes", default="all",
                            help="comma-separated scene names or .toml paths (default: all)")
        parser.add_argument("--save-blend", action="store_true",
                            help="keep each built scene as DIR/<scene>/<scene>.blend")
        resolution_help = f"picture height in pixels (default: {DEFAULT_RESOLUTION})"
        default_out = "out/demo"
    parser.add_argument("--engines", default="cycles,eevee",
                        help="comma-separated: cycles, eevee (default: both)")
    parser.add_argument("--resolution", type=int,
                        default=None if compare_mode else DEFAULT_RESOLUTION,
                        help=resolution_help)
    parser.add_argument("--out", default=default_out,
                        help=f"output folder (default: {default_out})")
    parser.add_argument("--shard", default=None, help=scenes.SHARD_HELP)
    parser.add_argument("--peers", default="",
                        help="other renderers to compare: threejs (exports each scene as a "
                             "three.js page and renders it in headless Chromium)")
    args = parser.parse_args(argv[1:] if compare_mode else argv)
    args.compare = compare_mode
    engines = [e.strip().lower() for e in args.engines.split(",") if e.strip()]
    unknown = sorted(set(engines) - {"cycles", "eevee"})
    if unknown or not engines:
        parser.error(f"--engines: unknown engine(s) {', '.join(unknown) or '(none given)'}; "
                     "expected cycles and/or eevee")
    if args.resolution is not None and not 8 <= args.resolution <= 4096:
        parser.error(f"--resolution must be between 8 and 4096, got {args.resolution}")
    args.engines = engines
    args.peers = parse_peers(parser, args.peers)
    parse_shard(parser, args)
    return args


def parse_report_args(argv):
    parser = argparse.ArgumentParser(
        prog="phong report", description="Rebuild DIR/index.html from the finished scene "
        "folders and check the run (demo, compare or bake): exit 0 when every scene of "
        "DIR/run.json is there and matches (bake: is baked and exported, and its glTF check "
        "passed), 1 naming those missing or failed, 2 when DIR is not a run's folder.")
    parser.add_argument("dir", help="the output folder of a run (its --out)")
    return parser.parse_args(argv)


def report_main(argv) -> int:
    """``report DIR``: the completeness check of a (sharded) run."""
    args = parse_report_args(argv)
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


def main(argv=None) -> int:
    """Run the command; Ctrl+C / SIGTERM end it with 130 / 143 and one line on stderr."""
    state = {"done": 0, "total": 0}
    previous = {sig: signal.signal(sig, _on_signal) for sig in (signal.SIGINT, signal.SIGTERM)}
    try:
        return _main(argv, state)
    except KeyboardInterrupt as stop:
        signum = getattr(stop, "signum", signal.SIGINT)
        print(f"phong: interrupted by {signal.Signals(signum).name} after {state['done']} of "
              f"{state['total']} scene(s); finished scene folders are complete, nothing "
              "half-written was kept", file=sys.stderr)
        return 128 + signum
    finally:
        for sig, handler in previous.items():
            signal.signal(sig, handler)


def _main(argv, state) -> int:
    argv = sys.argv[1:] if argv is None else argv
    if argv and argv[0] == "report":
        return report_main(argv[1:])
    if argv and argv[0] == "bake":  # Bake Phong Lighting and glTF: tools/phong_bake.py
        import phong_bake  # noqa: PLC0415  (beside this file)

        return phong_bake.run(argv[1:], check_interrupt, state, _terminal)
    args = parse_args(argv)
    problem = peer_problem(args.peers)
    if problem is not None:
        print(f"phong: {problem}", file=sys.stderr)
        return 2
    registered = []
    try:
        return _run(args, state, registered)
    finally:
        # unregistered on every path: bpy 4.2 crashes at interpreter exit while classes that
        # were registered without an add-on (here: by hand) are still registered
        if registered:
            registered[0].unregister()


def _run(args, state, registered) -> int:
    try:
        if args.compare:
            # bpy must read the .blend before anything is written
            import phong_nodes  # noqa: PLC0415

            phong_nodes.register()
            registered.append(phong_nodes)
            jobs, every = _blend_jobs(args)
        else:
            selected = scenes.load_all(scenes.resolve(args.scenes))
            jobs, every = _demo_jobs(scenes.shard(selected, args.shard), args), [
                d["name"] for d in selected]
    except (scenes.SceneError, BadInput) as error:
        print(f"phong: {error}", file=sys.stderr)
        return 2
    state["total"] = len(jobs)
    out = os.path.abspath(args.out)
    problem = outputs.output_problem(out, refuse_package=False)
    if problem is not None:
        print(f"phong: {problem}", file=sys.stderr)
        return 2
    outputs.clean_stale(out)  # what a killed run left behind
    report.write_run(out, every, "compare" if args.compare else "demo")
    check_interrupt()

    say = _terminal()
    start = time.perf_counter()
    what = f"of {len(every)} in {args.file}" if args.compare else f"of {len(every)}"
    shard = (f" (shard {args.shard}{f' from {args.shard_source}' if args.shard_source else ''})"
             if args.shard else "")
    print(f"phong: {len(jobs)} scene(s) {what}{shard}, engines {', '.join(args.engines)}, "
          f"{f'{args.resolution} px high' if args.resolution else 'own resolution'} -> {out}",
          file=say)
    import phong_nodes  # noqa: PLC0415  (after the checks: importing bpy takes a second)

    if not registered:
        phong_nodes.register()
        registered.append(phong_nodes)
    results, failed = _bake_scenes(jobs, args, out, say, state)
    index = report.write_index(out)
    print("", *summary_table(results), sep="\n", file=say)
    ok = not failed and all(m["ok"] for m in results)
    status = "every engine matches the reference" if ok else (
        f"MISMATCH or failure ({', '.join(failed + [m['scene'] for m in results if not m['ok']])})")
    print(f"\n{status}; {len(results)} scene(s) in {time.perf_counter() - start:.1f} s; "
          f"report: {index}", file=say)
    say.flush()
    return 0 if ok else 1


class Job:
    """One scene to compare: *make()* returns the Blender scene; *done(scene, folder, name)*
    runs before its report folder is put in place."""

    def __init__(self, name, make, done=None, drop=False):
        self.name, self.make, self.done, self.drop = name, make, done, drop


def _demo_jobs(mine, args) -> list:
    def make(data):
        from phong_nodes.addon.demos import builder  # noqa: PLC0415

        return builder.build(data, args.resolution)

    def save(scene, folder, name):
        import bpy  # noqa: PLC0415

        bpy.data.libraries.write(os.path.join(folder, f"{name}.blend"), {scene},
                                 path_remap="NONE", fake_user=False)

    return [Job(d["name"], lambda d=d: make(d), save if args.save_blend else None, drop=True)
            for d in mine]


def _blend_jobs(args):
    """The jobs of the scenes of args.file with Phong materials (BadInput: exit 2)."""
    import bpy  # noqa: PLC0415

    from phong_nodes.addon.comparison import engine
    from phong_nodes.addon.scene import describe  # noqa: PLC0415

    names, wanted = open_blend(args.file, args.scenes)
    if wanted is None:
        wanted = [n for n in names
                  if describe.phong_objects(bpy.data.scenes[n],
                                            describe.view_layer_of(bpy.data.scenes[n]))]
        if not wanted:
            raise BadInput(f"{args.file}: no scene has an object with a Phong material "
                           "(Apply Phong Material first)")
    for name in wanted:
        try:
            engine.check(bpy.data.scenes[name])
        except engine.ComparisonError as error:
            raise BadInput(f"{args.file}: {error}") from None
    # of every scene, so that each shard names the same folder for a scene
    folders = outputs.distinct(describe.folder_name(bpy.data.scenes[name]) for name in wanted)
    try:
        mine = scenes.shard(list(zip(wanted, folders)), args.shard)
    except scenes.SceneError as error:
        raise BadInput(str(error)) from None
    jobs = [Job(folder, lambda n=name: bpy.data.scenes[n]) for name, folder in mine]
    return jobs, folders


def _terminal():
    """A stream to the terminal for our own lines: Blender's render log goes to fd 1, which
    is sent to /dev/null unless PHONG_VERBOSE=1."""
    say = os.fdopen(os.dup(1), "w", buffering=1)
    if os.environ.get("PHONG_VERBOSE") != "1":
        devnull = os.open(os.devnull, os.O_WRONLY)
        sys.stdout.flush()
        os.dup2(devnull, 1)
        os.close(devnull)
    return say


def _bake_scenes(jobs, args, out, say, state):
    """Make and bake each job's scene into out/<name>; returns (metrics list, failed names)."""
    from phong_nodes.addon.comparison import engine
    from phong_nodes.addon.demos import builder  # noqa: PLC0415

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
                                peers=args.peers,
                                on_folder=None if job.done is None
                                else lambda folder, s=scene: job.done(s, folder, job.name))
            if job.drop:
                builder.remove(scene)
        except Exception as error:  # noqa: BLE001  (one bad scene must not hide the others)
            print(f"\nphong: {job.name}: bake failed: {error}", file=sys.stderr)
            failed.append(job.name)
            continue
        print(f"\n      {compare.verdict_text(metrics['verdict'])}", file=say)
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
        v = (m["verdict"].get(engine) if pair.endswith("reference") or pair == "threejs-cycles"
             else None)
        mark = "" if v is None else ("OK" if v["ok"] else "FAIL")
        psnr = "inf" if p["psnr_db"] is None else f"{p['psnr_db']:.1f}"
        lines.append(f"{m['scene']:<{scene_w}}{pair:<{pair_w}}{p['max_abs']:>10.2e}"
                     f"{p['mean_abs']:>10.2e}{psnr:>8}{p['share_over_1_255']:>9.3%}  {mark}")
    return lines


def exit_process(code: int) -> None:
    """Exit with *code*, without bpy's clean-up where it would crash (compat)."""
    if "bpy" in sys.modules:
        from phong_nodes.addon import compat  # noqa: PLC0415

        compat.leave_if_exit_crashes(code)
    sys.exit(code)


if __name__ == "__main__":
    exit_process(main())
