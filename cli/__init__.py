# SPDX-License-Identifier: GPL-3.0-or-later
"""``phong``, the command line of Phong Nodes (installed by ``pip install -e .``; also
``python -m phong_nodes.cli``): headless Blender through the ``bpy`` module.

* ``args``      every subcommand and option (one argparse parser);
* ``runs``      demo, compare and report; ``bake``: Bake Phong Lighting and glTF;
  ``apply``: Apply Phong Material on every scene of a .blend, written as a new file;
* ``slurm``     a run as a Slurm job array; ``cluster``: a one-node cluster to try it;
* ``inputs``    scene files (.blend, or imported by the extension's importers), peers;
* ``terminal``  interrupts, our own lines beside Blender's log, exit without a crash;
* ``system``    the Debian packages bpy, the browser peer and the cluster need (standard
  library only: ``python3 cli/system.py`` runs before any environment exists).

Not part of the Blender extension (the zip leaves ``cli/`` out); it imports the extension's
packages relatively, as they import each other.
"""

from __future__ import annotations

import sys


def main(argv=None) -> int:
    """Run ``phong`` with *argv* (default: the process's arguments); returns the exit code."""
    from . import args as args_mod  # noqa: PLC0415

    argv = sys.argv[1:] if argv is None else list(argv)
    try:
        args = args_mod.parse(argv)
    except args_mod.SubmitError as error:
        print(f"phong slurm: {error}", file=sys.stderr)
        return 2
    command = args.command
    if command == "which":
        return _which()
    if command == "cluster":
        from . import cluster  # noqa: PLC0415

        return cluster.main([args.action, args.dir])
    if command == "slurm":
        from . import slurm  # noqa: PLC0415

        return slurm.main(args)
    if command == "report":
        from . import runs  # noqa: PLC0415

        return runs.report_main(args)
    from .terminal import run_interruptible  # noqa: PLC0415

    state = {"done": 0, "total": 0}
    if command == "bake":
        from . import bake  # noqa: PLC0415

        return run_interruptible(lambda: bake.run(args, state), state)
    if command == "apply":
        from . import apply  # noqa: PLC0415

        return run_interruptible(lambda: apply.run(args, state), state)
    from . import runs  # noqa: PLC0415

    return run_interruptible(lambda: runs.run(args, state), state)


def _which() -> int:
    from importlib import metadata  # noqa: PLC0415

    try:
        release = f"bpy {metadata.version('bpy')}"
    except metadata.PackageNotFoundError:
        release = "no bpy in this environment"
    print(f"{release} on Python {sys.version.split()[0]} ({sys.executable})")
    return 0


def console() -> None:
    """The ``phong`` console script."""
    from .terminal import exit_process  # noqa: PLC0415

    exit_process(main())
