# SPDX-License-Identifier: GPL-3.0-or-later
"""Mesh data for demo scenes, tests and benchmarks, built without operators (runs headless)."""

import bmesh
import bpy


def uv_sphere(name: str, radius: float = 1.0, segments: int = 64, rings: int = 32):
    """A smooth-shaded UV sphere mesh with UVs."""
    mesh = bpy.data.meshes.new(name)
    bm = bmesh.new()
    try:
        bmesh.ops.create_uvsphere(bm, u_segments=segments, v_segments=rings, radius=radius,
                                  calc_uvs=True)
        bm.to_mesh(mesh)
    finally:
        bm.free()
    mesh.shade_smooth()
    return mesh
