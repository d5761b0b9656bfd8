# SPDX-License-Identifier: GPL-3.0-or-later
"""The command line of ``phong``: every subcommand and option, in one argparse parser.

    phong demo    [--scenes a,b|all] [--engines cycles,eevee] [--resolution N] [--out DIR]
                  [--shard i/n|auto] [--peers threejs,x_ite] [--save-blend]
    phong compare FILE [--scenes a,b] [--engines ...] [--resolution N] [--out DIR]
                  [--shard i/n|auto] [--peers threejs,x_ite] [--apply]
                  (FILE: a .blend, or a file an importer reads: core/suffixes.py)
    phong apply   FILE.blend -o OUT.blend [--scenes a,b]
    phong bake    FILE.blend --target image|vertex [--term T] [--view camera|none] [--scenes a,b]
                  [--resolution N] [--format png|exr] [--smart-uv] [--out DIR] [--shard i/n]
                  [--peers threejs] [--check-height N]
    phong report  DIR
    phong slurm   [--tasks N] [--wait] [sbatch options] -- demo|compare|bake ...
    phong cluster start|stop DIR
    phong which

Parsing writes nothing and imports no ``bpy``: a bad option exits 2 with argparse's message.
"""

from __future__ import annotations

import argparse

from ..core import scenes, suffixes

DEFAULT_RESOLUTION = 256
ENGINES = ("cycles", "eevee")
PEERS = ("threejs", "x_ite")
#: The peers of ``bake --peers``: the glTF check runs in three.js only.
BAKE_PEERS = ("threejs",)
TARGETS = ("image", "vertex")
TERMS = ("color", "irradiant", "ambient", "diffuse", "specular")
VIEWS = ("camera", "none")
#: The commands a Slurm array task can run (``phong slurm -- ...``).
FARM_COMMANDS = ("demo", "compare", "bake")
SLURM_USAGE = ("phong slurm [--tasks N] [--wait] [sbatch options] -- demo|compare|bake ... "
               "(see phong slurm --help)")
SLURM_SET_BY_US = ("-a", "--array", "-d", "--dependency", "-W")


class SubmitError(Exception):
    """``phong slurm``: exit 2 with this one line; nothing was submitted."""


def _engines(text: str) -> list:
    engines = [e.strip().lower() for e in text.split(",") if e.strip()]
    unknown = sorted(set(engines) - set(ENGINES))
    if unknown or not engines:
        raise argparse.ArgumentTypeError(
            f"unknown engine(s) {', '.join(unknown) or '(none given)'}; expected cycles "
            "and/or eevee")
    return engines


def _peers(text: str, known=PEERS) -> list:
    peers = [p.strip().lower() for p in text.split(",") if p.strip()]
    unknown = sorted(set(peers) - set(known))
    if unknown:
        raise argparse.ArgumentTypeError(f"unknown peer(s) {', '.join(unknown)}; expected "
                                         + " and/or ".join(known))
    return peers


def _bake_peers(text: str) -> list:
    return _peers(text, BAKE_PEERS)


def _comparison_options(parser, resolution_default, resolution_help, out_default) -> None:
    parser.add_argument("--engines", type=_engines, default=list(ENGINES),
                        help="comma-separated: cycles, eevee (default: both)")
    parser.add_argument("--resolution", type=int, default=resolution_default,
                        help=resolution_help)
    parser.add_argument("--out", default=out_default,
                        help=f"output folder (default: {out_default})")
    parser.add_argument("--shard", default=None, help=scenes.SHARD_HELP)
    parser.add_argument("--peers", type=_peers, default=[],
                        help="other renderers to compare, comma-separated: threejs (exports "
                             "each scene as a three.js page and renders it in headless "
                             "Chromium), x_ite (exports each scene as X3D and renders it with "
                             "the X3D browser X_ITE in headless Chromium)")


def parser() -> argparse.ArgumentParser:
    top = argparse.ArgumentParser(
        prog="phong", description="Phong Nodes on the command line (headless Blender, the "
        "bpy module): demo scenes and any scene file rendered by Eevee and Cycles and checked "
        "against the numpy reference of the formulas; bakes; Slurm job arrays.")
    sub = top.add_subparsers(dest="command", required=True, metavar="COMMAND")

    demo = sub.add_parser(
        "demo", help="build the seed figures (scenes/*.toml) as live scenes and compare them",
        description="Build every demo scene of scenes/*.toml (or those named) as an ordinary "
        "Blender scene and compare Eevee and Cycles with the reference; DIR/index.html covers "
        "every scene folder of DIR.")
    demo.add_argument("--scenes", default="all",
                      help="comma-separated scene names or .toml paths (default: all)")
    demo.add_argument("--save-blend", action="store_true",
                      help="keep each built scene as DIR/<scene>/<scene>.blend")
    _comparison_options(demo, DEFAULT_RESOLUTION,
                        f"picture height in pixels (default: {DEFAULT_RESOLUTION})", "out/demo")

    compare = sub.add_parser(
        "compare", help="compare the scenes of a .blend (or an imported "
        f"{', '.join(suffixes.importable_suffixes())} file) with the reference",
        description="Compare every scene of a .blend that has Phong materials (or a file "
        f"imported as Phong: {suffixes.importable_text()}) with the numpy reference of the "
        "formulas.")
    compare.add_argument("file", help="the .blend file, or a file of another program: "
                         f"{', '.join(suffixes.importable_suffixes())} (.gz: gzipped X3D or "
                         "VRML97)")
    compare.add_argument("--scenes", default=None,
                         help="comma-separated scene names of the file (default: every scene "
                              "with Phong materials)")
    _comparison_options(compare, None, "picture height in pixels (default: each scene's own "
                        "size)", "out/compare")
    compare.add_argument("--apply", action="store_true",
                         help="first give every object that renders with materials Phong "
                              "materials (as phong apply does; in memory, the file is not "
                              "written), then compare")

    apply = sub.add_parser(
        "apply", help="give every object of a .blend that renders with materials Phong "
        "materials, written as a new .blend",
        description="Apply Phong Material on every scene of a .blend (or those named): every "
        "object that renders with materials gets Phong materials driven by the scene's "
        "lights; a report says what was converted and what not. OUT.blend is written whole "
        "or not at all; the input file is never written.")
    apply.add_argument("file", help="the .blend file")
    apply.add_argument("-o", "--output", required=True, metavar="OUT.blend",
                       help="the .blend to write (not the input file)")
    apply.add_argument("--scenes", default=None,
                       help="comma-separated scene names of the file (default: every scene)")

    bake = sub.add_parser(
        "bake", help="bake Phong lighting of a .blend into textures or vertex colours, write glTF",
        description="Bake Phong Lighting on every scene of a .blend with Phong materials and "
        "write glTF with the bake (KHR_materials_unlit).")
    bake.add_argument("file", help="the .blend file")
    bake.add_argument("--target", required=True, choices=TARGETS,
                      help="image: an image per object (UV map needed); vertex: a colour "
                           "attribute per vertex (Gouraud shading)")
    bake.add_argument("--term", default="color", choices=TERMS,
                      help="the Phong colour (default) or one term")
    bake.add_argument("--view", default="camera", choices=VIEWS,
                      help="camera: the specular as the scene camera sees it (default); none: "
                           "without specular")
    bake.add_argument("--scenes", default=None,
                      help="comma-separated scene names (default: every scene with Phong "
                           "materials)")
    bake.add_argument("--resolution", type=int, default=1024,
                      help="image width and height in pixels (target image; default 1024)")
    bake.add_argument("--format", default="png", choices=("png", "exr"),
                      help="png: 8-bit sRGB (default); exr: 32-bit float linear")
    bake.add_argument("--smart-uv", action="store_true",
                      help="give objects without a UV map a Smart UV Project")
    bake.add_argument("--out", default="out/bake", help="output folder (default: out/bake)")
    bake.add_argument("--shard", default=None, help=scenes.SHARD_HELP)
    bake.add_argument("--peers", type=_bake_peers, default=[],
                      help="threejs: check the .glb in three.js's GLTFLoader (headless "
                           "Chromium) against Cycles rendering the baked scene")
    bake.add_argument("--check-height", type=int, default=256,
                      help="picture height of the check in pixels (default 256)")

    report = sub.add_parser(
        "report", help="rebuild DIR/index.html and check that a (sharded) run is whole",
        description="Rebuild DIR/index.html from the finished scene folders and check the run "
        "(demo, compare or bake): exit 0 when every scene of DIR/run.json is there and matches "
        "(bake: is baked and exported, and its glTF check passed), 1 naming those missing or "
        "failed, 2 when DIR is not a run's folder.")
    report.add_argument("dir", help="the output folder of a run (its --out)")

    slurm = sub.add_parser(
        "slurm", usage=SLURM_USAGE, add_help=False,
        help="submit demo, compare or bake as a Slurm job array and a final check",
        description="Submit the command after '--' as a Slurm job array (each task "
        "--shard auto) and a check job (report DIR) after it; other options before '--' go "
        "to sbatch as given.")
    slurm.add_argument("-h", "--help", action="store_true", help="show this help and exit")
    slurm.add_argument("--tasks", type=int, default=4,
                       help="number of array tasks (shards), default 4")
    slurm.add_argument("--wait", action="store_true",
                       help="wait for the check job and exit with its code")

    cluster = sub.add_parser(
        "cluster", help="start or stop a throwaway one-node Slurm cluster (root, Debian's "
        "Slurm and MUNGE)", description="start DIR prints DIR/slurm.conf: export "
        "SLURM_CONF=$(phong cluster start DIR); stop DIR cancels its jobs and stops its "
        "daemons.")
    cluster.add_argument("action", choices=("start", "stop"))
    cluster.add_argument("dir", help="the cluster's folder (its key, config, state and logs)")

    sub.add_parser("which", help="print the Blender (bpy) release and Python this command runs")
    return top


def parse(argv) -> argparse.Namespace:
    """The parsed command line; exits 2 with argparse's message on a bad option."""
    argv = list(argv)
    if argv and argv[0] == "slurm":
        return parse_slurm(argv[1:])
    top = parser()
    args = top.parse_args(argv)
    sub = top._subparsers._group_actions[0].choices[args.command]  # noqa: SLF001
    _check(sub, args)
    return args


def _check(sub, args) -> None:
    """Range checks argparse's types cannot say, and --shard auto resolved."""
    if args.command in ("demo", "compare"):
        if args.resolution is not None and not 8 <= args.resolution <= 4096:
            sub.error(f"--resolution must be between 8 and 4096, got {args.resolution}")
    if args.command == "bake":
        if not 8 <= args.resolution <= 16384:
            sub.error(f"--resolution must be between 8 and 16384, got {args.resolution}")
        if not 8 <= args.check_height <= 4096:
            sub.error(f"--check-height must be between 8 and 4096, got {args.check_height}")
    if args.command in FARM_COMMANDS:
        try:
            args.shard, args.shard_source = scenes.resolve_shard(args.shard)
        except scenes.SceneError as error:
            sub.error(str(error))


def parse_slurm(argv) -> argparse.Namespace:
    """``phong slurm``: its own options, the sbatch flags (``.flags``) and the command after
    '--' (``.farm``: its words, ``.farm_args``: parsed as that command); SubmitError for what
    phong slurm sets itself or refuses."""
    top = parser()
    slurm = top._subparsers._group_actions[0].choices["slurm"]  # noqa: SLF001
    if "--" not in argv:
        if any(a in ("-h", "--help") for a in argv):
            slurm.print_help()
            raise SystemExit(0)
        raise SubmitError(f"expected the command after '--': {SLURM_USAGE}")
    cut = argv.index("--")
    own, flags = slurm.parse_known_args(argv[:cut])
    own.command = "slurm"
    if own.tasks < 1:
        raise SubmitError(f"--tasks must be at least 1, got {own.tasks}")
    for flag in flags:
        if flag.split("=")[0] in SLURM_SET_BY_US:
            raise SubmitError(f"{flag}: set by phong slurm itself (--tasks N gives the array)")
    farm = argv[cut + 1:]
    if farm and farm[0] == "apply":
        raise SubmitError("apply writes one .blend, which an array's tasks cannot share: run "
                          "phong apply itself (compare --apply runs as an array)")
    if farm and farm[0] == "report":
        raise SubmitError("the command is demo, compare or bake; the check job runs report "
                          "itself")
    if not farm or farm[0] not in FARM_COMMANDS:
        farm = ["demo", *farm]
    if any(a == "--shard" or a.startswith("--shard=") for a in farm):
        raise SubmitError("leave out --shard: each task takes its shard from the array "
                          "(--shard auto)")
    own.flags, own.farm, own.farm_args = flags, farm, parse(farm)
    return own
