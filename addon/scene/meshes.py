# SPDX-License-Identifier: GPL-3.0-or-later
"""Mesh data for demo scenes, tests and benchmarks, built without operators (runs headless)."""

import bmesh
import bpy


def uv_sphere(name: str, radius: float = 1.0, segments: int = 64, rings: int = 32,
              uvs: bool = False):
    """A smooth-shaded UV sphere mesh; with *uvs* its UV map "UVMap" (Eevee then draws the
    UV seam as a separate edge: a rare pixel along it differs)."""
    mesh = bpy.data.meshes.new(name)
    bm = bmesh.new()
    try:
        if uvs:
            bm.loops.layers.uv.new("UVMap")  # calc_uvs fills the UV layer the BMesh has
        bmesh.ops.create_uvsphere(bm, u_segments=segments, v_segments=rings, radius=radius,
                                  calc_uvs=uvs)
        bm.to_mesh(mesh)
    finally:
        bm.free()
    mesh.shade_smooth()
    return mesh
