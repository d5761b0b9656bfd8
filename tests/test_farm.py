# SPDX-License-Identifier: GPL-3.0-or-later
"""Render farms: ``--shard auto`` from a scheduler's variables, the completeness check
(``report DIR``), the summary table, ``phong slurm``'s own checks, and a run on a real
one-node Slurm cluster (phong cluster, cli/cluster.py) with one task killed mid-scene and requeued.

The Slurm test needs root and Debian's ``slurmctld slurmd slurm-client munge``: it skips
with its reason elsewhere, except under CI (``CI`` set), where it fails: CI must run it.  It
runs once per CI run, with the default bpy: it skips when ``PHONG_BPY`` picks another release
(the farm code is the same Python on every release)."""

import json
import os
import re
import shutil
import signal
import subprocess
import sys
import time

import pytest

import blender_env as be
from phong_nodes.core import scenes

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
#: The `phong` command of this environment (what tools/phong.sh runs).
PHONG = [sys.executable, "-m", "phong_nodes.cli"]
#: Four scenes for four tasks; the longest scene name of the shipped ones among them.
FARM_SCENES = ("threejs_point_cutoff", "lambert_vs_phong", "two_lights", "color_product")


def run(tmp_path, *args, env=None, timeout=300):
    env = {**os.environ, "BLENDER_USER_RESOURCES": str(tmp_path / "user"), **(env or {})}
    for name in [k for k in env if k.startswith("SLURM_") and k != "SLURM_CONF"]:
        del env[name]  # the test itself may run inside a Slurm job
    env.pop("JOB_COMPLETION_INDEX", None)
    return subprocess.run([*PHONG, *args], capture_output=True, text=True, env=env,
                          timeout=timeout)


# -- --shard auto -----------------------------------------------------------------------

def slurm_env(task, count, low=0):
    return {"SLURM_ARRAY_TASK_ID": str(task), "SLURM_ARRAY_TASK_COUNT": str(count),
            "SLURM_ARRAY_TASK_MIN": str(low), "SLURM_ARRAY_TASK_MAX": str(low + count - 1)}


def test_shard_auto_maps_every_array_task_to_one_shard():
    items = list(range(10))
    for low in (0, 1):  # --array=0-3 and --array=1-4
        parts = []
        for task in range(low, low + 4):
            spec, source = scenes.resolve_shard("auto", slurm_env(task, 4, low))
            assert spec == f"{task - low + 1}/4"
            assert f"SLURM_ARRAY_TASK_ID={task}" in source
            parts.append(scenes.shard(items, spec))
        assert sorted(sum(parts, [])) == items, "every item in exactly one shard"
    # Kubernetes Indexed Job: the index, the count given
    assert scenes.resolve_shard("auto/3", {"JOB_COMPLETION_INDEX": "2"})[0] == "3/3"
    # one array task resubmitted alone (sbatch --array=2): the count given, the id as is
    alone = {"SLURM_ARRAY_TASK_ID": "2", "SLURM_ARRAY_TASK_COUNT": "1",
             "SLURM_ARRAY_TASK_MIN": "2", "SLURM_ARRAY_TASK_MAX": "2"}
    assert scenes.resolve_shard("auto/4", alone)[0] == "3/4"
    assert scenes.resolve_shard("2/5", {}) == ("2/5", "")
    assert scenes.resolve_shard(None, slurm_env(1, 4)) == (None, "")


@pytest.mark.parametrize("spec, environ, message", [
    ("auto", {}, "no scheduler index in the environment"),
    ("auto", {"JOB_COMPLETION_INDEX": "1"}, "use --shard auto/N"),
    ("auto/2", {"JOB_COMPLETION_INDEX": "2"}, "JOB_COMPLETION_INDEX=2 is outside 0..1"),
    ("auto", {"SLURM_ARRAY_TASK_ID": "x", "SLURM_ARRAY_TASK_COUNT": "4"},
     "SLURM_ARRAY_TASK_ID='x' is not a whole number"),
    ("auto", {"SLURM_ARRAY_TASK_ID": "4", "SLURM_ARRAY_TASK_COUNT": "3",
              "SLURM_ARRAY_TASK_MIN": "0", "SLURM_ARRAY_TASK_MAX": "8"},
     "the Slurm array 0-8 has 3 task(s)"),
    ("auto/0", {"JOB_COMPLETION_INDEX": "0"}, "N must be at least 1"),
    ("autox", {}, "expected i/n"),
])
def test_shard_auto_refuses_with_one_clear_line(spec, environ, message):
    with pytest.raises(scenes.SceneError) as info:
        scenes.resolve_shard(spec, environ)
    assert message in str(info.value) and "\n" not in str(info.value)


def test_cli_shard_auto_without_a_scheduler_exits_2_and_writes_nothing(tmp_path):
    out = tmp_path / "out"
    result = run(tmp_path, "demo", "--shard", "auto", "--out", str(out))
    assert result.returncode == 2
    assert "--shard auto: no scheduler index" in result.stderr
    assert "Traceback" not in result.stderr and not out.exists()


# -- the summary table --------------------------------------------------------------------

def test_summary_table_keeps_its_columns_for_long_scene_names():
    from phong_nodes.cli import runs as phong  # noqa: PLC0415
    pair = {"max_abs": 1e-6, "mean_abs": 1e-8, "psnr_db": 140.0, "share_over_1_255": 0.0}
    ok = {"ok": True}
    results = [{"scene": name, "verdict": {"cycles": ok, "eevee": ok, "threejs": ok},
                "pairs": {"cycles-reference": pair, "eevee-reference": pair,
                          "threejs-cycles": pair}}
               for name in ("a", "threejs_point_cutoff", "a_scene_name_of_forty_characters__")]
    header, rule, *rows = phong.summary_table(results)
    starts = [header.index("pair"), header.index("max |d|")]
    for row in rows:
        scene, pair_name = row.split()[:2]
        assert row.index(pair_name) == starts[0], row  # the pair column starts in one place
        assert row[starts[0] - 1] == " " and row[starts[1] - 2] == " ", row
    assert "threejs_point_cutoff  eevee-reference" in "\n".join(phong.summary_table(results[:2]))


# -- the completeness check on real runs ----------------------------------------------------

@pytest.mark.slow
@pytest.mark.cycles
def test_report_finds_a_deleted_scene_folder_and_an_empty_shard(tmp_path):
    out = tmp_path / "run"
    names = "lambert_vs_phong,two_lights"
    # shard 3/3 of two scenes has nothing to bake: it still records the run
    empty = run(tmp_path, "demo", "--scenes", names, "--engines", "cycles", "--resolution", "16",
                "--shard", "3/3", "--out", str(out))
    assert empty.returncode == 0, empty.stderr[-2000:]
    assert json.loads((out / "run.json").read_text())["scenes"] == names.split(",")
    check = run(tmp_path, "report", str(out))
    assert check.returncode == 1
    assert "missing lambert_vs_phong, two_lights" in check.stdout
    for part in ("1/3", "2/3"):
        result = run(tmp_path, "demo", "--scenes", names, "--engines", "cycles", "--resolution", "16",
                     "--shard", part, "--out", str(out))
        assert result.returncode == 0, result.stderr[-2000:]
    check = run(tmp_path, "report", str(out))
    assert check.returncode == 0, check.stdout + check.stderr
    assert "complete: 2 of 2 scene(s)" in check.stdout
    assert "two_lights" in check.stdout.split("phong report")[0], "the summary table"
    shutil.rmtree(out / "two_lights")
    check = run(tmp_path, "report", str(out))
    assert check.returncode == 1 and "missing two_lights" in check.stdout
    page = (out / "index.html").read_text()
    assert "two_lights/sheet.png" not in page and "lambert_vs_phong/sheet.png" in page
    assert "INCOMPLETE: 1 of 2 scene(s)" in page
    # a metrics.json cut short counts as failed, not as a traceback
    (out / "lambert_vs_phong" / "metrics.json").write_text('{"ok": tr')
    check = run(tmp_path, "report", str(out))
    assert check.returncode == 1 and "failed lambert_vs_phong" in check.stdout
    assert "Traceback" not in check.stderr


def test_report_of_a_bake_run_names_scenes_without_their_glb_or_with_a_failed_check(tmp_path):
    """A bake run's folders (run.json "command": "bake"): whole with metrics.json and the
    .glb it names; the check's verdict decides ok."""
    out = tmp_path / "bake"
    out.mkdir()
    (out / "run.json").write_text(json.dumps({"command": "bake",
                                              "scenes": ["a", "b", "c", "d"]}))
    for name, ok, glb in (("a", True, True), ("b", False, True), ("c", True, False)):
        (out / name).mkdir()
        (out / name / "metrics.json").write_text(json.dumps({"glb": f"{name}.glb", "ok": ok}))
        if glb:
            (out / name / f"{name}.glb").write_bytes(b"glTF")
    result = run(tmp_path, "report", str(out))
    assert result.returncode == 1, result.stdout + result.stderr
    assert ("INCOMPLETE: 1 of 4 scene(s) baked and exported; missing d; failed b, c"
            in result.stdout), result.stdout
    assert not (out / "index.html").exists()  # no comparison index for a bake run
    for name in ("b", "c", "d"):
        shutil.rmtree(out / name, ignore_errors=True)
    (out / "run.json").write_text(json.dumps({"command": "bake", "scenes": ["a"]}))
    result = run(tmp_path, "report", str(out))
    assert result.returncode == 0 and "complete: 1 of 1 scene(s), every one baked" in \
        result.stdout


@pytest.mark.parametrize("case", ["no-folder", "no-run", "bad-run"])
def test_report_of_a_folder_that_is_no_run_exits_2(tmp_path, case):
    folder = tmp_path / "x"
    if case != "no-folder":
        folder.mkdir()
    if case == "bad-run":
        (folder / "run.json").write_text('{"scenes": "all"}')
    message = {"no-folder": "no such folder", "no-run": "run.json: missing",
               "bad-run": "run.json: scenes: expected a list"}[case]
    result = run(tmp_path, "report", str(folder))
    assert result.returncode == 2 and message in result.stderr
    assert "Traceback" not in result.stderr


# -- phong slurm's own checks (nothing submitted) --------------------------------------------

@pytest.mark.parametrize("args, message", [
    (["--tasks", "2"], "expected the command after '--'"),
    (["--", "demo", "--shard", "1/2"], "leave out --shard"),
    (["--array=0-3", "--", "demo"], "--array=0-3: set by phong slurm itself"),
    (["--tasks", "0", "--", "demo"], "--tasks must be at least 1"),
    (["--", "demo", "--scenes", "nope"], "unknown scene 'nope'"),
    (["--", "compare", "missing.blend"], "missing.blend: no such file"),
    (["--", "bake", "missing.blend", "--target", "vertex"], "missing.blend: no such file"),
    (["--", "bake", "missing.blend"], "the following arguments are required: --target"),
    (["--", "bake", "x.blend", "--target", "vertex", "--shard", "auto"], "leave out --shard"),
    (["--", "apply", "x.blend", "-o", "y.blend"], "apply writes one .blend"),
])
def test_slurm_refuses_bad_commands_before_submitting(tmp_path, args, message):
    result = run(tmp_path, "slurm", *args, env={"PATH": "/nonexistent"})
    assert result.returncode == 2, result.stderr
    assert message in result.stderr and "Traceback" not in result.stderr


# -- a real one-node Slurm cluster ---------------------------------------------------------

@pytest.fixture(scope="module")
def cluster(tmp_path_factory):
    """A one-node Slurm cluster started here, and stopped afterwards (no daemon left)."""
    if os.environ.get("PHONG_BPY"):
        pytest.skip("the Slurm test runs once per CI run, with the default bpy "
                    f"(PHONG_BPY={os.environ['PHONG_BPY']} is set)")
    from phong_nodes.cli import cluster as tool  # noqa: PLC0415
    problem = tool.unavailable()
    if problem:
        if os.environ.get("CI"):
            pytest.fail(f"CI runs the Slurm test: {problem}")
        pytest.skip(problem)
    one = tool.Cluster(str(tmp_path_factory.mktemp("slurm")))
    one.start()
    yield one
    one.stop()
    assert not one.running(), f"daemons still running: {one.running()}"


def job_state(cluster, job) -> dict:
    text = cluster.run("scontrol", "show", "job", job, check=False).stdout
    return dict(re.findall(r"\b(JobState|ExitCode|Restarts)=(\S+)", text))


def wait_for(condition, timeout, what):
    end = time.monotonic() + timeout
    while not condition():
        if time.monotonic() > end:
            pytest.fail(f"timed out after {timeout} s waiting for {what}")
        time.sleep(0.2)


@pytest.mark.slow
@pytest.mark.cycles
def test_slurm_array_killed_task_requeued_completes_the_run(tmp_path, cluster):
    common = ["--scenes", ",".join(FARM_SCENES), "--engines", "cycles", "--resolution", "32"]
    # the same run on one machine, for the metrics
    single = run(tmp_path, "demo", *common, "--out", str(tmp_path / "single"))
    assert single.returncode == 0, single.stderr[-2000:]

    out = tmp_path / "farm"
    t0 = time.monotonic()
    submit = run(tmp_path, "slurm", "--tasks", "4", "--", "demo", *common, "--out", str(out),
                 env={"SLURM_CONF": cluster.conf})
    assert submit.returncode == 0, submit.stdout + submit.stderr
    array = re.search(r"array job (\d+)", submit.stdout).group(1)
    check = re.search(r"check job (\d+)", submit.stdout).group(1)

    # kill one task mid-scene, as a lost node would (SIGKILL: it cleans nothing up)
    partial = re.compile(r"^\.partial-(%s)\.[^.]+\.(\d+)\." % "|".join(FARM_SCENES))
    end = time.monotonic() + 240
    victim = None
    while victim is None and time.monotonic() < end:
        for name in os.listdir(out) if out.exists() else ():
            match = partial.match(name)
            if match and (out / name).is_dir() and not (out / match.group(1)).exists():
                victim = match.group(1), int(match.group(2))
                break
        else:
            time.sleep(0.005)
    assert victim, "no task was seen mid-scene"
    scene, pid = victim
    os.kill(pid, signal.SIGKILL)
    task = FARM_SCENES.index(scene)  # shard i/4 of four scenes is scene i: array index i-1
    be.report(f"slurm: killed task {array}_{task} (pid {pid}) in the middle of {scene}")

    # the other tasks finish; the check job runs after every task (afterany) and fails
    wait_for(lambda: not cluster.jobs(), 300, "the array and the check job")
    assert job_state(cluster, f"{array}_{task}")["JobState"] == "FAILED"
    state = job_state(cluster, check)
    assert (state["JobState"], state["ExitCode"]) == ("FAILED", "1:0"), state
    check_log = (out / "slurm-logs" / f"phong-check-{check}.log").read_text()
    assert f"missing {scene}" in check_log, check_log
    page = (out / "index.html").read_text()
    assert f"{scene}/sheet.png" not in page and f"id=\"{scene}\"" not in page, \
        "the index never lists a half-written folder"
    assert not (out / scene).exists()
    others = [s for s in FARM_SCENES if s != scene]
    assert all(f"{s}/sheet.png" in page for s in others)
    # each task baked its own shard, and only it: no file written by two tasks
    logs = {i: (out / "slurm-logs" / f"phong-{array}_{i}.log").read_text() for i in range(4)}
    for i, text in logs.items():
        assert f"shard {i + 1}/4 from SLURM_ARRAY_TASK_ID={i} of SLURM_ARRAY_TASK_COUNT=4" \
            in text, text
        baked = re.findall(r"^\[\d+/\d+\] (\w+):", text, re.M)
        # (the killed task's line may not have reached its log)
        assert baked == [FARM_SCENES[i]] or (i == task and not baked), (i, baked)

    # requeue the killed task: the run completes
    requeued = time.monotonic()
    cluster.run("scontrol", "requeue", f"{array}_{task}")
    wait_for(lambda: job_state(cluster, f"{array}_{task}")["JobState"] == "COMPLETED", 300,
             "the requeued task")
    be.report(f"slurm: 4 tasks of {len(FARM_SCENES)} scenes at 32 px (Cycles); the requeued "
              f"task completed {time.monotonic() - requeued:.1f} s after scontrol requeue; "
              f"{time.monotonic() - t0:.1f} s from submit")
    assert job_state(cluster, f"{array}_{task}")["Restarts"] == "1"
    assert not [n for n in os.listdir(out) if n.startswith(".")], "the killed task's temp folder"
    final = run(tmp_path, "report", str(out))
    assert final.returncode == 0, final.stdout + final.stderr
    assert f"complete: {len(FARM_SCENES)} of {len(FARM_SCENES)} scene(s)" in final.stdout

    # the sharded run's metrics are those of the one-machine run: the same pixels compared,
    # the same verdicts, the errors within the float32 noise by which two one-machine runs
    # of the same scene differ (mean |d| by up to 4e-9 here, max |d| by nothing)
    for name in FARM_SCENES:
        farm = json.loads((out / name / "metrics.json").read_text())
        alone = json.loads((tmp_path / "single" / name / "metrics.json").read_text())
        assert farm["resolution"] == alone["resolution"] and farm["pixels"] == alone["pixels"]
        assert {e: v["ok"] for e, v in farm["verdict"].items()} == \
            {e: v["ok"] for e, v in alone["verdict"].items()}, name
        pairs = {**farm["pairs"], **{f"term {t}": v for t, v in farm.get("terms", {}).items()}}
        wanted = {**alone["pairs"], **{f"term {t}": v for t, v in alone.get("terms", {}).items()}}
        assert pairs.keys() == wanted.keys(), name
        for key, got in pairs.items():
            want = wanted[key]
            assert (got["pixels"], got["share_over_1_255"]) == \
                (want["pixels"], want["share_over_1_255"]), (name, key)
            assert abs(got["max_abs"] - want["max_abs"]) <= 1e-6, (name, key, got, want)
            assert abs(got["mean_abs"] - want["mean_abs"]) <= 1e-7, (name, key, got, want)


def test_ci_installs_the_cluster_packages_that_check_system_names(tmp_path):
    """.ci/run installs (as root) what ``cli/system.py --cluster-packages`` prints: it runs
    with a bare python3 and names the package of every command the cluster needs."""
    tool = os.path.join(ROOT, "cli", "system.py")
    empty = tmp_path / "empty"
    empty.mkdir()
    # a PATH without Slurm's client commands: at least slurm-client is named
    python3 = shutil.which("python3", path="/usr/bin:/bin") or sys.executable
    named = subprocess.run([python3, "-I", tool, "--cluster-packages"], capture_output=True,
                           text=True, env={"PATH": str(empty)}, check=True).stdout.split()
    assert "slurm-client" in named and set(named) <= {"slurmctld", "slurmd", "slurm-client",
                                                      "munge"}
    with open(os.path.join(ROOT, ".ci", "run"), encoding="utf-8") as handle:
        assert "cli/system.py --cluster-packages" in handle.read()


def test_cluster_says_why_it_cannot_start(monkeypatch):
    """What the Slurm test skips with (or fails with under CI): one line naming the fix."""
    from phong_nodes.cli import cluster as tool  # noqa: PLC0415
    check = tool.system
    monkeypatch.setattr(check, "cluster_packages", lambda: ["munge", "slurmd"])
    assert tool.unavailable().endswith("apt-get install -y munge slurmd (as root)")
    monkeypatch.setattr(check, "cluster_packages", lambda: [])
    monkeypatch.setattr(tool.os, "geteuid", lambda: 1000)
    assert "run as root" in tool.unavailable()
    with pytest.raises(tool.ClusterError, match="run as root"):
        tool.Cluster("/nonexistent/cluster").start()
