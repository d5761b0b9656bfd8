# SPDX-License-Identifier: GPL-3.0-or-later
"""What a uniform World gives a Principled BSDF, as a Phong ambient colour Ka.

Under a World of one colour L, Cycles shows a Principled surface (Diffuse Roughness 0, no
coat, sheen or transmission) seen along a direction of cosine mu as

    L * [ (1 - m) * (Kd * (1 - max_c E_c(mu)) + E_c(mu)) + m * M_c(mu) ]

Kd the Base Color, m the Metallic, E_c(mu) the albedo of the dielectric specular layer in
channel c (the share of the World it reflects towards the eye) and M_c(mu) the metal's.  The
diffuse base is attenuated by the layer above it by the largest channel of its albedo, as
Cycles layers closures (``closure_layering_weight``: one scalar, so a tinted layer does not
tint what is under it).  Phong's ambient term is L * Ka with no view direction, so Ka is that
bracket averaged over the view directions of a hemisphere, cosine-weighted (what an
orthographic camera sees of a sphere, pixel for pixel):

    Ka = Kd * scale + offset

with *scale* and *offset* per channel (:func:`principled_ambient`); Ka = Kd exactly when the
specular layer reflects nothing (Specular IOR Level 0) and the surface is no metal.

The specular layer, as Cycles builds it for the Principled BSDF (Blender 4.0 on):

* GGX microfacets of alpha = Roughness², height-correlated Smith masking-shadowing
  G2 = 1 / (1 + Lambda(wi) + Lambda(wo));
* dielectric: F0 = ((IOR - 1) / (IOR + 1))² × 2 × Specular IOR Level, the index of that F0
  taken as the layer's index, and the Fresnel term mix(F0 × Specular Tint, 1, s) with
  s = (F_dielectric(cos) - F0) / (1 - F0) (white Specular Tint: the exact dielectric Fresnel);
* metal: the F82-tint Fresnel of Kutz et al. (2021) with F0 = Base Color and F82 = Specular
  Tint: F = F0 + (1 - F0)(1 - cos)^5 - b cos (1 - cos)^6;
* Multiscatter GGX (the default distribution): each lobe scaled by 1 + Fms (1 - E1) / E1
  (Kulla and Conty 2017, "Revisiting Physically Based Shading at Imageworks"), E1 the albedo
  of the lobe with F = 1, Fms = Fss E1avg / (1 - Fss (1 - E1avg)), Fss the Fresnel term
  averaged over the hemisphere; plain GGX: no such scale.

The albedos are integrated numerically here once per process (numpy, Gauss-Legendre over the
microfacet normal's GGX distribution and over mu; :func:`tables`, about a quarter of a second)
on a grid of Roughness and F0, and interpolated linearly between its nodes.
"""

from __future__ import annotations

import functools
import math

import numpy as np

#: Grid of the tables: Roughness (Cycles' perceptual roughness, alpha = Roughness²) and the
#: dielectric F0 (finer near 0, where real materials are: F0 = t² for t on an even grid).
ROUGHNESS = np.linspace(0.0, 1.0, 21)
F0 = np.linspace(0.0, 1.0, 21) ** 2
#: Quadrature points: the view cosine mu (cosine-weighted average), the microfacet normal's
#: GGX distribution (u) and azimuth (phi).
MU_POINTS, U_POINTS, PHI_POINTS = 24, 64, 32
#: F82-tint's angle: cos = 1/7 (Kutz et al. 2021).
F82_COS = 1.0 / 7.0


def _gauss(n, a, b):
    x, w = np.polynomial.legendre.leggauss(n)
    return 0.5 * (b - a) * x + 0.5 * (b + a), 0.5 * (b - a) * w


def fresnel_dielectric(cos, eta):
    """The unpolarised Fresnel reflectance of a dielectric of relative index *eta* (≥ 1) at
    the incidence cosine *cos* (arrays broadcast)."""
    c = np.abs(cos)
    g2 = eta * eta - 1.0 + c * c
    g = np.sqrt(np.maximum(g2, 0.0))
    a = (g - c) / np.maximum(g + c, 1e-300)
    b = (c * (g + c) - 1.0) / np.maximum(c * (g - c) + 1.0, 1e-300)
    return np.where(g2 > 0.0, 0.5 * a * a * (1.0 + b * b), 1.0)


def ior_of_f0(f0):
    """The index whose normal-incidence reflectance is *f0* (0 ≤ f0 < 1)."""
    r = np.sqrt(np.clip(f0, 0.0, 0.999999))
    return (1.0 + r) / (1.0 - r)


def _lambda(alpha2, cos):
    cos2 = np.clip(cos * cos, 1e-12, 1.0)
    return 0.5 * (np.sqrt(1.0 + alpha2 * (1.0 / cos2 - 1.0)) - 1.0)


@functools.cache
def tables():
    """The integrals, once: a dict of arrays over (roughness, mu) or (roughness, F0, mu):
    "mu", "mu_weight" (cosine-weighted averaging weights over mu, summing to 1), "one" (the
    single-scattering albedo with F = 1: E1), "p5" (with F = (1 - cos)^5), "p6" (with
    F = cos (1 - cos)^6), "s" (with the dielectric's s of each F0 of :data:`F0`), and
    "fss" (per F0: the dielectric Fresnel averaged over the hemisphere)."""
    mu, wmu = _gauss(MU_POINTS, 0.0, 1.0)
    mu_weight = 2.0 * mu * wmu
    mu_weight /= mu_weight.sum()
    u, wu = _gauss(U_POINTS, 0.0, 1.0)
    phi, wphi = _gauss(PHI_POINTS, 0.0, math.pi)
    wphi = wphi / math.pi
    etas = ior_of_f0(F0)
    one = np.zeros((len(ROUGHNESS), MU_POINTS))
    p5, p6 = np.zeros_like(one), np.zeros_like(one)
    s = np.zeros((len(ROUGHNESS), len(F0), MU_POINTS))
    weight = (wu[:, None] * wphi[None, :])[None]  # (1, u, phi)
    sin_phi, cos_phi = np.sin(phi)[None, None, :], np.cos(phi)[None, None, :]
    for i, rough in enumerate(ROUGHNESS):
        alpha2 = rough ** 4
        # the microfacet normal h: tan² theta_h = alpha² u / (1 - u) samples D(h) cos theta_h
        tan2 = alpha2 * u / (1.0 - u)
        cos_h = (1.0 / np.sqrt(1.0 + tan2))[None, :, None]
        sin_h = np.sqrt(np.maximum(0.0, 1.0 - cos_h * cos_h))
        m = mu[:, None, None]
        sin_i = np.sqrt(np.maximum(0.0, 1.0 - m * m))
        # wi = (sin_i, 0, mu); h = (sin_h cos phi, sin_h sin phi, cos_h)
        i_dot_h = sin_i * sin_h * cos_phi + m * cos_h
        cos_o = 2.0 * i_dot_h * cos_h - m  # wo = 2 (wi·h) h - wi, its z
        valid = (i_dot_h > 0.0) & (cos_o > 0.0)
        g2 = 1.0 / (1.0 + _lambda(alpha2, m) + _lambda(alpha2, np.maximum(cos_o, 1e-9)))
        integrand = np.where(valid, g2 * i_dot_h / (m * cos_h), 0.0) * weight
        c = np.clip(i_dot_h, 0.0, 1.0)
        one[i] = integrand.sum(axis=(1, 2))
        p5[i] = (integrand * (1.0 - c) ** 5).sum(axis=(1, 2))
        p6[i] = (integrand * c * (1.0 - c) ** 6).sum(axis=(1, 2))
        for j, (f0, eta) in enumerate(zip(F0, etas)):
            if f0 <= 0.0:
                continue  # eta 1: no reflection, s = 0
            shape = (fresnel_dielectric(c, eta) - f0) / (1.0 - f0) if f0 < 1.0 else \
                np.ones_like(c)
            s[i, j] = (integrand * shape).sum(axis=(1, 2))
    fss = np.array([float((mu_weight * fresnel_dielectric(mu, eta)).sum()) if f0 > 0 else 0.0
                    for f0, eta in zip(F0, etas)])
    return {"mu": mu, "mu_weight": mu_weight, "one": one, "p5": p5, "p6": p6, "s": s,
            "fss": fss}


def _interp_rough(array, roughness):
    """*array* (over ROUGHNESS first) at *roughness*, linearly."""
    x = float(np.clip(roughness, 0.0, 1.0)) * (len(ROUGHNESS) - 1)
    i = min(int(x), len(ROUGHNESS) - 2)
    t = x - i
    return (1.0 - t) * array[i] + t * array[i + 1]


def _interp_f0(array, f0):
    """*array* (over F0 first) at *f0*, linearly in F0."""
    f0 = float(np.clip(f0, 0.0, 1.0))
    j = min(int(np.searchsorted(F0, f0, side="right")) - 1, len(F0) - 2)
    t = (f0 - F0[j]) / (F0[j + 1] - F0[j])
    return (1.0 - t) * array[j] + t * array[j + 1]


def _multiscatter(one_mu, weights, fss):
    """(1 - E1) / E1 per mu, and Fms per channel, for the Fresnel averages *fss*."""
    e1 = np.maximum(one_mu, 1e-6)
    e1_avg = float((weights * one_mu).sum())
    fms = fss * e1_avg / (1.0 - fss * (1.0 - e1_avg))
    return (1.0 - e1) / e1, fms


def dielectric_albedo(roughness, ior, level, tint=(1.0, 1.0, 1.0), multiscatter=True):
    """(3 channels, mu) array: the albedo E_c(mu) of Principled's dielectric specular layer
    at the view cosines ``tables()["mu"]``."""
    t = tables()
    f0 = ((ior - 1.0) / (ior + 1.0)) ** 2 * 2.0 * max(0.0, level) if ior > 0 else 0.0
    f0 = min(f0, float(F0[-1]))
    tint = np.clip(np.asarray(tint, dtype=float)[:3], 0.0, None)
    if f0 <= 0.0:
        return np.zeros((3, len(t["mu"])))
    one = _interp_rough(t["one"], roughness)
    s = _interp_f0(_interp_rough(t["s"], roughness), f0)
    f0_c = (f0 * tint)[:, None]
    single = f0_c * (one - s)[None] + s[None]  # F = mix(f0 tint, 1, s), linear in F
    if not multiscatter:
        return single
    fss_diel = float(_interp_f0(t["fss"], f0))
    fss = tint * f0 + (1.0 - tint * f0) * np.clip((fss_diel - f0) / (1.0 - f0), 0.0, 1.0)
    missing, fms = _multiscatter(one, t["mu_weight"], fss)
    return single * (1.0 + fms[:, None] * missing[None])


def metal_albedo(roughness, base, f82=(1.0, 1.0, 1.0), multiscatter=True):
    """(3 channels, mu) array: the albedo M_c(mu) of Principled's metal lobe (F82-tint
    Fresnel, F0 *base*, F82 *f82*)."""
    t = tables()
    f0 = np.clip(np.asarray(base, dtype=float)[:3], 0.0, 1.0)[:, None]
    f82 = np.clip(np.asarray(f82, dtype=float)[:3], 0.0, 1.0)[:, None]
    one, p5, p6 = (_interp_rough(t[k], roughness)[None] for k in ("one", "p5", "p6"))
    f = 1.0 - F82_COS
    schlick_82 = f0 + (1.0 - f0) * f ** 5
    b = schlick_82 * (1.0 - f82) / (F82_COS * f ** 6)
    single = f0 * (one - p5) + p5 - b * p6
    if not multiscatter:
        return single
    fss = (f0 + (1.0 - f0) / 21.0 - b / 126.0)[:, 0]  # F averaged over the hemisphere
    missing, fms = _multiscatter(one[0], t["mu_weight"], fss)
    return single * (1.0 + fms[:, None] * missing[None])


def principled_ambient(roughness=0.5, ior=1.5, level=0.5, tint=(1.0, 1.0, 1.0), metallic=0.0,
                       base=(0.8, 0.8, 0.8), multiscatter=True):
    """(scale, offset), 3 floats each: a Principled BSDF's ambient colour under a uniform
    World is Ka = Kd * scale + offset (module text), Kd its Base Color.  The metal part is
    linear in the base colour only up to its multiple scattering, taken at *base* (which
    only a metal reads).  Remembered per distinct value (0.4 ms each otherwise: a file's
    thousands of materials mostly share their settings)."""
    metallic = float(np.clip(metallic, 0.0, 1.0))
    base = tuple(float(v) for v in tuple(base)[:3]) if metallic > 0.0 else None
    return _principled_ambient(float(roughness), float(ior), float(level),
                               tuple(float(v) for v in tuple(tint)[:3]), metallic, base,
                               bool(multiscatter))


@functools.lru_cache(maxsize=4096)
def _principled_ambient(roughness, ior, level, tint, metallic, base, multiscatter):
    t = tables()
    w = t["mu_weight"]
    roughness = float(np.clip(roughness, 0.0, 1.0))
    metallic = float(np.clip(metallic, 0.0, 1.0))
    dielectric = dielectric_albedo(roughness, float(ior), float(level), tint, multiscatter)
    under = 1.0 - float((w * np.clip(dielectric.max(axis=0), 0.0, 1.0)).sum())
    scale = np.full(3, (1.0 - metallic) * under)
    offset = (1.0 - metallic) * (dielectric * w[None]).sum(axis=1)
    if metallic > 0.0:
        base = np.clip(np.asarray(base, dtype=float)[:3], 0.0, 1.0)
        metal = (metal_albedo(roughness, base, tint, multiscatter) * w[None]).sum(axis=1)
        zero = (metal_albedo(roughness, np.zeros(3), tint, multiscatter) * w[None]).sum(axis=1)
        whole = (metal_albedo(roughness, np.ones(3), tint, multiscatter) * w[None]).sum(axis=1)
        # M(base) = base * slope + M(0), the slope taken through *base* (exact where the
        # Base Color is that value; a texture's other colours follow the line), through 1
        # for a channel near 0
        near = base < 0.05
        slope = np.where(near, whole - zero, (metal - zero) / np.where(near, 1.0, base))
        scale = scale + metallic * slope
        offset = offset + metallic * zero
    return tuple(float(v) for v in scale), tuple(float(v) for v in offset)


__all__ = ["F0", "ROUGHNESS", "dielectric_albedo", "fresnel_dielectric", "ior_of_f0",
           "metal_albedo", "principled_ambient", "tables"]
