#!/usr/bin/env python3
"""Headless command of Phong Nodes (runs on the ``bpy`` module).

    python tools/phong.py [--out DIR] [--resolution N] [--engines cycles,eevee]

Renders the demo sphere with each engine to ``DIR/sphere_<engine>.png`` and
prints how far the two pictures are apart.  Exit code 0 on success, 2 on bad
arguments, 1 when a render fails.
"""

from __future__ import annotations

import argparse
import importlib.util
import os
import sys
import time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def import_extension():
    """Import the extension from this source tree as the package ``phong_nodes``."""
    spec = importlib.util.spec_from_file_location(
        "phong_nodes", os.path.join(ROOT, "__init__.py"), submodule_search_locations=[ROOT])
    module = importlib.util.module_from_spec(spec)
    sys.modules["phong_nodes"] = module
    spec.loader.exec_module(module)
    return module


def parse_args(argv):
    parser = argparse.ArgumentParser(prog="phong", description=__doc__.split("\n\n")[0])
    parser.add_argument("--out", default="out/demo", help="output folder (default: out/demo)")
    parser.add_argument("--resolution", type=int, default=256, help="square image size in pixels")
    parser.add_argument("--engines", default="cycles,eevee", help="comma-separated: cycles, eevee")
    parser.add_argument("--samples", type=int, default=16, help="samples per pixel (anti-aliasing)")
    args = parser.parse_args(argv)
    engines = [e.strip().lower() for e in args.engines.split(",") if e.strip()]
    unknown = sorted(set(engines) - {"cycles", "eevee"})
    if unknown or not engines:
        parser.error(f"--engines: unknown engine(s) {', '.join(unknown) or '(none given)'}; "
                     "expected cycles and/or eevee")
    if not 8 <= args.resolution <= 4096:
        parser.error(f"--resolution must be between 8 and 4096, got {args.resolution}")
    if args.samples < 1:
        parser.error(f"--samples must be at least 1, got {args.samples}")
    args.engines = engines
    return args


def main(argv=None) -> int:
    args = parse_args(sys.argv[1:] if argv is None else argv)
    out = os.path.abspath(args.out)
    try:
        os.makedirs(out, exist_ok=True)
        probe = os.path.join(out, ".write-test")
        open(probe, "w").close()
        os.remove(probe)
    except OSError as error:
        print(f"phong: cannot write to output folder {out}: {error.strerror}", file=sys.stderr)
        return 2

    import bpy  # noqa: F401  (after argument checks: importing bpy takes a second)

    phong = import_extension()
    phong.register()
    from phong_nodes.addon import demo

    scene = demo.build_scene(args.resolution)
    paths = {}
    for engine in args.engines:
        path = os.path.join(out, f"sphere_{engine}.png")
        start = time.perf_counter()
        demo.render(scene, engine.upper(), path, samples=args.samples)
        paths[engine] = path
        print(f"{engine:>6}: {path}  ({time.perf_counter() - start:.1f} s)")
    if len(paths) == 2:
        import numpy as np
        a, b = (np.asarray(_read_png(p), dtype=np.float64) for p in paths.values())
        diff = np.abs(a - b)
        print(f"Eevee vs Cycles: mean |difference| {diff.mean():.2f}/255, max {diff.max():.0f}/255")
    phong.unregister()
    return 0


def _read_png(path):
    import OpenImageIO as oiio

    buf = oiio.ImageBuf(path)
    return buf.get_pixels(oiio.UINT8)


def exit_process(code: int) -> None:
    """Exit with *code*.  The bpy 4.x module can crash in its own clean-up at interpreter
    exit after an Eevee render (seen with 4.2.23), turning success into signal 11: once our
    files are written and closed, leave without running it."""
    sys.stdout.flush()
    sys.stderr.flush()
    bpy = sys.modules.get("bpy")
    if bpy is not None and bpy.app.version < (5, 0, 0):
        os._exit(code)
    sys.exit(code)


if __name__ == "__main__":
    exit_process(main())
