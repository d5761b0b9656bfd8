#!/usr/bin/env python3
"""Headless command of Phong Nodes (runs on the ``bpy`` module): the seed figures as scenes,
rendered by Eevee and Cycles and checked against the numpy reference of the formulas.

    python tools/phong.py [--scenes a,b|all] [--engines cycles,eevee] [--resolution N]
                          [--out DIR] [--shard i/n]

Builds every demo scene of ``scenes/*.toml`` (or those named; a path to a .toml file also
works), bakes each comparison into ``DIR/<scene>/`` (pictures, heatmaps, term images,
sheet.png, metrics.json), writes ``DIR/index.html`` over every scene folder in DIR (so
shards writing into one DIR merge) and prints a summary table.

Exit codes: 0 every engine matches the reference (Cycles max |error| <= 1e-4, Eevee within
1/255 on >= 99.5% of pixels); 1 some engine does not match, or a render failed; 2 bad
arguments or a bad scene file (nothing is written then).
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
    parser = argparse.ArgumentParser(prog="phong", description=__doc__.split("\n\n")[0])
    parser.add_argument("--scenes", default="all",
                        help="comma-separated scene names or .toml paths (default: all)")
    parser.add_argument("--engines", default="cycles,eevee",
                        help="comma-separated: cycles, eevee (default: both)")
    parser.add_argument("--resolution", type=int, default=DEFAULT_RESOLUTION,
                        help=f"picture height in pixels (default: {DEFAULT_RESOLUTION})")
    parser.add_argument("--out", default="out/demo", help="output folder (default: out/demo)")
    parser.add_argument("--shard", default=None,
                        help="i/n: bake only every n-th scene starting at the i-th (1-based)")
    args = parser.parse_args(argv)
    engines = [e.strip().lower() for e in args.engines.split(",") if e.strip()]
    unknown = sorted(set(engines) - {"cycles", "eevee"})
    if unknown or not engines:
        parser.error(f"--engines: unknown engine(s) {', '.join(unknown) or '(none given)'}; "
                     "expected cycles and/or eevee")
    if not 8 <= args.resolution <= 4096:
        parser.error(f"--resolution must be between 8 and 4096, got {args.resolution}")
    args.engines = engines
    return args


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
    args = parse_args(sys.argv[1:] if argv is None else argv)
    try:
        selected = scenes.load_all(scenes.resolve(args.scenes))
        mine = scenes.shard(selected, args.shard)
    except scenes.SceneError as error:
        print(f"phong: {error}", file=sys.stderr)
        return 2
    state["total"] = len(mine)
    out = os.path.abspath(args.out)
    problem = outputs.output_problem(out, refuse_package=False)
    if problem is not None:
        print(f"phong: {problem}", file=sys.stderr)
        return 2
    outputs.clean_stale(out)  # what a killed run left behind
    check_interrupt()

    say = _terminal()
    start = time.perf_counter()
    print(f"phong: {len(mine)} scene(s) of {len(selected)}"
          f"{f' (shard {args.shard})' if args.shard else ''}, engines {', '.join(args.engines)}, "
          f"{args.resolution} px high -> {out}", file=say)
    import phong_nodes  # noqa: PLC0415  (after the checks: importing bpy takes a second)

    phong_nodes.register()
    try:
        results, failed = _bake_scenes(mine, args, out, say, state)
    finally:
        phong_nodes.unregister()
    index = report.write_index(out)
    print("", *summary_table(results), sep="\n", file=say)
    ok = not failed and all(m["ok"] for m in results)
    status = "every engine matches the reference" if ok else (
        f"MISMATCH or failure ({', '.join(failed + [m['scene'] for m in results if not m['ok']])})")
    print(f"\n{status}; {len(results)} scene(s) in {time.perf_counter() - start:.1f} s; "
          f"report: {index}", file=say)
    say.flush()
    return 0 if ok else 1


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


def _bake_scenes(mine, args, out, say, state):
    """Build and bake each scene into out/<name>; returns (metrics list, failed names)."""
    import bpy  # noqa: PLC0415

    from phong_nodes.addon.demos import bake, builder  # noqa: PLC0415

    check_interrupt()
    results, failed = [], []
    for number, data in enumerate(mine, start=1):
        t0 = time.perf_counter()
        name = data["name"]
        print(f"[{number}/{len(mine)}] {name}: build", end="", file=say)

        def progress(fraction, text, t0=t0):
            if fraction < 1.0:  # at 1.0 the scene folder is already in place
                check_interrupt()
            print(f" | {time.perf_counter() - t0:.1f} s: {text}", end="", file=say)

        try:
            scene = builder.build(data, args.resolution)
            metrics = bake.bake(scene, os.path.join(out, name), engines=args.engines,
                                progress=progress)
            bpy.data.scenes.remove(scene)
        except Exception as error:  # noqa: BLE001  (one bad scene must not hide the others)
            print(f"\nphong: {name}: bake failed: {error}", file=sys.stderr)
            failed.append(name)
            continue
        print(f"\n      {compare.verdict_text(metrics['verdict'])}", file=say)
        results.append(metrics)
        state["done"] += 1
        check_interrupt()
    return results, failed


def summary_table(results) -> list:
    """The terminal table: one line per scene and pair of pictures."""
    header = (f"{'scene':<18}{'pair':<19}{'max |d|':>10}{'mean |d|':>10}{'PSNR':>8}"
              f"{'>1/255':>9}  verdict")
    lines = [header, "-" * len(header)]
    for m in results:
        for pair, p in m["pairs"].items():
            engine = pair.split("-")[0]
            v = m["verdict"].get(engine) if pair.endswith("reference") else None
            mark = "" if v is None else ("OK" if v["ok"] else "FAIL")
            psnr = "inf" if p["psnr_db"] is None else f"{p['psnr_db']:.1f}"
            lines.append(f"{m['scene']:<18}{pair:<19}{p['max_abs']:>10.2e}"
                         f"{p['mean_abs']:>10.2e}{psnr:>8}{p['share_over_1_255']:>9.3%}  {mark}")
    return lines


def exit_process(code: int) -> None:
    """Exit with *code* (through the Blender layer once bpy is loaded: see compat)."""
    if "bpy" in sys.modules:
        from phong_nodes.addon import compat  # noqa: PLC0415

        compat.exit_process(code)
    sys.exit(code)


if __name__ == "__main__":
    exit_process(main())
