# SPDX-License-Identifier: GPL-3.0-or-later
"""X_ITE as a peer of the comparison: the scene exported as X3D by the
extension's own exporter (``interchange/x3d_export.py``, the code of *File ▸ Export ▸ X3D /
VRML97 (Phong)*), that file rendered by the X3D browser X_ITE in headless Chromium
(``core/x_ite.py``) at the comparison's size.  The file and the page stay in the report folder
(``x_ite/scene.x3d``, ``x_ite/scene.html``), and the exporter's warnings go into
metrics.json.

The export runs with the scene's render size set to the comparison's (and put back after), so
that the Viewpoint's ``fieldOfView`` (the angle of the picture's smaller side) is the one of the
picture X_ITE draws, and with every face set ``solid FALSE`` (Backface Culling off meanwhile):
the comparison judges both sides of every face, as Cycles draws them.
"""

from __future__ import annotations

import os
from types import SimpleNamespace

import bpy

from ...core import x_ite
from ..interchange import x3d_export


def render(scene, layer, objects, data, width: int, height: int, folder: str) -> tuple:
    """(X_ITE's RGBA picture (row 0 at the top; its canvas holds the equation's I), seconds in
    the browser, warnings): the scene exported into *folder*/x_ite/scene.x3d and rendered.
    *objects* and *data* (the comparison's Phong objects and their description) are not needed
    by the exporter, which writes every visible object and light of *layer*, as File ▸ Export
    does."""
    del objects, data
    path = os.path.join(folder, "x_ite", "scene.x3d")
    os.makedirs(os.path.dirname(path), exist_ok=True)
    warnings = write(scene, layer, width, height, path)
    result = x_ite.render_file(path, width, height,
                               page_path=os.path.join(folder, "x_ite", "scene.html"))
    return result.rgba, result.seconds, warnings + [f"X_ITE: {e}" for e in result.errors]


def write(scene, layer, width: int, height: int, path: str) -> list:
    """Export *scene* (view layer *layer*) as X3D XML to *path* at a render size of
    width × height; returns the exporter's warnings."""
    render = scene.render
    saved = (render.resolution_x, render.resolution_y, render.resolution_percentage)
    # every face set solid FALSE: the comparison judges both sides of every face, as Cycles
    # draws them whatever Backface Culling says (engine._culled)
    culled = [m for m in bpy.data.materials if m.use_backface_culling]
    try:
        render.resolution_x, render.resolution_y = int(width), int(height)
        render.resolution_percentage = 100
        for material in culled:
            material.use_backface_culling = False
        # the page draws no shadows: the comparison leaves the shadowed pixels out
        return list(x3d_export.export(SimpleNamespace(scene=scene, view_layer=layer), path,
                                      shadows=False))
    finally:
        render.resolution_x, render.resolution_y, render.resolution_percentage = saved
        for material in culled:
            material.use_backface_culling = True
