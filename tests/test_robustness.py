# SPDX-License-Identifier: GPL-3.0-or-later
"""Bad input, interruptions and where outputs go (issue 6, items 4 and 5).

Each bad-input case asserts the whole message line: in Blender an operator's ERROR report
reaches Python as ``RuntimeError("Error: <message>\\n")``; the CLI exits with 2 and prints one
line on stderr, without a traceback.
"""

from __future__ import annotations

import json
import os
import re
import signal
import subprocess
import sys
import time

import pytest

import blender_env as be
import phong_nodes

ROOT = be.REPO_ROOT
#: The `phong` command of this environment (what tools/phong.sh runs).
CLI = [sys.executable, "-m", "phong_nodes.cli"]
SCENES = ["point_falloff", "lambert_vs_phong", "four_terms", "color_product"]
CODE = "__import__('os').system('touch {marker}')"


def _cli_env(tmp_path, **extra):
    return dict(os.environ, BLENDER_USER_RESOURCES=str(tmp_path / "user"), **extra)


def run_cli(tmp_path, *args, **kwargs):
    return subprocess.run([*CLI, *args], capture_output=True, text=True,
                          env=_cli_env(tmp_path), timeout=300, **kwargs)


def _one_line(stderr: str) -> str:
    lines = [line for line in stderr.splitlines() if line.strip()]
    assert len(lines) == 1, f"expected one line on stderr, got:\n{stderr}"
    assert "Traceback" not in stderr
    return lines[0]


def _error(excinfo) -> str:
    """The message of an operator's ERROR report, from the RuntimeError it raised."""
    text = str(excinfo.value)
    assert text.startswith("Error: ") and text.endswith("\n"), repr(text)
    return text[len("Error: "):-1]


# -- the CLI: bad input -------------------------------------------------------------------

def test_cli_scene_file_that_is_not_toml(tmp_path):
    bad = tmp_path / "notes.toml"
    bad.write_text("this is not TOML\n")
    out = tmp_path / "out"
    result = run_cli(tmp_path, "demo", "--scenes", str(bad), "--out", str(out))
    assert result.returncode == 2
    line = _one_line(result.stderr)
    assert re.fullmatch(rf"phong: {re.escape(str(bad))}: not valid TOML: .+ "
                        r"\(at line 1, column \d+\)", line), line
    assert not out.exists()


def test_cli_unknown_scene_name(tmp_path):
    out = tmp_path / "out"
    result = run_cli(tmp_path, "demo", "--scenes", "point_falloff,nope", "--out", str(out))
    assert result.returncode == 2
    line = _one_line(result.stderr)
    assert re.fullmatch(r"phong: --scenes: unknown scene 'nope'; expected one of "
                        r"([a-z0-9_]+, )+[a-z0-9_]+ or a path to a \.toml file", line), line
    assert not out.exists()


def test_cli_unwritable_output_folder(tmp_path):
    blocker = tmp_path / "file"
    blocker.write_text("not a folder")
    result = run_cli(tmp_path, "demo", "--scenes", "point_falloff", "--out", str(blocker / "sub"))
    assert result.returncode == 2
    line = _one_line(result.stderr)
    assert line == f"phong: cannot write to output folder {blocker / 'sub'}: Not a directory"


# -- the CLI: interrupted, then run again ----------------------------------------------------

def _finished(out):
    return [n for n in os.listdir(out) if not n.startswith(".")
            and os.path.isfile(os.path.join(out, n, "metrics.json"))]


def _assert_clean(out, scenes):
    """No hidden temporary entry; every scene folder complete; index lists only those."""
    names = os.listdir(out)
    assert not [n for n in names if n.startswith(".")], f"temporary entries left: {names}"
    folders = [n for n in names if os.path.isdir(os.path.join(out, n))]
    assert sorted(folders) == sorted(scenes), folders
    for name in folders:
        files = set(os.listdir(os.path.join(out, name)))
        assert {"metrics.json", "sheet.png", "cycles.png", "reference.png"} <= files, name
        metrics = json.loads((out / name / "metrics.json").read_text())
        assert metrics["scene"] == name
    if (out / "index.html").exists():
        page = (out / "index.html").read_text()
        listed = set(re.findall(r"<section id=\"([a-z0-9_]+)\">", page))
        assert listed <= set(folders), listed


def _snapshot_pycache():
    found = {}
    for folder, dirs, files in os.walk(ROOT):
        dirs[:] = [d for d in dirs if d not in (".git", ".venv", "out")]
        if os.path.basename(folder) == "__pycache__" and not folder.startswith(
                os.path.join(ROOT, "tests")):
            for f in files:
                found[os.path.join(folder, f)] = os.stat(os.path.join(folder, f)).st_mtime_ns
    return found


@pytest.mark.slow
@pytest.mark.cycles
@pytest.mark.parametrize("sig", [signal.SIGTERM, signal.SIGINT], ids=["SIGTERM", "SIGINT"])
def test_cli_interrupted_then_run_again(tmp_path, sig):
    out = tmp_path / "out"
    args = [*CLI, "demo", "--scenes", ",".join(SCENES), "--engines", "cycles",
            "--resolution", "16", "--out", str(out)]
    proc = subprocess.Popen(args, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
                            env=_cli_env(tmp_path))
    deadline = time.monotonic() + 120
    while not (out.is_dir() and _finished(out)) and time.monotonic() < deadline:
        assert proc.poll() is None, proc.communicate()
        time.sleep(0.02)
    proc.send_signal(sig)
    _stdout, stderr = proc.communicate(timeout=120)
    assert proc.returncode == 128 + sig, stderr
    line = _one_line(stderr)
    assert re.fullmatch(rf"phong: interrupted by {sig.name} after [1-3] of 4 scene\(s\); "
                        r"finished scene folders are complete, nothing half-written was kept",
                        line), line
    done = _finished(out)
    _assert_clean(out, done)
    assert not (out / "index.html").exists(), "an interrupted run writes no index"

    if sig != signal.SIGTERM:
        return
    # a run killed outright (SIGKILL) leaves its temporary folder: the next run removes it
    dead = subprocess.Popen([sys.executable, "-c", "pass"])
    dead.wait()
    stale = out / f".partial-four_terms.{_outputs_module()._host()}.{dead.pid}.abcd1234"
    stale.mkdir()
    (stale / "metrics.json").write_text('{"half": ')
    # ... and nothing may be written outside --out: not in the current folder, HOME, TMPDIR
    # or the source tree (no __pycache__)
    for sub in ("cwd", "home", "tmp"):
        (tmp_path / sub).mkdir()
    before = _snapshot_pycache()
    result = subprocess.run(args, capture_output=True, text=True, timeout=300,
                            cwd=tmp_path / "cwd", env=_cli_env(
                                tmp_path, HOME=str(tmp_path / "home"),
                                TMPDIR=str(tmp_path / "tmp")))
    assert result.returncode == 0, result.stderr[-3000:]
    _assert_clean(out, SCENES)
    page = (out / "index.html").read_text()
    assert all(f'<section id="{s}">' in page for s in SCENES)
    for sub in ("cwd", "home", "tmp"):
        # Blender itself creates the empty folders of its thumbnail cache (~/.cache/thumbnails)
        written = [os.path.join(d, f) for d, _dirs, files in os.walk(tmp_path / sub)
                   for f in files]
        assert not written, f"the CLI wrote outside --out: {written}"
    assert _snapshot_pycache() == before, "the CLI wrote __pycache__ into the source tree"


def _outputs_module():
    from phong_nodes.core import outputs  # noqa: PLC0415

    return outputs


def test_stale_entries_of_live_processes_are_kept(tmp_path):
    outputs = _outputs_module()
    mine = tmp_path / (outputs.temp_prefix("partial", "a") + "x1")
    mine.mkdir()
    foreign = tmp_path / ".partial-a.otherhost.1.x2"
    foreign.mkdir()
    assert outputs.clean_stale(str(tmp_path)) == []
    assert mine.exists() and foreign.exists()


# -- scene files are data ----------------------------------------------------------------

GOOD = """
title = "{title}"
description = "{title}"
[camera]
location = [0, -5, 0]
[[lights]]
name = "{light}"
type = "point"
position = [1, -2, 3]
[[objects]]
name = "ball"
label = "{title}"
"""


def _scenes_module():
    from phong_nodes.core import scenes  # noqa: PLC0415

    return scenes


def test_scene_strings_are_never_executed(tmp_path):
    scenes = _scenes_module()
    marker = tmp_path / "pwned"
    code = CODE.format(marker=marker)
    path = tmp_path / "code.toml"
    path.write_text(GOOD.format(title=code, light="key"))
    data = scenes.load(str(path))
    assert data["title"] == code and data["objects"][0]["label"] == code  # plain strings
    path.write_text(GOOD.format(title="t", light=code))
    with pytest.raises(scenes.SceneError) as excinfo:
        scenes.load(str(path))
    assert re.fullmatch(rf"{re.escape(str(path))}: lights\[0\]\.name: expected a name matching "
                        r"\^\[a-z0-9_\]\+\$, got [\"']__import__\(.*", str(excinfo.value))
    assert not marker.exists()


def test_no_python_evaluation_in_the_sources():
    pattern = re.compile(r"(?<![\w.])(eval|exec|compile|__import__)\s*\(|pickle|marshal")
    offenders = []
    for folder in ("addon", "node_groups", "core", "cli", "tools"):
        for name in os.listdir(os.path.join(ROOT, folder)):
            if name.endswith(".py"):
                with open(os.path.join(ROOT, folder, name), encoding="utf-8") as handle:
                    for number, line in enumerate(handle, 1):
                        if pattern.search(line):
                            offenders.append(f"{folder}/{name}:{number}: {line.strip()}")
    assert not offenders, "\n".join(offenders)


# -- the operators -----------------------------------------------------------------------

def test_apply_material_without_selection_or_mesh(bpy_clean):
    bpy = bpy_clean
    scene = bpy.context.scene
    with pytest.raises(RuntimeError) as excinfo:
        bpy.ops.phong.apply_material()
    assert _error(excinfo) == ("Apply Phong Material: nothing is selected; select meshes, "
                               "curves, text or surfaces")
    cam = bpy.data.objects.new("Cam", bpy.data.cameras.new("Cam"))
    lamp = bpy.data.objects.new("Lamp", bpy.data.lights.new("Lamp", "POINT"))
    for obj in (cam, lamp):
        scene.collection.objects.link(obj)
        obj.select_set(True)
    with pytest.raises(RuntimeError) as excinfo:
        bpy.ops.phong.apply_material()
    assert _error(excinfo) == ("Apply Phong Material: no object with materials among the "
                               "selected objects (Cam, Lamp); select meshes, curves, text or "
                               "surfaces")


def test_add_node_group_outside_the_shader_editor_and_unknown_group(bpy_clean):
    bpy = bpy_clean
    with pytest.raises(RuntimeError) as excinfo:
        bpy.ops.phong.add_node_group(group_name="Phong Diffuse")
    assert str(excinfo.value) == ("Operator bpy.ops.phong.add_node_group.poll() Add Phong Node "
                                  "Group: open a material's node tree in the Shader Editor first")
    from phong_nodes.addon.ui import operators  # noqa: PLC0415  (needs bpy)

    tree = bpy.data.node_groups.new("t", "ShaderNodeTree")
    with pytest.raises(ValueError) as excinfo:
        operators.add_group_node(tree, "Phong Nope", (0, 0))
    assert re.fullmatch(r"Unknown Phong group 'Phong Nope'; expected one of: "
                        r"((Phong|three\.js|X3D) [A-Za-z ]+, )+X3D Spot Light", str(excinfo.value))


def test_build_demo_scene_unknown_name_and_bad_file(bpy_clean, tmp_path):
    bpy = bpy_clean
    with pytest.raises(TypeError) as excinfo:
        bpy.ops.phong.build_demo_scene(name="nope")
    assert re.fullmatch(r"Converting py args to operator properties: enum \"nope\" not found in "
                        r"\(('[a-z0-9_]+', )+'[a-z0-9_]+'\)", str(excinfo.value))
    bad = tmp_path / "notes.toml"
    bad.write_text("this is not TOML\n")
    scenes_before = len(bpy.data.scenes)
    with pytest.raises(RuntimeError) as excinfo:
        bpy.ops.phong.build_demo_scene(filepath=str(bad))
    assert re.fullmatch(rf"Build Phong Demo Scene: {re.escape(str(bad))}: not valid TOML: .+ "
                        r"\(at line 1, column \d+\)", _error(excinfo))
    missing = tmp_path / "missing.toml"
    with pytest.raises(RuntimeError) as excinfo:
        bpy.ops.phong.build_demo_scene(filepath=str(missing))
    assert _error(excinfo) == f"Build Phong Demo Scene: {missing}: no such scene file"
    assert len(bpy.data.scenes) == scenes_before
    # a scene file of one's own, with Python-looking strings: built, never run
    marker = tmp_path / "pwned"
    good = tmp_path / "mine.toml"
    good.write_text(GOOD.format(title=CODE.format(marker=marker), light="key"))
    assert bpy.ops.phong.build_demo_scene(filepath=str(good), resolution=8) == {"FINISHED"}
    assert len(bpy.data.scenes) == scenes_before + 1
    assert not marker.exists()


def _demo_scene(bpy):
    bpy.ops.phong.build_demo_scene(name="point_falloff", resolution=8)
    return bpy.data.scenes["point_falloff"]


def test_bake_refuses_unwritable_folder_and_the_extension_folder(bpy_clean, tmp_path):
    bpy = bpy_clean
    scene = _demo_scene(bpy)
    blocker = tmp_path / "file"
    blocker.write_text("not a folder")
    with bpy.context.temp_override(scene=scene):
        with pytest.raises(RuntimeError) as excinfo:
            bpy.ops.phong.compare_scene(directory=str(blocker / "sub"))
        assert _error(excinfo) == ("Compare Phong Scene: cannot write to output folder "
                                   f"{blocker / 'sub'}: Not a directory")
        package = os.path.dirname(phong_nodes.__file__)
        for target in (package, os.path.join(package, "phong_bake")):
            with pytest.raises(RuntimeError) as excinfo:
                bpy.ops.phong.compare_scene(directory=target)
            assert _error(excinfo) == (
                f"Compare Phong Scene: output folder {target} is inside the extension's own "
                f"folder {os.path.realpath(package)}; choose another folder")
        assert not os.path.exists(os.path.join(package, "phong_bake"))
        assert not os.path.exists(os.path.join(package, "point_falloff"))
