# SPDX-License-Identifier: GPL-3.0-or-later
"""Render settings under which Eevee and Cycles shade exactly the pixel centres.

Cycles: one sample, no denoiser, a box filter narrower than a pixel, so each pixel is
the shader evaluated at its centre.  Eevee: one TAA sample (its first sample sits at
the pixel centre), no filter, nothing that adds light, and high-quality GPU normals
(with the default ones narrow highlights differ from Cycles by up to 1e-2).
"""

from .. import compat

_EEVEE_OFF = ("use_shadows", "use_raytracing", "use_gtao", "use_bloom", "use_volumetric_shadows")


def plain_picture(scene, width: int, height: int) -> None:
    """Pixels that are the shader's values: square pixels, no compositing, sequencer,
    dithering or transparency, Standard view transform without look, exposure or gamma."""
    r = scene.render
    r.resolution_x, r.resolution_y, r.resolution_percentage = width, height, 100
    r.pixel_aspect_x = r.pixel_aspect_y = 1.0
    r.film_transparent = False
    r.use_compositing = False
    r.use_sequencer = False
    r.dither_intensity = 0.0
    view = scene.view_settings
    view.view_transform = "Standard"
    view.look = "None"
    view.exposure = 0.0
    view.gamma = 1.0


def exact(scene, engine: str) -> None:
    """Configure *scene* for an exact check with *engine* ('cycles' or 'eevee')."""
    if engine == "cycles":
        scene.render.engine = "CYCLES"
        cy = scene.cycles
        cy.device = "CPU"
        cy.samples = 1
        cy.use_denoising = False
        cy.use_adaptive_sampling = False
        cy.pixel_filter_type = "BOX"
        cy.filter_width = 0.01
        cy.max_bounces = 0
        cy.seed = 0
        if hasattr(cy, "use_light_tree"):
            cy.use_light_tree = False
    elif engine == "eevee":
        scene.render.engine = compat.eevee_engine()
        scene.eevee.taa_render_samples = 1
        scene.render.filter_size = 0.0
        if hasattr(scene.render, "use_high_quality_normals"):
            scene.render.use_high_quality_normals = True
        for attr in _EEVEE_OFF:
            if hasattr(scene.eevee, attr):
                setattr(scene.eevee, attr, False)
    else:
        raise ValueError(f"unknown engine {engine!r}: expected 'cycles' or 'eevee'")
