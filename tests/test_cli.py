# SPDX-License-Identifier: GPL-3.0-or-later
"""The headless command (`phong`, cli/): scene CLI, report, exit codes, bad input."""

import json
import re
import os
import subprocess
import sys

import pytest

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
#: The `phong` command of this environment (what tools/phong.sh runs).
CLI = [sys.executable, "-m", "phong_nodes.cli"]

GOOD = """
title = "t"
[camera]
location = [0, -5, 0]
[[lights]]
type = "point"
position = [1, -2, 3]
[[objects]]
name = "ball"
material = { exponent = 10 }
"""


def run_cli(tmp_path, *args):
    env = dict(os.environ, BLENDER_USER_RESOURCES=str(tmp_path / "user"))
    return subprocess.run([*CLI, *args], capture_output=True, text=True,
                          env=env, timeout=300)


@pytest.mark.eevee
@pytest.mark.cycles
def test_one_scene_end_to_end(tmp_path):
    out = tmp_path / "report"
    result = run_cli(tmp_path, "demo", "--out", str(out), "--scenes", "point_falloff",
                     "--resolution", "24")
    assert result.returncode == 0, result.stdout[-3000:] + result.stderr[-3000:]
    assert "[1/1] point_falloff" in result.stdout
    assert "every engine matches the reference" in result.stdout
    assert "point_falloff     cycles-reference" in result.stdout  # the summary table
    metrics = json.loads((out / "point_falloff" / "metrics.json").read_text())
    assert metrics["ok"] and metrics["resolution"] == [96, 24]
    assert metrics["pairs"]["cycles-reference"]["max_abs"] <= 1e-4
    page = (out / "index.html").read_text()
    assert "point_falloff/sheet.png" in page and "plot_falloff.svg" in page
    assert "α" in page, "the scene's parameters are in the report"
    assert not [n for n in os.listdir(out) if n.startswith(".")], "no half-written file"


@pytest.mark.parametrize("old, new, message", [
    ('title = "t"\n', "", "title: expected a string (missing)"),
    ("position = [1, -2, 3]", 'position = "up"', "lights[0].position: expected a list of 3"),
    ("exponent = 10", "exponent = -1", "objects[0].material.exponent: expected a number >= 0"),
    ('type = "point"', 'type = "area"', "lights[0].type: expected one of 'point'"),
], ids=["missing-key", "wrong-type", "negative-exponent", "unknown-light-type"])
def test_broken_scene_file_exits_2_and_writes_nothing(tmp_path, old, new, message):
    bad = tmp_path / "bad.toml"
    bad.write_text(GOOD.replace(old, new, 1))
    out = tmp_path / "out"
    result = run_cli(tmp_path, "demo", "--out", str(out), "--scenes", f"lambert_vs_phong,{bad}")
    assert result.returncode == 2, result.stderr
    assert f"{bad}: {message}" in result.stderr
    assert "Traceback" not in result.stderr
    assert not out.exists(), "no partial output"


@pytest.mark.parametrize("args, message", [
    (["--engines", "luxcore"], "unknown engine(s) luxcore"),
    (["--resolution", "3"], "--resolution must be between 8 and 4096"),
    (["--shard", "3/2"], "--shard: expected i/n"),
    (["--scenes", "nope"], "unknown scene 'nope'"),
])
def test_bad_arguments_exit_2_with_a_clear_line(tmp_path, args, message):
    out = tmp_path / "x"
    result = run_cli(tmp_path, "demo", "--out", str(out), *args)
    assert result.returncode == 2
    assert message in result.stderr
    assert "Traceback" not in result.stderr
    assert not out.exists()


def test_unwritable_output_folder_exits_2(tmp_path):
    blocker = tmp_path / "file"
    blocker.write_text("not a folder")
    result = run_cli(tmp_path, "demo", "--out", str(blocker / "sub"))
    assert result.returncode == 2
    assert "cannot write to output folder" in result.stderr
    assert "Traceback" not in result.stderr


@pytest.fixture(scope="module")
def plain_blend(tmp_path_factory):
    """A .blend without Phong materials (Blender's start-up scene), saved by bpy."""
    path = tmp_path_factory.mktemp("blend") / "plain.blend"
    code = ("import bpy, sys; bpy.ops.wm.save_as_mainfile(filepath=sys.argv[1]); "
            "print(len(bpy.data.materials))")
    env = dict(os.environ, BLENDER_USER_RESOURCES=str(path.parent / "user"))
    subprocess.run([sys.executable, "-c", code, str(path)], check=True, env=env,
                   capture_output=True, timeout=120)
    return path


@pytest.mark.parametrize("case", ["missing", pytest.param("broken", marks=pytest.mark.slow),
                                  pytest.param("no-phong", marks=pytest.mark.slow), "bad-option",
                                  pytest.param("unknown-scene", marks=pytest.mark.slow)])
def test_compare_bad_input_exits_2_with_one_line_and_writes_nothing(tmp_path, plain_blend,
                                                                     case):
    broken = tmp_path / "broken.blend"
    broken.write_bytes(b"BLENDER-v500 but not really a blend file" * 10)
    args, message = {
        "missing": ([str(tmp_path / "nope.blend")], "nope.blend: no such file"),
        "broken": ([str(broken)], "broken.blend: cannot open as a .blend file"),
        "no-phong": ([str(plain_blend)], "plain.blend: no scene has an object with a Phong "
                                         "material"),
        "bad-option": ([str(plain_blend), "--resolution", "3"],
                       "--resolution must be between 8 and 4096"),
        "unknown-scene": ([str(plain_blend), "--scenes", "Nope"], "--scenes: no scene 'Nope'"),
    }[case]
    out = tmp_path / "out"
    result = run_cli(tmp_path, "compare", *args, "--out", str(out))
    assert result.returncode == 2, result.stderr
    lines = [l for l in result.stderr.splitlines() if l.startswith("phong")]
    assert len(lines) == 1 and message in lines[0], result.stderr
    assert "Traceback" not in result.stderr
    assert not out.exists(), "nothing written"


@pytest.mark.slow
@pytest.mark.cycles
def test_save_blend_keeps_a_demo_scene_that_compare_checks(tmp_path):
    out = tmp_path / "demo"
    result = run_cli(tmp_path, "demo", "--scenes", "lambert_vs_phong", "--resolution", "16",
                     "--engines", "cycles", "--save-blend", "--out", str(out))
    assert result.returncode == 0, result.stderr[-3000:]
    blend = out / "lambert_vs_phong" / "lambert_vs_phong.blend"
    assert blend.is_file()
    result = run_cli(tmp_path, "compare", str(blend), "--engines", "cycles", "--out",
                     str(tmp_path / "check"))
    assert result.returncode == 0, result.stderr[-3000:]
    metrics = json.loads((tmp_path / "check" / "lambert_vs_phong" / "metrics.json").read_text())
    assert metrics["ok"] and metrics["resolution"] == [32, 16], "the saved scene's own size"


DATA = os.path.join(ROOT, "tests", "data")


@pytest.mark.slow
@pytest.mark.cycles
@pytest.mark.parametrize("path, says", [
    ("obj/illum.obj", ["has no camera: added one", "has no light: added a sun"]),
    ("collada/hand_lit.dae", ["has no camera: added one", "decimal commas"]),
    ("fbx/maya_cube_7500_binary.fbx", ["has no light: added a sun"]),
], ids=["obj", "dae", "fbx"])
def test_compare_reads_files_of_other_programs(tmp_path, path, says):
    """``phong compare`` imports .obj, .dae and .fbx files as Phong (the extension's own
    importers) into an empty scene, frames them when the file has no camera, lights them
    when it has no light, and compares like a .blend."""
    out = tmp_path / "out"
    result = run_cli(tmp_path, "compare", os.path.join(DATA, path), "--engines", "cycles",
                     "--resolution", "24", "--out", str(out))
    assert result.returncode == 0, result.stdout[-2000:] + result.stderr[-2000:]
    for text in says:
        assert text in result.stderr, result.stderr
    (folder,) = [p for p in out.iterdir() if p.is_dir()]
    metrics = json.loads((folder / "metrics.json").read_text())
    assert metrics["pixels"]["compared"] >= 40, "the framing camera sees the objects"
    assert metrics["pairs"]["cycles-reference"]["max_abs"] <= 1e-4 and metrics["ok"]
    framed = "has no camera: added one" in result.stderr
    assert metrics.get("notes") == (["framed: the file has no camera"] if framed else None)
    assert ("framed: the file has no camera" in result.stdout) is framed


#: A part as KiCad exports it (0201: 0.24 units wide), its materials as KiCad's, and no
#: Viewpoint: the standard's default view from (0 0 10) sees it on about one pixel.
TINY_PART = """#VRML V2.0 utf8
Shape {
  appearance Appearance { material Material {
    diffuseColor 0.8 0.3 0.2 specularColor 0.5 0.5 0.5 shininess 0.3 } }
  geometry Box { size 0.24 0.12 0.1 }
}
"""


@pytest.mark.slow
@pytest.mark.cycles
def test_compare_frames_a_file_without_viewpoint(tmp_path):
    """A .wrl without Viewpoint is compared on a framed picture: X3D's default view (down
    -Z, Blender's +Y) moved back along its direction until the part fills 90% of the
    picture's width, said on the terminal and in the report."""
    from phong_nodes.addon.scene import framing  # noqa: PLC0415
    path = tmp_path / "R_0201_0603Metric.wrl"
    path.write_text(TINY_PART)
    out = tmp_path / "out"
    result = run_cli(tmp_path, "compare", str(path), "--engines", "cycles", "--resolution", "64",
                     "--out", str(out))
    assert result.returncode == 0, result.stdout[-2000:] + result.stderr[-2000:]
    assert "has no Viewpoint" in result.stderr and "framed: the file has no Viewpoint" in \
        result.stdout
    metrics = json.loads((out / "R_0201_0603Metric" / "metrics.json").read_text())
    assert metrics["ok"] and metrics["notes"] == ["framed: the file has no Viewpoint"]
    assert "framed: the file has no Viewpoint" in (out / "index.html").read_text()
    # the headlight looks where the camera does: the default view's direction, kept
    (headlight,) = metrics["parameters"]["lights"]
    assert headlight["direction"] == pytest.approx([0.0, 1.0, 0.0], abs=1e-6)
    # seen head-on, the box's front face (0.24 × 0.12, twice as wide as high) is wider than
    # the picture (16:9): it spans FILL of the width and half that in height, give or take
    # the pixels its outline crosses
    width, height = metrics["resolution"]
    across = framing.FILL * width
    expected = across * across / 2.0
    assert abs(metrics["pixels"]["compared"] - expected) <= 2 * (across + across / 2) + 4
    assert metrics["coverage"]["pixels"] / (width * height) > 0.2


@pytest.mark.slow
@pytest.mark.cycles
def test_compare_of_a_camera_that_sees_nothing_fails_and_says_why(tmp_path):
    """A Viewpoint that looks away from every shape: exit 1 and a message, not a pass of
    three black pictures."""
    path = tmp_path / "away.wrl"
    path.write_text(TINY_PART + "Viewpoint { position 0 0 10 orientation 0 1 0 3.14159 }\n")
    out = tmp_path / "out"
    result = run_cli(tmp_path, "compare", str(path), "--engines", "cycles", "--resolution", "32",
                     "--out", str(out))
    assert result.returncode == 1, result.stdout[-2000:] + result.stderr[-2000:]
    assert "FAIL: the camera sees 0 of" in result.stdout and "frame the scene" in result.stdout
    assert "NOTHING TO COMPARE (away" in result.stdout
    assert "every engine matches" not in result.stdout and "framed" not in result.stdout
    metrics = json.loads((out / "away" / "metrics.json").read_text())
    assert not metrics["ok"] and not metrics["coverage"]["ok"]
    assert metrics["coverage"]["pixels"] == 0 and "notes" not in metrics
    page = (out / "index.html").read_text()
    assert "the camera sees 0 of" in page and "sees (almost) no Phong surface" in page


@pytest.mark.parametrize("name, text, message", [
    ("broken.dae", "<COLLADA><library_geometries>", "broken.dae"),
    ("broken.fbx", "Kaydara FBX Binary  \x00 truncated", "broken.fbx"),
    ("notes.txt", "hello", "not a file this command reads (.blend, .obj, .dae, .fbx, .wrl"),
], ids=["dae", "fbx", "txt"])
@pytest.mark.slow
def test_compare_refuses_an_unreadable_file_with_one_line(tmp_path, name, text, message):
    bad = tmp_path / name
    bad.write_text(text)
    out = tmp_path / "out"
    result = run_cli(tmp_path, "compare", str(bad), "--out", str(out))
    assert result.returncode == 2, result.stderr[-2000:]
    assert message in result.stderr and "Traceback" not in result.stderr
    assert not out.exists(), "nothing written"


@pytest.mark.slow
@pytest.mark.cycles
def test_a_scene_file_light_with_falloff_exponent_3_is_compared_exactly(tmp_path):
    """falloff_exponent = 3 builds a Blender light with the power falloff i0/d^3, and the
    comparison's reference (from the scene as Blender evaluates it) agrees with Cycles."""
    scene = tmp_path / "cubic.toml"
    scene.write_text(GOOD.replace("position = [1, -2, 3]",
                                  "position = [1, -2, 3]\nintensity = 20\nfalloff_exponent = 3"))
    out = tmp_path / "out"
    result = run_cli(tmp_path, "demo", "--scenes", str(scene), "--engines", "cycles",
                     "--resolution", "24", "--out", str(out))
    assert result.returncode == 0, result.stdout[-2000:] + result.stderr[-2000:]
    metrics = json.loads((out / "cubic" / "metrics.json").read_text())
    (light,) = metrics["parameters"]["lights"]
    assert light["falloff"] == "power" and light["power_k"] == 3.0
    assert metrics["pairs"]["cycles-reference"]["max_abs"] <= 1e-4
    assert metrics["pixels"]["compared"] > 100


def test_every_help_names_every_format_the_command_reads():
    """`phong --help` and `phong compare --help` name every suffix of the table of formats
    that an importer reads (core/suffixes.py, the table's pure column: the help is generated
    from it, so it cannot drift), and parsing imports no bpy."""
    from phong_nodes.core import suffixes as formats  # noqa: PLC0415

    suffixes = formats.importable_suffixes()
    assert {".obj", ".dae", ".fbx", ".wrl", ".x3d"} <= set(suffixes)
    for argv in (["--help"], ["compare", "--help"]):
        result = subprocess.run([*CLI, *argv], capture_output=True, text=True, timeout=60,
                                env=dict(os.environ, COLUMNS="200"))
        assert result.returncode == 0, result.stderr
        named = set(re.findall(r"(?<![\w.])\.\w+", result.stdout))
        assert set(suffixes) <= named, (argv, sorted(set(suffixes) - named), result.stdout)
    probe = ("import sys; from phong_nodes.cli import args; args.parse(['compare', 'x.wrl']); "
             "print('bpy' in sys.modules)")
    result = subprocess.run([sys.executable, "-c", probe], capture_output=True, text=True,
                            timeout=60)
    assert result.stdout.strip() == "False", result.stdout + result.stderr
