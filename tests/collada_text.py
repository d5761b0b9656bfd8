# SPDX-License-Identifier: GPL-3.0-or-later
"""Helpers of the COLLADA tests (``test_collada.py``, ``test_collada_files.py``): the test data,
small documents written as text, schema validation, the file's data blocks by kind."""

from __future__ import annotations

import os
import sys

import numpy as np
import pytest

import blender_env as be

from phong_nodes.core import collada


DATA = os.path.join(os.path.dirname(os.path.abspath(__file__)), "data", "collada")
LIT = os.path.join(DATA, "hand_lit.dae")
F32 = np.float32


def _doc(body, asset="", version="1.4.1"):
    ns = collada.NS14 if version == "1.4.1" else collada.NS15
    return (f'<?xml version="1.0"?><COLLADA xmlns="{ns}" version="{version}">'
            f"<asset>{asset}</asset>{body}</COLLADA>").encode()


_VALIDATE = """
import sys
import lxml.etree
from collada import schema
validator = schema.ColladaValidator()
document = lxml.etree.fromstring(sys.stdin.buffer.read())
if not validator.validate(document):
    print(validator.COLLADA_SCHEMA_1_4_1_INSTANCE.error_log)
    sys.exit(1)
"""


def _valid(text):
    """*text* validates against the COLLADA 1.4.1 schema.  In a Python of its own: lxml's
    libxml2 and the one bpy loads clash in one process (a segfault in lxml's XMLSchema once
    Blender has loaded its own, depending on which tests ran before)."""
    import subprocess  # noqa: PLC0415

    be.need_module("lxml")
    be.need_module("collada.schema")
    done = subprocess.run([sys.executable, "-c", _VALIDATE], input=text.encode("utf-8"),
                          capture_output=True, timeout=120)
    assert done.returncode == 0, (done.stdout + done.stderr).decode("utf-8", "replace")[-3000:]


def _f32(values):
    return pytest.approx(tuple(float(v) for v in F32(values)), abs=0)


def be_reset(bpy):
    import blender_env as be  # noqa: PLC0415

    be.reset_empty_file()


def _ids(bpy):
    return {kind: {b.name for b in getattr(bpy.data, kind)} for kind in
            ("objects", "meshes", "materials", "lights", "cameras", "images", "worlds",
             "node_groups")}
