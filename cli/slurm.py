# SPDX-License-Identifier: GPL-3.0-or-later
"""Submit a comparison run to Slurm as a job array and a final check.

    phong slurm [--tasks N] [--wait] [sbatch options] -- demo [options]
    phong slurm [--tasks N] [--wait] [sbatch options] -- compare FILE.blend [options]
    phong slurm [--tasks N] [--wait] [sbatch options] -- bake FILE.blend --target T [options]

Submits (1) an array of N tasks (``--array=0-<N-1>``, default 4), each running the command
with ``--shard auto``: task i bakes every N-th scene from the (i+1)-th into the one output
folder; (2) a check job, ``--dependency=afterany`` on the array: ``report DIR``, which rebuilds
DIR/index.html from the finished scene folders and fails naming the scenes missing or failed.
``afterany`` so the check also runs, and says what is missing, when a task failed.  Other
options before ``--`` (``--partition=...``, ``--time=...``, ``--mem=...``, ``--account=...``)
go to both sbatch calls as given.  Task logs go to DIR/slurm-logs/ unless ``--output`` is given.
``--wait`` waits for the check and exits with its code (0: the run is whole).

The command is checked before anything is submitted (bad options, scene files: exit 2).  The
tasks run this environment's Python (the submitting one) as ``-m phong_nodes.cli``: on a cluster the
checkout and its environment must be on a filesystem every node sees, and so must DIR.
A task killed or lost is run again with ``scontrol requeue <job>_<index>`` (or
``sbatch --array=<index>`` of the same command with ``--shard auto/N``); a requeued task
removes what the killed one left (same host) and skips nothing: then run ``report DIR``.
"""

from __future__ import annotations

import os
import shlex
import shutil
import subprocess
import sys

from ..core import outputs, scenes
from .args import SubmitError

#: How a task runs phong: this environment's Python on the package (no path to a script).
PHONG = ("-m", "phong_nodes.cli")


def check_command(command, args) -> int | None:
    """The number of scenes of a demo run (SubmitError for a bad scene file); None for
    compare and bake (their scenes are known once Blender reads the file)."""
    if command and command[0] in ("compare", "bake"):
        if not os.path.isfile(args.file):
            raise SubmitError(f"{args.file}: no such file")
        return None
    try:
        return len(scenes.load_all(scenes.resolve(args.scenes)))
    except scenes.SceneError as error:
        raise SubmitError(str(error)) from None


def _given(flags, *names) -> bool:
    return any(f.split("=")[0] in names for f in flags)


def sbatch(flags, script: str, wait: bool = False) -> tuple:
    """Submit *script* (on stdin); (job id, completed process)."""
    command = ["sbatch", "--parsable", *flags] + (["--wait"] if wait else [])
    done = subprocess.run(command, input=script, capture_output=True, text=True, check=False)
    job = done.stdout.strip().split(";")[0].splitlines()[0] if done.stdout.strip() else ""
    if not job.isdigit():
        last = (done.stderr.strip() or done.stdout.strip() or "no output").splitlines()[-1]
        raise SubmitError(f"sbatch failed ({' '.join(command)}): {last}")
    return job, done


def script(*words) -> str:
    return "#!/bin/bash\n# submitted by phong slurm\nexec " + shlex.join(words) + "\n"


def main(own) -> int:
    """``phong slurm`` with its parsed options (``args.parse_slurm``)."""
    flags, command, args = own.flags, own.farm, own.farm_args
    try:
        count = check_command(command, args)
        if shutil.which("sbatch") is None:
            raise SubmitError("sbatch not found: run this where Slurm's commands work (a "
                              "login node), or start a one-node cluster with phong cluster "
                              "start DIR")
        out = os.path.abspath(args.out)
        problem = outputs.output_problem(out, refuse_package=False)
        if problem:
            raise SubmitError(problem)
        logs = os.path.join(out, "slurm-logs")
        os.makedirs(logs, exist_ok=True)
        python = sys.executable
        task_flags = list(flags)
        if not _given(flags, "-J", "--job-name"):
            task_flags.append("--job-name=phong")
        if not _given(flags, "-o", "--output"):
            task_flags.append(f"--output={os.path.join(logs, '%x-%A_%a.log')}")
        array, _ = sbatch([f"--array=0-{own.tasks - 1}", *task_flags],
                          script(python, *PHONG, *command, "--out", out, "--shard", "auto"))
        check_flags = [f for f in flags if f.split("=")[0] not in ("-o", "--output")]
        check_flags += [f"--dependency=afterany:{array}", "--job-name=phong-check",
                        f"--output={os.path.join(logs, '%x-%j.log')}"]
        print(f"phong slurm: array job {array} ({own.tasks} tasks, --shard auto"
              f"{f', {count} scene(s)' if count is not None else ''}) -> {out}; "
              f"logs in {logs}", flush=True)
        if count is not None and own.tasks > count:
            print(f"phong slurm: {own.tasks - count} of the {own.tasks} tasks have no scene "
                  "to bake", flush=True)
        if own.wait:
            print("phong slurm: waiting for the check job (report after every task)...",
                  flush=True)
        check, done = sbatch(check_flags, script(python, *PHONG, "report", out), wait=own.wait)
        print(f"phong slurm: check job {check}: report {out} once every task has ended; "
              f"a task killed or lost: scontrol requeue {array}_<index>, then "
              f"phong report {out}", flush=True)
    except SubmitError as error:
        print(f"phong slurm: {error}", file=sys.stderr)
        return 2
    if not own.wait:
        return 0
    log = os.path.join(logs, f"phong-check-{check}.log")
    if os.path.exists(log):
        with open(log, encoding="utf-8", errors="replace") as handle:
            print(handle.read().rstrip())
    return done.returncode

