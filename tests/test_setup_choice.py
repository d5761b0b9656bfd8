# SPDX-License-Identifier: GPL-3.0-or-later
"""Which Blender `tools/phong.sh` takes: the newest supported release (requirements/releases.txt,
bpy 5.3 today) on Python 3.13 where one exists, else Python 3.11's newest (bpy 5.0.1); PHONG_BPY
picks a release on the Python its wheels need; a machine without the Python it needs gets one
line naming what to install.  `phong.sh which` prints the choice and changes nothing; each case
runs with a PATH holding only the interpreters it names."""

from __future__ import annotations

import glob
import os
import subprocess
import sys

import pytest

import blender_env as be

SCRIPT = os.path.join(be.REPO_ROOT, "tools", "phong.sh")
_releases = be.supported_releases


def _release_key(bpy: str) -> tuple:
    return tuple(int(part) for part in bpy.split("."))


def test_the_release_list_is_newest_first_with_one_default_per_python():
    rows = _releases()
    versions = [bpy for bpy, _py, _flags in rows]
    assert versions == sorted(versions, key=_release_key, reverse=True), versions
    assert len(set(versions)) == len(versions)
    for python in {py for _bpy, py, _flags in rows}:
        defaults = [bpy for bpy, py, flags in rows if py == python and "default" in flags]
        newest = next(bpy for bpy, py, _flags in rows if py == python)
        assert defaults == [newest], (python, defaults)  # each Python's default is its newest
    assert rows[0][1] == "3.13" and "ci" in rows[0][2]     # the newest release is tested
    for bpy, python, _flags in rows:   # Blender's rule: 5.1 and later on 3.13, before on 3.11
        assert python == ("3.13" if _release_key(bpy) >= (5, 1) else "3.11"), bpy
        assert os.path.exists(os.path.join(be.REPO_ROOT, "requirements", f"python{python}.txt"))


def test_releases_lists_the_flagged_ones():
    out = subprocess.run(["bash", SCRIPT, "releases", "ci"], capture_output=True, text=True,
                         timeout=60, check=True).stdout.split()
    assert out == [bpy for bpy, _py, flags in _releases() if "ci" in flags]
    assert "4.2.23" in out and "5.3.0" in out


def _interpreter(version: str) -> str | None:
    """A real interpreter of Python *version* on this machine (pyenv's, or the system's)."""
    found = sorted(glob.glob(os.path.expanduser(f"~/.pyenv/versions/{version}*/bin/python{version}")))
    found += [p for p in (f"/usr/bin/python{version}", f"/usr/local/bin/python{version}")
              if os.path.exists(p)]
    if sys.version_info[:2] == tuple(map(int, version.split("."))):
        found.append(sys.executable)
    return found[0] if found else None


@pytest.fixture
def machine(tmp_path):
    """run(pythons, **env): `phong.sh which` on a machine whose only Pythons are *pythons*
    ({"3.13": path, ...}): every other program of /usr/bin and /bin is there, no python."""
    bin_dir = tmp_path / "bin"
    bin_dir.mkdir()
    for folder in ("/usr/bin", "/bin"):
        for name in os.listdir(folder):
            target = bin_dir / name
            if not name.startswith("python") and not target.exists():
                target.symlink_to(os.path.join(folder, name))

    def run(pythons: dict, **env):
        for version, path in pythons.items():
            (bin_dir / f"python{version}").symlink_to(path)
        result = subprocess.run(
            ["bash", SCRIPT, "which"], capture_output=True, text=True, timeout=60,
            env={"PATH": str(bin_dir), "HOME": str(tmp_path), "PYENV_ROOT": str(tmp_path / "none"),
                 **env})
        return result.returncode, result.stdout.strip(), result.stderr.strip()

    return run


def _need(*versions):
    paths = {v: _interpreter(v) for v in versions}
    missing = [v for v, p in paths.items() if p is None]
    if missing:
        if os.environ.get("CI"):
            pytest.fail(f"CI needs Python {', '.join(missing)} for this test")
        pytest.skip(f"no Python {', '.join(missing)} on this machine")
    return paths


def test_python_3_13_gives_the_newest_blender(machine):
    code, out, _err = machine(_need("3.13", "3.11"))
    assert code == 0 and out.startswith("bpy 5.3.0 on Python 3.13 ("), out


def test_only_python_3_11_gives_blender_5_0(machine):
    code, out, _err = machine(_need("3.11"))
    assert code == 0 and out.startswith("bpy 5.0.1 on Python 3.11 ("), out
    assert "no Python 3.13 found" in out


def test_phong_bpy_takes_the_python_its_wheels_need(machine):
    pythons = _need("3.13", "3.11")
    assert machine(pythons, PHONG_BPY="4.2.23")[1].startswith("bpy 4.2.23 on Python 3.11 (")
    assert machine({}, PHONG_BPY="5.1.2")[1].startswith("bpy 5.1.2 on Python 3.13 (")  # unlisted
    assert machine({}, PHONG_BPY="5.3.0")[1].startswith("bpy 5.3.0 on Python 3.13 (")


def test_no_usable_python_is_one_line_naming_what_to_install(machine):
    code, out, err = machine({})
    assert code == 2 and out == "" and len(err.splitlines()) == 1, err
    assert "install python3.13" in err


def test_a_release_without_its_python_is_one_line(machine):
    code, out, err = machine(_need("3.13"), PHONG_BPY="4.5.15")
    assert code == 2 and out == "" and len(err.splitlines()) == 1, err
    assert "bpy 4.5.15 needs Python 3.11" in err and "install python3.11" in err


def test_not_a_release(machine):
    code, _out, err = machine({}, PHONG_BPY="latest")
    assert code == 2 and "PHONG_BPY=latest: not a bpy release" in err
