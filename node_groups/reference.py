# SPDX-License-Identifier: GPL-3.0-or-later
"""Independent numpy reference of the Phong node groups (the ground truth for tests).

Pure numpy, no ``bpy``: every function evaluates, in float64 and vectorised, exactly the
formula that docs/contract.md assigns to one node group.  Vectors and colours are arrays of shape
``(..., 3)`` (an RGBA colour's alpha is dropped), scalars have shape ``(...)`` or are python
floats; all arguments broadcast against each other.

Sources (section numbers of the two seed documents, restated and cited in docs/model.md):

* seed 000 (French lecture notes)
    - §1.3 colours: addition ``min(a + b, 1)`` per channel, multiplication term by term;
      example: magenta light (1, 0, 1) on a yellow object (1, 1, 0) is seen red (1, 0, 0).
    - §1.4 notations: ℓ unit from P toward the source S, n unit normal, v unit from P
      toward the observer O.
    - §2.1 directional light: ℓ = -u/‖u‖, constant over P.
    - §2.2 point light: ℓ = PS/‖PS‖, Proposition 1 ``i = i0/r²``, generalised
      ``i = 1/(αr² + βr + γ)`` (α = 1/i0, β = γ = 0 gives back i0/r²).
    - §2.3 spot: Proposition 2, P is in the cone iff ``cos ω >= cos θ`` with
      ``cos ω = -ℓ·u``; soft edge ``(cos ω)^e_att`` (e_att = 0: hard edge).
    - §3.1 Phong model: Cl = Cl_irr ⊕ Cl_amb ⊕ Cl_diff ⊕ Cl_spec.
    - §3.2 irradiant Cl_irr; §3.3 ambient ``i Cl_source ⊗ Cl_objet``;
      §3.4 diffuse ``i max(ℓ·n, 0) Cl_source ⊗ Cl_objet``;
      §3.5 specular, Lemma 1 ``r = 2(ℓ·n)n - ℓ``, ``i (r·v)^e Cl_source ⊗ Cl_objet`` when
      ℓ·n >= 0 and r·v >= 0, else black; Blinn-Phong variant ``h = (ℓ+v)/‖ℓ+v‖``,
      ``i (h·n)^e ...`` when ℓ·n >= 0 and h·n >= 0.
* seed 004 (Italian slides)
    - slide 43: with no light at all the result is black (0, 0, 0);
    - slides 44-45: directional / positional lights, ω_i = (p_L - p)/‖p_L - p‖;
    - slide 46: falloff ``1/d^k``, k = 2 physical, 1 softer, 0 no attenuation;
    - slides 57-64: R = -ω_i + 2(ω_i·n)n, Phong ``(ω_r·R)^s H ⊗ L``, Blinn-Phong
      ``(n·ω_h)^s H ⊗ L`` (H = the highlight colour, our "Specular Color").

Project conventions that complete the seeds where they are silent (docs/contract.md,
"Edge cases"; docs/model.md, "Where the project goes beyond the seeds"):

* ``normalize(v)`` = v/‖v‖, and a zero vector (‖v‖ <= 1e-30) gives the zero vector.
* A Normal input equal to zero means the geometry normal (``geometry_normal``, normalized);
  any other value is normalized.  A View Vector equal to zero means ``incoming``
  (Geometry ▸ Incoming, normalized); any other value is normalized.
* Light Vector inputs of the term groups are used as given (not re-normalized).
* Exponents are clamped at 0 (``max(e, 0)``) and ``pow(0, 0) = 1``.  The masked power
  bases are ``max(x, 0)``.  Falloff denominators are ``max(denominator, 1e-6)``.
* The inequalities are non-strict (ℓ·n >= 0, r·v >= 0, h·n >= 0, cos ω >= cos θ) and are
  applied literally, also for a zero Light Vector.

Each function returns a dict keyed by the contract's output socket names; ``GROUPS`` maps every
group name of the contract to a generic ``f(inputs, geometry) -> outputs`` evaluator.
"""

import math

import numpy as np

__all__ = [
    "EPS_LENGTH",
    "EPS_DENOMINATOR",
    "normalize",
    "dot",
    "resolve_normal",
    "resolve_view",
    "directional_light",
    "point_light",
    "spot_light",
    "power_falloff",
    "irradiant",
    "ambient",
    "diffuse",
    "specular",
    "blinn_specular",
    "color_add",
    "color_multiply",
    "phong_shading",
    "threejs_point_light",
    "threejs_spot_light",
    "threejs_ambient",
    "threejs_phong",
    "x3d_attenuation",
    "x3d_directional_light",
    "x3d_point_light",
    "x3d_spot_light",
    "x3d_light_terms",
    "GROUPS",
    "DEFAULTS",
]

#: A vector whose length is at most this is the zero vector.
EPS_LENGTH = 1e-30
#: Falloff denominators are taken as max(denominator, EPS_DENOMINATOR).
EPS_DENOMINATOR = 1e-6

_ZERO3 = (0.0, 0.0, 0.0)
_ONE3 = (1.0, 1.0, 1.0)
_UP = (0.0, 0.0, 1.0)


# ---------------------------------------------------------------------------
# helpers
# ---------------------------------------------------------------------------

def _vec(x):
    """float64 array of shape (..., 3)."""
    a = np.asarray(x, dtype=np.float64)
    if a.ndim == 0 or a.shape[-1] != 3:
        raise ValueError("expected a 3-vector (shape (..., 3)), got shape %r" % (a.shape,))
    return a


def _col(x):
    """float64 colour of shape (..., 3); an RGBA colour loses its alpha (docs/contract.md)."""
    a = np.asarray(x, dtype=np.float64)
    if a.ndim >= 1 and a.shape[-1] == 4:
        a = a[..., :3]
    if a.ndim == 0 or a.shape[-1] != 3:
        raise ValueError("expected an RGB colour (shape (..., 3)), got shape %r" % (a.shape,))
    return a


def _sca(x):
    """float64 scalar array of shape (...)."""
    return np.asarray(x, dtype=np.float64)


def dot(a, b):
    """a·b over the last axis (shape (...))."""
    return np.sum(np.asarray(a, dtype=np.float64) * np.asarray(b, dtype=np.float64), axis=-1)


def _length(v):
    return np.sqrt(dot(v, v))


def normalize(v):
    """v/‖v‖; the zero vector (‖v‖ <= 1e-30) gives the zero vector."""
    v = _vec(v)
    n = _length(v)
    ok = n > EPS_LENGTH
    safe = np.where(ok, n, 1.0)
    return np.where(ok[..., None], v / safe[..., None], 0.0)


def _is_zero(v):
    return _length(v) <= EPS_LENGTH


def resolve_normal(normal, geometry_normal):
    """Normal socket: zero -> normalize(geometry_normal), otherwise normalize(normal)."""
    normal = _vec(normal)
    return np.where(_is_zero(normal)[..., None], normalize(geometry_normal), normalize(normal))


def resolve_view(view_vector, incoming):
    """View Vector socket: zero -> normalize(incoming), otherwise normalize(view_vector)."""
    view_vector = _vec(view_vector)
    return np.where(_is_zero(view_vector)[..., None], normalize(incoming), normalize(view_vector))


def _masked_pow(base, mask, exponent):
    """mask · max(base, 0)^max(exponent, 0), with pow(0, 0) = 1 and 0 outside the mask."""
    e = np.maximum(_sca(exponent), 0.0)
    with np.errstate(over="ignore", invalid="ignore"):
        p = np.power(np.maximum(base, 0.0), e)
    return np.where(mask, p, 0.0)


def _falloff(intensity, distance, quadratic, linear, constant):
    """i0 / max(α r² + β r + γ, 1e-6)."""
    r = _sca(distance)
    den = _sca(quadratic) * r * r + _sca(linear) * r + _sca(constant)
    return _sca(intensity) / np.maximum(den, EPS_DENOMINATOR)


# ---------------------------------------------------------------------------
# light models (seed 000 §2, seed 004 slides 44-46; docs/model.md §Light models)
# ---------------------------------------------------------------------------

def directional_light(direction=(0.0, 0.0, -1.0), intensity=1.0, geometry_position=_ZERO3):
    """Phong Directional Light (seed 000 §2.1): ℓ = -u/‖u‖, Intensity = i, both constant over P.

    ``geometry_position`` (P) only fixes the output shape (outputs broadcast over it).
    Zero u gives ℓ = 0 (no light).
    """
    u = _vec(direction)
    p = _vec(geometry_position)
    ell = -normalize(u)
    batch = np.broadcast_shapes(ell.shape[:-1], p.shape[:-1], _sca(intensity).shape)
    ell = np.broadcast_to(ell, batch + (3,)).copy()
    i = np.broadcast_to(_sca(intensity), batch).copy()
    return {"Light Vector": ell, "Intensity": i}


def point_light(position=_ZERO3, intensity=1.0, quadratic=1.0, linear=0.0, constant=0.0,
                geometry_position=_ZERO3):
    """Phong Point Light (seed 000 §2.2, seed 004 slides 45-46).

    ℓ = (S-P)/‖S-P‖ (zero when S = P), r = ‖S-P‖, Intensity = i0 / max(αr² + βr + γ, 1e-6).
    ``position`` is the light's Position socket S, ``geometry_position`` the shaded point P.
    """
    d = _vec(position) - _vec(geometry_position)
    r = _length(d)
    ell = normalize(d)
    i = _falloff(intensity, r, quadratic, linear, constant)
    batch = np.broadcast_shapes(ell.shape[:-1], i.shape)
    return {
        "Light Vector": np.broadcast_to(ell, batch + (3,)).copy(),
        "Intensity": np.broadcast_to(i, batch).copy(),
        "Distance": np.broadcast_to(r, batch).copy(),
    }


def spot_light(position=_ZERO3, direction=(0.0, 0.0, -1.0), half_angle=math.radians(30.0),
               edge_exponent=0.0, intensity=1.0, quadratic=1.0, linear=0.0, constant=0.0,
               geometry_position=_ZERO3):
    """Phong Spot Light (seed 000 §2.3, Proposition 2).

    ℓ = normalize(S-P), r = ‖S-P‖, cos ω = -ℓ·normalize(u), In Cone = [cos ω >= cos θ],
    Intensity = i0/max(αr²+βr+γ, 1e-6) · max(cos ω, 0)^max(e_att, 0) · In Cone.
    """
    d = _vec(position) - _vec(geometry_position)
    r = _length(d)
    ell = normalize(d)
    u = normalize(direction)
    cos_w = -dot(ell, u)
    in_cone = cos_w >= np.cos(_sca(half_angle))
    i = _falloff(intensity, r, quadratic, linear, constant) * _masked_pow(cos_w, in_cone, edge_exponent)
    batch = np.broadcast_shapes(ell.shape[:-1], i.shape, cos_w.shape, in_cone.shape)
    return {
        "Light Vector": np.broadcast_to(ell, batch + (3,)).copy(),
        "Intensity": np.broadcast_to(i, batch).copy(),
        "Distance": np.broadcast_to(r, batch).copy(),
        "Cos Angle": np.broadcast_to(cos_w, batch).astype(np.float64),
        "In Cone": np.broadcast_to(in_cone, batch).astype(np.float64),
    }


def power_falloff(distance=1.0, intensity=1.0, exponent=2.0):
    """Phong Power Falloff (seed 004 slide 46): Intensity = i0 / max(max(d, 0)^max(k, 0), 1e-6).

    k = 2 physical, k = 1 softer, k = 0 no attenuation (pow(0, 0) = 1).
    """
    d = np.maximum(_sca(distance), 0.0)
    k = np.maximum(_sca(exponent), 0.0)
    with np.errstate(over="ignore"):
        den = np.power(d, k)
    return {"Intensity": _sca(intensity) / np.maximum(den, EPS_DENOMINATOR)}


# ---------------------------------------------------------------------------
# Phong terms (seed 000 §3, seed 004 slides 38-66)
# ---------------------------------------------------------------------------

def irradiant(color=_ZERO3):
    """Phong Irradiant (seed 000 §3.2): Color = Cl_irr, the input."""
    return {"Color": _col(color).copy()}


def ambient(intensity=1.0, light_color=_ONE3, object_color=(0.8, 0.8, 0.8)):
    """Phong Ambient (seed 000 §3.3): Color = i · Cl_source ⊗ Cl_objet."""
    return {"Color": _sca(intensity)[..., None] * _col(light_color) * _col(object_color)}


def diffuse(light_vector=_ZERO3, intensity=1.0, light_color=_ONE3, object_color=(0.8, 0.8, 0.8),
            normal=_ZERO3, geometry_normal=_UP):
    """Phong Diffuse (seed 000 §3.4): Color = i · max(ℓ·n, 0) · Cl_source ⊗ Cl_objet."""
    n = resolve_normal(normal, geometry_normal)
    f = np.maximum(dot(_vec(light_vector), n), 0.0)
    return {"Color": (_sca(intensity) * f)[..., None] * _col(light_color) * _col(object_color)}


def phong_factor(light_vector, normal, view):
    """[ℓ·n >= 0 and r·v >= 0] · max(r·v, 0) base and mask, r = 2(ℓ·n)n - ℓ (Lemma 1).

    ``normal`` and ``view`` are already resolved; returns (min(r·v, 1), mask).  For a unit ℓ,
    r·v ≤ 1 anyway; the bound keeps (r·v)^e finite when the Light Vector is not unit.
    """
    ell = _vec(light_vector)
    ln = dot(ell, normal)
    r = 2.0 * ln[..., None] * normal - ell
    rv = dot(r, view)
    return np.minimum(rv, 1.0), (ln >= 0.0) & (rv >= 0.0)


def blinn_factor(light_vector, normal, view):
    """h = normalize(ℓ + v); returns (h·n, mask) with mask = [ℓ·n >= 0 and h·n >= 0]."""
    ell = _vec(light_vector)
    ln = dot(ell, normal)
    h = normalize(ell + view)
    hn = dot(h, normal)
    return hn, (ln >= 0.0) & (hn >= 0.0)


def specular(light_vector=_ZERO3, intensity=1.0, light_color=_ONE3, specular_color=_ONE3,
             exponent=30.0, normal=_ZERO3, view_vector=_ZERO3, geometry_normal=_UP, incoming=_UP):
    """Phong Specular (seed 000 §3.5, seed 004 slides 57-58).

    r = 2(ℓ·n)n - ℓ; Color = i · (r·v)^e · Cl_source ⊗ Cl_spec where ℓ·n >= 0 and r·v >= 0,
    else 0 (e clamped at 0, pow(0, 0) = 1).
    """
    n = resolve_normal(normal, geometry_normal)
    v = resolve_view(view_vector, incoming)
    rv, mask = phong_factor(light_vector, n, v)
    f = _masked_pow(rv, mask, exponent)
    return {"Color": (_sca(intensity) * f)[..., None] * _col(light_color) * _col(specular_color)}


def blinn_specular(light_vector=_ZERO3, intensity=1.0, light_color=_ONE3, specular_color=_ONE3,
                   exponent=30.0, normal=_ZERO3, view_vector=_ZERO3, geometry_normal=_UP,
                   incoming=_UP):
    """Phong Blinn Specular (seed 000 §3.5 Blinn-Phong, seed 004 slides 61-64).

    h = (ℓ+v)/‖ℓ+v‖ (zero if ℓ+v = 0); Color = i · (h·n)^e · Cl_source ⊗ Cl_spec where
    ℓ·n >= 0 and h·n >= 0, else 0.
    """
    n = resolve_normal(normal, geometry_normal)
    v = resolve_view(view_vector, incoming)
    hn, mask = blinn_factor(light_vector, n, v)
    f = _masked_pow(hn, mask, exponent)
    return {"Color": (_sca(intensity) * f)[..., None] * _col(light_color) * _col(specular_color)}


# ---------------------------------------------------------------------------
# colour operations (seed 000 §1.3)
# ---------------------------------------------------------------------------

def color_add(a=_ZERO3, b=_ZERO3):
    """Phong Color Add (seed 000 §1.3): Color = min(A + B, 1) per channel (no lower clamp)."""
    return {"Color": np.minimum(_col(a) + _col(b), 1.0)}


def color_multiply(a=_ONE3, b=_ONE3, factor=1.0):
    """Phong Color Multiply (seed 000 §1.3): Color = Factor · A ⊗ B."""
    return {"Color": _sca(factor)[..., None] * _col(a) * _col(b)}


# ---------------------------------------------------------------------------
# one light, every term
# ---------------------------------------------------------------------------

def phong_shading(light_vector=_ZERO3, light_intensity=1.0, light_color=_ONE3,
                  object_color=(0.8, 0.8, 0.8), irradiant_color=_ZERO3, ambient_intensity=0.1,
                  ambient_color=_ONE3, diffuse_strength=1.0, specular_strength=1.0,
                  specular_color=_ONE3, exponent=30.0, blinn=0.0, normal=_ZERO3,
                  view_vector=_ZERO3, geometry_normal=_UP, incoming=_UP):
    """Phong Shading (seed 000 §3.1): one light, every term.

    Irradiant = Irradiant Color
    Ambient   = Ambient Intensity · Ambient Color ⊗ Object Color
    Diffuse   = Diffuse Strength · Light Intensity · max(ℓ·n, 0) · Light Color ⊗ Object Color
    Specular  = Specular Strength · Light Intensity · ((1-Blinn)·phong + Blinn·blinn)
                · Light Color ⊗ Specular Color   (phong, blinn: the masked powers)
    Color     = min(Irradiant + Ambient + Diffuse + Specular, 1) per channel
    (The Shader output, Emission(Color), is not represented here.)
    """
    ell = _vec(light_vector)
    n = resolve_normal(normal, geometry_normal)
    v = resolve_view(view_vector, incoming)
    lc = _col(light_color)
    oc = _col(object_color)
    li = _sca(light_intensity)

    irr = _col(irradiant_color)
    amb = _sca(ambient_intensity)[..., None] * _col(ambient_color) * oc
    dif = (_sca(diffuse_strength) * li * np.maximum(dot(ell, n), 0.0))[..., None] * lc * oc
    rv, pmask = phong_factor(ell, n, v)
    hn, bmask = blinn_factor(ell, n, v)
    pf = _masked_pow(rv, pmask, exponent)
    bf = _masked_pow(hn, bmask, exponent)
    b = _sca(blinn)
    spec_f = (1.0 - b) * pf + b * bf
    spe = (_sca(specular_strength) * li * spec_f)[..., None] * lc * _col(specular_color)
    color = np.minimum(irr + amb + dif + spe, 1.0)
    batch = color.shape
    return {
        "Irradiant": np.broadcast_to(irr, batch).copy(),
        "Ambient": np.broadcast_to(amb, batch).copy(),
        "Diffuse": np.broadcast_to(dif, batch).copy(),
        "Specular": np.broadcast_to(spe, batch).copy(),
        "Color": color,
    }


# ---------------------------------------------------------------------------
# three.js r181 (docs/threejs.md): MeshPhongMaterial / MeshLambertMaterial per light
# ---------------------------------------------------------------------------
# Restated from three.js's GLSL (src/renderers/shaders/ShaderChunk, npm three@0.181.0),
# not from node_groups/library.py.  GLSL's saturate(x) = clamp(x, 0, 1).

#: MeshPhongMaterial.specular default 0x111111 in linear RGB (sRGB 17/255 decoded).
THREEJS_SPECULAR = tuple([((17 / 255 + 0.055) / 1.055) ** 2.4] * 3)


def _saturate(x):
    return np.clip(x, 0.0, 1.0)


def threejs_distance_attenuation(distance, cutoff, decay):
    """getDistanceAttenuation (lights_pars_begin): 1/max(d^decay, 0.01), and when the
    cut-off distance is > 0 also (saturate(1 - (d/cutoff)^4))^2."""
    d, c, k = _sca(distance), _sca(cutoff), _sca(decay)
    with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
        att = 1.0 / np.maximum(np.power(d, k), 0.01)
        ratio = np.where(c > 0, d / np.where(c > 0, c, 1.0), 0.0)
    window = np.square(_saturate(1.0 - ratio ** 4))
    return np.where(c > 0, att * window, att)


def threejs_smoothstep(edge0, edge1, x):
    """GLSL smoothstep; edge0 = edge1 (penumbra 0) is the step x > edge0."""
    e0, e1, x = np.broadcast_arrays(_sca(edge0), _sca(edge1), _sca(x))
    with np.errstate(divide="ignore", invalid="ignore"):
        t = _saturate((x - e0) / np.where(e1 > e0, e1 - e0, 1.0))
    t = np.where(e1 > e0, t, (x > e0).astype(np.float64))
    return t * t * (3.0 - 2.0 * t)


def threejs_point_light(position=_ZERO3, intensity=1.0, distance=0.0, decay=2.0,
                        geometry_position=_ZERO3):
    """three.js Point Light (getPointLightInfo): ℓ = normalize(S - P), d = ‖S - P‖,
    Intensity = i · getDistanceAttenuation(d, distance, decay)."""
    to_light = _vec(position) - _vec(geometry_position)
    d = _length(to_light)
    return {"Light Vector": normalize(to_light),
            "Intensity": _sca(intensity) * threejs_distance_attenuation(d, distance, decay),
            "Distance": d}


def threejs_spot_light(position=_ZERO3, direction=(0.0, 0.0, -1.0), angle=math.pi / 3.0,
                       penumbra=0.0, intensity=1.0, distance=0.0, decay=2.0,
                       geometry_position=_ZERO3):
    """three.js Spot Light (getSpotLightInfo, getSpotAttenuation; WebGLLights: coneCos =
    cos(angle), penumbraCos = cos(angle·(1 - penumbra))): Intensity = i ·
    smoothstep(coneCos, penumbraCos, cos ω) · getDistanceAttenuation, cos ω = ℓ·(-u)."""
    to_light = _vec(position) - _vec(geometry_position)
    d = _length(to_light)
    ell = normalize(to_light)
    cos_w = -dot(ell, normalize(direction))
    a = _sca(angle)
    cone = threejs_smoothstep(np.cos(a), np.cos(a * (1.0 - _sca(penumbra))), cos_w)
    return {"Light Vector": ell,
            "Intensity": _sca(intensity) * cone * threejs_distance_attenuation(d, distance, decay),
            "Distance": d, "Cos Angle": cos_w}


def threejs_ambient(intensity=1.0, light_color=_ONE3, diffuse_color=_ONE3):
    """three.js Ambient (RE_IndirectDiffuse_BlinnPhong / _Lambert with irradiance =
    ambientLightColor = intensity · colour): irradiance · BRDF_Lambert(color) = i·L⊗C/π."""
    return {"Color": _sca(intensity)[..., None] * _col(light_color) * _col(diffuse_color) / math.pi}


def threejs_phong(light_vector=_ZERO3, intensity=1.0, light_color=_ONE3, diffuse_color=_ONE3,
                  specular_color=THREEJS_SPECULAR, shininess=30.0, specular_strength=1.0,
                  normal=_ZERO3, view_vector=_ZERO3, geometry_normal=_UP, incoming=_UP):
    """three.js Phong (RE_Direct_BlinnPhong; RE_Direct_Lambert when Specular Strength is 0):

    irradiance = saturate(n·ℓ) · i · light colour
    Diffuse  = irradiance ⊗ color/π                                  (BRDF_Lambert)
    Specular = irradiance ⊗ F · 0.25 · D · specularStrength           (BRDF_BlinnPhong)
      h = normalize(ℓ + v), F = f0 (1 - f) + f, f = 2^((-5.55473 v·h - 6.98316) v·h)
      (F_Schlick, f90 = 1), D = (s/2 + 1)/π · saturate(n·h)^s, s = max(shininess, 1e-4)
      (WebGLMaterials clamps shininess, so pow(0, 0) never happens)
    Color = Diffuse + Specular
    """
    ell = _vec(light_vector)
    n = resolve_normal(normal, geometry_normal)
    v = resolve_view(view_vector, incoming)
    irradiance = (_saturate(dot(n, ell)) * _sca(intensity))[..., None] * _col(light_color)
    diffuse = irradiance * _col(diffuse_color) / math.pi
    h = normalize(ell + v)
    nh = _saturate(dot(n, h))
    vh = _saturate(dot(v, h))
    s = np.maximum(_sca(shininess), 1e-4)
    fresnel = np.exp2((-5.55473 * vh - 6.98316) * vh)[..., None]
    f = _col(specular_color) * (1.0 - fresnel) + fresnel
    with np.errstate(over="ignore", invalid="ignore"):
        d = (s * 0.5 + 1.0) / math.pi * np.power(nh, s)
    specular = irradiance * f * (0.25 * d)[..., None] * _sca(specular_strength)[..., None]
    return {"Diffuse": diffuse, "Specular": specular, "Color": diffuse + specular}


# ---------------------------------------------------------------------------
# X3D / VRML97 (docs/x3d.md): the ISO lighting equations per light
# ---------------------------------------------------------------------------
# Restated from ISO/IEC 19775-1 (X3D) §17.2.2.4 "Lighting equations" and ISO/IEC 14772-1
# (VRML97) §4.14.4, not from node_groups/library.py:
#
#   I = O_E + Σ_i on_i · attenuation_i · spot_i · IL_i ⊗ (ambient_i + diffuse_i + specular_i)
#   attenuation_i = 1 / max(a0 + a1·d + a2·d², 1)          (directional lights: 1)
#   spot_i        = 0 where ω ≥ cutOffAngle, 1 where ω ≤ beamWidth, else
#                   (ω - cutOffAngle) / (beamWidth - cutOffAngle)   (ω = acos(-ℓ·u))
#   ambient_i     = Ia_i · O_a,  O_a = material ambientIntensity × diffuseColor
#   diffuse_i     = I_i · O_d · max(N·L, 0)
#   specular_i    = I_i · O_s · max(N·H, 0)^(128 × shininess),  H = normalize(L + V)
#
# a point or spot light reaches only the points within its radius (d ≤ radius).  The
# specular term has no N·L condition (the standards have none).


def x3d_attenuation(distance, constant=1.0, linear=0.0, quadratic=0.0):
    """1 / max(a0 + a1·d + a2·d², 1): never above 1 (the clamp of both standards)."""
    d = _sca(distance)
    return 1.0 / np.maximum(_sca(constant) + _sca(linear) * d + _sca(quadratic) * d * d, 1.0)


def _x3d_reach(distance, radius):
    """1 where the point is within the radius (d ≤ radius; a negative radius: everywhere)."""
    r = _sca(radius)
    return ((_sca(distance) <= r) | (r < 0.0)).astype(np.float64)


def x3d_directional_light(direction=(0.0, 0.0, -1.0), intensity=1.0, ambient_intensity=0.0,
                          geometry_position=_ZERO3):
    """X3D DirectionalLight: ℓ = -u/‖u‖ everywhere, no attenuation, no radius."""
    ell = -normalize(direction)
    shape = np.broadcast_shapes(np.shape(_vec(geometry_position)), np.shape(ell))
    return {"Light Vector": np.broadcast_to(ell, shape).copy(),
            "Intensity": _sca(intensity) + np.zeros(shape[:-1]),
            "Ambient": _sca(ambient_intensity) + np.zeros(shape[:-1])}


def x3d_point_light(position=_ZERO3, intensity=1.0, ambient_intensity=0.0, constant=1.0,
                    linear=0.0, quadratic=0.0, radius=100.0, geometry_position=_ZERO3):
    """X3D PointLight: Intensity = I·attenuation and Ambient = Ia·attenuation within the
    radius, 0 beyond it."""
    to_light = _vec(position) - _vec(geometry_position)
    d = _length(to_light)
    factor = x3d_attenuation(d, constant, linear, quadratic) * _x3d_reach(d, radius)
    return {"Light Vector": normalize(to_light), "Intensity": _sca(intensity) * factor,
            "Ambient": _sca(ambient_intensity) * factor, "Distance": d}


def x3d_spot_factor(spot_angle, beam_width, cut_off_angle):
    """spot_i of the standards: a linear ramp in the angle from the beam to the cut-off."""
    w, beam, cut = np.broadcast_arrays(_sca(spot_angle), _sca(beam_width), _sca(cut_off_angle))
    with np.errstate(divide="ignore", invalid="ignore"):
        ramp = np.where(beam != cut, (w - cut) / np.where(beam != cut, beam - cut, 1.0), 0.0)
    return np.where(w >= cut, 0.0, np.where(w <= beam, 1.0, ramp))


def x3d_spot_light(position=_ZERO3, direction=(0.0, 0.0, -1.0), beam_width=0.7854,
                   cut_off_angle=1.570796, intensity=1.0, ambient_intensity=0.0,
                   constant=1.0, linear=0.0, quadratic=0.0, radius=100.0,
                   geometry_position=_ZERO3):
    """X3D SpotLight (X3D's defaults as the standard writes them: beamWidth 0.7854,
    cutOffAngle 1.570796; VRML97's are the other way round, which its reader gives): the
    point light times spot_i of ω = acos(-ℓ·u)."""
    point = x3d_point_light(position, intensity, ambient_intensity, constant, linear, quadratic,
                            radius, geometry_position)
    cos_w = np.clip(-dot(point["Light Vector"], normalize(direction)), -1.0, 1.0)
    w = np.arccos(cos_w)
    spot = x3d_spot_factor(w, beam_width, cut_off_angle)
    return {"Light Vector": point["Light Vector"], "Intensity": point["Intensity"] * spot,
            "Ambient": point["Ambient"] * spot, "Distance": point["Distance"],
            "Spot Angle": w}


def x3d_light_terms(light_vector=_ZERO3, intensity=1.0, ambient=0.0, light_color=_ONE3,
                    exponent=25.6, normal=_UP, view_vector=_UP):
    """One light's share of the X3D lighting equation before the material's colours, for a
    unit normal and view vector: Diffuse Light = I·max(N·L, 0)·IL, Specular Light =
    I·max(N·H, 0)^e·IL (no N·L condition; e = 128 × shininess, 0^0 = 1), Ambient Light =
    Ia·IL (Ia already attenuated and spotted)."""
    ell, n, v = _vec(light_vector), _vec(normal), _vec(view_vector)
    color = _col(light_color)
    i = _sca(intensity)
    diffuse = (i * np.maximum(dot(n, ell), 0.0))[..., None] * color
    nh = np.maximum(dot(n, normalize(ell + v)), 0.0)
    e = np.maximum(_sca(exponent), 0.0)
    with np.errstate(over="ignore", invalid="ignore", divide="ignore"):
        highlight = np.where(e == 0.0, 1.0, np.power(nh, e))
    specular = (i * highlight)[..., None] * color
    return {"Diffuse Light": diffuse, "Specular Light": specular,
            "Ambient Light": _sca(ambient)[..., None] * color}


# ---------------------------------------------------------------------------
# shadows: a light's visibility against the scene's triangles
# ---------------------------------------------------------------------------

#: A blocker nearer to the shaded point than this, times 1 + max |P|, is the surface itself
#: (the triangle the point lies on, or one it touches): not a shadow.
SHADOW_START = 1.0e-4
#: Pairs tested at once (memory: about 200 bytes each).
_CHUNK = 1 << 19
#: Triangles per cluster of the pre-test (a box around them, tested first), and clusters
#: per super-cluster (a box around theirs, tested before).
_CLUSTER = 16
_SUPER = 32


def _pairs_hit(o, d, start, reach, v0, e1, e2):
    """Möller–Trumbore for paired rays and triangles (all arrays (M, 3) / (M,)): whether the
    ray o + t·d meets the triangle (v0, v0 + e1, v0 + e2), either face, at start < t < reach."""
    pvec = np.cross(d, e2)
    det = np.einsum("mk,mk->m", pvec, e1)
    ok = np.abs(det) > 1e-20
    inv = np.where(ok, 1.0 / np.where(ok, det, 1.0), 0.0)
    tvec = o - v0
    u = np.einsum("mk,mk->m", tvec, pvec) * inv
    qvec = np.cross(tvec, e1)
    v = np.einsum("mk,mk->m", d, qvec) * inv
    t = np.einsum("mk,mk->m", e2, qvec) * inv
    return ok & (u >= 0.0) & (v >= 0.0) & (u + v <= 1.0) & (t > start) & (t < reach - 1e-9)


def _clusters(tris):
    """The triangles grouped _CLUSTER at a time by a median split of their centres along the
    longest axis, recursively: (members (C, _CLUSTER) indices, -1 for none; box lows (C, 3),
    highs (C, 3))."""
    centres = tris.mean(axis=1)
    groups, done = [np.arange(len(tris))], []
    while groups:
        group = groups.pop()
        if len(group) <= _CLUSTER:
            done.append(group)
            continue
        c = centres[group]
        axis = int(np.argmax(c.max(axis=0) - c.min(axis=0)))
        order = group[np.argsort(c[:, axis], kind="stable")]
        half = len(order) // 2
        groups += [order[:half], order[half:]]
    return _boxes(done, tris.min(axis=1), tris.max(axis=1), _CLUSTER)


def _boxes(groups, lows, highs, size):
    """(members (G, size), -1 for none; box lows (G, 3); highs (G, 3)) of *groups* (index
    arrays into *lows* / *highs*, the items' own boxes)."""
    members = np.full((len(groups), size), -1, np.int64)
    for row, group in enumerate(groups):
        members[row, :len(group)] = group
    first = members[:, :1]
    safe = np.where(members >= 0, members, first)  # a missing item repeats the group's first
    return members, lows[safe].min(axis=1), highs[safe].max(axis=1)


def _expand(ray, members):
    """(ray, item) pairs: each of *ray* with each item of its row of *members* (-1: none)."""
    rays = np.repeat(ray, members.shape[1])
    items = members.reshape(-1)
    keep = items >= 0
    return rays[keep], items[keep]


def _box_hit(o, inv, reach, lo, hi):
    """Slab test of paired rays (origins *o*, 1/direction *inv*) and boxes: whether the ray
    meets the box at 0 <= t <= *reach* (a NaN from 0 · inf counts as no limit)."""
    with np.errstate(invalid="ignore"):
        t1, t2 = (lo - o) * inv, (hi - o) * inv
        near = np.nanmax(np.minimum(t1, t2), axis=-1)
        far = np.nanmin(np.maximum(t1, t2), axis=-1)
    return ~(near > np.minimum(far, reach)) & ~(far < 0.0)


def visibility(points, light, triangles):
    """Per point of *points* (N, 3): 1.0 where nothing of *triangles* (T, 3, 3: the corners
    of the scene's shadow-casting triangles, world space) lies on the segment from the point
    to a point or spot *light*'s ``position`` (or, a directional light, on the ray from the
    point against its ``direction``), else 0.0; a light whose ``shadows`` is false: 1.0
    everywhere.  Hits nearer than ``SHADOW_START`` · (1 + max |P|) to the point, and at the
    light itself, do not count.  Möller–Trumbore's ray/triangle test, both faces, on the
    (ray, triangle) pairs whose ray meets the box of the triangle's cluster (``_clusters``: a
    box test first, so a scene of many triangles is not N × T exact tests), vectorised in
    chunks."""
    P = np.asarray(points, np.float64).reshape(-1, 3)
    seen = np.ones(len(P))
    tris = np.asarray(triangles, np.float64).reshape(-1, 3, 3)
    if not light.get("shadows") or not len(P) or not len(tris):
        return seen
    if light["type"] == "directional":
        D = np.broadcast_to(-normalize(_vec(light["direction"])), P.shape)
        reach = np.full(len(P), np.inf)
    else:
        D = _vec(light["position"]) - P
        reach = _length(D)
        D = D / np.maximum(reach, 1e-30)[:, None]
    start = SHADOW_START * (1.0 + np.abs(P).max(axis=-1))
    members, lo, hi = _clusters(tris)
    supers = [np.arange(i, min(i + _SUPER, len(lo))) for i in range(0, len(lo), _SUPER)]
    super_members, super_lo, super_hi = _boxes(supers, lo, hi, _SUPER)
    v0 = tris[:, 0]
    e1, e2 = tris[:, 1] - v0, tris[:, 2] - v0
    with np.errstate(divide="ignore", invalid="ignore"):
        inv_d = 1.0 / D
    blocked = np.zeros(len(P), bool)
    step = max(1, _CHUNK // (3 * len(super_lo)))
    for a in range(0, len(P), step):
        b = min(a + step, len(P))
        near = _box_hit(P[a:b, None, :], inv_d[a:b, None, :], reach[a:b, None],
                        super_lo[None], super_hi[None])
        ray, group = np.nonzero(near)
        ray, cluster = _expand(ray + a, super_members[group])
        for c in range(0, len(ray), _CHUNK):
            rr, cc = ray[c:c + _CHUNK], cluster[c:c + _CHUNK]
            keep = _box_hit(P[rr], inv_d[rr], reach[rr], lo[cc], hi[cc]) & ~blocked[rr]
            rays, tri = _expand(rr[keep], members[cc[keep]])
            for e in range(0, len(rays), _CHUNK):
                r3, t3 = rays[e:e + _CHUNK], tri[e:e + _CHUNK]
                hit = _pairs_hit(P[r3], D[r3], start[r3], reach[r3], v0[t3], e1[t3], e2[t3])
                blocked[r3[hit]] = True
    seen[blocked] = 0.0
    return seen


# ---------------------------------------------------------------------------
# generic table: group name -> f(inputs, geometry)
# ---------------------------------------------------------------------------

#: Per group: (function, {input socket name: keyword}, {geometry key: keyword}).
_TABLE = {
    "Phong Directional Light": (
        directional_light,
        {"Direction": "direction", "Intensity": "intensity"},
        {"Position": "geometry_position"},
    ),
    "Phong Point Light": (
        point_light,
        {"Position": "position", "Intensity": "intensity", "Quadratic": "quadratic",
         "Linear": "linear", "Constant": "constant"},
        {"Position": "geometry_position"},
    ),
    "Phong Spot Light": (
        spot_light,
        {"Position": "position", "Direction": "direction", "Half Angle": "half_angle",
         "Edge Exponent": "edge_exponent", "Intensity": "intensity", "Quadratic": "quadratic",
         "Linear": "linear", "Constant": "constant"},
        {"Position": "geometry_position"},
    ),
    "Phong Power Falloff": (
        power_falloff,
        {"Distance": "distance", "Intensity": "intensity", "Exponent": "exponent"},
        {},
    ),
    "Phong Irradiant": (irradiant, {"Color": "color"}, {}),
    "Phong Ambient": (
        ambient,
        {"Intensity": "intensity", "Light Color": "light_color", "Object Color": "object_color"},
        {},
    ),
    "Phong Diffuse": (
        diffuse,
        {"Light Vector": "light_vector", "Intensity": "intensity", "Light Color": "light_color",
         "Object Color": "object_color", "Normal": "normal"},
        {"Normal": "geometry_normal"},
    ),
    "Phong Specular": (
        specular,
        {"Light Vector": "light_vector", "Intensity": "intensity", "Light Color": "light_color",
         "Specular Color": "specular_color", "Exponent": "exponent", "Normal": "normal",
         "View Vector": "view_vector"},
        {"Normal": "geometry_normal", "Incoming": "incoming"},
    ),
    "Phong Blinn Specular": (
        blinn_specular,
        {"Light Vector": "light_vector", "Intensity": "intensity", "Light Color": "light_color",
         "Specular Color": "specular_color", "Exponent": "exponent", "Normal": "normal",
         "View Vector": "view_vector"},
        {"Normal": "geometry_normal", "Incoming": "incoming"},
    ),
    "three.js Point Light": (
        threejs_point_light,
        {"Position": "position", "Intensity": "intensity", "Distance": "distance",
         "Decay": "decay"},
        {"Position": "geometry_position"},
    ),
    "three.js Spot Light": (
        threejs_spot_light,
        {"Position": "position", "Direction": "direction", "Angle": "angle",
         "Penumbra": "penumbra", "Intensity": "intensity", "Distance": "distance",
         "Decay": "decay"},
        {"Position": "geometry_position"},
    ),
    "three.js Ambient": (
        threejs_ambient,
        {"Intensity": "intensity", "Light Color": "light_color", "Diffuse Color": "diffuse_color"},
        {},
    ),
    "three.js Phong": (
        threejs_phong,
        {"Light Vector": "light_vector", "Intensity": "intensity", "Light Color": "light_color",
         "Diffuse Color": "diffuse_color", "Specular Color": "specular_color",
         "Shininess": "shininess", "Specular Strength": "specular_strength",
         "Normal": "normal", "View Vector": "view_vector"},
        {"Normal": "geometry_normal", "Incoming": "incoming"},
    ),
    "X3D Directional Light": (
        x3d_directional_light,
        {"Direction": "direction", "Intensity": "intensity",
         "Ambient Intensity": "ambient_intensity"},
        {"Position": "geometry_position"},
    ),
    "X3D Point Light": (
        x3d_point_light,
        {"Position": "position", "Intensity": "intensity",
         "Ambient Intensity": "ambient_intensity", "Constant": "constant", "Linear": "linear",
         "Quadratic": "quadratic", "Radius": "radius"},
        {"Position": "geometry_position"},
    ),
    "X3D Spot Light": (
        x3d_spot_light,
        {"Position": "position", "Direction": "direction", "Beam Width": "beam_width",
         "Cut Off Angle": "cut_off_angle", "Intensity": "intensity",
         "Ambient Intensity": "ambient_intensity", "Constant": "constant", "Linear": "linear",
         "Quadratic": "quadratic", "Radius": "radius"},
        {"Position": "geometry_position"},
    ),
    "Phong Color Add": (color_add, {"A": "a", "B": "b"}, {}),
    "Phong Color Multiply": (color_multiply, {"A": "a", "B": "b", "Factor": "factor"}, {}),
    "Phong Shading": (
        phong_shading,
        {"Light Vector": "light_vector", "Light Intensity": "light_intensity",
         "Light Color": "light_color", "Object Color": "object_color",
         "Irradiant Color": "irradiant_color", "Ambient Intensity": "ambient_intensity",
         "Ambient Color": "ambient_color", "Diffuse Strength": "diffuse_strength",
         "Specular Strength": "specular_strength", "Specular Color": "specular_color",
         "Exponent": "exponent", "Blinn": "blinn", "Normal": "normal",
         "View Vector": "view_vector"},
        {"Normal": "geometry_normal", "Incoming": "incoming"},
    ),
}

#: Input socket names accepted by each group, in the contract's order.
INPUTS = {name: tuple(spec[1]) for name, spec in _TABLE.items()}


def _defaults(func):
    import inspect

    return {p.name: p.default for p in inspect.signature(func).parameters.values()}


#: Default value of every input socket, per group: {group: {socket: default}}.
DEFAULTS = {
    name: {sock: _defaults(func)[kw] for sock, kw in sockets.items()}
    for name, (func, sockets, _geo) in _TABLE.items()
}

_VECTOR_GEOMETRY = ("Position", "Normal", "Incoming")


def _make_group(name):
    func, sockets, geo_map = _TABLE[name]
    # The shape of each output for one shaded point, from the formula itself (the function on
    # its unbatched defaults), not from the output's name.
    core_shapes = {key: np.shape(val) for key, val in func().items()}

    def evaluate(inputs=None, geometry=None):
        inputs = dict(inputs or {})
        geometry = dict(geometry or {})
        unknown = set(inputs) - set(sockets)
        if unknown:
            raise KeyError("%s has no input(s) %s" % (name, sorted(unknown)))
        kwargs = {sockets[k]: v for k, v in inputs.items()}
        for key, kw in geo_map.items():
            if key in geometry:
                kwargs[kw] = geometry[key]
        out = func(**kwargs)
        # Broadcast every output over the geometry's batch shape (one value per shaded point).
        shapes = [np.shape(geometry[k])[:-1] for k in _VECTOR_GEOMETRY if k in geometry]
        if shapes:
            batch = np.broadcast_shapes(*shapes)
            res = {}
            for key, val in out.items():
                core = core_shapes[key]  # () for a scalar, (3,) for a vector or colour
                vb = np.broadcast_shapes(val.shape[:val.ndim - len(core)], batch)
                res[key] = np.broadcast_to(val, vb + core).astype(np.float64)
            out = res
        return out

    evaluate.__name__ = func.__name__ + "_group"
    evaluate.__doc__ = "GROUPS[%r]: inputs keyed by socket names %s.\n\n%s" % (
        name, list(sockets), func.__doc__)
    return evaluate


#: group name -> f(inputs: {input socket: value}, geometry: {"Position", "Normal",
#: "Incoming"}) -> {output socket: float64 array}.  Missing inputs take the defaults.
GROUPS = {name: _make_group(name) for name in _TABLE}
