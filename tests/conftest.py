# SPDX-License-Identifier: GPL-3.0-or-later
"""Shared fixtures: the extension enabled from this source tree, once per session.

The tests import the extension by its name, ``phong_nodes`` (``tools/phong.sh setup`` makes
the source tree that package in the virtual environment), and Blender enables that same
package: every file has one module name.  ``tests/test_install.py`` installs the built zip
as a user would, in a process of its own.

``bpy`` is imported lazily (only by the fixtures below), so the pure tests run without
touching Blender.  Before the first ``import bpy`` ``BLENDER_USER_RESOURCES`` points at a
fresh temp folder so the user's own Blender configuration is neither read nor written.
"""

from __future__ import annotations

import os
import shutil
import sys

import pytest

import blender_env as be

# Set at conftest import: pytest's Package node for the repository root (which has an
# __init__.py, the extension's) imports it at setup time; it does not import bpy, but set
# the folder before anything can.
be.user_resources()


@pytest.fixture(scope="session")
def blender_tmp(tmp_path_factory):
    return tmp_path_factory.mktemp("blender")


@pytest.fixture(scope="session")
def extension():
    """The extension enabled in Blender (from this source tree); returns bpy.  Disabled again
    at the end of the session: register and unregister are symmetric (and bpy 4.2 crashes at
    exit with an operator class still registered)."""
    be.enable()
    yield be.import_bpy()
    be.disable()


@pytest.fixture
def bpy_clean(extension):
    """An empty file with the extension still enabled (function scope)."""
    be.reset_empty_file()
    assert be.addon_enabled(), f"{be.EXT_MODULE} not enabled after resetting the file"
    return extension


@pytest.fixture(autouse=True)
def _reset_blender(request):
    """Reset Blender to an empty file between Blender tests (not for pure tests)."""
    uses_blender = any(name in request.fixturenames for name in ("extension", "bpy_clean"))
    if uses_blender and "bpy" in sys.modules:
        be.reset_empty_file()
    yield


def pytest_terminal_summary(terminalreporter, exitstatus, config):
    if be.SUMMARY:
        terminalreporter.section("Phong render summary")
        for line in be.SUMMARY:
            terminalreporter.write_line(line)


def pytest_sessionfinish(session, exitstatus):
    _STATUS[0] = int(exitstatus)
    if hasattr(session.config, "workeroutput"):  # an xdist worker: its lines go to the controller
        session.config.workeroutput["phong_summary"] = list(be.SUMMARY)
    folder = be.user_resources(create=False)
    if folder and os.path.isdir(folder):
        shutil.rmtree(folder, ignore_errors=True)


@pytest.hookimpl(optionalhook=True)
def pytest_testnodedown(node, error):
    """pytest-xdist (``tools/phong.sh test`` runs the quick tests on two processes): each
    worker's render summary lines, printed by the controller's summary above."""
    be.SUMMARY.extend(getattr(node, "workeroutput", {}).get("phong_summary", []))


@pytest.hookimpl(trylast=True)
def pytest_unconfigure(config):
    """Blender 4.2 crashes in its clean-up at exit once its glTF exporter has exported (the
    bake tests export glTF; see compat.exit_crashes): then leave with pytest's own status,
    everything being reported by now.  Elsewhere Python ends as usual."""
    if "bpy" in sys.modules:
        from phong_nodes.addon import compat  # noqa: PLC0415

        compat.leave_if_exit_crashes(_STATUS[0])


_STATUS = [0]
