# SPDX-License-Identifier: GPL-3.0-or-later
"""Shared fixtures: install the extension like a user, once per session.

``bpy`` is imported lazily (only by the fixtures below), so the pure-numpy tests
(tests/test_reference.py) run without touching Blender.  Before the first ``import bpy``
``BLENDER_USER_RESOURCES`` points at a fresh temp folder so the user's own Blender
configuration is neither read nor written.

Environment knobs:
  PHONG_EXT_SOURCE   build the zip from this folder instead of the repository root.
"""

from __future__ import annotations

import os
import shutil
import sys
import tempfile
import time

import pytest

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))

import blender_env as be  # noqa: E402  (pure python: bpy is imported lazily inside)

_USER_RES = None
SUMMARY: list[str] = []  # lines for the terminal summary (renders, errors per group)


def _user_resources() -> str:
    global _USER_RES
    if _USER_RES is None:
        if "bpy" in sys.modules:
            raise RuntimeError("bpy was imported before BLENDER_USER_RESOURCES was set")
        _USER_RES = tempfile.mkdtemp(prefix="phong_user_res_")
        os.environ["BLENDER_USER_RESOURCES"] = _USER_RES
    return _USER_RES


# Set at conftest import: pytest's Package node for the repository root (which has an
# __init__.py, the extension's) imports that __init__.py -- and so bpy -- at setup time, before
# any fixture runs.  bpy itself is still imported lazily.
_user_resources()


def report(line: str) -> None:
    """Record a line for the end-of-run summary (and print it for -s)."""
    SUMMARY.append(line)
    print(line)


class Installed:
    """What the session install produced (the tests assert on it)."""

    def __init__(self, zip_path, build_output, validate_result, names, seconds):
        self.zip_path = zip_path
        self.build_output = build_output
        self.validate = validate_result
        self.names = names
        self.seconds = seconds


@pytest.fixture(scope="session")
def blender_tmp(tmp_path_factory):
    return tmp_path_factory.mktemp("blender")


@pytest.fixture(scope="session")
def installed(blender_tmp) -> Installed:
    """Build the zip with Blender's extension tool, validate it, install and enable it."""
    _user_resources()
    t0 = time.perf_counter()
    bpy = be.import_bpy()
    source = os.environ.get("PHONG_EXT_SOURCE", be.REPO_ROOT)
    out_dir = str(blender_tmp / "dist")
    os.makedirs(out_dir, exist_ok=True)
    zip_path = be.build_zip(source, out_dir)
    val = be.validate_zip(zip_path)
    names = be.zip_names(zip_path)
    bpy.ops.wm.read_homefile(use_empty=True)
    be.install_zip(zip_path)
    seconds = time.perf_counter() - t0
    report(f"[install] build+validate+install {seconds:.1f} s ({zip_path})")
    return Installed(zip_path, None, val, names, seconds)


@pytest.fixture
def bpy_clean(installed):
    """An empty file with the add-on still enabled (function scope)."""
    be.reset_empty_file()
    assert be.addon_enabled(), f"{be.EXT_MODULE} not enabled after resetting the file"
    return be.import_bpy()


@pytest.fixture(autouse=True)
def _reset_blender(request):
    """Reset Blender to an empty file between Blender tests (not for pure-numpy tests)."""
    uses_blender = any(name in request.fixturenames for name in ("installed", "bpy_clean"))
    if uses_blender and "bpy" in sys.modules:
        be.reset_empty_file()
    yield


def pytest_configure(config):
    for marker in ("cycles: renders with Cycles", "eevee: renders with Eevee",
                   "slow: takes more than a few seconds"):
        config.addinivalue_line("markers", marker)


def pytest_terminal_summary(terminalreporter, exitstatus, config):
    if SUMMARY:
        terminalreporter.section("Phong render summary")
        for line in SUMMARY:
            terminalreporter.write_line(line)


def pytest_sessionfinish(session, exitstatus):
    if _USER_RES and os.path.isdir(_USER_RES):
        shutil.rmtree(_USER_RES, ignore_errors=True)
