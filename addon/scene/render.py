# SPDX-License-Identifier: GPL-3.0-or-later
"""Render settings under which Eevee and Cycles shade exactly the pixel centres.

Cycles: one sample, no denoiser, a box filter narrower than a pixel, so each pixel is
the shader evaluated at its centre; SVM, not Open Shading Language (OSL writes no AOVs).
Eevee: one TAA sample (its first sample sits at the pixel centre), no filter, nothing that
adds light, and high-quality GPU normals (with the default ones narrow highlights differ from
Cycles by up to 1e-2).
:class:`Overrides` changes settings for a while and puts them back (the comparison,
Bake Phong Lighting).
"""

import os

import bpy

from .. import compat
from ..lighting import loop as light_loop
from ..lighting import rig, shadows


class Overrides:
    """Settings changed for a bake and put back in reverse order by :meth:`restore`."""

    def __init__(self):
        self._undo = []

    def set(self, owner, attr: str, value) -> None:
        if not hasattr(owner, attr):
            return
        old = getattr(owner, attr)
        if hasattr(old, "__len__") and not isinstance(old, str):
            old = tuple(old)
        if old == value:
            return
        setattr(owner, attr, value)
        self._undo.append(lambda: setattr(owner, attr, old))

    def later(self, function) -> None:
        """Call *function* on restore (after the settings made after it are put back)."""
        self._undo.append(function)

    def restore(self) -> None:
        """Put everything back; an enum that must wait for another (an EXR colour depth
        for a PNG) gets a second pass."""
        failed = []
        for undo in reversed(self._undo):
            try:
                undo()
            except (TypeError, ValueError, RuntimeError):
                failed.append(undo)
            except ReferenceError:  # its data block was deleted meanwhile
                pass
        for undo in failed:
            try:
                undo()
            except (TypeError, ValueError, RuntimeError, ReferenceError):
                pass
        self._undo.clear()


_EEVEE_OFF = ("use_shadows", "use_raytracing", "use_gtao", "use_bloom", "use_volumetric_shadows")


def _set_all(owner, values: dict, set_) -> None:
    for attr, value in values.items():
        if hasattr(owner, attr):
            set_(owner, attr, value)


def plain_picture(scene, width: int, height: int, set_=setattr) -> None:
    """Pixels that are the shader's values: square pixels, no border, compositing,
    sequencer, motion blur, simplify, dithering or transparency, Standard view transform
    without look, exposure or gamma.  *set_(owner, attribute, value)* does the setting (the
    bake passes one that remembers the old values)."""
    _set_all(scene.render, {
        "resolution_x": width, "resolution_y": height, "resolution_percentage": 100,
        "pixel_aspect_x": 1.0, "pixel_aspect_y": 1.0, "use_border": False,
        "film_transparent": False, "use_compositing": False, "use_sequencer": False,
        "use_motion_blur": False, "use_simplify": False, "dither_intensity": 0.0}, set_)
    _set_all(scene.view_settings, {"view_transform": "Standard", "look": "None",
                                   "exposure": 0.0, "gamma": 1.0, "use_curve_mapping": False},
             set_)


def exact(scene, engine: str, set_=setattr) -> None:
    """Configure *scene* for an exact check with *engine* ('cycles' or 'eevee')."""
    if engine == "cycles":
        set_(scene.render, "engine", "CYCLES")
        _set_all(scene.cycles, {
            "device": "CPU", "samples": 1, "use_denoising": False,
            "use_adaptive_sampling": False, "pixel_filter_type": "BOX", "filter_width": 0.01,
            "max_bounces": 0, "seed": 0, "use_animated_seed": False, "film_exposure": 1.0,
            "use_light_tree": False,
            # Open Shading Language writes no AOVs (the term passes, the probes): SVM
            "shading_system": False}, set_)
    elif engine == "eevee":
        set_(scene.render, "engine", compat.eevee_engine())
        set_(scene.eevee, "taa_render_samples", 1)
        _set_all(scene.render, {"filter_size": 0.0, "use_high_quality_normals": True}, set_)
        _set_all(scene.eevee, {attr: False for attr in _EEVEE_OFF}, set_)
        if eevee_shadows(scene):  # the light loop's Shadow Raycast reads the shadow maps
            _set_all(scene.eevee, {"use_shadows": True, "shadow_resolution_scale": 1.0,
                                   "shadow_ray_count": 1, "shadow_step_count": 16}, set_)
            # the model's shadows are hard: no filter of the shadow maps' edges (a real
            # character file with Blender's default filter radius of 1: 99.15% of the
            # pixels within 1/255, with 0: 99.57%)
            for light in {o.data for o in scene.objects if o.type == "LIGHT"}:
                _set_all(light, {"shadow_filter_radius": 0.0}, set_)
    else:
        raise ValueError(f"unknown engine {engine!r}: expected 'cycles' or 'eevee'")


#: The note of a comparison (or bake) of a scene whose Cycles uses Open Shading Language.
OSL_NOTE = ("Cycles rendered with SVM: the scene's Open Shading Language writes no AOVs "
            "(its setting is put back afterwards)")


def uses_osl(scene) -> bool:
    """Whether *scene*'s Cycles shades with Open Shading Language (``exact`` turns it off)."""
    return bool(getattr(getattr(scene, "cycles", None), "shading_system", False))


def eevee_shadows(scene) -> bool:
    """Whether Eevee shows shadows on *scene*'s Phong materials: a lights group of it has the
    loop part with its Shadow Raycast (Blender 5.3+, ``lighting/loop.py``)."""
    return any(light_loop.has_loop(tree) and shadows.has_shadows(tree)
               for tree in rig.groups_of(scene))


def render_exr(scene, path: str, set_=setattr) -> None:
    """Render *scene* into the file *path* with its output settings."""
    set_(scene.render, "filepath", path)
    set_(scene.render, "use_file_extension", False)
    with bpy.context.temp_override(scene=scene):
        bpy.ops.render.render(write_still=True, scene=scene.name)
    if not os.path.exists(path):
        raise RuntimeError(f"the render did not write {path}")
