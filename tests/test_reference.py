# SPDX-License-Identifier: GPL-3.0-or-later
"""Tests of the numpy reference (node_groups/reference.py) against the seeds.

Every expected value below is derived by hand from the seed documents (seed 000 = French
lecture notes, seed 004 = Italian slides) and docs/contract.md, never copied from running the code.
"""

import math

import numpy as np
import pytest

from phong_nodes.node_groups import reference as ref


S2 = math.sqrt(0.5)  # 1/√2
Z = (0.0, 0.0, 1.0)
WHITE = (1.0, 1.0, 1.0)


def close(a, b, tol=1e-12):
    np.testing.assert_allclose(np.asarray(a, dtype=np.float64), np.asarray(b, dtype=np.float64),
                               rtol=0, atol=tol)


# ---------------------------------------------------------------------------
# module shape
# ---------------------------------------------------------------------------

SPEC_GROUPS = [
    "Phong Directional Light", "Phong Point Light", "Phong Spot Light", "Phong Power Falloff",
    "Phong Irradiant", "Phong Ambient", "Phong Diffuse", "Phong Specular",
    "Phong Blinn Specular", "Phong Color Add", "Phong Color Multiply", "Phong Shading",
    "three.js Point Light", "three.js Spot Light", "three.js Ambient", "three.js Phong",
    "X3D Directional Light", "X3D Point Light", "X3D Spot Light",
]


def test_no_bpy_and_groups_table():
    with open(ref.__file__, encoding="utf-8") as fh:
        src = fh.read()
    assert "import bpy" not in src
    assert sorted(ref.GROUPS) == sorted(SPEC_GROUPS)
    assert ref.__doc__ and "§" in ref.__doc__


def test_all_outputs_float64():
    for name in SPEC_GROUPS:
        out = ref.GROUPS[name]({}, {})
        for val in out.values():
            assert val.dtype == np.float64
            assert np.all(np.isfinite(val))


# ---------------------------------------------------------------------------
# colours (seed 000 §1.3)
# ---------------------------------------------------------------------------

def test_magenta_light_on_yellow_object_is_red():
    close(ref.color_multiply(a=(1, 0, 1), b=(1, 1, 0))["Color"], (1, 0, 0))
    close(ref.ambient(intensity=1.0, light_color=(1, 0, 1), object_color=(1, 1, 0))["Color"],
          (1, 0, 0))
    close(ref.GROUPS["Phong Color Multiply"]({"A": (1, 0, 1), "B": (1, 1, 0)}, {})["Color"],
          (1, 0, 0))


def test_color_multiply_factor():
    # 0.5 · (0.4, 0.5, 1) ⊗ (0.5, 0.2, 0.3) = 0.5 · (0.2, 0.1, 0.3)
    close(ref.color_multiply(a=(0.4, 0.5, 1), b=(0.5, 0.2, 0.3), factor=0.5)["Color"],
          (0.1, 0.05, 0.15))


def test_color_add_clamps_at_one_only():
    close(ref.color_add(a=(0.7, 0.2, 1), b=(0.5, 0.3, 0.4))["Color"], (1, 0.5, 1))
    # no lower clamp: -0.5 + 0.2 = -0.3
    close(ref.color_add(a=(-0.5, 0, 0.25), b=(0.2, 0, 0.25))["Color"], (-0.3, 0, 0.5))


def test_rgba_alpha_ignored():
    close(ref.color_add(a=(0.1, 0.2, 0.3, 0.5), b=(0.1, 0.1, 0.1, 1.0))["Color"], (0.2, 0.3, 0.4))


# ---------------------------------------------------------------------------
# lights (seed 000 §2, seed 004 slides 44-46)
# ---------------------------------------------------------------------------

def test_directional_light_constant_over_p():
    P = np.array([[0, 0, 0], [1, 2, 3], [-5, 4, 0.5], [100, -7, 2]], dtype=float)
    out = ref.directional_light(direction=(0, 0, -2), intensity=0.7, geometry_position=P)
    close(out["Light Vector"], np.tile([0, 0, 1], (4, 1)))
    close(out["Intensity"], [0.7] * 4)
    # u = (1, 2, 2), ‖u‖ = 3 -> ℓ = -(1, 2, 2)/3
    out = ref.directional_light(direction=(1, 2, 2))
    close(out["Light Vector"], (-1 / 3, -2 / 3, -2 / 3))
    close(out["Intensity"], 1.0)
    # zero direction -> zero light vector
    close(ref.directional_light(direction=(0, 0, 0))["Light Vector"], (0, 0, 0))


def test_point_light_vector_distance_and_inverse_square():
    # S = (0, 0, 0), P = (3, 4, 0): r = 5, ℓ = (S-P)/r = (-0.6, -0.8, 0)
    out = ref.point_light(position=(0, 0, 0), intensity=4.0, geometry_position=(3, 4, 0))
    close(out["Distance"], 5.0)
    close(out["Light Vector"], (-0.6, -0.8, 0))
    close(out["Intensity"], 4.0 / 25.0)  # Proposition 1: i0/r²
    # Generalised form with i0 = 1, α = 1/i0, β = γ = 0 gives back i0/r²
    gen = ref.point_light(position=(0, 0, 0), intensity=1.0, quadratic=1 / 4.0, linear=0.0,
                          constant=0.0, geometry_position=(3, 4, 0))
    close(gen["Intensity"], 4.0 / 25.0)
    # linear only: 1/(β r) = 1/5 ; constant only: 1/γ
    close(ref.point_light(quadratic=0, linear=1, geometry_position=(3, 4, 0))["Intensity"], 0.2)
    close(ref.point_light(quadratic=0, constant=2, geometry_position=(3, 4, 0))["Intensity"], 0.5)
    # α r² + β r + γ = 25 + 2·5 + 3 = 38
    close(ref.point_light(quadratic=1, linear=2, constant=3,
                          geometry_position=(3, 4, 0))["Intensity"], 1 / 38)


def test_point_light_vector_is_independent_of_distance():
    S = (1.0, 1.0, 1.0)
    for t in (0.5, 2.0, 10.0):
        out = ref.point_light(position=S, geometry_position=(1.0, 1.0, 1.0 - t))
        close(out["Light Vector"], Z)
        close(out["Distance"], t)
        close(out["Intensity"], 1 / t ** 2)


def test_spot_on_axis_inside():
    # default u = (0, 0, -1); P two units below S is on the axis: cos ω = 1
    out = ref.spot_light(position=(0, 0, 0), direction=(0, 0, -5), geometry_position=(0, 0, -2))
    close(out["Cos Angle"], 1.0)
    close(out["In Cone"], 1.0)
    close(out["Distance"], 2.0)
    close(out["Light Vector"], Z)
    close(out["Intensity"], 0.25)


def _spot_point(angle, dist=2.0):
    """P at `angle` from the axis u = (0, 0, -1) of a spot sitting at the origin."""
    return (dist * math.sin(angle), 0.0, -dist * math.cos(angle))


def test_spot_cone_test_just_inside_just_outside():
    theta = math.pi / 4
    inside = ref.spot_light(half_angle=theta, geometry_position=_spot_point(theta - 1e-6))
    outside = ref.spot_light(half_angle=theta, geometry_position=_spot_point(theta + 1e-6))
    close(inside["In Cone"], 1.0)
    close(inside["Intensity"], 0.25)  # e_att = 0: full i0/r² right to the edge (hard edge)
    close(outside["In Cone"], 0.0)
    close(outside["Intensity"], 0.0)
    close(inside["Cos Angle"], math.cos(theta - 1e-6), 1e-12)
    close(outside["Cos Angle"], math.cos(theta + 1e-6), 1e-12)


def test_spot_boundary_is_inclusive():
    # θ = 0: only the axis; cos ω = 1 = cos 0 -> inside (non-strict inequality)
    out = ref.spot_light(half_angle=0.0, geometry_position=(0, 0, -2))
    close(out["In Cone"], 1.0)
    close(out["Intensity"], 0.25)
    close(ref.spot_light(half_angle=0.0, geometry_position=_spot_point(1e-4))["In Cone"], 0.0)
    # θ = π: the whole space, including straight behind (cos ω = -1 = cos π)
    behind = ref.spot_light(half_angle=math.pi, geometry_position=(0, 0, 2))
    close(behind["Cos Angle"], -1.0)
    close(behind["In Cone"], 1.0)
    # literally max(cos ω, 0)^0 = 0^0 = 1 with e_att = 0
    close(behind["Intensity"], 0.25)
    close(ref.spot_light(half_angle=math.pi, edge_exponent=2.0,
                         geometry_position=(0, 0, 2))["Intensity"], 0.0)


def test_spot_cos_angle_is_minus_l_dot_u():
    rng = np.random.default_rng(1)
    P = rng.normal(size=(50, 3)) * 3
    S = np.array([0.5, -1.0, 2.0])
    u = np.array([1.0, 2.0, -2.0])  # ‖u‖ = 3, normalized inside
    out = ref.spot_light(position=S, direction=u, half_angle=1.0, geometry_position=P)
    d = S - P
    ell = d / np.linalg.norm(d, axis=1, keepdims=True)
    close(out["Light Vector"], ell)
    close(out["Cos Angle"], -(ell @ (u / 3.0)))
    close(out["In Cone"], (-(ell @ (u / 3.0)) >= math.cos(1.0)).astype(float))


def test_spot_edge_exponent_soft_and_hard_edge():
    theta = math.radians(40)
    for a in (0.0, math.radians(10), math.radians(30), math.radians(39.9)):
        P = _spot_point(a)
        hard = ref.spot_light(half_angle=theta, edge_exponent=0.0, geometry_position=P)
        soft = ref.spot_light(half_angle=theta, edge_exponent=2.0, geometry_position=P)
        close(hard["Intensity"], 0.25)  # no transition at all inside the cone
        close(soft["Intensity"], 0.25 * math.cos(a) ** 2)
    # generalised falloff times the edge term: 1/(α r² + β r + γ) (cos ω)^e_att
    out = ref.spot_light(half_angle=theta, edge_exponent=3.0, quadratic=0.0, linear=1.0,
                         constant=1.0, geometry_position=_spot_point(math.radians(20)))
    close(out["Intensity"], 1 / 3.0 * math.cos(math.radians(20)) ** 3)


def test_power_falloff_k_2_1_0():
    close(ref.power_falloff(distance=2.0, exponent=2.0)["Intensity"], 0.25)
    close(ref.power_falloff(distance=2.0, exponent=1.0)["Intensity"], 0.5)
    close(ref.power_falloff(distance=2.0, exponent=0.0)["Intensity"], 1.0)  # no attenuation
    close(ref.power_falloff(distance=0.5, intensity=3.0, exponent=2.0)["Intensity"], 12.0)
    d = np.array([0.1, 1.0, 7.0, 1e3])
    close(ref.power_falloff(distance=d, intensity=2.5, exponent=0.0)["Intensity"], [2.5] * 4)
    # default exponent k = 2
    close(ref.power_falloff(distance=4.0)["Intensity"], 1 / 16)


def test_power_falloff_degenerate():
    close(ref.power_falloff(distance=0.0, exponent=0.0)["Intensity"], 1.0)  # 0^0 = 1
    close(ref.power_falloff(distance=0.0, exponent=2.0)["Intensity"], 1e6)  # 1/max(0, 1e-6)
    close(ref.power_falloff(distance=-3.0, exponent=1.0)["Intensity"], 1e6)  # negative d -> 0
    close(ref.power_falloff(distance=2.0, exponent=-2.0)["Intensity"], 1.0)  # k clamped at 0
    big = ref.power_falloff(distance=1e10, exponent=1e3)["Intensity"]
    assert np.isfinite(big) and big >= 0


# ---------------------------------------------------------------------------
# terms (seed 000 §3, seed 004 slides 38-66)
# ---------------------------------------------------------------------------

def test_irradiant_passes_through():
    close(ref.irradiant(color=(0.1, 0.2, 0.3))["Color"], (0.1, 0.2, 0.3))
    close(ref.irradiant()["Color"], (0, 0, 0))


def test_ambient():
    close(ref.ambient(intensity=0.5, light_color=(1, 0.5, 0), object_color=(0.2, 0.4, 1))["Color"],
          (0.1, 0.1, 0.0))


def test_diffuse_cosine_and_light_behind():
    oc = (0.8, 0.4, 0.2)
    close(ref.diffuse(light_vector=Z, intensity=2.0, object_color=oc, normal=Z)["Color"],
          (1.6, 0.8, 0.4))
    # 45°: ℓ·n = 1/√2
    close(ref.diffuse(light_vector=(S2, 0, S2), object_color=oc, normal=Z)["Color"],
          (0.8 * S2, 0.4 * S2, 0.2 * S2))
    # grazing and behind: black
    close(ref.diffuse(light_vector=(1, 0, 0), object_color=oc, normal=Z)["Color"], (0, 0, 0))
    close(ref.diffuse(light_vector=(0, 0, -1), object_color=oc, normal=Z)["Color"], (0, 0, 0))
    close(ref.diffuse(light_vector=(0, -S2, -S2), object_color=oc, normal=Z)["Color"], (0, 0, 0))


def test_lemma1_mirror_gives_full_specular():
    """r = 2(ℓ·n)n - ℓ is the mirror of ℓ: unit, same angle with n, in the (ℓ, n) plane."""
    rng = np.random.default_rng(7)
    for _ in range(20):
        n = rng.normal(size=3)
        n /= np.linalg.norm(n)
        ell = rng.normal(size=3)
        ell /= np.linalg.norm(ell)
        if ell @ n < 0:
            ell = -ell
        # the mirror built geometrically: ℓ = α n + β p  ->  r = α n - β p
        alpha = ell @ n
        bp = ell - alpha * n
        mirror = alpha * n - bp
        close(np.linalg.norm(mirror), 1.0, 1e-12)
        close(mirror @ n, ell @ n, 1e-12)
        # with v = mirror, r·v = 1 -> (r·v)^e = 1 for every exponent
        for e in (1.0, 30.0, 1000.0):
            out = ref.specular(light_vector=ell, exponent=e, normal=n, view_vector=mirror)
            close(out["Color"], WHITE, 1e-9)
        # e = 1 and v = r gives exactly r·v = 1; any other unit v gives r·v < 1
        other = ref.specular(light_vector=ell, exponent=1.0, normal=n, view_vector=n)
        close(other["Color"], [ell @ n] * 3, 1e-12)  # r·n = ℓ·n


def test_specular_hand_values():
    # ℓ = (1/√2, 0, 1/√2), n = z -> r = (-1/√2, 0, 1/√2)
    ell = (S2, 0, S2)
    sc = (0.5, 1.0, 0.25)
    lc = (1.0, 0.5, 1.0)
    out = ref.specular(light_vector=ell, intensity=2.0, light_color=lc, specular_color=sc,
                       exponent=30.0, normal=Z, view_vector=(-S2, 0, S2))
    close(out["Color"], (1.0, 1.0, 0.5))
    # v = z: r·v = 1/√2 ; e = 2 -> 1/2
    out = ref.specular(light_vector=ell, exponent=2.0, normal=Z, view_vector=Z)
    close(out["Color"], (0.5, 0.5, 0.5))


def test_specular_zero_when_light_behind_or_viewer_wrong_side():
    # ℓ·n < 0: ℓ = -z, n = z -> r = -z; with v = -z, r·v = 1 but the light is behind
    out = ref.specular(light_vector=(0, 0, -1), exponent=0.0, normal=Z, view_vector=(0, 0, -1))
    close(out["Color"], (0, 0, 0))
    # r·v < 0: ℓ = (1/√2, 0, 1/√2), r = (-1/√2, 0, 1/√2), v = x: r·v = -1/√2
    # (exponent 0 so only the mask can make it zero)
    out = ref.specular(light_vector=(S2, 0, S2), exponent=0.0, normal=Z, view_vector=(1, 0, 0))
    close(out["Color"], (0, 0, 0))
    # same for Blinn: ℓ·n < 0
    out = ref.blinn_specular(light_vector=(0, 0, -1), exponent=0.0, normal=Z, view_vector=Z)
    close(out["Color"], (0, 0, 0))
    # h·n < 0: ℓ = x (ℓ·n = 0 allowed), v = (0, 0.6, -0.8): h ∝ (1, 0.6, -0.8), h·n < 0
    out = ref.blinn_specular(light_vector=(1, 0, 0), exponent=0.0, normal=Z,
                             view_vector=(0, 0.6, -0.8))
    close(out["Color"], (0, 0, 0))


def test_blinn_half_vector_bisects():
    # ℓ = x, v = y: h = (1, 1, 0)/√2 ; with n = x, h·n = 1/√2, e = 2 -> 1/2
    out = ref.blinn_specular(light_vector=(1, 0, 0), exponent=2.0, normal=(1, 0, 0),
                             view_vector=(0, 1, 0))
    close(out["Color"], (0.5, 0.5, 0.5))
    # n on the bisector -> h = n -> factor 1 for any exponent
    out = ref.blinn_specular(light_vector=(1, 0, 0), exponent=1000.0, normal=(S2, S2, 0),
                             view_vector=(0, 1, 0))
    close(out["Color"], WHITE)


def test_blinn_and_phong_agree_at_mirror_direction():
    # v is the mirror of ℓ about n  <=>  n bisects ℓ and v  (seed 004 slide 62)
    ell, v = (S2, 0, S2), (-S2, 0, S2)
    for e in (0.0, 1.0, 30.0, 1000.0):
        p = ref.specular(light_vector=ell, exponent=e, normal=Z, view_vector=v)["Color"]
        b = ref.blinn_specular(light_vector=ell, exponent=e, normal=Z, view_vector=v)["Color"]
        close(p, WHITE)
        close(b, WHITE)


# ---------------------------------------------------------------------------
# Normal / View Vector conventions
# ---------------------------------------------------------------------------

def test_zero_normal_uses_geometry_normal():
    kw = dict(light_vector=Z, object_color=WHITE)
    close(ref.diffuse(normal=(0, 0, 0), geometry_normal=(0, 0, 1), **kw)["Color"], WHITE)
    close(ref.diffuse(normal=(0, 0, 0), geometry_normal=(1, 0, 0), **kw)["Color"], (0, 0, 0))
    # a non-zero Normal overrides the geometry normal and is normalized (ℓ·n = 1, not 5)
    close(ref.diffuse(normal=(0, 0, 5), geometry_normal=(1, 0, 0), **kw)["Color"], WHITE)
    close(ref.diffuse(normal=(0, 0, 0), geometry_normal=(0, 0, 3), **kw)["Color"], WHITE)
    # per point: mixed zero / non-zero normals
    N = np.array([[0, 0, 0], [0, 0, 2], [0, 0, 0]], dtype=float)
    G = np.array([[0, 0, 1], [1, 0, 0], [0, 1, 0]], dtype=float)
    close(ref.diffuse(normal=N, geometry_normal=G, **kw)["Color"], [WHITE, WHITE, (0, 0, 0)])


def test_zero_view_uses_incoming():
    ell = (S2, 0, S2)
    close(ref.specular(light_vector=ell, normal=Z, view_vector=(0, 0, 0),
                       incoming=(-S2, 0, S2))["Color"], WHITE)
    # incoming along ℓ: r·v = -1/2 + 1/2 = 0 -> 0^30 = 0
    close(ref.specular(light_vector=ell, normal=Z, view_vector=(0, 0, 0),
                       incoming=ell)["Color"], (0, 0, 0))
    # a non-zero View Vector is normalized and wins over incoming
    close(ref.specular(light_vector=ell, normal=Z, view_vector=(-3, 0, 3),
                       incoming=ell)["Color"], WHITE)
    close(ref.blinn_specular(light_vector=ell, normal=Z, view_vector=(0, 0, 0),
                             incoming=(-S2, 0, S2))["Color"], WHITE)


def test_light_vector_used_as_given():
    # not re-normalized: ℓ = 2z on n = z gives 2 · Cl
    close(ref.diffuse(light_vector=(0, 0, 2), object_color=WHITE, normal=Z)["Color"],
          (2, 2, 2))


# ---------------------------------------------------------------------------
# Phong Shading (seed 000 §3.1)
# ---------------------------------------------------------------------------

def test_shading_hand_value_below_one():
    # ℓ = n = v = z: ℓ·n = 1, r = z, r·v = 1
    out = ref.phong_shading(light_vector=Z, light_intensity=0.1, light_color=WHITE,
                            object_color=(0.5, 0.2, 0.1), irradiant_color=(0.05, 0, 0),
                            ambient_intensity=0.1, ambient_color=WHITE,
                            specular_color=(0.1, 0.1, 0.1), exponent=30.0, normal=Z,
                            view_vector=Z)
    close(out["Irradiant"], (0.05, 0, 0))
    close(out["Ambient"], (0.05, 0.02, 0.01))
    close(out["Diffuse"], (0.05, 0.02, 0.01))
    close(out["Specular"], (0.01, 0.01, 0.01))
    close(out["Color"], (0.16, 0.05, 0.03))


def test_shading_clamps_at_one():
    out = ref.phong_shading(light_vector=Z, light_intensity=1.0, object_color=(0.8, 0.8, 0.8),
                            irradiant_color=(0.1, 0, 0), ambient_intensity=0.1, normal=Z,
                            view_vector=Z)
    # 0.1 + 0.08 + 0.8 + 1 = 1.98 and 0.08 + 0.8 + 1 = 1.88 -> clamped to 1
    close(out["Ambient"], (0.08, 0.08, 0.08))
    close(out["Diffuse"], (0.8, 0.8, 0.8))
    close(out["Specular"], WHITE)
    close(out["Color"], WHITE)


def test_shading_strengths_and_terms_match_groups():
    rng = np.random.default_rng(3)
    n_pts = 64
    ell = rng.normal(size=(n_pts, 3))
    ell /= np.linalg.norm(ell, axis=1, keepdims=True)
    geo_n = rng.normal(size=(n_pts, 3))
    inc = rng.normal(size=(n_pts, 3))
    kw = dict(light_vector=ell, light_intensity=1.3, light_color=(1, 0.9, 0.7),
              object_color=(0.6, 0.3, 0.2), irradiant_color=(0.02, 0.01, 0),
              ambient_intensity=0.2, ambient_color=(0.5, 0.5, 1), diffuse_strength=0.7,
              specular_strength=0.4, specular_color=(0.9, 0.9, 1), exponent=12.0,
              normal=(0, 0, 0), view_vector=(0, 0, 0), geometry_normal=geo_n, incoming=inc)
    geo = dict(normal=(0, 0, 0), view_vector=(0, 0, 0), geometry_normal=geo_n, incoming=inc)
    for blinn in (0.0, 1.0, 0.5):
        out = ref.phong_shading(blinn=blinn, **kw)
        close(out["Irradiant"], np.broadcast_to((0.02, 0.01, 0), (n_pts, 3)))
        close(out["Ambient"], np.broadcast_to(
            ref.ambient(intensity=0.2, light_color=(0.5, 0.5, 1),
                        object_color=(0.6, 0.3, 0.2))["Color"], (n_pts, 3)))
        close(out["Diffuse"], ref.diffuse(light_vector=ell, intensity=0.7 * 1.3,
                                          light_color=(1, 0.9, 0.7),
                                          object_color=(0.6, 0.3, 0.2),
                                          normal=geo["normal"],
                                          geometry_normal=geo_n)["Color"])
        sk = dict(light_vector=ell, intensity=0.4 * 1.3, light_color=(1, 0.9, 0.7),
                  specular_color=(0.9, 0.9, 1), exponent=12.0, **geo)
        phong = ref.specular(**sk)["Color"]
        blinn_c = ref.blinn_specular(**sk)["Color"]
        close(out["Specular"], (1 - blinn) * phong + blinn * blinn_c)
        if blinn == 0.5:  # the average of the two
            close(out["Specular"], 0.5 * (phong + blinn_c))
        total = out["Irradiant"] + out["Ambient"] + out["Diffuse"] + out["Specular"]
        close(out["Color"], np.minimum(total, 1.0))


def test_no_light_is_black():
    # seed 004 slide 43: with no light at all every object is black
    P = np.zeros((5, 3))
    out = ref.phong_shading(light_vector=Z, light_intensity=0.0, ambient_intensity=0.0,
                            irradiant_color=(0, 0, 0), normal=Z, view_vector=Z)
    close(out["Color"], (0, 0, 0))
    # zero Light Vector (no light) with Phong specular and e > 0 -> black as well
    out = ref.phong_shading(light_vector=(0, 0, 0), ambient_intensity=0.0, normal=Z,
                            view_vector=Z, exponent=30.0, blinn=0.0)
    close(out["Color"], (0, 0, 0))
    # several lights summed with Phong Color Add: zero lights -> the black start value
    acc = np.zeros_like(P)
    close(acc, np.zeros((5, 3)))


def test_two_lights_add():
    # seed 004 slide 42: lighting is additive, seed 000 §1.3: clamped addition
    d1 = ref.diffuse(light_vector=Z, light_color=(0.6, 0, 0), object_color=WHITE, normal=Z)
    d2 = ref.diffuse(light_vector=(S2, 0, S2), light_color=(0.6, 0.5, 0), object_color=WHITE,
                     normal=Z)
    close(ref.color_add(a=d1["Color"], b=d2["Color"])["Color"],
          (min(0.6 + 0.6 * S2, 1.0), 0.5 * S2, 0.0))


# ---------------------------------------------------------------------------
# degenerate inputs and broadcasting
# ---------------------------------------------------------------------------

def test_zero_light_vector_literal_result():
    # ℓ = 0: ℓ·n = 0 >= 0, r = 0, r·v = 0 >= 0 and 0^0 = 1 -> literal result kept
    out = ref.specular(light_vector=(0, 0, 0), exponent=0.0, normal=Z, view_vector=Z)
    close(out["Color"], WHITE)
    out = ref.specular(light_vector=(0, 0, 0), exponent=5.0, normal=Z, view_vector=Z)
    close(out["Color"], (0, 0, 0))


def test_degenerate_inputs_are_finite():
    zero = (0.0, 0.0, 0.0)
    outs = []
    for e in (0.0, 1.0, 1000.0, -3.0):
        for ell in (zero, Z, (0, 0, -1), (1, 0, 0)):
            for n in (zero, Z):
                for v in (zero, (0, 0, -1), Z):
                    kw = dict(light_vector=ell, exponent=e, normal=n, view_vector=v,
                              geometry_normal=zero, incoming=zero)
                    outs.append(ref.specular(**kw)["Color"])
                    outs.append(ref.blinn_specular(**kw)["Color"])
                    outs.extend(ref.phong_shading(blinn=0.5, **kw).values())
        outs.append(ref.diffuse(light_vector=zero, normal=zero, geometry_normal=zero)["Color"])
        for theta in (0.0, math.pi, math.radians(30)):
            for P in ((0, 0, 0), (0, 0, -1), (0, 0, 1)):
                outs.extend(ref.spot_light(position=(0, 0, 0), direction=zero, half_angle=theta,
                                           edge_exponent=e, quadratic=0, linear=0, constant=0,
                                           geometry_position=P).values())
        outs.extend(ref.point_light(quadratic=0, linear=0, constant=0).values())  # r = 0
        outs.extend(ref.power_falloff(distance=0.0, exponent=e).values())
        outs.extend(ref.directional_light(direction=zero).values())
    for o in outs:
        assert np.all(np.isfinite(o))
    # α = β = γ = 0 -> i0 / 1e-6
    close(ref.point_light(quadratic=0, linear=0, constant=0,
                          geometry_position=(0, 0, -3))["Intensity"], 1e6, 1e-6)
    # r = 0: zero light vector, intensity i0 / max(0, 1e-6)
    out = ref.point_light(position=(1, 2, 3), geometry_position=(1, 2, 3))
    close(out["Light Vector"], (0, 0, 0))
    close(out["Distance"], 0.0)
    close(out["Intensity"], 1e6, 1e-6)


def test_negative_exponent_clamped_to_zero():
    ell = (S2, 0, S2)
    # e < 0 -> e = 0 -> factor 1 where the masks hold
    close(ref.specular(light_vector=ell, exponent=-4.0, normal=Z, view_vector=Z)["Color"], WHITE)
    close(ref.blinn_specular(light_vector=ell, exponent=-4.0, normal=Z,
                             view_vector=Z)["Color"], WHITE)
    out = ref.spot_light(edge_exponent=-2.0, half_angle=math.radians(40),
                         geometry_position=_spot_point(math.radians(30)))
    close(out["Intensity"], 0.25)


def test_broadcasting_matches_row_by_row():
    rng = np.random.default_rng(11)
    n_pts = 32
    ell = rng.normal(size=(n_pts, 3))
    n = rng.normal(size=(n_pts, 3))
    v = rng.normal(size=(n_pts, 3))
    inten = rng.uniform(0, 2, size=n_pts)
    oc = rng.uniform(0, 1, size=(n_pts, 3))
    batch = ref.specular(light_vector=ell, intensity=inten, specular_color=oc, exponent=4.0,
                         normal=n, view_vector=v)["Color"]
    batch_d = ref.diffuse(light_vector=ell, intensity=inten, object_color=oc, normal=n)["Color"]
    assert batch.shape == (n_pts, 3)
    for k in range(n_pts):
        row = ref.specular(light_vector=ell[k], intensity=inten[k], specular_color=oc[k],
                           exponent=4.0, normal=n[k], view_vector=v[k])["Color"]
        close(batch[k], row)
        row_d = ref.diffuse(light_vector=ell[k], intensity=float(inten[k]), object_color=oc[k],
                            normal=n[k])["Color"]
        close(batch_d[k], row_d)
    # spot over a (4, 5, 3) grid of points
    P = rng.normal(size=(4, 5, 3))
    out = ref.spot_light(position=(0, 0, 1), geometry_position=P)
    assert out["Light Vector"].shape == (4, 5, 3)
    for key in ("Intensity", "Distance", "Cos Angle", "In Cone"):
        assert out[key].shape == (4, 5)


# ---------------------------------------------------------------------------
# GROUPS generic table
# ---------------------------------------------------------------------------

def test_groups_use_socket_names_and_geometry():
    geo = {"Position": np.array([[3.0, 4.0, 0.0], [0.0, 0.0, -2.0]]),
           "Normal": np.array([[0.0, 0.0, 1.0], [0.0, 0.0, 1.0]]),
           "Incoming": np.array([[-S2, 0.0, S2], [0.0, 0.0, 1.0]])}
    pt = ref.GROUPS["Phong Point Light"]({"Position": (0, 0, 0), "Intensity": 4.0}, geo)
    close(pt["Distance"], [5.0, 2.0])
    close(pt["Intensity"], [4 / 25, 1.0])
    sp = ref.GROUPS["Phong Spot Light"]({"Half Angle": math.radians(30), "Edge Exponent": 0.0,
                                         "Quadratic": 1.0}, geo)
    close(sp["In Cone"], [0.0, 1.0])
    dl = ref.GROUPS["Phong Directional Light"]({"Direction": (0, 0, -1)}, geo)
    close(dl["Light Vector"], [Z, Z])
    close(dl["Intensity"], [1.0, 1.0])
    pf = ref.GROUPS["Phong Power Falloff"]({"Distance": 2.0, "Exponent": 1.0}, geo)
    close(pf["Intensity"], [0.5, 0.5])
    spec = ref.GROUPS["Phong Specular"]({"Light Vector": (S2, 0, S2)}, geo)
    close(spec["Color"][0], WHITE)  # zero View Vector -> Incoming = mirror direction
    diff = ref.GROUPS["Phong Diffuse"]({"Light Vector": Z, "Object Color": (1, 0, 1)}, geo)
    close(diff["Color"], [(1, 0, 1), (1, 0, 1)])
    sh = ref.GROUPS["Phong Shading"]({"Light Vector": Z, "Blinn": 1.0}, geo)
    assert set(sh) == {"Irradiant", "Ambient", "Diffuse", "Specular", "Color"}
    assert sh["Color"].shape == (2, 3)
    irr = ref.GROUPS["Phong Irradiant"]({"Color": (0.1, 0.2, 0.3)}, geo)
    close(irr["Color"], [(0.1, 0.2, 0.3)] * 2)
    add = ref.GROUPS["Phong Color Add"]({"A": (0.7, 0.2, 1), "B": (0.5, 0.3, 0.4)}, {})
    close(add["Color"], (1, 0.5, 1))
    amb = ref.GROUPS["Phong Ambient"]({"Light Color": (1, 0, 1), "Object Color": (1, 1, 0)}, {})
    close(amb["Color"], (1, 0, 0))  # default Intensity 1
    bl = ref.GROUPS["Phong Blinn Specular"]({"Light Vector": (1, 0, 0), "Exponent": 2.0,
                                             "Normal": (1, 0, 0), "View Vector": (0, 1, 0)}, {})
    close(bl["Color"], (0.5, 0.5, 0.5))
    with pytest.raises(KeyError):
        ref.GROUPS["Phong Diffuse"]({"Lightvector": Z}, geo)


def test_spec_defaults():
    d = ref.DEFAULTS
    close(d["Phong Directional Light"]["Direction"], (0, 0, -1))
    assert d["Phong Point Light"]["Quadratic"] == 1 and d["Phong Point Light"]["Linear"] == 0
    assert d["Phong Point Light"]["Constant"] == 0 and d["Phong Point Light"]["Intensity"] == 1
    close(d["Phong Spot Light"]["Half Angle"], math.radians(30))
    assert d["Phong Spot Light"]["Edge Exponent"] == 0
    assert d["Phong Power Falloff"]["Exponent"] == 2
    close(d["Phong Irradiant"]["Color"], (0, 0, 0))
    assert d["Phong Color Multiply"]["Factor"] == 1
    assert d["Phong Shading"]["Diffuse Strength"] == 1
    assert d["Phong Shading"]["Specular Strength"] == 1
    assert d["Phong Shading"]["Blinn"] == 0
    for name, sockets in ref.INPUTS.items():
        assert set(sockets) == set(d[name])


# ---------------------------------------------------------------------------
# three.js r181 (docs/threejs.md); hand values from the GLSL of three@0.181.0
# ---------------------------------------------------------------------------

def test_threejs_specular_default_is_0x111111_decoded():
    c = 17 / 255  # > 0.04045: the power branch of the sRGB decoding
    close(ref.THREEJS_SPECULAR, [((c + 0.055) / 1.055) ** 2.4] * 3)
    assert 0.0056 < ref.THREEJS_SPECULAR[0] < 0.0057


def test_threejs_point_decay_and_floor():
    # d = 3 above the point: 1/d^2 = 1/9; decay 1: 1/3; decay 0: 1; d = 0.05: max(d², 0.01)
    for decay, want in ((2.0, 1 / 9), (1.0, 1 / 3), (0.0, 1.0)):
        out = ref.threejs_point_light((0, 0, 3), 2.0, 0.0, decay, geometry_position=(0, 0, 0))
        close(out["Intensity"], 2.0 * want)
        close(out["Light Vector"], Z)
        close(out["Distance"], 3.0)
    out = ref.threejs_point_light((0, 0, 0.05), 1.0, 0.0, 2.0, geometry_position=(0, 0, 0))
    close(out["Intensity"], 100.0)  # 1/max(0.0025, 0.01)


def test_threejs_point_cutoff_window():
    # distance 4, d = 2: (1 - (1/2)^4)^2 = (15/16)^2; d >= 4: 0
    out = ref.threejs_point_light((0, 0, 2), 1.0, 4.0, 2.0, geometry_position=(0, 0, 0))
    close(out["Intensity"], 0.25 * (15 / 16) ** 2)
    out = ref.threejs_point_light((0, 0, 5), 1.0, 4.0, 2.0, geometry_position=(0, 0, 0))
    close(out["Intensity"], 0.0)


def test_threejs_spot_penumbra_smoothstep():
    # angle 60°, penumbra 0.5: coneCos = cos 60° = 0.5, penumbraCos = cos 30°
    a = math.radians(60)
    lo, hi = 0.5, math.cos(math.radians(30))
    for cos_w in (0.45, 0.6, 0.7, 0.8, 0.95):
        sin_w = math.sqrt(1 - cos_w * cos_w)
        p = (sin_w, 0.0, 2.0 - 1.0 * cos_w)  # at distance 1 from the light at (0, 0, 2)
        p = (sin_w, 0.0, 2.0 - cos_w)
        out = ref.threejs_spot_light((0, 0, 2), (0, 0, -1), a, 0.5, 1.0, 0.0, 0.0,
                                     geometry_position=p)
        t = min(max((cos_w - lo) / (hi - lo), 0.0), 1.0)
        close(out["Intensity"], t * t * (3 - 2 * t), 1e-12)
        close(out["Cos Angle"], cos_w, 1e-12)


def test_threejs_spot_penumbra_zero_is_a_hard_edge():
    a = math.radians(30)
    inside = (math.tan(math.radians(29)), 0.0, 0.0)
    outside = (math.tan(math.radians(31)), 0.0, 0.0)
    for p, want in ((inside, 1.0), (outside, 0.0)):
        out = ref.threejs_spot_light((0, 0, 1), (0, 0, -1), a, 0.0, 1.0, 0.0, 0.0,
                                     geometry_position=p)
        close(out["Intensity"], want)


def test_threejs_lambert_divides_by_pi():
    out = ref.threejs_phong(Z, 2.0, WHITE, (0.5, 0.25, 0.1), specular_strength=0.0,
                            geometry_normal=Z, incoming=Z)
    close(out["Diffuse"], [1 / math.pi, 0.5 / math.pi, 0.2 / math.pi])
    close(out["Specular"], [0, 0, 0])
    # 60° off the normal: cos 60° = 1/2; from behind: 0
    ell = (math.sin(math.radians(60)), 0.0, 0.5)
    close(ref.threejs_phong(ell, 1.0, WHITE, WHITE, specular_strength=0.0,
                            geometry_normal=Z, incoming=Z)["Diffuse"], [0.5 / math.pi] * 3)
    close(ref.threejs_phong((0, 0, -1), 1.0, WHITE, WHITE, geometry_normal=Z,
                            incoming=Z)["Color"], [0, 0, 0])


def test_threejs_blinn_phong_at_the_half_vector():
    # ℓ = v = n: n·h = v·h = 1; f = 2^(-12.53789); D = (s/2 + 1)/π
    f = 2.0 ** (-5.55473 - 6.98316)
    for s in (1.0, 30.0, 100.0):
        out = ref.threejs_phong(Z, 1.0, WHITE, (0, 0, 0), (0.2, 0.5, 1.0), s, 1.0,
                                geometry_normal=Z, incoming=Z)
        spec = [(c * (1 - f) + f) * 0.25 * (s / 2 + 1) / math.pi for c in (0.2, 0.5, 1.0)]
        close(out["Specular"], spec)
    # Fresnel with a black specular colour still reflects f90 · fresnel (MeshPhongMaterial)
    out = ref.threejs_phong(Z, 1.0, WHITE, (0, 0, 0), (0, 0, 0), 30.0, 1.0,
                            geometry_normal=Z, incoming=Z)
    close(out["Specular"], [f * 0.25 * 16 / math.pi] * 3)
    # half-way: ℓ and v 90° apart in the plane, n = h: v·h = cos 45°
    ell, v = (S2, 0.0, S2), (-S2, 0.0, S2)
    vh = S2
    fr = 2.0 ** ((-5.55473 * vh - 6.98316) * vh)
    out = ref.threejs_phong(ell, 1.0, WHITE, (0, 0, 0), (0.3, 0.3, 0.3), 10.0, 0.5,
                            geometry_normal=Z, incoming=v)
    close(out["Specular"], [S2 * (0.3 * (1 - fr) + fr) * 0.25 * 6 / math.pi * 0.5] * 3)


def test_threejs_ambient_divides_by_pi():
    close(ref.threejs_ambient(0.5, (1.0, 0.5, 0.0), (0.8, 0.8, 0.8))["Color"],
          [0.4 / math.pi, 0.2 / math.pi, 0.0])
