# SPDX-License-Identifier: GPL-3.0-or-later
"""Helpers of the pure VRML97 / X3D tests (``test_x3d_core.py``, ``test_x3d_files.py``): scenes
written as text, read through ``core.x3d``, and matrices worked out independently of it."""

from __future__ import annotations

import math
import os
import time

import numpy as np

from phong_nodes.core import x3d

DATA = os.path.join(os.path.dirname(os.path.abspath(__file__)), "data", "x3d")
VRML = "#VRML V2.0 utf8\n"
X3DV = "#X3D V3.3 utf8\nPROFILE Immersive\n"


def xml(scene: str, head: str = "", version: str = "3.3") -> str:
    return (f'<?xml version="1.0" encoding="UTF-8"?>\n<X3D profile="Immersive" '
            f'version="{version}"><head>{head}</head><Scene>{scene}</Scene></X3D>')


def read(text, name="scene.wrl", folder="/nonexistent-folder"):
    return x3d.loads(text, os.path.join(str(folder), name))


def write(folder, name, text) -> str:
    path = os.path.join(str(folder), name)
    with open(path, "wb" if isinstance(text, bytes) else "w") as handle:
        handle.write(text)
    return path


def timed(function, *args, limit=2.0):
    """function(*args), asserting that it returns within *limit* seconds of this process's
    CPU time (a guard against work that explodes, such as a DEF/USE bomb: CPU time, not the
    wall clock, so that other processes on a loaded machine do not make it fail)."""
    start = time.process_time()
    result = function(*args)
    elapsed = time.process_time() - start
    assert elapsed < limit, f"took {elapsed:.2f} s of CPU time (limit {limit} s)"
    return result


def warned(doc, *words) -> str:
    """The one warning that holds all *words* (asserting there is one)."""
    hits = [w for w in doc.warnings if all(word in w for word in words)]
    assert len(hits) == 1, f"{words} in {doc.warnings}"
    return hits[0]


def kinds(doc) -> list:
    return [inst.shape.geometry.kind for inst in doc.instances]


def rot(axis, angle) -> np.ndarray:
    """Rodrigues' rotation (written here, independently of the module), 4×4."""
    x, y, z = np.asarray(axis, float) / np.linalg.norm(axis)
    k = np.array([[0, -z, y], [z, 0, -x], [-y, x, 0]])
    out = np.eye(4)
    out[:3, :3] = np.eye(3) + math.sin(angle) * k + (1 - math.cos(angle)) * (k @ k)
    return out


def move(v) -> np.ndarray:
    out = np.eye(4)
    out[:3, 3] = v
    return out


def faces(mesh) -> list:
    """The faces of *mesh* as lists of corner indices."""
    out, start = [], 0
    for size in mesh.face_sizes.tolist():
        out.append(mesh.corners[start:start + size].tolist())
        start += size
    return out
