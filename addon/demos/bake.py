# SPDX-License-Identifier: GPL-3.0-or-later
"""The comparison bake: Eevee, Cycles and the numpy reference of one demo scene.

* Cycles renders the AOV view layer (1 sample at the pixel centres, box filter 0.01): the
  picture, plus per pixel the position P, shading normal N, incoming I, object colour and
  object index.
* Eevee renders the picture view layer (no AOVs: every AOV costs shader compile time in
  Eevee), 1 TAA sample, filter size 0: its first sample sits at the pixel centre too.
* ``core.compare`` computes the reference picture from Cycles' AOVs and the metrics;
  ``core.report`` writes the pictures, the sheet and metrics.json.

Everything is written into a hidden temporary folder beside the destination and renamed
into place at the end, so an interrupted bake leaves no folder that looks finished.
"""

from __future__ import annotations

import json
import os
import shutil
import tempfile
import time

import bpy

from ...core import compare, outputs, report
from .. import compat
from . import builder, render


# -- rendering ---------------------------------------------------------------------

def configure(scene, engine: str) -> None:
    """Exact-check settings of *engine*; Cycles renders the AOV layer, Eevee the picture."""
    layers = scene.view_layers
    render.exact(scene, engine)
    cycles = engine == "cycles"
    layers[builder.AOV_LAYER].use = cycles
    layers[builder.PICTURE_LAYER].use = not cycles
    builder.set_aov_outputs(scene, cycles)
    compat.set_multilayer_exr(scene.render.image_settings)


def render_exr(scene, path: str) -> None:
    scene.render.filepath = path
    scene.render.use_file_extension = False
    with bpy.context.temp_override(scene=scene):
        bpy.ops.render.render(write_still=True, scene=scene.name)
    if not os.path.exists(path):
        raise RuntimeError(f"the render did not write {path}")


def render_passes(scene, engine: str, folder: str) -> dict:
    """Render *scene* with *engine* into a scratch EXR in *folder*; {pass: array}."""
    configure(scene, engine)
    path = os.path.join(folder, f"{engine}.exr")
    render_exr(scene, path)
    try:
        return compare.read_exr(path)
    finally:
        os.remove(path)


# -- the bake ---------------------------------------------------------------------------

def bake(scene, out_dir: str, engines=compare.ENGINES, progress=None) -> dict:
    """Render and compare *scene* (built by builder.build) into *out_dir* (replaced whole).

    *progress(fraction, text)* is called between steps.  Returns the metrics dict (also
    written as metrics.json).
    """
    data = builder.scene_dict(scene)
    if data is None:
        raise ValueError(f"scene {scene.name!r} is not a Phong demo scene "
                         "(build one with phong.build_demo_scene)")
    engines = [e for e in compare.ENGINES if e in engines]
    progress = progress or (lambda f, t: None)
    parent = os.path.dirname(os.path.abspath(out_dir)) or "."
    os.makedirs(parent, exist_ok=True)
    tmp = tempfile.mkdtemp(prefix=outputs.temp_prefix("partial", os.path.basename(out_dir)),
                           dir=parent)
    timings = {}
    try:
        t0 = time.perf_counter()
        progress(0.05, "Cycles (picture + AOVs)")
        aovs = render_passes(scene, "cycles", tmp)
        images = {"cycles": aovs["Combined"][..., :3]}
        timings["cycles_s"] = time.perf_counter() - t0
        if "eevee" in engines:
            t0 = time.perf_counter()
            progress(0.35, "Eevee (picture)")
            images["eevee"] = render_passes(scene, "eevee", tmp)["Combined"][..., :3]
            timings["eevee_s"] = time.perf_counter() - t0
            configure(scene, "cycles")  # leave the AOV outputs on for the user

        t0 = time.perf_counter()
        progress(0.7, "reference and report")
        metrics, refimg, mask = compare.evaluate(data, images, aovs, engines)
        metrics["resolution"] = [scene.render.resolution_x, scene.render.resolution_y]
        timings["reference_s"] = time.perf_counter() - t0
        t0 = time.perf_counter()
        report.write_scene(tmp, data, images, refimg, mask, metrics)
        timings["report_s"] = time.perf_counter() - t0
        metrics["timings"] = timings
        with open(os.path.join(tmp, "metrics.json"), "w", encoding="utf-8") as handle:
            json.dump(metrics, handle, indent=2, ensure_ascii=False)
        progress(0.95, "finishing")
        outputs.replace_dir(tmp, out_dir)
    except BaseException:
        shutil.rmtree(tmp, ignore_errors=True)
        raise
    progress(1.0, "done")
    return metrics
