# SPDX-License-Identifier: GPL-3.0-or-later
"""The albedo of Principled's specular layer (``core/specular_albedo.py``), without Blender:
its quadrature against a Monte Carlo estimate that samples the other way round (outgoing
directions, cosine-weighted, the BRDF evaluated as written in the papers), a mirror's known
hemispherical reflectance, and the cases that must leave Ka = Kd."""

from __future__ import annotations

import math

import numpy as np
import pytest

from phong_nodes.core import specular_albedo as sa


def _monte_carlo(alpha, mu, fresnel, n=1_000_000, seed=7):
    """Directional albedo of a GGX BRDF with height-correlated Smith G2 at view cosine *mu*:
    E = ∫ D G2 F / (4 mu cos_o) cos_o dwo, wo drawn cosine-weighted (pdf cos_o / π)."""
    rng = np.random.default_rng(seed)
    u1, u2 = rng.random(n), rng.random(n)
    r, phi = np.sqrt(u1), 2.0 * math.pi * u2
    wo = np.stack([r * np.cos(phi), r * np.sin(phi), np.sqrt(1.0 - u1)], axis=-1)
    wi = np.array([math.sqrt(1.0 - mu * mu), 0.0, mu])
    h = wo + wi
    h /= np.linalg.norm(h, axis=1)[:, None]
    a2 = alpha * alpha
    d = a2 / (math.pi * (1.0 + (a2 - 1.0) * h[:, 2] ** 2) ** 2)

    def lam(c):
        return 0.5 * (np.sqrt(1.0 + a2 * (1.0 / (c * c) - 1.0)) - 1.0)

    g2 = 1.0 / (1.0 + lam(mu) + lam(wo[:, 2]))
    brdf = d * g2 * fresnel(h @ wi) / (4.0 * mu * wo[:, 2])
    return float(np.mean(brdf * math.pi))


@pytest.mark.parametrize("roughness", [0.5, 0.75, 1.0])
def test_albedo_tables_agree_with_monte_carlo(roughness):
    tables = sa.tables()
    for k in (6, 12, 23):   # low, middle, head-on view cosines of the tables
        mu = float(tables["mu"][k])
        one = float(sa._interp_rough(tables["one"], roughness)[k])
        assert one == pytest.approx(_monte_carlo(roughness ** 2, mu, lambda c: 1.0), abs=4e-3)
        f0 = 0.04
        eta = float(sa.ior_of_f0(f0))
        s = float(sa._interp_f0(sa._interp_rough(tables["s"], roughness), f0)[k])
        expected = _monte_carlo(roughness ** 2, mu,
                                lambda c: (sa.fresnel_dielectric(c, eta) - f0) / (1 - f0))
        assert s == pytest.approx(expected, abs=1e-3)


def test_a_smooth_dielectric_reflects_its_hemispherical_fresnel():
    """Roughness 0, IOR 1.5 (F0 0.04 at Specular IOR Level 0.5): the layer reflects 9.18%
    of a uniform World (the hemispherical reflectance of glass, a textbook figure), and the
    base under it sees the rest."""
    scale, offset = sa.principled_ambient(0.0, 1.5, 0.5)
    assert offset == pytest.approx((0.0918,) * 3, abs=2e-4)
    assert scale == pytest.approx(tuple(1.0 - v for v in offset), abs=1e-12)


def test_no_specular_layer_leaves_ka_as_kd():
    for distribution in (True, False):
        assert sa.principled_ambient(0.5, 1.45, 0.0, multiscatter=distribution) == \
            ((1.0, 1.0, 1.0), (0.0, 0.0, 0.0))


def test_a_white_metal_reflects_the_whole_world_with_multiple_scattering():
    """F0 = 1: Multiscatter GGX keeps all the energy (Kulla and Conty's compensation), plain
    GGX loses what single scattering does (1 - E1avg, about 0.12 at Roughness 0.5)."""
    for roughness in (0.25, 0.5, 1.0):
        scale, offset = sa.principled_ambient(roughness, metallic=1.0, base=(1.0, 1.0, 1.0))
        assert [a + b for a, b in zip(scale, offset)] == pytest.approx([1.0] * 3, abs=1e-9)
    scale, offset = sa.principled_ambient(0.5, metallic=1.0, base=(1.0, 1.0, 1.0),
                                          multiscatter=False)
    assert 0.85 < scale[0] + offset[0] < 0.92


def test_a_tinted_layer_tints_its_own_light_not_the_base():
    scale, offset = sa.principled_ambient(0.5, 1.5, 0.5, tint=(1.0, 0.5, 0.0))
    assert scale[0] == scale[1] == scale[2]
    assert offset[0] > offset[1] > offset[2] > 0.0
