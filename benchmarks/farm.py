#!/usr/bin/env python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""The demo run on a Slurm job array (issue 21): one task against two concurrent tasks, and
what the scheduler costs per task.  Needs root and Debian's Slurm packages: it starts its own
one-node cluster (phong cluster, cli/cluster.py) in a temporary folder and stops it at the end.

    .venv/bin/python benchmarks/farm.py              # ~4 min on a 2-core CPU
    .venv/bin/python benchmarks/farm.py --repeats 1 --resolution 32

Measured side by side in each repeat (the order rotates from repeat to repeat), every case
the same demo run (the eight scenes in the seeds' model, Cycles and Eevee) into a fresh
folder, wall time from the start (``sbatch`` called) to the end (the array gone from
``squeue``, polled every 0.1 s; for direct runs, the processes' exit):

* ``slurm 1 task``: ``sbatch --array=0-0``, the task runs ``--shard auto`` = 1/1;
* ``slurm 2 tasks``: ``sbatch --array=0-1``, two tasks at once on the two cores;
* ``direct 1``, ``direct 2``: the same commands started directly (``--shard 1/1``; ``1/2`` and
  ``2/2`` at once), no scheduler, each in a session of its own as Slurm starts its tasks;
* ``slurm 8 empty tasks``: ``sbatch --array=0-7 --wrap true``: the scheduler alone.

Figures: two tasks / one task (Slurm); scheduler overhead per task = slurm 1 task − direct 1
(submit, start, end of one task), and the 8 empty tasks' wall time / 8.
Writes ``benchmarks/farm_results.json`` and prints a Markdown table.
"""

from __future__ import annotations

import argparse
import importlib.metadata
import json
import os
import platform
import shlex
import statistics
import subprocess
import sys
import tempfile
import time

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)
#: The `phong` command of this environment.
PHONG = [sys.executable, "-m", "phong_nodes.cli"]
SCENES = ("color_product", "exponents", "four_terms", "lambert_vs_phong", "point_falloff",
          "spot_edges", "textured", "two_lights")


def _env(cluster, tmp):
    env = {k: v for k, v in cluster.env.items() if not k.startswith("SLURM_") or
           k == "SLURM_CONF"}
    env["BLENDER_USER_RESOURCES"] = os.path.join(tmp, "user")
    return env


def phong_command(args, out, shard):
    return [*PHONG, "demo", "--scenes", ",".join(SCENES), "--resolution",
            str(args.resolution), "--engines", "cycles,eevee", "--out", out, "--shard", shard]


def slurm_run(cluster, env, tasks, command, logs) -> float:
    """Wall seconds from sbatch to the array gone from squeue."""
    t0 = time.perf_counter()
    job = subprocess.run(["sbatch", "--parsable", f"--array=0-{tasks - 1}",
                          f"--output={logs}/%A_%a.log", "--wrap", command],
                         capture_output=True, text=True, env=env, check=True
                         ).stdout.strip().split(";")[0]
    while True:
        left = subprocess.run(["squeue", "-h", "-j", job], capture_output=True, text=True,
                              env=env, check=False).stdout.strip()
        if not left:
            return time.perf_counter() - t0
        time.sleep(0.1)


def direct_run(env, commands) -> float:
    t0 = time.perf_counter()
    # Each in a session of its own, as Slurm starts its tasks: with Linux's autogroup
    # scheduling a session shares the CPUs with other sessions as one, so two processes of
    # one session on a busy machine get the share of one.
    children = [subprocess.Popen(c, env=env, stdout=subprocess.DEVNULL,
                                 stderr=subprocess.DEVNULL, start_new_session=True)
                for c in commands]
    codes = [c.wait() for c in children]
    if any(codes):
        raise RuntimeError(f"a direct run failed: exit codes {codes}")
    return time.perf_counter() - t0


def measure(args) -> dict:
    from phong_nodes.cli import cluster as tool  # noqa: PLC0415
    problem = tool.unavailable()
    if problem:
        sys.exit(f"farm benchmark: {problem}")
    with tempfile.TemporaryDirectory(prefix="phong-farm-") as tmp:
        cluster = tool.Cluster(os.path.join(tmp, "cluster"))
        cluster.start()
        try:
            env = _env(cluster, tmp)
            runs = {"slurm 1 task": [], "slurm 2 tasks": [], "direct 1": [], "direct 2": [],
                    "slurm 8 empty tasks": []}
            counter = [0]

            def fresh():
                counter[0] += 1
                out = os.path.join(tmp, f"run{counter[0]}")
                os.makedirs(os.path.join(out, "logs"))
                return out

            def case(name):
                out = fresh()
                logs = os.path.join(out, "logs")
                if name == "slurm 8 empty tasks":
                    return slurm_run(cluster, env, 8, "true", logs)
                if name.startswith("slurm"):
                    tasks = int(name.split()[1])
                    command = shlex.join(phong_command(args, out, "auto"))
                    seconds = slurm_run(cluster, env, tasks, command, logs)
                else:
                    n = int(name.split()[1])
                    seconds = direct_run(env, [phong_command(args, out, f"{i}/{n}")
                                               for i in range(1, n + 1)])
                check = subprocess.run([*PHONG, "report", out],
                                       capture_output=True, text=True, env=env, check=False)
                if check.returncode != 0:
                    raise RuntimeError(f"{name}: the run is not whole: {check.stdout[-500:]}")
                return seconds

            names = list(runs)
            case("direct 1")  # warm-up: file caches, Python bytecode, Mesa
            for repeat in range(args.repeats):
                order = names[repeat % len(names):] + names[:repeat % len(names)]
                for name in order:
                    runs[name].append(case(name))
                    print(f"  repeat {repeat + 1}: {name}: {runs[name][-1]:.2f} s", flush=True)
        finally:
            cluster.stop()
    return runs


def figures(runs: dict) -> list:
    med = {k: statistics.median(v) for k, v in runs.items()}

    def spread(values):
        return f"{min(values):.2f}–{max(values):.2f}"

    overhead = [a - b for a, b in zip(runs["slurm 1 task"], runs["direct 1"])]
    return [
        ("Two tasks at once / one task (Slurm, 2 cores)",
         f"{med['slurm 2 tasks'] / med['slurm 1 task']:.2f}×",
         f"{med['slurm 2 tasks']:.2f} ({spread(runs['slurm 2 tasks'])}) s vs "
         f"{med['slurm 1 task']:.2f} ({spread(runs['slurm 1 task'])}) s"),
        ("The same without a scheduler: two processes / one",
         f"{med['direct 2'] / med['direct 1']:.2f}×",
         f"{med['direct 2']:.2f} ({spread(runs['direct 2'])}) s vs "
         f"{med['direct 1']:.2f} ({spread(runs['direct 1'])}) s"),
        ("Scheduler overhead of one task: Slurm 1 task − direct 1",
         f"{statistics.median(overhead):.2f} s",
         f"spread {min(overhead):.2f}–{max(overhead):.2f} s (submit, start, end seen by squeue)"),
        ("Scheduler alone: 8 empty tasks (2 at a time) / 8",
         f"{med['slurm 8 empty tasks'] / 8:.2f} s",
         f"{med['slurm 8 empty tasks']:.2f} ({spread(runs['slurm 8 empty tasks'])}) s for 8"),
    ]


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--repeats", type=int, default=3)
    parser.add_argument("--resolution", type=int, default=128)
    parser.add_argument("--json", default=os.path.join(HERE, "farm_results.json"))
    args = parser.parse_args(argv)
    load_before = os.getloadavg()
    t0 = time.perf_counter()
    runs = measure(args)
    rows = figures(runs)
    lines = ["| figure | median | detail |", "|---|---|---|"]
    lines += [f"| {a} | {b} | {c} |" for a, b, c in rows]
    about = (f"{args.repeats} repeats; {len(SCENES)} scenes at {args.resolution} px high, "
             f"Cycles and Eevee; {os.cpu_count()} CPUs; load average {load_before} before, "
             f"{os.getloadavg()} after; run took {time.perf_counter() - t0:.0f} s")
    print("\n".join(lines) + "\n\n" + about)
    with open(args.json, "w", encoding="utf-8") as handle:
        json.dump({"runs_s": runs, "figures": rows, "scenes": SCENES,
                   "resolution": args.resolution, "repeats": args.repeats,
                   "cpus": os.cpu_count(), "load_before": load_before,
                   "load_after": os.getloadavg(), "python": platform.python_version(),
                   "bpy": importlib.metadata.version("bpy")},
                  handle, indent=1)
        handle.write("\n")
    return 0


if __name__ == "__main__":
    sys.exit(main())
