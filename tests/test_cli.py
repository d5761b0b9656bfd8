# SPDX-License-Identifier: GPL-3.0-or-later
"""The headless command (tools/phong.py): renders the demo in both engines, refuses bad input."""

import os
import subprocess
import sys

import numpy as np
import pytest

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
CLI = os.path.join(ROOT, "tools", "phong.py")


def run_cli(tmp_path, *args):
    env = dict(os.environ, BLENDER_USER_RESOURCES=str(tmp_path / "user"))
    return subprocess.run([sys.executable, CLI, *args], capture_output=True, text=True,
                          env=env, timeout=300)


def read_png(path):
    import OpenImageIO as oiio
    return oiio.ImageBuf(str(path)).get_pixels(oiio.UINT8).astype(float)


@pytest.mark.slow
@pytest.mark.eevee
@pytest.mark.cycles
def test_demo_renders_the_sphere_in_both_engines(tmp_path):
    out = tmp_path / "demo"
    result = run_cli(tmp_path, "--out", str(out), "--resolution", "48", "--samples", "1")
    assert result.returncode == 0, result.stderr[-2000:]
    images = {e: read_png(out / f"sphere_{e}.png") for e in ("cycles", "eevee")}
    for engine, img in images.items():
        assert img.shape == (48, 48, 3)
        assert np.all(img[0, 0] == 0), f"{engine}: no light, no ambient outside the sphere"
        centre = img[24, 24]
        assert centre[0] > centre[1] > centre[2] > 0, f"{engine}: orange object colour, lit"
    assert not [n for n in os.listdir(out) if n.startswith(".partial")], "no half-written file"
    diff = np.abs(images["cycles"] - images["eevee"])
    assert np.median(diff) <= 1.0
    assert "Eevee vs Cycles" in result.stdout


@pytest.mark.parametrize("args, message", [
    (["--engines", "luxcore"], "unknown engine(s) luxcore"),
    (["--resolution", "3"], "--resolution must be between 8 and 4096"),
    (["--samples", "0"], "--samples must be at least 1"),
])
def test_bad_arguments_exit_2_with_a_clear_line(tmp_path, args, message):
    result = run_cli(tmp_path, "--out", str(tmp_path / "x"), *args)
    assert result.returncode == 2
    assert message in result.stderr
    assert "Traceback" not in result.stderr


def test_unwritable_output_folder_exits_2(tmp_path):
    blocker = tmp_path / "file"
    blocker.write_text("not a folder")
    result = run_cli(tmp_path, "--out", str(blocker / "sub"))
    assert result.returncode == 2
    assert "cannot write to output folder" in result.stderr
    assert "Traceback" not in result.stderr
