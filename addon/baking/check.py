# SPDX-License-Identifier: GPL-3.0-or-later
"""The check of glTF with Baked Phong Lighting: the .glb rendered by three.js's own
GLTFLoader in headless Chromium (``core/gltf_page.py``, ``core/browser.py``) against Cycles
rendering the baked scene (the objects showing their bakes, ``show.py``) from the same camera
at the same size, one sample at each pixel centre.  Compared on the pixels both cover, in
display values (three.js's canvas is 8-bit sRGB): the verdict asks for at least 99% of them
within 2/255 (``core/compare``'s three.js rule).  Everything the check changes (render
settings, other objects hidden, the materials shown) is put back afterwards."""

from __future__ import annotations

import os
import shutil
import tempfile
import time

import numpy as np

from ...core import browser, compare, gltf_page, report, threejs
from .. import compat
from ..scene import render
from ..scene.render import Overrides, render_exr
from ..interchange import threejs_export
from . import show

def _cycles(scene, objects, width, height, folder) -> np.ndarray:
    """Cycles' RGBA (linear, row 0 at the top) of *scene* with only *objects* showing their
    bakes."""
    o = Overrides()
    shown_before = {obj.name for obj in objects if show.is_shown(obj)}
    try:
        render.plain_picture(scene, width, height, o.set)
        render.exact(scene, "cycles", o.set)
        o.set(scene.render, "film_transparent", True)
        compat.set_multilayer_exr(scene.render.image_settings, o.set)
        baked = set(objects)
        for other in scene.objects:
            if other.type == "MESH" and other not in baked:
                o.set(other, "hide_render", True)
        for obj in objects:
            show.show(obj)
        path = os.path.join(folder, "cycles.exr")
        render_exr(scene, path, o.set)
        passes = compare.read_exr(path)
        os.remove(path)
    finally:
        for obj in objects:
            if obj.name not in shown_before:
                show.restore(obj)
        o.restore()
    return passes["Combined"]


def check(scene, objects, glb_path: str, folder: str, height: int) -> dict:
    """Render *glb_path* (exported from *scene*'s *objects*) in Chromium and the baked scene
    in Cycles, *height* pixels high at the scene's aspect; write ``cycles.png``,
    ``threejs.png``, ``difference.png`` and ``sheet.png`` into *folder*; returns the metrics
    and the verdict.  BrowserError / ThreeMissing when the browser side cannot run."""
    problem = threejs.unavailable()
    if problem is not None:
        raise browser.BrowserError(problem)
    aspect = scene.render.resolution_x / scene.render.resolution_y
    width = max(1, round(height * aspect))
    os.makedirs(folder, exist_ok=True)
    scratch = tempfile.mkdtemp(prefix="phong-gltf-check-")
    try:
        t0 = time.perf_counter()
        cycles = _cycles(scene, objects, width, height, scratch)
        cycles_s = time.perf_counter() - t0
        layer = scene.view_layers[0]
        camera = threejs_export.camera_dict(scene, layer.depsgraph, width, height,
                                            gltf_page.y_up)
        page = gltf_page.write_page(os.path.join(scratch, "page"), glb_path, camera, width,
                                    height)
        # GLTFLoader decodes textures off the main thread after the load event: the DOM is
        # taken when the page says it has finished (a virtual time budget raced the decoding)
        result = browser.render_page(page, until_done=True)
    finally:
        shutil.rmtree(scratch, ignore_errors=True)
    if result.errors:
        raise browser.BrowserError("the glTF page reported: " + "; ".join(result.errors))
    rgba = result.rgba
    if rgba.shape[:2] != (height, width):
        raise browser.BrowserError(f"the glTF page drew {rgba.shape[1]}×{rgba.shape[0]} "
                                   f"pixels, not {width}×{height}")
    covered_cycles = cycles[..., 3] > 0.5
    covered_three = rgba[..., 3] > 0
    both = covered_cycles & covered_three
    metrics = compare.compare_display(rgba, cycles[..., :3], both)
    within = metrics["share_within_2_255"]
    verdict = {"ok": bool(within >= compare.THREEJS_SHARE and metrics["pixels"] > 0),
               "rule": f"≥ {compare.THREEJS_SHARE:.0%} of pixels both cover within 2/255 of "
                       "Cycles",
               "value": f"{within:.3%}"}
    cycles_display = compare.srgb_encode(cycles[..., :3])
    three_display = rgba[..., :3] / 255.0
    difference = report.heatmap(three_display, cycles_display, both)
    report.write_png(os.path.join(folder, "cycles.png"), cycles_display)
    report.write_png(os.path.join(folder, "threejs.png"), three_display)
    report.write_png(os.path.join(folder, "difference.png"), difference)
    tiles = [("Cycles: the baked scene", cycles_display),
             ("three.js GLTFLoader: the .glb", three_display),
             ("|three.js - Cycles| (display)", difference)]
    report.write_png(os.path.join(folder, "sheet.png"), report.sheet(
        tiles, f"glTF with Baked Phong Lighting: {scene.name}",
        f"{verdict['value']} of {metrics['pixels']} pixels within 2/255, max "
        f"{metrics['max_abs'] * 255:.2f}/255", 3))
    return {"metrics": metrics, "verdict": verdict, "size": [width, height],
            "covered": {"cycles": int(covered_cycles.sum()), "threejs": int(covered_three.sum()),
                        "both": int(both.sum())},
            "seconds": {"cycles": cycles_s, "browser": result.seconds}}
