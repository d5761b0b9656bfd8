# SPDX-License-Identifier: GPL-3.0-or-later
"""The Phong node-group library: every group of docs/contract.md, as Python.

Each group is a function that declares its sockets (name, kind: float, vector, colour or
shader, default, range, tooltip) and its outputs as expressions (``expr.py``) that read like
the formulas of docs/model.md.  The same definitions are written as nodes by
``addon/loader.py`` and evaluated on numpy arrays by the tests.  Comments cite the sections of
docs/model.md (where each formula comes from in the seeds) and docs/contract.md (sockets,
defaults, edge cases).

No ``bpy`` here.
"""

from __future__ import annotations

import hashlib
import itertools
import math
from dataclasses import dataclass, field

from . import models
from .expr import (
    COLOR, FLOAT, SHADER, VECTOR, Expr, acos, at_least, combine, cos, dot, emission, equal,
    evaluate, faceforward, geometry, greater_than, input_, raycast, scale_add, switch,
    length, less_than, maximum, minimum, multiply_add, normalize, power, reflect_about, saturate,
    select,
)

#: Bump when any group changes: files with older groups are upgraded in place.
LIBRARY_VERSION = 3

#: Smallest falloff denominator (docs/contract.md, "Edge cases": max(denominator, 10⁻⁶)).
MIN_DENOMINATOR = 1e-6

WHITE = (1.0, 1.0, 1.0)
BLACK = (0.0, 0.0, 0.0)
GREY = (0.8, 0.8, 0.8)
ZERO = (0.0, 0.0, 0.0)
DOWN = (0.0, 0.0, -1.0)
UP = (0.0, 0.0, 1.0)
#: A lights group's light reads its light's axis as its unit +Z axis (the World copy
#: "UNIT_AXIS", addon/lighting/world_copies.py), normalised by its drivers: a sun's ℓ itself,
#: a spot's cos ω = ℓ·(this), with no node per light to normalise or negate the -Z axis.
_REVERSED_AXIS = ("Reversed Axis", UP, "The light's unit +Z axis (its -Z axis reversed): "
                  "toward a sun; a spot's cos ω is ℓ·(this)")
BIG = 1.0e9


# -- the model's formulas, shared by the groups ------------------------------

def lambert(l, n):
    """max(ℓ·n, 0): Lambert's cosine law, zero for light from behind.

    docs/model.md §Diffuse (seed 000 §3.4; seed 004 slides 30 and 38)."""
    return maximum(dot(l, n), 0.0)


def both_at_least_zero(a, b):
    """1 where a ≥ 0 and b ≥ 0, else 0 (as min(a, b) ≥ 0: one comparison instead of two)."""
    return at_least(minimum(a, b), 0.0)


def phong_factor(l, n, v, e):
    """(r·v)^e where ℓ·n ≥ 0 and r·v ≥ 0, else 0 (docs/model.md §Specular (Phong)), with the
    mirror direction r = 2(ℓ·n)n - ℓ (Lemma 1) computed as -reflect_about(ℓ, n), one node.

    r·v is taken as at most 1: exact for a unit ℓ (then |r| = 1 and r·v ≤ 1), and it keeps
    (r·v)^e finite for a Light Vector input that is not unit (‖ℓ‖ = 10⁶, e = 30 overflowed).
    """
    rv = -dot(reflect_about(l, n), v)  # r·v, r = 2(ℓ·n)n - ℓ = -reflect_about(ℓ, n)
    return both_at_least_zero(dot(l, n), rv) * power(saturate(rv), maximum(e, 0.0))


def blinn_factor(l, n, v, e):
    """(h·n)^e with h = (ℓ+v)/‖ℓ+v‖, where ℓ·n ≥ 0 and h·n ≥ 0, else 0.

    docs/model.md §Blinn-Phong."""
    hn = dot(normalize(l + v), n)
    return both_at_least_zero(dot(l, n), hn) * power(maximum(hn, 0.0), maximum(e, 0.0))


def falloff(i0, r, quadratic, linear, constant):
    """i0/(αr² + βr + γ), denominator at least 1e-6 (docs/model.md §Point light); the
    denominator as (αr + β)r + γ, two multiply-adds."""
    denominator = multiply_add(multiply_add(quadratic, r, linear), r, constant)
    return i0 / maximum(denominator, MIN_DENOMINATOR)


def clamp_add(a, b):
    """Cl1 ⊕ Cl2 = min(Cl1 + Cl2, 1) per channel (docs/model.md §Colours)."""
    return minimum(a + b, 1.0)


# -- declaring groups ------------------------------------------------------

#: The Blender socket type of each socket kind.
SOCKET_TYPES = {FLOAT: "NodeSocketFloat", VECTOR: "NodeSocketVector", COLOR: "NodeSocketColor",
                SHADER: "NodeSocketShader"}
_KINDS = {socket_type: kind for kind, socket_type in SOCKET_TYPES.items()}


@dataclass
class Socket:
    """One socket of a group's interface; its kind (float, vector, colour, shader) is declared
    by the method that made it (``GroupDef.value`` / ``vector`` / ``color`` / ``output``)."""

    name: str
    socket_type: str  # SOCKET_TYPES[kind]
    description: str = ""
    default: object = None
    min: float | None = None
    max: float | None = None
    subtype: str | None = None

    @property
    def kind(self) -> str:
        """FLOAT, VECTOR, COLOR or SHADER."""
        return _KINDS[self.socket_type]


@dataclass
class GroupDef:
    name: str
    description: str
    inputs: list = field(default_factory=list)
    outputs: list = field(default_factory=list)
    expressions: dict = field(default_factory=dict)

    # inputs ---------------------------------------------------------------
    def _input(self, kind, name, description, default, min=None, max=None, subtype=None) -> Expr:
        self.inputs.append(Socket(name, SOCKET_TYPES[kind], description, default, min, max, subtype))
        return input_(name, kind)

    def value(self, name, default, description, min=-BIG, max=BIG, subtype=None) -> Expr:
        return self._input(FLOAT, name, description, float(default), min, max, subtype)

    def vector(self, name, default, description) -> Expr:
        return self._input(VECTOR, name, description, tuple(default), -BIG, BIG)

    def color(self, name, default, description) -> Expr:
        return self._input(COLOR, name, description, (*default, 1.0))

    def normal(self) -> Expr:
        """The Normal input: zero means Geometry ▸ Normal, anything else is normalized."""
        n = self.vector("Normal", ZERO, "Surface normal n; leave at zero for the shading normal, "
                                         "or plug a Normal Map / Bump node")
        return select(less_than(length(n), 1e-30), geometry("Normal"), normalize(n))

    def view(self) -> Expr:
        """The View Vector input: zero means Geometry ▸ Incoming, anything else is normalized."""
        v = self.vector("View Vector", ZERO, "Unit vector v from the point toward the viewer; "
                                              "leave at zero for the camera direction")
        return select(less_than(length(v), 1e-30), geometry("Incoming"), normalize(v))

    # outputs --------------------------------------------------------------
    def output(self, name, expression, description="", color=False) -> None:
        """An output computing *expression*; ``color=True`` declares a vector a colour (RGBA)."""
        kind = expression.kind
        if color:
            if kind != VECTOR:
                raise TypeError(f"output {name!r}: only a vector expression can be a colour")
            kind = COLOR
        self.outputs.append(Socket(name, SOCKET_TYPES[kind], description))
        self.expressions[name] = expression

    # for the tests and the loader ------------------------------------------
    def defaults(self) -> dict:
        return {s.name: s.default for s in self.inputs}

    def evaluate(self, inputs: dict, geometry_values: dict | None = None) -> dict:
        """The group's outputs on numpy arrays; missing inputs take their defaults."""
        values = {**self.defaults(), **inputs}
        memo: dict = {}
        return {name: evaluate(e, values, geometry_values or {}, memo)
                for name, e in self.expressions.items() if e.kind != SHADER}

    @property
    def fingerprint(self) -> str:
        """Changes whenever the sockets or the formulas change (and only then: it is the text of
        the sockets and of the formulas, so the groups in users' files are rewritten on load when
        what they compute changes, not when the writer's code does)."""
        text = repr((self.inputs, self.outputs, sorted(self.expressions.items())))
        return hashlib.sha256(text.encode()).hexdigest()[:16]


GROUPS: dict = {}
#: Groups that the scenes' lights groups are built from (``addon/lighting/rig.py``), not
#: part of the library that users browse (docs/contract.md, "Several lights").
RIG_GROUPS: dict = {}


def group(name, description, into=GROUPS):
    def register(fn):
        g = GroupDef(name, description)
        fn(g)
        into[name] = g
        return fn
    return register


#: Variants of a group for a feature of the running Blender: {name: {feature: GroupDef}}, the
#: same sockets and the same values with fewer nodes where the feature allows
#: (``definition(name, features)``; the loader passes ``compat.NODE_FEATURES``).
VARIANTS: dict = {}
#: Blender 5.3's Switch node in shader trees: Blender's inliner keeps only the branch that a
#: constant condition chooses (``expr.SWITCH``).
SWITCH_FEATURE = "switch"


def variant(name, feature, description):
    """Register a variant of group *name* for *feature* (see ``VARIANTS``)."""
    def register(fn):
        g = GroupDef(name, description)
        fn(g)
        VARIANTS.setdefault(name, {})[feature] = g
        return fn
    return register


def definition(name: str, features=()) -> GroupDef:
    """The definition of the library's or the lights groups' group *name*: its variant for
    the first of *features* that has one, else the group as every release writes it."""
    for feature in features:
        found = VARIANTS.get(name, {}).get(feature)
        if found is not None:
            return found
    return GROUPS[name] if name in GROUPS else RIG_GROUPS[name]


# Tooltips used by several groups
_L = "Unit vector ℓ from the shaded point toward the light (from a Phong light group)"
_I = "Light intensity i_source (dimensionless, not watts)"
_LC = "Colour of the light, Cl_source"
_OC = "Colour of the object, Cl_objet"
_SC = "Colour of the highlights (seed 004's H; seed 000 uses the object colour)"
_E = "Specular exponent (shininess): higher gives smaller, sharper highlights"
_POS = "Position S of the light in world space"
_I0 = "Intensity i0 received at distance 1"
_ALPHA = "α in 1/(αr²+βr+γ): 1 gives the physical i0/r²"
_BETA = "β in 1/(αr²+βr+γ)"
_GAMMA = "γ in 1/(αr²+βr+γ)"


# -- light models (docs/model.md §Light models: seed 000 §2, seed 004 slides 44-46) --

@group("Phong Directional Light", "Sun-like light: the same direction and intensity everywhere (seed 000 §2.1)")
def _directional(g):
    """docs/model.md §Directional light."""
    u = g.vector("Direction", DOWN, "Direction u in which the rays travel")
    i = g.value("Intensity", 1.0, _I, min=0.0)
    g.output("Light Vector", -normalize(u), "ℓ = -u/‖u‖")
    g.output("Intensity", i, "The light's intensity, the same at every point")


#: The falloff i0/(αr²+βr+γ) a light has unless it says otherwise: α = 1, the physical i0/r².
#: The one owner of these defaults: the groups' inputs, the scene files (``core/scenes.py``)
#: and the Blender lights' settings (``addon/lighting/properties.py``) read them from here.
FALLOFF_DEFAULTS = {"quadratic": 1.0, "linear": 0.0, "constant": 0.0}


def _falloff_inputs(g):
    i0 = g.value("Intensity", 1.0, _I0, min=0.0)
    a = g.value("Quadratic", FALLOFF_DEFAULTS["quadratic"], _ALPHA, min=0.0)
    b = g.value("Linear", FALLOFF_DEFAULTS["linear"], _BETA, min=0.0)
    c = g.value("Constant", FALLOFF_DEFAULTS["constant"], _GAMMA, min=0.0)
    return i0, a, b, c


@group("Phong Point Light", "Bulb-like light radiating from a point, with distance falloff (seed 000 §2.2)")
def _point(g):
    """docs/model.md §Point light."""
    s = g.vector("Position", ZERO, _POS)
    i0, a, b, c = _falloff_inputs(g)
    to_light = s - geometry("Position")
    r = length(to_light)
    g.output("Light Vector", normalize(to_light), "ℓ = (S-P)/‖S-P‖")
    g.output("Intensity", falloff(i0, r, a, b, c), "i0/(αr²+βr+γ)")
    g.output("Distance", r, "r = ‖S-P‖")


@group("Phong Spot Light", "Point light limited to a cone, with a cos^e soft edge (seed 000 §2.3)")
def _spot(g):
    """docs/model.md §Spot light (Proposition 2, soft edge)."""
    s = g.vector("Position", ZERO, _POS)
    u = g.vector("Direction", DOWN, "Axis u of the cone (normalized inside)")
    theta = g.value("Half Angle", math.radians(30.0), "Half angle θ of the cone",
                    min=0.0, max=math.pi, subtype="ANGLE")
    e_att = g.value("Edge Exponent", 0.0, "e_att: 0 gives a hard edge, higher values a softer one",
                    min=0.0, max=10000.0)
    i0, a, b, c = _falloff_inputs(g)
    to_light = s - geometry("Position")
    r = length(to_light)
    l = normalize(to_light)
    cos_w = -dot(l, normalize(u))
    in_cone = at_least(cos_w, cos(theta))
    edge = power(maximum(cos_w, 0.0), maximum(e_att, 0.0))
    g.output("Light Vector", l, "ℓ = (S-P)/‖S-P‖")
    g.output("Intensity", falloff(i0, r, a, b, c) * edge * in_cone,
             "i0/(αr²+βr+γ)·cos(ω)^e_att inside the cone, else 0")
    g.output("Distance", r, "r = ‖S-P‖")
    g.output("Cos Angle", cos_w, "cos ω = -ℓ·u")
    g.output("In Cone", in_cone, "1 where cos ω ≥ cos θ, else 0")


@group("Phong Power Falloff", "Attenuation i0/d^k (seed 004 slide 46: k = 2 physical, 1 softer, 0 none)")
def _power_falloff(g):
    """docs/model.md §Power falloff."""
    d = g.value("Distance", 1.0, "Distance d to the light", min=0.0)
    i0 = g.value("Intensity", 1.0, _I0, min=0.0)
    k = g.value("Exponent", 2.0, "k: 2 physical, 1 softer, 0 no attenuation", min=0.0, max=16.0)
    g.output("Intensity", i0 / maximum(power(maximum(d, 0.0), maximum(k, 0.0)), MIN_DENOMINATOR),
             "i0/d^k")


# -- Phong terms (docs/model.md §The Phong model, docs/contract.md §Phong terms) --

@group("Phong Irradiant", "Light emitted by the object itself, Cl_irr (seed 000 §3.2)")
def _irradiant(g):
    """docs/model.md §Irradiant."""
    g.output("Color", g.color("Color", BLACK, "Irradiant colour Cl_irr"), "Cl_irr", color=True)


@group("Phong Ambient", "Sourceless light, the same everywhere (seed 000 §3.3)")
def _ambient(g):
    """docs/model.md §Ambient."""
    i = g.value("Intensity", 1.0, "Ambient intensity i_source", min=0.0)
    lc = g.color("Light Color", WHITE, "Colour of the ambient light")
    oc = g.color("Object Color", GREY, _OC)
    g.output("Color", i * lc * oc, "i·Cl_source ⊗ Cl_objet", color=True)


def _term_inputs(g, color_name, color_default, color_tip):
    l = g.vector("Light Vector", ZERO, _L)
    i = g.value("Intensity", 1.0, _I, min=0.0)
    lc = g.color("Light Color", WHITE, _LC)
    c = g.color(color_name, color_default, color_tip)
    return l, i, lc, c


@group("Phong Diffuse", "Lambert diffuse term of matte surfaces (seed 000 §3.4)")
def _diffuse(g):
    """docs/model.md §Diffuse."""
    l, i, lc, oc = _term_inputs(g, "Object Color", GREY, _OC)
    n = g.normal()
    g.output("Color", (i * lambert(l, n)) * (lc * oc), "i·max(ℓ·n, 0)·Cl_source ⊗ Cl_objet",
             color=True)


def _specular_group(g, factor, formula):
    l, i, lc, sc = _term_inputs(g, "Specular Color", WHITE, _SC)
    e = g.value("Exponent", 30.0, _E, min=0.0, max=10000.0)
    n = g.normal()
    v = g.view()
    g.output("Color", (i * factor(l, n, v, e)) * (lc * sc), formula, color=True)


@group("Phong Specular", "Phong highlight around the mirror direction (seed 000 §3.5)")
def _specular(g):
    """docs/model.md §Specular (Phong), §Highlight colour."""
    _specular_group(g, phong_factor, "i·(r·v)^e·Cl_source ⊗ Cl_spec, r = 2(ℓ·n)n - ℓ")


@group("Phong Blinn Specular", "Blinn-Phong highlight with the half vector (seed 000 §3.5)")
def _blinn(g):
    """docs/model.md §Blinn-Phong."""
    _specular_group(g, blinn_factor, "i·(h·n)^e·Cl_source ⊗ Cl_spec, h = (ℓ+v)/‖ℓ+v‖")


# -- colour operations (docs/model.md §Colours) --------------------------------

@group("Phong Color Add", "Colour addition without exceeding 1 (seed 000 §1.3)")
def _color_add(g):
    a = g.color("A", BLACK, "First colour")
    b = g.color("B", BLACK, "Second colour")
    g.output("Color", clamp_add(a, b), "min(A + B, 1) per channel", color=True)


@group("Phong Color Multiply", "Colour product: the colour an object shows under a light (seed 000 §1.3)")
def _color_multiply(g):
    a = g.color("A", WHITE, "First colour, e.g. the light's")
    b = g.color("B", WHITE, "Second colour, e.g. the object's")
    f = g.value("Factor", 1.0, "Multiplier to brighten dark products", min=0.0)
    g.output("Color", f * a * b, "Factor·A ⊗ B", color=True)


# -- one light, every term (docs/model.md §The Phong model, docs/contract.md §Phong Shading) --

@group("Phong Shading", "The whole Phong model for one light: irradiant + ambient + diffuse + specular")
def _shading(g):
    """docs/model.md §The Phong model and its subsections, §Separate diffuse and specular
    intensities."""
    l = g.vector("Light Vector", ZERO, _L)
    i = g.value("Light Intensity", 1.0, _I, min=0.0)
    lc = g.color("Light Color", WHITE, _LC)
    oc = g.color("Object Color", GREY, _OC)
    irr = g.color("Irradiant Color", BLACK, "Light emitted by the object itself, Cl_irr")
    amb_i = g.value("Ambient Intensity", 0.1, "Intensity of the ambient light", min=0.0)
    amb_c = g.color("Ambient Color", WHITE, "Colour of the ambient light")
    kd = g.value("Diffuse Strength", 1.0, "i_source,diff / i_source (seed 000 §3.5)", min=0.0)
    ks = g.value("Specular Strength", 1.0, "i_source,spec / i_source (seed 000 §3.5)", min=0.0)
    sc = g.color("Specular Color", WHITE, _SC)
    e = g.value("Exponent", 30.0, _E, min=0.0, max=10000.0)
    blinn = g.value("Blinn", 0.0, "0 = Phong, 1 = Blinn-Phong, between = blend", min=0.0, max=1.0,
                    subtype="FACTOR")
    n = g.normal()
    v = g.view()
    ambient = amb_i * amb_c * oc
    # Colour products in brackets: constant in most materials, so the renderer folds them.
    diffuse = (kd * i * lambert(l, n)) * (lc * oc)
    factor = (1.0 - blinn) * phong_factor(l, n, v, e) + blinn * blinn_factor(l, n, v, e)
    specular = (ks * i * factor) * (lc * sc)
    color = minimum(irr + ambient + diffuse + specular, 1.0)
    g.output("Irradiant", irr, "Cl_irr", color=True)
    g.output("Ambient", ambient, "Ambient term", color=True)
    g.output("Diffuse", diffuse, "Diffuse term", color=True)
    g.output("Specular", specular, "Specular term", color=True)
    g.output("Color", color, "Clamped sum of the four terms", color=True)
    g.output("Shader", emission(color), "Emission of Color at strength 1: the model's colour in any engine")


# -- the parts of a scene's lights group (addon/lighting/rig.py) ------------------------
#
# A lights group computes what one Phong Shading per light, summed with Phong Color Add,
# computes (docs/contract.md, "Several lights"), with fewer nodes: every Eevee pass of every
# material expands them again (measured: about 40 µs per node per material per render).  So
# the normal and the view vector are resolved once for all lights (Phong Surface), each light
# adds only its diffuse and specular light (its light group, below), and the material colours, the
# ambient, the irradiant and the clamp are taken once, in the lights group.  The products of
# driven values (strengths, light colour) stand in brackets of their own, so Blender folds
# them into one value before it writes the shader (it does not fold a material's RGB node:
# hence the material colours multiply the sums, not each light).

@group("Phong Surface", "The unit normal and view vector of the shaded point, once for all lights",
       into=RIG_GROUPS)
def _surface(g):
    """The Normal / View Vector inputs as every Phong term reads them (GroupDef.normal, view)."""
    g.output("Normal", g.normal(), "normalize(Normal), or Geometry ▸ Normal when it is zero")
    g.output("View Vector", g.view(),
             "normalize(View Vector), or Geometry ▸ Incoming when it is zero")


# -- one light of a lights group, whole (the seeds' model: addon/lighting/rig.py) -----------
#
# What a light costs is the nodes it adds to every material's shader (Cycles spends about
# 14 µs per inlined node per material before the first sample, Eevee 5.2 about 40 µs per
# node per material per pass: benchmarks/README.md), so each light of the seeds' model is
# one group whose formula is the fewest exact nodes: its light model, its shadow ray, its
# diffuse and specular light added to the sums of the lights before it.  Its type, falloff
# and shadow are chosen when the lights group is built (one group each), the highlight by a
# Switch on 5.3.  What is the same for every light is computed once per material, by Phong
# Surface and Phong Surface Rays: the unit normal n and view vector v, the mirror image of
# v (so that r·v is one dot product), the normal scaled for the gate below, the ray's lift.
#
# Three identities carry it, every term being ≥ 0:
# * ℓ·r = S - P is also the shadow ray's direction (Length 1 from the lifted origin), and
#   r·v = ℓ·(2(n·v)n - v), the view vector reflected once per material (the three.js and
#   X3D groups read ℓ too: ``_rig_light_of``); where β = 0 (i0 from a light's Power) 5.3's
#   Switch leaves αr² + γ with r² one dot product;
# * ℓ·n ≥ 0 and r·v ≥ 0 (the highlight's condition) as one clamped minimum,
#   saturate(min(r·v, G·(ℓ·n))), G = 2⁴⁰: r·v where ℓ·n ≥ 2⁻⁴⁰·r·v, 0 where either is
#   negative; then x^max(e, 10⁻³⁰) is 0 at x = 0 and x^e elsewhere, so the condition costs
#   no node.  The diffuse light reads G·(ℓ·n) too, its colour times 2⁻⁴⁰ (exact: powers
#   of two); a spot's cone and edge the same way, saturate(min(cos ω, G·(cos ω - cos θ)));
# * a shadowed point's light divided by 10³⁰ + its falloff, not multiplied by 0: the shadow
#   ray's hit goes into the denominator, the one division every light already has.

#: The gate's scale G (see above): 2⁴⁰, a power of two, so that G·x·2⁻⁴⁰ is x exactly.
GATE_SCALE = 2.0 ** 40
#: The smallest exponent of the highlight and the spot's edge: x^1e-30 is 1 for any
#: positive float and 0 at 0, which is what the conditions need where e = 0.
MIN_GATED_EXPONENT = 1.0e-30
#: What a hit adds to a light's falloff denominator: its light becomes 10⁻³⁰ of itself.
SHADOW_DENOMINATOR = 1.0e30
#: A sun's shadow ray's length (in units of its unit direction): "to infinity" within float
#: range.
SUN_RAY_LENGTH = 1.0e8
#: The scale of the normal that three.js's lights read saturate(n·ℓ) with (``_threejs_light``):
#: 2⁻⁷, a power of two, so that n·ℓ·2⁻⁷ over the falloff's denominator (at least 0.01) stays
#: below 1 and one clamped division is max(n·ℓ, 0)/denominator·2⁻⁷ exactly.
LAMBERT_SCALE = 2.0 ** -7
#: The rig's light types (a Blender light's: ``models.drawn_as``), falloffs and shadows, and
#: the name of each group.
LIGHT_KINDS = {"POINT": "Point", "SPOT": "Spot", "SUN": "Sun"}
#: The sums a light adds to (the Plain ones: without its shadow, what Eevee shows before 5.3).
_SUMS = (("Diffuse Sum", "diffuse"), ("Specular Sum", "specular"),
         ("Plain Diffuse Sum", "unshadowed diffuse"), ("Plain Specular Sum", "unshadowed specular"))
FALLOFFS = {"QUADRATIC": "", "POWER": " (i0/d^k)"}
#: The highlights of a light group of a model that blends Phong's and Blinn-Phong's by the
#: material's Blinn (``models.LightingModel.blinn``): the blend (any Blinn; on 5.3 its Switch
#: leaves one highlight where Blinn is 0 or 1), and a variant with only Phong's (Blinn 0) or
#: only Blinn-Phong's (Blinn 1), what a lights group before 5.3 uses for a material whose Blinn
#: is exactly 0 or 1 (the same values, the other highlight's and the blend's nodes fewer).
BLEND, PHONG, BLINN = "BLEND", "PHONG", "BLINN"
HIGHLIGHTS = {BLEND: "", PHONG: " (Phong highlight)", BLINN: " (Blinn-Phong highlight)"}


#: Before Blender 5.3 (no Switch node): the constants of a light that choose nodes of its
#: light group in the three.js and X3D models, each a fact that holds or not, by the light
#: types it concerns, with what a group's name says where it holds and where it does not.  On
#: 5.3 a Switch on the constant keeps one branch inside the one group; before, the lights group
#: takes the group of the light's facts (``rig_light_group``: *facts*), which has only that
#: branch, or, where a setting is animated or driven, the general one, which has both.
#: A fact holds where the condition of its Switch does.  (fact, light types, name where it
#: holds, name where it does not)
LIGHT_FACTS = {
    "threejs": (("cut-off", ("POINT", "SPOT"), "cut-off", "no cut-off"),
                ("decay 2", ("POINT", "SPOT"), "decay 2", "any decay"),
                ("penumbra", ("SPOT",), "penumbra", "hard edge")),
    "x3d": (("ramp", ("SPOT",), "ramp", "hard edge"),
            ("ambient 0", ("POINT", "SPOT", "SUN"), "no ambient", "own ambient")),
}


def light_facts(model: str, kind: str) -> tuple:
    """The facts (``LIGHT_FACTS``) that choose nodes of *model*'s light group of *kind*."""
    return tuple(fact for fact, kinds, _yes, _no in LIGHT_FACTS.get(model, ()) if kind in kinds)


def rig_light_group(model: str, kind: str, falloff: str = "QUADRATIC",
                    shadows: bool = False, highlight: str = BLEND, facts=None) -> str:
    """The light group a lights group of *model* (``models.MODELS``: its ``rig``) draws a
    light of *kind* (POINT, SPOT, SUN) and *falloff* with, with a shadow ray or not, with
    *highlight* (``HIGHLIGHTS``; ignored by a model without the blend), and *facts* (a
    {fact: bool} of ``light_facts``, or None: the general group, where any value goes): e.g.
    "Phong Rig Spot (i0/d^k) with Shadow (Phong highlight)", "three.js Rig Point with
    Shadow [no cut-off, decay 2]"."""
    entry = models.get(model)
    name = f"{entry.rig} {LIGHT_KINDS[kind]}"
    if kind != "SUN" and entry.power_falloff:
        name += FALLOFFS[falloff]
    name += " with Shadow" if shadows else ""
    name += HIGHLIGHTS[highlight] if entry.blinn else ""
    if facts:
        words = {fact: (yes, no) for fact, _kinds, yes, no in LIGHT_FACTS[model]}
        name += " [" + ", ".join(words[fact][0 if facts[fact] else 1]
                                 for fact in light_facts(model, kind)) + "]"
    return name


@group("Phong Surface Rays", "What every light of a lights group reads of the shaded point, "
       "once for all lights", into=RIG_GROUPS)
def _surface_rays(g):
    """The view vector reflected about the normal, the normal times G (the gate, see above)
    and the shaded point's position."""
    n = g.vector("Normal", (0.0, 0.0, 1.0), "Unit surface normal n (Phong Surface)")
    v = g.vector("View Vector", (0.0, 0.0, 1.0), "Unit vector v toward the viewer (Phong Surface)")
    g.output("Reflected View", -reflect_about(v, n), "2(n·v)n - v: r·v = ℓ·(this)")
    g.output("Light Gate Normal", n * GATE_SCALE, "G·n: G·(ℓ·n) = ℓ·(this)")
    g.output("Position", geometry("Position"), "The shaded point P")


def _light_of(g, kind, falloff, shadows, switched, highlight=BLEND):
    """One light, whole (see above): its diffuse and specular light added to the sums;
    *highlight*: the blend by Blinn, or only one highlight (``HIGHLIGHTS``: no Blinn input)."""
    near = kind in ("POINT", "SPOT")
    s = g.vector("Position", ZERO, _POS) if near else None
    t = g.vector(*_REVERSED_AXIS) if kind != "POINT" else None
    if kind == "SPOT":
        theta = g.value("Half Angle", math.radians(30.0), "Half angle θ of the cone",
                        min=0.0, max=math.pi, subtype="ANGLE")
        e_att = g.value("Edge Exponent", 0.0, "e_att: 0 gives a hard edge, higher values a "
                        "softer one", min=0.0, max=10000.0)
    i0 = g.value("Intensity", 1.0, _I0 if near else _I, min=0.0)
    if near and falloff == "QUADRATIC":
        a = g.value("Quadratic", FALLOFF_DEFAULTS["quadratic"], _ALPHA, min=0.0)
        b = g.value("Linear", FALLOFF_DEFAULTS["linear"], _BETA, min=0.0)
        c = g.value("Constant", FALLOFF_DEFAULTS["constant"], _GAMMA, min=0.0)
    elif near:
        k = g.value("Falloff Exponent", 2.0, "k of i0/d^k: 2 physical, 1 softer, 0 none",
                    min=0.0, max=16.0)
    lc = g.color("Light Color", WHITE, _LC)
    kd = g.value("Diffuse Strength", 1.0, "i_source,diff / i_source (seed 000 §3.5)", min=0.0)
    ks = g.value("Specular Strength", 1.0, "i_source,spec / i_source (seed 000 §3.5)", min=0.0)
    e = g.value("Exponent", 30.0, _E, min=0.0, max=10000.0)
    blinn = g.value("Blinn", 0.0, "0 = Phong, 1 = Blinn-Phong, between = blend", min=0.0,
                    max=1.0, subtype="FACTOR") if highlight == BLEND else None
    n = g.vector("Normal", (0.0, 0.0, 1.0), "Unit surface normal n (Phong Surface)")
    v = g.vector("View Vector", (0.0, 0.0, 1.0), "Unit vector v toward the viewer (Phong Surface)")
    reflected = g.vector("Reflected View", (0.0, 0.0, 1.0), "2(n·v)n - v (Phong Surface Rays)")
    gate_n = g.vector("Light Gate Normal", (0.0, 0.0, GATE_SCALE), "G·n (Phong Surface Rays)")
    p = g.vector("Surface Position", ZERO, "The shaded point P (Phong Surface Rays)")
    if shadows:
        ng = g.vector("True Normal", (0.0, 0.0, 1.0), "The true (geometric) normal Ng")
        lift = g.vector("Ray Lift", ZERO, "offset·Ng: the ray starts at P + sign(Ng·ℓ)·"
                        "offset·Ng, on the light's side of the surface")
        casts = g.value("Cast Shadow", 1.0, "1: the light casts shadows, 0: it does not",
                        min=0.0, max=1.0)
    sums = {name: g.vector(name, ZERO, f"The {what} light of the lights before")
            for name, what in _SUMS[:4 if shadows else 2]}

    if near:
        toward = s - p  # ℓ·r: the light vector and the shadow ray's direction
        r = length(toward)
        ell = normalize(toward)
    else:
        ell = t  # toward the sun, a unit vector
    numerator = i0
    if kind == "SPOT":  # cos ω = -ℓ·û = ℓ·t; [cos ω ≥ cos θ]·max(cos ω, 0)^e_att (above)
        cos_w = dot(ell, t)
        base = saturate(minimum(cos_w, multiply_add(cos_w, GATE_SCALE, -GATE_SCALE * cos(theta))))
        numerator = i0 * power(base, maximum(e_att, MIN_GATED_EXPONENT))
    hit = None
    if shadows:
        origin = p - faceforward(lift, ell, ng)  # P + sign(Ng·ℓ)·offset·Ng, Ng·ℓ = 0: + too
        hit = (raycast(origin, toward, 1.0) if near  # from the origin, as far as ℓ·r
               else raycast(origin, ell, SUN_RAY_LENGTH))

    def intensity(shade):
        """i0 (times a spot's cone and edge) over the falloff; *shade*: the denominator plus
        hit·cast·10³⁰ (one node: cast·10³⁰ is the light's constant)."""
        def more(denominator):
            return multiply_add(hit, casts * SHADOW_DENOMINATOR, denominator) if shade \
                else denominator

        if near and falloff == "QUADRATIC":
            denominator = multiply_add(multiply_add(a, r, b), r, more(c))
            if switched:  # β = 0 (i0 from the Power: i0/r²): αr² + γ, r² one dot product
                denominator = switch(equal(b, 0.0), denominator,
                                     multiply_add(a, dot(toward, toward), more(c)))
            return numerator / maximum(denominator, MIN_DENOMINATOR)
        if near:
            return numerator / maximum(more(power(r, maximum(k, 0.0))), MIN_DENOMINATOR)
        return numerator / more(1.0) if shade else numerator

    ln_g = dot(ell, gate_n)  # G·(ℓ·n)
    e_1 = maximum(e, MIN_GATED_EXPONENT)
    if highlight != BLINN:
        phong = power(saturate(minimum(dot(ell, reflected), ln_g)), e_1)
    if highlight != PHONG:
        blinn_f = power(saturate(minimum(dot(normalize(v + ell), n), ln_g)), e_1)
    if highlight == BLEND:
        factor = (1.0 - blinn) * phong + blinn * blinn_f
        if switched:
            factor = switch(equal(blinn, 0.0), switch(equal(blinn, 1.0), factor, blinn_f), phong)
    else:
        factor = phong if highlight == PHONG else blinn_f
    diffuse_color = (kd * (1.0 / GATE_SCALE)) * lc  # G·(ℓ·n) times 2⁻⁴⁰: ℓ·n, exactly
    for prefix, shade in (("", shadows), ("Plain ", False))[:2 if shadows else 1]:
        i = intensity(shade)
        g.output(f"{prefix}Diffuse Sum",
                 scale_add(diffuse_color, i * maximum(ln_g, 0.0), sums[f"{prefix}Diffuse Sum"]),
                 "+ i·max(ℓ·n, 0)·k_d·Cl_source" + (", unshadowed" if prefix else ""),
                 color=True)
        g.output(f"{prefix}Specular Sum",
                 scale_add(ks * lc, i * factor, sums[f"{prefix}Specular Sum"]),
                  {BLEND: "+ i·[ℓ·n ≥ 0]·((1-Blinn)·(r·v)^e + Blinn·(h·n)^e)·k_s·Cl_source",
                  PHONG: "+ i·[ℓ·n ≥ 0]·(r·v)^e·k_s·Cl_source",
                  BLINN: "+ i·[ℓ·n ≥ 0]·(h·n)^e·k_s·Cl_source"}[highlight] +
                 (", unshadowed" if prefix else ""), color=True)


def _register_lights():
    for kind in LIGHT_KINDS:
        for falloff in (FALLOFFS if kind != "SUN" else ("QUADRATIC",)):
            for shadows in (False, True):
                name = rig_light_group("seeds", kind, falloff, shadows)
                what = (f"One {LIGHT_KINDS[kind].lower()} light of a lights group: its diffuse "
                        "and specular light added to the sums" +
                        (", shadowed by its shadow ray" if shadows else ""))
                group(name, what, into=RIG_GROUPS)(
                    lambda g, k=kind, f=falloff, s=shadows: _light_of(g, k, f, s, False))
                variant(name, SWITCH_FEATURE, what)(
                    lambda g, k=kind, f=falloff, s=shadows: _light_of(g, k, f, s, True))
                for highlight in (PHONG, BLINN):  # before 5.3: Blinn exactly 0 or 1
                    group(rig_light_group("seeds", kind, falloff, shadows, highlight),
                          what + f", {HIGHLIGHTS[highlight].strip(' ()')} only",
                          into=RIG_GROUPS)(
                        lambda g, k=kind, f=falloff, s=shadows, h=highlight:
                        _light_of(g, k, f, s, False, h))


_register_lights()


# -- three.js (docs/threejs.md: three.js r181's shader chunks, npm three@0.181.0) ---------
#
# What three.js's MeshPhongMaterial and MeshLambertMaterial compute per light, so that a
# scene in the three.js model (docs/threejs.md) shows in Blender what the browser shows.
# Each helper cites the chunk (src/renderers/shaders/ShaderChunk/<chunk>.glsl.js) it
# restates.  Directional lights are the seeds' Phong Directional Light: three.js's
# direction is the same ℓ = -u/‖u‖ (lights_pars_begin, getDirectionalLightInfo).

#: three.js's MeshPhongMaterial.specular default, 0x111111, as linear RGB (three.js converts
#: hex colours from sRGB).
THREEJS_SPECULAR = (((17 / 255 + 0.055) / 1.055) ** 2.4,) * 3
#: 1/π as three.js writes it (common: RECIPROCAL_PI).
RECIPROCAL_PI = 0.3183098861837907


def distance_attenuation(r, cutoff, decay):
    """1/max(r^decay, 0.01), times (saturate(1 - (r/cutoff)^4))² when cutoff > 0
    (lights_pars_begin: getDistanceAttenuation)."""
    falloff = 1.0 / maximum(power(r, decay), 0.01)
    x = r / cutoff
    x2 = x * x
    window = saturate(1.0 - x2 * x2)
    return falloff * select(less_than(0.0, cutoff), window * window, 1.0)


def smoothstep(edge0, edge1, x):
    """GLSL smoothstep: t = saturate((x - edge0)/(edge1 - edge0)), t²(3 - 2t)
    (lights_pars_begin: getSpotAttenuation).  With edge0 = edge1 (penumbra 0) GLSL divides
    by zero: t is 1 where x > edge0 and 0 below (what SwiftShader and GPUs do), a hard
    edge."""
    t = saturate((x - edge0) / (edge1 - edge0))
    t = select(less_than(edge0, edge1), t, less_than(edge0, x))
    return t * t * (3.0 - 2.0 * t)


def f_schlick(f0, dot_vh):
    """F_Schlick(f0, f90 = 1, v·h) with Epic's exp2 form of (1 - v·h)^5 (common: F_Schlick)."""
    fresnel = power(2.0, (-5.55473 * dot_vh - 6.98316) * dot_vh)
    return f0 * (1.0 - fresnel) + WHITE * fresnel  # f90 = 1 in every channel


def brdf_blinn_phong(l, v, n, specular, shininess):
    """F · G · D with G = 0.25 (G_BlinnPhong_Implicit) and D = (s/2 + 1)/π · (n·h)^s
    (bsdfs: BRDF_BlinnPhong, D_BlinnPhong); h = normalize(ℓ + v)."""
    h = normalize(l + v)
    dot_nh = saturate(dot(n, h))
    dot_vh = saturate(dot(v, h))
    d = RECIPROCAL_PI * (shininess * 0.5 + 1.0) * power(dot_nh, shininess)
    return f_schlick(specular, dot_vh) * (0.25 * d)


_T_CUTOFF = "three.js distance: the light reaches 0 there (smooth window); 0 = no cut-off"
_T_DECAY = "three.js decay: intensity/d^decay (2 physical)"


def _threejs_falloff_inputs(g):
    i = g.value("Intensity", 1.0, "three.js light intensity (the light's colour is multiplied by it)",
                min=0.0)
    cutoff = g.value("Distance", 0.0, _T_CUTOFF, min=0.0)
    decay = g.value("Decay", 2.0, _T_DECAY, min=0.0, max=16.0)
    return i, cutoff, decay


@group("three.js Point Light", "three.js PointLight: intensity/d^decay with a cut-off window (lights_pars_begin)")
def _threejs_point(g):
    """docs/threejs.md §Point light."""
    s = g.vector("Position", ZERO, _POS)
    i, cutoff, decay = _threejs_falloff_inputs(g)
    to_light = s - geometry("Position")
    r = length(to_light)
    g.output("Light Vector", normalize(to_light), "ℓ = (S-P)/‖S-P‖")
    g.output("Intensity", i * distance_attenuation(r, cutoff, decay),
             "i/max(d^decay, 0.01) · saturate(1-(d/distance)⁴)²")
    g.output("Distance", r, "d = ‖S-P‖")


@group("three.js Spot Light", "three.js SpotLight: cone with a smoothstep penumbra and distance attenuation (lights_pars_begin)")
def _threejs_spot(g):
    """docs/threejs.md §Spot light."""
    s = g.vector("Position", ZERO, _POS)
    u = g.vector("Direction", DOWN, "Axis u of the cone, from the light toward its target")
    angle = g.value("Angle", math.pi / 3.0, "three.js angle: half angle of the cone",
                    min=0.0, max=math.pi / 2.0, subtype="ANGLE")
    penumbra = g.value("Penumbra", 0.0, "three.js penumbra: share of the cone that fades",
                       min=0.0, max=1.0, subtype="FACTOR")
    i, cutoff, decay = _threejs_falloff_inputs(g)
    to_light = s - geometry("Position")
    r = length(to_light)
    l = normalize(to_light)
    cos_w = -dot(l, normalize(u))
    cone = smoothstep(cos(angle), cos(angle * (1.0 - penumbra)), cos_w)
    g.output("Light Vector", l, "ℓ = (S-P)/‖S-P‖")
    g.output("Intensity", i * cone * distance_attenuation(r, cutoff, decay),
             "i · smoothstep(cos angle, cos(angle·(1-penumbra)), cos ω) · attenuation")
    g.output("Distance", r, "d = ‖S-P‖")
    g.output("Cos Angle", cos_w, "cos ω = -ℓ·u")


@group("three.js Ambient", "three.js AmbientLight on a Phong or Lambert material (lights_phong_pars_fragment)")
def _threejs_ambient(g):
    """docs/threejs.md §Ambient light."""
    i = g.value("Intensity", 1.0, "three.js AmbientLight intensity", min=0.0)
    lc = g.color("Light Color", WHITE, "Colour of the ambient light")
    c = g.color("Diffuse Color", WHITE, "The material's color (three.js's diffuse colour)")
    g.output("Color", (i * RECIPROCAL_PI) * (lc * c), "i·light ⊗ color / π", color=True)


@group("three.js Phong", "One light on three.js's MeshPhongMaterial (Specular Strength 0: MeshLambertMaterial)")
def _threejs_phong(g):
    """docs/threejs.md §Direct light: RE_Direct_BlinnPhong (lights_phong_pars_fragment) and
    RE_Direct_Lambert (lights_lambert_pars_fragment)."""
    l = g.vector("Light Vector", ZERO, _L)
    i = g.value("Intensity", 1.0, "Intensity of the light at the point (from a three.js light group)",
                min=0.0)
    lc = g.color("Light Color", WHITE, _LC)
    c = g.color("Diffuse Color", WHITE, "The material's color (three.js's diffuse colour)")
    sc = g.color("Specular Color", THREEJS_SPECULAR, "The material's specular colour (three.js default 0x111111)")
    s = g.value("Shininess", 30.0, "three.js shininess", min=0.0, max=10000.0)
    strength = g.value("Specular Strength", 1.0,
                       "three.js specularStrength: 1 MeshPhongMaterial, 0 MeshLambertMaterial",
                       min=0.0, max=1.0, subtype="FACTOR")
    n = g.normal()
    v = g.view()
    irradiance = (i * saturate(dot(n, l))) * lc
    diffuse = irradiance * (RECIPROCAL_PI * c)
    specular = irradiance * brdf_blinn_phong(l, v, n, sc, maximum(s, 1e-4)) * strength
    g.output("Diffuse", diffuse, "saturate(n·ℓ)·i·light ⊗ color/π", color=True)
    g.output("Specular", specular, "saturate(n·ℓ)·i·light ⊗ F·G·D · specular strength", color=True)
    g.output("Color", diffuse + specular, "Diffuse + Specular (not clamped)", color=True)


# -- one three.js light of a lights group, whole (addon/lighting/rig.py) --------------------
#
# Its model's part of the one shape of the three.js and X3D light groups (``_rig_light_of``
# below: ℓ, the shadow ray).  saturate(n·ℓ) over the falloff max(d^decay, 0.01) is one
# clamped division of ℓ·(n·2⁻⁷) (n·2⁻⁷ once per material, ``rig.py``; a power of two, so
# that the quotient stays below 1 and the clamp is the max(·, 0); the light's colour times
# 2⁷, a constant); the shadow ray's hit goes into that denominator (a sun's: into n·ℓ before its clamp, so
# that a shadowed point's n·ℓ is -10³⁰).  The highlight reads the half vector's length:
# for unit v and ℓ, |v + ℓ| = 2 v·h, so n·h = n·(v + ℓ)/|v + ℓ| (its clamp the division's)
# and Schlick's v·h is half that length, with no second normalisation nor dot product.  The
# light's colour times F = f0 + (1 - f0)·fresnel is split over two sums, Σ lc·i·(n·h)^s and
# Σ lc·i·(n·h)^s·fresnel, which the material's colours multiply once (three.js Rig
# Material), as they do the diffuse sum: the material's colours are not constants where the
# lights group is inlined (its RGB nodes are not folded), so a product with them per light
# would cost nodes.  A spot's hard edge (penumbra 0) and n·ℓ are one clamped minimum,
# saturate(min(n·ℓ, E·(cos ω - cos angle))): E = 2¹⁰⁰, a power of two, so that the
# product's sign is exact and any positive difference a float can hold gives at least 1.
# On 5.3 Switches on the light's and the material's constants keep only what is used: the
# cut-off window where the light's distance is above 0, d² as one dot product where its
# decay is 2, a smoothstep penumbra where its penumbra is above 0 (else the hard edge), the
# highlight where the material's Specular Strength is above 0 (MeshLambertMaterial: 0).

#: The spot's hard edge as a clamped minimum with n·ℓ (above): 2¹⁰⁰.
EDGE_SCALE = 2.0 ** 100


def _threejs_settings(g, kind):
    """The three.js light group's own inputs: the light's settings, the material's."""
    own = {}
    if kind == "SPOT":
        own["angle"] = g.value("Angle", math.pi / 3.0, "three.js angle: half angle of the cone",
                               min=0.0, max=math.pi / 2.0, subtype="ANGLE")
        own["penumbra"] = g.value("Penumbra", 0.0, "three.js penumbra: share of the cone that "
                                  "fades", min=0.0, max=1.0, subtype="FACTOR")
    own["i"] = g.value("Intensity", 1.0, "three.js light intensity (the light's colour is "
                       "multiplied by it)", min=0.0)
    if kind != "SUN":
        own["cutoff"] = g.value("Distance", 0.0, _T_CUTOFF, min=0.0)
        own["decay"] = g.value("Decay", 2.0, _T_DECAY, min=0.0, max=16.0)
    own["lc"] = g.color("Light Color", WHITE, _LC)
    own["shininess"] = g.value("Exponent", 30.0, "three.js shininess", min=0.0, max=10000.0)
    own["strength"] = g.value("Specular Strength", 1.0, "three.js specularStrength (0: no "
                              "highlight)", min=0.0, max=1.0, subtype="FACTOR")
    own["n_s"] = g.vector("Lambert Normal", (0.0, 0.0, LAMBERT_SCALE),
                          "n·2⁻⁷, once per material (the lights group)")
    return own


def _constant_choice(switched, facts):
    """``choose(fact, condition, if_true, if_false)`` of a light group: the branch of the
    light's *facts* where they are known (a group of its facts, before 5.3: ``LIGHT_FACTS``),
    a Switch on the constant *condition* on 5.3 (*switched*), else both branches selected by
    the condition."""
    def choose(fact, condition, if_true, if_false):
        if facts:
            return if_true if facts[fact] else if_false
        return switch(condition, if_false, if_true) if switched \
            else select(condition, if_true, if_false)
    return choose


def _threejs_light(g, light, own, sums, switched, facts=None):
    """One three.js light's diffuse light and its highlight's two sums (*facts*: the
    light's, ``LIGHT_FACTS``, or None)."""
    choose = _constant_choice(switched, facts)

    ln = dot(light.l, own["n_s"])  # n·ℓ·2⁻⁷
    numerator, gate = own["i"], ln  # saturate(n·ℓ)·2⁻⁷: clamped with the falloff (below)
    if light.kind == "SPOT":  # smoothstep(cos angle, cos(angle·(1 - penumbra)), cos ω)
        cos_w = dot(light.l, light.t)  # cos ω = -ℓ·û, û the light's -Z axis
        e0, e1 = cos(own["angle"]), cos(own["angle"] * (1.0 - own["penumbra"]))
        slope = 1.0 / (e1 - e0)
        t = saturate(multiply_add(cos_w, slope, -e0 * slope))
        smooth = (t * t) * multiply_add(t, -2.0, 3.0)
        if switched or facts:  # penumbra 0: the hard edge in n·ℓ's clamp (above)
            edge = minimum(ln, multiply_add(cos_w, EDGE_SCALE, -EDGE_SCALE * e0))
            numerator = choose("penumbra", less_than(e0, e1), numerator * smooth, numerator)
            gate = choose("penumbra", less_than(e0, e1), gate, edge)
        else:
            numerator = numerator * choose("penumbra", less_than(e0, e1), smooth,
                                           greater_than(cos_w, e0))
    falloff = None
    if light.to_light is not None:
        d2 = dot(light.to_light, light.to_light)
        d = length(light.to_light)
        # the cut-off window (saturate(1 - (d/distance)⁴))², 1 where distance is 0 (1/0 is 0
        # in a Math node: the window is then 1, and on 5.3 a Switch drops it)
        squared = switched or (facts and facts["decay 2"])  # d not needed but here
        window = saturate(multiply_add(d2 * d2 if squared else power(d, 4.0),
                                       -power(1.0 / own["cutoff"], 4.0), 1.0))
        windowed = numerator * (window * window)
        numerator = choose("cut-off", less_than(0.0, own["cutoff"]), windowed, numerator) \
            if switched or facts else windowed
        falloff = power(d, own["decay"])
        if switched or facts:  # decay 2: d² is the dot product
            falloff = choose("decay 2", equal(own["decay"], 2.0), d2, falloff)

    def weight(shade):
        """i (times a spot's cone, the window) · saturate(n·ℓ) / max(d^decay, 0.01) · 2⁻⁷
        (n·ℓ·2⁻⁷ ≤ 2⁻⁷ over at least 0.01 is below 1: the division's clamp is max(·, 0));
        *shade*: the shadow ray's hit in the denominator (a sun's: in n·ℓ)."""
        if falloff is None:
            return numerator * (saturate(light.shade(ln, -SHADOW_DENOMINATOR)) if shade
                                else maximum(gate, 0.0))
        return numerator * saturate(
            gate / maximum(light.shade(falloff) if shade else falloff, 0.01))

    half = light.v + light.l  # v + ℓ: |v + ℓ| = 2 v·h
    size = length(half)
    highlight = power(saturate(dot(light.n, half) / size), maximum(own["shininess"], 1e-4))
    fresnel = power(2.0, multiply_add(size, -5.55473 / 4.0, -6.98316 / 2.0) * size)
    lc = own["lc"] * (1.0 / LAMBERT_SCALE)  # the weight's 2⁻⁷ undone: a constant
    for prefix, shade in _passes(light.hit is not None):
        w = weight(shade)
        lit = w * highlight
        specular = scale_add(lc, lit, sums[prefix + "Specular Sum"])
        fresnel_sum = scale_add(lc, lit * fresnel, sums[prefix + "Fresnel Sum"])
        if switched:  # Specular Strength 0 (MeshLambertMaterial): no highlight
            specular = switch(equal(own["strength"], 0.0), specular,
                              sums[prefix + "Specular Sum"])
            fresnel_sum = switch(equal(own["strength"], 0.0), fresnel_sum,
                                 sums[prefix + "Fresnel Sum"])
        g.output(f"{prefix}Diffuse Sum", scale_add(lc, w, sums[prefix + "Diffuse Sum"]),
                 "+ i·saturate(n·ℓ)·light", color=True)
        g.output(f"{prefix}Specular Sum", specular, "+ i·saturate(n·ℓ)·light·saturate(n·h)^s",
                 color=True)
        g.output(f"{prefix}Fresnel Sum", fresnel_sum,
                 "+ i·saturate(n·ℓ)·light·saturate(n·h)^s·2^((-5.55473 v·h - 6.98316) v·h)",
                 color=True)


@group("three.js Rig Material", "The three.js lights group's sums times the material's "
       "colours: its Diffuse and Specular terms", into=RIG_GROUPS)
def _threejs_rig_material(g):
    """docs/threejs.md §Direct light: Diffuse = Σ irradiance ⊗ color/π, Specular = Σ
    irradiance ⊗ F·0.25·D·specularStrength with F = f0 + (1 - f0)·fresnel and D = (s/2 + 1)/π
    ·(n·h)^s, from the sums of the lights' groups (above)."""
    diffuse = g.vector("Diffuse Sum", ZERO, "Σ i·saturate(n·ℓ)·light")
    specular = g.vector("Specular Sum", ZERO, "Σ i·saturate(n·ℓ)·light·saturate(n·h)^s")
    fresnel = g.vector("Fresnel Sum", ZERO, "Σ … ·fresnel")
    c = g.color("Diffuse Color", WHITE, "The material's color (three.js's diffuse colour)")
    f0 = g.color("Specular Color", THREEJS_SPECULAR, "The material's specular colour")
    shininess = g.value("Shininess", 30.0, "three.js shininess", min=0.0, max=10000.0)
    strength = g.value("Specular Strength", 1.0, "three.js specularStrength", min=0.0, max=1.0,
                       subtype="FACTOR")
    k = (0.25 * strength) * multiply_add(maximum(shininess, 1e-4), 0.5 * RECIPROCAL_PI,
                                         RECIPROCAL_PI)
    g.output("Diffuse", diffuse * (RECIPROCAL_PI * c), "Σ irradiance ⊗ color/π", color=True)
    g.output("Specular", (specular * f0 + fresnel * (WHITE - f0)) * k,
             "Σ irradiance ⊗ F·0.25·D·specularStrength", color=True)


# -- X3D / VRML97 (docs/x3d.md: ISO/IEC 19775-1 §17.2.2.4, ISO/IEC 14772-1 §4.14.4) ------
#
# The standards' lighting equation is this project's model with a few additions, each a
# formula here: every light brings its own ambient light (ambientIntensity × its colour,
# attenuated and spotted like its direct light), the attenuation is clamped (never above 1),
# a point or spot light reaches only the points within its radius, a spot fades linearly in
# the angle from beamWidth to cutOffAngle, and the highlight is Blinn's without the N·L
# condition: I = O_E + Σ attenuation·spot·IL ⊗ (Ia·O_a + I·O_d·max(N·L, 0) +
# I·O_s·max(N·H, 0)^(128·shininess)).

#: X3D's SpotLight defaults (VRML97's swap them: beamWidth π/2, cutOffAngle π/4; the reader
#: of each standard gives its own).
X3D_BEAM_WIDTH = 0.7854
X3D_CUT_OFF_ANGLE = 1.570796
#: X3D's PointLight / SpotLight radius default.
X3D_RADIUS = 100.0
_X_IA = "X3D ambientIntensity: the light's ambient light, attenuated and spotted as its direct light"


def x3d_attenuation(d, constant, linear, quadratic):
    """1/max(a0 + a1·d + a2·d², 1), the denominator as (a2·d + a1)·d + a0."""
    return 1.0 / maximum(multiply_add(multiply_add(quadratic, d, linear), d, constant), 1.0)


def _x3d_falloff_inputs(g):
    i = g.value("Intensity", 1.0, "X3D intensity of the direct light", min=0.0)
    ia = g.value("Ambient Intensity", 0.0, _X_IA, min=0.0)
    a0 = g.value("Constant", 1.0, "a0 of 1/max(a0 + a1·d + a2·d², 1)", min=0.0)
    a1 = g.value("Linear", 0.0, "a1 of 1/max(a0 + a1·d + a2·d², 1)", min=0.0)
    a2 = g.value("Quadratic", 0.0, "a2 of 1/max(a0 + a1·d + a2·d², 1)", min=0.0)
    radius = g.value("Radius", X3D_RADIUS, "The light reaches only the points within this "
                     "distance (negative: everywhere)")
    return i, ia, a0, a1, a2, radius


def _x3d_near(s, i, ia, a0, a1, a2, radius):
    """(ℓ, d, attenuation × the radius's cut-off) of a point or spot light at S."""
    to_light = s - geometry("Position")
    d = length(to_light)
    reach = maximum(at_least(radius, d), less_than(radius, 0.0))
    return normalize(to_light), d, x3d_attenuation(d, a0, a1, a2) * reach


@group("X3D Directional Light", "X3D / VRML97 DirectionalLight: direct and ambient light, the same everywhere")
def _x3d_directional(g):
    """docs/x3d.md §Lights."""
    u = g.vector("Direction", DOWN, "Direction u in which the rays travel")
    i = g.value("Intensity", 1.0, "X3D intensity of the direct light", min=0.0)
    ia = g.value("Ambient Intensity", 0.0, _X_IA, min=0.0)
    g.output("Light Vector", -normalize(u), "ℓ = -u/‖u‖")
    g.output("Intensity", i, "I, the same everywhere")
    g.output("Ambient", ia, "Ia, the same everywhere")


@group("X3D Point Light", "X3D / VRML97 PointLight: 1/max(a0 + a1·d + a2·d², 1) within a radius")
def _x3d_point(g):
    """docs/x3d.md §Lights."""
    s = g.vector("Position", ZERO, _POS)
    i, ia, a0, a1, a2, radius = _x3d_falloff_inputs(g)
    l, d, factor = _x3d_near(s, i, ia, a0, a1, a2, radius)
    g.output("Light Vector", l, "ℓ = (S-P)/‖S-P‖")
    g.output("Intensity", i * factor, "I/max(a0 + a1·d + a2·d², 1) where d ≤ radius, else 0")
    g.output("Ambient", ia * factor, "Ia/max(a0 + a1·d + a2·d², 1) where d ≤ radius, else 0")
    g.output("Distance", d, "d = ‖S-P‖")


@group("X3D Spot Light", "X3D / VRML97 SpotLight: a point light with a linear ramp from beamWidth to cutOffAngle")
def _x3d_spot(g):
    """docs/x3d.md §Lights: spot = 1 where ω ≤ beamWidth, 0 where ω ≥ cutOffAngle, linear in
    ω between (a hard edge at cutOffAngle when beamWidth ≥ cutOffAngle)."""
    s = g.vector("Position", ZERO, _POS)
    u = g.vector("Direction", DOWN, "Axis u of the cone (normalized inside)")
    beam = g.value("Beam Width", X3D_BEAM_WIDTH, "X3D beamWidth: full intensity within this "
                   "angle of the axis", min=0.0, max=math.pi, subtype="ANGLE")
    cut = g.value("Cut Off Angle", X3D_CUT_OFF_ANGLE, "X3D cutOffAngle: no light beyond this "
                  "angle of the axis", min=0.0, max=math.pi, subtype="ANGLE")
    i, ia, a0, a1, a2, radius = _x3d_falloff_inputs(g)
    l, d, factor = _x3d_near(s, i, ia, a0, a1, a2, radius)
    w = acos(-dot(l, normalize(u)))
    ramp = saturate((w - cut) / (beam - cut))
    spot = less_than(w, cut) * maximum(at_least(beam, w), ramp)
    g.output("Light Vector", l, "ℓ = (S-P)/‖S-P‖")
    g.output("Intensity", (i * factor) * spot, "the point light's intensity times the spot factor")
    g.output("Ambient", (ia * factor) * spot, "the point light's ambient times the spot factor")
    g.output("Distance", d, "d = ‖S-P‖")
    g.output("Spot Angle", w, "ω = acos(-ℓ·u), the angle from the axis")


@group("X3D Light Terms", "One X3D light's diffuse, specular and ambient light, for a unit normal and view vector",
       into=RIG_GROUPS)
def _x3d_light_terms(g):
    """The lights group (rig.py) sums these over its lights and multiplies the sums by the
    material's diffuse (Object Color), specular (Specular Color) and ambient (Ambient Object
    Color = ambientIntensity × diffuseColor) colours."""
    l = g.vector("Light Vector", ZERO, _L)
    i = g.value("Intensity", 1.0, "I at the point (from an X3D light group)", min=0.0)
    ia = g.value("Ambient", 0.0, "Ia at the point (from an X3D light group)", min=0.0)
    lc = g.color("Light Color", WHITE, _LC)
    e = g.value("Exponent", 25.6, "128 × the X3D shininess", min=0.0, max=10000.0)
    n = g.vector("Normal", (0.0, 0.0, 1.0), "Unit surface normal n (Phong Surface)")
    v = g.vector("View Vector", (0.0, 0.0, 1.0), "Unit vector v toward the viewer (Phong Surface)")
    highlight = power(maximum(dot(normalize(l + v), n), 0.0), maximum(e, 0.0))
    g.output("Diffuse Light", (i * lambert(l, n)) * lc, "I·max(N·L, 0)·IL", color=True)
    g.output("Specular Light", (i * highlight) * lc, "I·max(N·H, 0)^e·IL", color=True)
    g.output("Ambient Light", ia * lc, "Ia·IL", color=True)


# -- one X3D light of a lights group, whole (addon/lighting/rig.py) -------------------------
#
# Its model's part of the one shape of the three.js and X3D light groups (``_rig_light_of``
# below).  The radius's cut-off is a denominator: a point beyond it has 10³⁰ added to its
# attenuation's, so that 1/max(a0 + a1·d + a2·d², 1) becomes 10⁻³⁰; so is the shadow ray's
# hit, added before the clamp at 1.  The light's colour times its attenuated intensity is
# one vector, which scales both max(N·L, 0) and the highlight (X3D's has no N·L
# condition).  A spot's ramp is saturate((ω - cutOffAngle)/(beamWidth - cutOffAngle)) with
# ω = π - acos(ℓ·û), which is 1 within the beam and 0 beyond the cut-off, or, where
# beamWidth ≥ cutOffAngle, the hard edge [ω < cutOffAngle] = [ℓ·û < -cos cutOffAngle] (on
# 5.3 a Switch on the two constants keeps only the one in use).  The light's own ambient
# light costs no node where its ambientIntensity is 0 (5.3: Switch).


def _x3d_settings(g, kind):
    """The X3D light group's own inputs: the light's settings, the material's exponent."""
    own = {}
    if kind == "SPOT":
        own["beam"] = g.value("Beam Width", X3D_BEAM_WIDTH, "X3D beamWidth: full intensity "
                              "within this angle of the axis", min=0.0, max=math.pi,
                              subtype="ANGLE")
        own["cut"] = g.value("Cut Off Angle", X3D_CUT_OFF_ANGLE, "X3D cutOffAngle: no light "
                             "beyond this angle of the axis", min=0.0, max=math.pi,
                             subtype="ANGLE")
    own["i"] = g.value("Intensity", 1.0, "X3D intensity of the direct light", min=0.0)
    own["ia"] = g.value("Ambient Intensity", 0.0, _X_IA, min=0.0)
    if kind != "SUN":
        own["a0"] = g.value("Constant", 1.0, "a0 of 1/max(a0 + a1·d + a2·d², 1)", min=0.0)
        own["a1"] = g.value("Linear", 0.0, "a1 of 1/max(a0 + a1·d + a2·d², 1)", min=0.0)
        own["a2"] = g.value("Quadratic", 0.0, "a2 of 1/max(a0 + a1·d + a2·d², 1)", min=0.0)
        own["radius"] = g.value("Radius", X3D_RADIUS, "The light reaches only the points "
                                "within this distance (negative: everywhere)")
    own["lc"] = g.color("Light Color", WHITE, _LC)
    own["e"] = g.value("Exponent", 25.6, "128 × the X3D shininess", min=0.0, max=10000.0)
    return own


def _x3d_light(g, light, own, sums, switched, facts=None):
    """One X3D light's diffuse, specular and ambient light added to the sums (*facts*: the
    light's, ``LIGHT_FACTS``, or None)."""
    choose = _constant_choice(switched, facts)
    spot = 1.0
    if light.kind == "SPOT":  # ω = acos(-ℓ·û) = acos(ℓ·t), û the light's -Z axis
        cos_w = dot(light.l, light.t)
        beam, cut = own["beam"], own["cut"]
        slope = 1.0 / (beam - cut)
        ramp = saturate(multiply_add(acos(cos_w), slope, -cut * slope))
        hard = greater_than(cos_w, cos(cut))  # ω < cutOffAngle, no arccosine
        soft = less_than(beam, cut)  # the two constants: the ramp, or the hard edge
        spot = choose("ramp", soft, ramp, hard)
    d = length(light.to_light) if light.to_light is not None else None

    def attenuated(numerator, shade):
        """numerator · spot/max(a0 + a1·d + a2·d², 1) within the radius, else 0 (10⁻³⁰ of
        it); *shade*: also where the shadow ray hits."""
        if d is None:  # a sun: no attenuation (its denominator is at least 1 already)
            return numerator / light.shade(1.0) if shade else numerator
        beyond = greater_than(d, select(less_than(own["radius"], 0.0),
                                        2.0 * SHADOW_DENOMINATOR, own["radius"]))
        denominator = multiply_add(multiply_add(own["a2"], d, own["a1"]), d,
                                   multiply_add(beyond, SHADOW_DENOMINATOR, own["a0"]))
        if shade:
            denominator = light.shade(denominator)
        return (numerator * spot if light.kind == "SPOT" else numerator) / \
            maximum(denominator, 1.0)

    ln = dot(light.l, light.n)
    highlight = power(maximum(dot(normalize(light.v + light.l), light.n), 0.0),
                      maximum(own["e"], 0.0))
    for prefix, shade in _passes(light.hit is not None):
        lit = own["lc"] * attenuated(own["i"], shade)  # IL · I · attenuation · spot
        g.output(f"{prefix}Diffuse Sum",
                 scale_add(lit, maximum(ln, 0.0), sums[prefix + "Diffuse Sum"]),
                 "+ I·max(N·L, 0)·IL", color=True)
        g.output(f"{prefix}Specular Sum", scale_add(lit, highlight, sums[prefix + "Specular Sum"]),
                 "+ I·max(N·H, 0)^e·IL", color=True)
    ambient = scale_add(own["ia"] * own["lc"], attenuated(1.0, False), sums["Ambient Sum"])
    if switched or facts:  # ambientIntensity 0 (its default): nothing to add
        ambient = choose("ambient 0", equal(own["ia"], 0.0), sums["Ambient Sum"], ambient)
    g.output("Ambient Sum", ambient, "+ Ia·IL, attenuated and spotted (not shadowed)",
             color=True)


# -- one light of a lights group in the three.js and X3D models: one shape ------------------
#
# Each model's light group (``rig_light_group``) is this shape with its model's settings and
# light (the table ``RIG_MODELS``): the light's position and axis, the model's inputs, what
# the lights group hands every light (Phong Surface's n and v, the shaded point; with shadow
# rays the true normal, the ray's lift and the light's Cast Shadow), the sums of the lights
# before it.  Computed here for every model: ℓ = (S - P)/|S - P| (a sun's: its unit +Z axis
# t, from its World copy) and the shadow ray, from P lifted to the light's side of the surface (faceforward of the
# material's offset·Ng by Ng·ℓ, one node, subtracted) along S - P itself (Length 1: it ends
# at the light, lifted as its origin) or along a sun's ℓ.


@dataclass(frozen=True)
class RigLight:
    """What a model's light reads of the shape: its type, n, v, unit ℓ toward the light,
    S - P (a point or spot light; None for a sun), the light's unit +Z axis t (None for a point
    light) and its shadow ray's hit (None: no shadow ray) times its Cast Shadow."""

    kind: str
    n: Expr
    v: Expr
    l: Expr
    to_light: Expr | None
    t: Expr | None
    hit: Expr | None
    casts: Expr | None

    def shade(self, x, scale=SHADOW_DENOMINATOR):
        """x + hit·cast·*scale*: one node (cast·scale is the light's constant)."""
        return multiply_add(self.hit, self.casts * scale, x)


def _passes(shadows):
    """(sum prefix, shadowed) of the outputs: the sums with the shadow ray, and the Plain
    ones without it (what Eevee shows before 5.3)."""
    return (("", shadows), ("Plain ", False))[:2 if shadows else 1]


@dataclass(frozen=True)
class RigModel:
    """A model's light group: *what* it adds (the group's description), its *settings*
    (g, kind) -> its own inputs, its *light* (g, RigLight, inputs, sums, switched) that
    writes the outputs, its *sums* and of them the *shadowed* ones (also Plain)."""

    label: str
    what: str
    settings: object
    light: object
    sums: tuple
    shadowed: tuple = ("Diffuse Sum", "Specular Sum")


#: The models whose light groups have this shape (the seeds' is ``_light_of``).
RIG_MODELS = {
    "threejs": RigModel("three.js", "its diffuse light and its highlight's sums",
                        _threejs_settings, _threejs_light,
                        ("Diffuse Sum", "Specular Sum", "Fresnel Sum"),
                        ("Diffuse Sum", "Specular Sum", "Fresnel Sum")),
    "x3d": RigModel("X3D", "its diffuse, specular and ambient light added to the sums",
                    _x3d_settings, _x3d_light, ("Diffuse Sum", "Specular Sum", "Ambient Sum")),
}


def _rig_light_of(g, model, kind, shadows, switched, facts=None):
    """One light of *model* (``RIG_MODELS``), whole: the shape above around its model's
    light (*facts*: the light's, ``LIGHT_FACTS``, or None)."""
    spec = RIG_MODELS[model]
    near = kind in ("POINT", "SPOT")
    s = g.vector("Position", ZERO, _POS) if near else None
    t = g.vector(*_REVERSED_AXIS) if kind != "POINT" else None
    own = spec.settings(g, kind)
    n = g.vector("Normal", (0.0, 0.0, 1.0), "Unit surface normal n (Phong Surface)")
    v = g.vector("View Vector", (0.0, 0.0, 1.0), "Unit vector v toward the viewer (Phong Surface)")
    p = g.vector("Surface Position", ZERO, "The shaded point P (Phong Surface Rays)")
    ng = lift = casts = None
    if shadows:
        ng = g.vector("True Normal", (0.0, 0.0, 1.0), "The true (geometric) normal Ng")
        lift = g.vector("Ray Lift", ZERO, "offset·Ng: the ray starts at P + sign(Ng·ℓ)·"
                        "offset·Ng, on the light's side of the surface")
        casts = g.value("Cast Shadow", 1.0, "1: the light casts shadows, 0: it does not",
                        min=0.0, max=1.0)
    names = spec.sums + (tuple("Plain " + name for name in spec.shadowed) if shadows else ())
    sums = {name: g.vector(name, ZERO, f"The lights before: their {name.lower()}")
            for name in names}
    to_light = s - p if near else None
    l = normalize(to_light) if near else t
    hit = None
    if shadows:  # from P + sign(Ng·ℓ)·offset·Ng: P - faceforward(offset·Ng, ℓ, Ng)
        origin = p - faceforward(lift, l, ng)
        hit = raycast(origin, to_light, 1.0) if near else raycast(origin, l, SUN_RAY_LENGTH)
    spec.light(g, RigLight(kind, n, v, l, to_light, t, hit, casts), own, sums, switched, facts)


def _register_rig_models():
    for model, spec in RIG_MODELS.items():
        for kind in LIGHT_KINDS:
            for shadows in (False, True):
                name = rig_light_group(model, kind, "QUADRATIC", shadows)
                what = (f"One {spec.label} {LIGHT_KINDS[kind].lower()} light of a lights "
                        f"group: {spec.what}" + (", shadowed by its shadow ray" if shadows
                                                 else ""))
                group(name, what, into=RIG_GROUPS)(
                    lambda g, m=model, k=kind, s=shadows: _rig_light_of(g, m, k, s, False))
                variant(name, SWITCH_FEATURE, what)(
                    lambda g, m=model, k=kind, s=shadows: _rig_light_of(g, m, k, s, True))
                facts = light_facts(model, kind)
                for values in itertools.product((False, True), repeat=len(facts)):
                    known = dict(zip(facts, values))  # before 5.3: one group per light's facts
                    group(rig_light_group(model, kind, "QUADRATIC", shadows, facts=known),
                          what + ", for a light whose constants are these", into=RIG_GROUPS)(
                        lambda g, m=model, k=kind, s=shadows, f=known:
                        _rig_light_of(g, m, k, s, False, f))


_register_rig_models()


# -- Eevee's light loop (Blender 5.3+; addon/lighting/loop.py) -------------------------------
#
# From Blender 5.3 Eevee wraps the nodes upstream of a Light Accumulation node that read the
# current light (Light Evaluation, Attribute of type Light, Vector Transform's Light space)
# into a loop over the lights, and adds Light Accumulation's Diffuse Light ⊗ Diffuse Color +
# Glossy Light ⊗ Glossy Color (+ Transmission) of every light, each Light clamped at 0 from
# below, each Color at [0, 1], and each light's part multiplied by Blender's own Diffuse /
# Specular factor of that light.  A material then has the same few nodes whatever the number
# of lights.  Per light, a model's loop group below turns what Light Evaluation
# gives (ℓ, the distance, the light's axis) and the light's own Phong settings, packed into a
# few numeric custom properties of the light (``loop_parameters``: Attribute nodes of type
# Light read them), into the Light and Color inputs of Light Accumulation.  What Light
# Accumulation does afterwards is restated by ``accumulate`` (for the tests).

#: Custom properties of a light (its data) that carry its settings to the loop: the prefix of
#: their keys, "phong_eevee_<model>_<name>".
LOOP_PREFIX = "phong_eevee_"
#: A hard cone edge as a smoothstep of this slope (three.js's penumbra 0): 0 to 1 within
#: 1e-7 of cos θ, inside the band the comparison leaves out (core/compare.py, AMBIGUOUS).
LOOP_HARD_EDGE = 1.0e7
#: Below this ℓ·n counts as negative in the loop (ℓ·n ≥ 0 as one comparison, ℓ·n > -1e-30).
LOOP_LIT = -1.0e-30
#: A spot's cone in one comparison: cos ω > cos θ - 1e-7 (cos ω ≥ cos θ but within 1e-7, which
#: the comparison leaves out: core/compare.py, AMBIGUOUS).
LOOP_CONE_MARGIN = 1.0e-7
#: The specular exponent is at least this in the loop: max(x, 0)^e is then 0 where x ≤ 0
#: (the highlight's condition without a node), and x^1e-9 differs from x^0 = 1 by < 1e-7.
LOOP_MIN_EXPONENT = 1.0e-9


@dataclass(frozen=True)
class LoopParameter:
    """A numeric custom property of a light read in the loop by an Attribute node of type
    Light: its key ("phong_eevee_<model>_<name>"), and the loop group's inputs fed by the
    Attribute's Vector (its first three numbers; or, with *components*, each of them through
    a Separate XYZ) and Alpha (its fourth) outputs, or by its Factor output (a property of
    one number)."""

    name: str
    vector: str | None = None
    alpha: str | None = None
    factor: str | None = None
    components: tuple | None = None

    def key(self, model: str) -> str:
        return f"{LOOP_PREFIX}{model}_{self.name}"

    @property
    def size(self) -> int:
        return 1 if self.factor is not None else 4


@dataclass(frozen=True)
class LoopModel:
    """How a lighting model runs in Eevee's light loop: its loop group (RIG_GROUPS), the
    light's properties it reads (``parameters``) and ``pack``, which computes them from the
    light (``light_values``); ``slots`` names the loop group's outputs that feed Light
    Accumulation: {"Diffuse": (light output, colour output), "Glossy": ...}.  Inputs of the
    loop group named like the lights group's (Object Color, Exponent ...) or "Normal" / "View
    Vector" (unit vectors, Phong Surface) come from the material; "Light Vector", "Distance"
    and "Light Axis" from Light Evaluation and Vector Transform."""

    group: str
    parameters: tuple
    slots: dict
    pack: object  # function(light values: dict) -> {parameter name: tuple of floats}
    #: slots whose light no shadow takes away (X3D's per-light ambient light)
    unshadowed: tuple = ()


LOOP_MODELS: dict = {}


def loop_parameters(model: str, light: dict) -> dict:
    """{custom property key: value} of one light for *model*'s loop: a tuple of 4 floats, or
    a float.  *light* holds plain values: "type" (POINT, SUN, SPOT; anything else gets zeros:
    the loop adds nothing for it), "color" (3 floats), "spot_size" (radians), "diffuse_factor"
    and "specular_factor" (Blender's own, which Light Accumulation multiplies by), "falloff"
    ("QUADRATIC" or "POWER") and the Phong settings by attribute ("intensity", "quadratic" ...
    as addon/lighting/properties.py names them)."""
    spec = LOOP_MODELS[model]
    values = spec.pack(light) if light.get("type") in ("POINT", "SUN", "SPOT") else {}
    out = {}
    for parameter in spec.parameters:
        value = values.get(parameter.name)
        if value is None:
            value = 0.0 if parameter.size == 1 else (0.0, 0.0, 0.0, 0.0)
        out[parameter.key(model)] = (float(value) if parameter.size == 1
                                     else tuple(float(x) for x in value))
    return out


def _over(value, factor):
    """value / factor, 0 when Blender's factor is 0 (Light Accumulation then adds nothing)."""
    return value / factor if factor > 0.0 else 0.0


def _light_colors(light, strength_d, strength_s):
    """(Cl·strength_d / Blender's Diffuse factor, Cl·strength_s / its Specular factor)."""
    color = tuple(light.get("color", (1.0, 1.0, 1.0)))[:3]
    kd = _over(strength_d, float(light.get("diffuse_factor", 1.0)))
    ks = _over(strength_s, float(light.get("specular_factor", 1.0)))
    return tuple(c * kd for c in color), tuple(c * ks for c in color)


def accumulate(light, color, factor=1.0):
    """What Light Accumulation adds for one light and one of its slots (Blender 5.3's
    node_light_accumulation): max(Light, 0) ⊗ clamp(Color, 0, 1) × the light's factor."""
    import numpy as np  # noqa: PLC0415  (numpy only where the tests evaluate)

    return np.maximum(light, 0.0) * np.clip(color, 0.0, 1.0) * factor


def _loop_model(model, parameters, slots, unshadowed=()):
    """*model*'s loop: its group is the model's ``loop`` in ``models.py``."""
    def register(pack):
        group_name = models.MODELS[model].loop
        LOOP_MODELS[model] = LoopModel(group_name, tuple(parameters), dict(slots), pack,
                                       tuple(unshadowed))
        return pack
    return register


_LV = "Unit vector ℓ toward the light (Light Evaluation's Direction)"
_LD = "Distance r to the light (Light Evaluation's Distance; 1 for a sun)"
_LA = "The light's +Z axis in world space, any length (Vector Transform from Light space)"
_UN = "Unit surface normal n (Phong Surface)"
_UV = "Unit vector v toward the viewer (Phong Surface)"


@group("Phong Loop Light", "One light of the seeds' model in Eevee's light loop: its diffuse "
       "and specular light from Light Evaluation and the light's packed settings",
       into=RIG_GROUPS)
def _phong_loop_light(g):
    """docs/model.md §Point light, §Spot light, §Power falloff, §Diffuse, §Specular (Phong),
    §Blinn-Phong: i = i0/max(α·r^a + βr + γ, 1e-6) · [cos ω ≥ cos θ] · max(cos ω, 0)^e_att,
    with the settings packed so that one formula serves every light: a quadratic falloff
    (α, β, γ) with a = 2, a power falloff i0/d^k as (1, 0, 0) with a = k, a sun (0, 0, 1);
    no cone: cos θ = -2, e_att = 0.  i0 and the strengths are in the light colours.  The
    conditions in one node each: the cone as cos ω > cos θ - 1e-7, max(x, 0)^max(e, 1e-9) is 0
    where x ≤ 0 (a highlight's own condition), ℓ·n ≥ 0 as ℓ·n > -1e-30; Light Accumulation
    takes max(Light, 0), which is Lambert's max(ℓ·n, 0)."""
    l = g.vector("Light Vector", ZERO, _LV)
    r = g.value("Distance", 1.0, _LD, min=0.0)
    axis = g.vector("Light Axis", (0.0, 0.0, 1.0), _LA)
    alpha = g.value("Quadratic", 1.0, "α (1 for i0/d^k, 0 for a sun)", min=0.0)
    beta = g.value("Linear", 0.0, "β (0 for i0/d^k and a sun)", min=0.0)
    gamma = g.value("Constant", 0.0, "γ (0 for i0/d^k, 1 for a sun)", min=0.0)
    a = g.value("Falloff Exponent", 2.0, "a of α·r^a: 2, or k for i0/d^k", min=0.0)
    dcol = g.color("Diffuse Light Color", WHITE,
                   "i0·k_d·Cl_source / the light's Diffuse factor (Light Accumulation's)")
    e_att = g.value("Edge Exponent", 0.0, "e_att of a spot, ≥ 0 (0 for the other lights)",
                    min=0.0)
    scol = g.color("Specular Light Color", WHITE,
                   "i0·k_s·Cl_source / the light's Specular factor (Light Accumulation's)")
    cos_t = g.value("Cone Threshold", -2.0,
                    "cos θ - 1e-7 of a spot's cone (-2 for the other lights)")
    oc = g.color("Object Color", GREY, _OC)
    sc = g.color("Specular Color", WHITE, _SC)
    e = g.value("Exponent", 30.0, _E, min=0.0, max=10000.0)
    blinn = g.value("Blinn", 0.0, "0 = Phong, 1 = Blinn-Phong, between = blend", min=0.0,
                    max=1.0, subtype="FACTOR")
    n = g.vector("Normal", (0.0, 0.0, 1.0), _UN)
    v = g.vector("View Vector", (0.0, 0.0, 1.0), _UV)
    cos_w = dot(l, normalize(axis))  # cos ω = -ℓ·u, u = the light's -Z axis
    # inside a cone cos ω > cos θ - 1e-7 ≥ -1e-7 (θ ≤ 90°: Blender's spot size is at most
    # 180°), and x^0 = 1 for any x (no cone): max(cos ω, 0) needs no node
    cone = greater_than(cos_w, cos_t) * power(cos_w, e_att)
    # at least 1e-6 as the contract's max(…, 1e-6) wherever r ≥ 0.001 or so: α = β = γ = 0 is
    # packed as γ = 1e-6 (loop_parameters), and only a point within a millimetre of the light
    # (the pixel saturates either way) sees a smaller denominator
    attenuation = cone / multiply_add(alpha, power(r, a), multiply_add(beta, r, gamma))
    ln = dot(l, n)
    e_1 = maximum(e, LOOP_MIN_EXPONENT)
    # r·v = -ℓ·(v - 2(n·v)n) = -ℓ·reflect(v, n), clamped at [0, 1] in the same Math node
    phong = power(saturate(-dot(l, reflect_about(v, n))), e_1)
    blinn_f = power(maximum(dot(normalize(l + v), n), 0.0), e_1)
    # Blinn 0 or 1 (a material's constant): the Switch leaves one highlight (one node each,
    # folded), a value between blends both
    factor = switch(equal(blinn, 0.0),
                    switch(equal(blinn, 1.0), multiply_add(blinn, blinn_f - phong, phong), blinn_f),
                    phong)
    g.output("Diffuse Light", (attenuation * ln) * dcol,
             "i·(ℓ·n)·k_d·Cl_source (Light Accumulation takes max(·, 0))", color=True)
    g.output("Diffuse Color", oc, "Cl_objet", color=True)
    g.output("Specular Light", ((attenuation * greater_than(ln, LOOP_LIT)) * factor) * scol,
             "i·[ℓ·n ≥ 0]·((1-Blinn)·(r·v)^e + Blinn·(h·n)^e)·k_s·Cl_source", color=True)
    g.output("Specular Color", sc, "Cl_spec", color=True)


@_loop_model("seeds", (
    LoopParameter("falloff", components=("Quadratic", "Linear", "Constant"),
                  alpha="Falloff Exponent"),
    LoopParameter("diffuse", vector="Diffuse Light Color", alpha="Edge Exponent"),
    LoopParameter("specular", vector="Specular Light Color", alpha="Cone Threshold")),
    {"Diffuse": ("Diffuse Light", "Diffuse Color"), "Glossy": ("Specular Light", "Specular Color")})
def _pack_seeds(light):
    kind, s = light["type"], light.get("settings", {})
    i0 = float(s.get("intensity", 1.0))
    diffuse, specular = _light_colors(light, i0 * float(s.get("diffuse", 1.0)),
                                      i0 * float(s.get("specular", 1.0)))
    if kind == "SUN":
        falloff = (0.0, 0.0, 1.0, 2.0)
    elif str(light.get("falloff", "QUADRATIC")).upper() == "POWER":
        falloff = (1.0, 0.0, 0.0, max(float(s.get("power_k", 2.0)), 0.0))
    else:
        falloff = tuple(float(s.get(key, FALLOFF_DEFAULTS[key]))
                        for key in ("quadratic", "linear", "constant")) + (2.0,)
        if falloff[:3] == (0.0, 0.0, 0.0):  # i0/max(0, 1e-6) (docs/contract.md)
            falloff = (0.0, 0.0, MIN_DENOMINATOR, 2.0)
    spot = kind == "SPOT"
    edge = max(float(s.get("edge_exponent", 0.0)), 0.0) if spot else 0.0
    threshold = (math.cos(float(light.get("spot_size", math.pi)) / 2.0) - LOOP_CONE_MARGIN
                 if spot else -2.0)
    return {"falloff": falloff, "diffuse": (*diffuse, edge), "specular": (*specular, threshold)}


@group("three.js Loop Light", "One light of the three.js model in Eevee's light loop: "
       "MeshPhongMaterial's diffuse and specular light (lights_phong_pars_fragment)",
       into=RIG_GROUPS)
def _threejs_loop_light(g):
    """docs/threejs.md: the light's intensity i·getDistanceAttenuation(d, distance, decay)·
    smoothstep(cos angle, cos(angle·(1-penumbra)), cos ω), packed so one formula serves
    every light: the smoothstep's t = saturate(cos ω·scale + offset) (scale = 1/(e1 - e0),
    offset = -e0·scale; 1e7 for penumbra 0; a light without a cone t = 1), the distance
    window with 1/distance (0: none; a sun has decay 0).  Light Accumulation takes
    max(·, 0) of both lights, which is saturate(n·ℓ) (n·ℓ ≤ 1 for unit vectors)."""
    l = g.vector("Light Vector", ZERO, _LV)
    r = g.value("Distance", 1.0, _LD, min=0.0)
    axis = g.vector("Light Axis", (0.0, 0.0, 1.0), _LA)
    dcol = g.color("Diffuse Light Color", WHITE,
                   "i·Cl_source / the light's Diffuse factor (Light Accumulation's)")
    decay = g.value("Decay", 2.0, _T_DECAY, min=0.0)
    scol = g.color("Specular Light Color", WHITE,
                   "i·Cl_source / the light's Specular factor (Light Accumulation's)")
    inverse = g.value("Inverse Distance", 0.0, "1/distance of the cut-off window (0: none)",
                      min=0.0)
    scale = g.value("Cone Scale", 1.0, "1/(cos(angle·(1-penumbra)) - cos angle)")
    offset = g.value("Cone Offset", 2.0, "-cos(angle)·Cone Scale")
    c = g.color("Object Color", WHITE, "The material's color (three.js's diffuse colour)")
    sc = g.color("Specular Color", THREEJS_SPECULAR, "The material's specular colour")
    shininess = g.value("Exponent", 30.0, "three.js shininess", min=0.0, max=10000.0)
    strength = g.value("Specular Strength", 1.0, "three.js specularStrength", min=0.0, max=1.0,
                       subtype="FACTOR")
    n = g.vector("Normal", (0.0, 0.0, 1.0), _UN)
    v = g.vector("View Vector", (0.0, 0.0, 1.0), _UV)
    t = saturate(multiply_add(dot(l, normalize(axis)), scale, offset))
    cone = (t * t) * multiply_add(t, -2.0, 3.0)
    x = r * inverse
    window = saturate(1.0 - power(x, 4.0))
    attenuation = ((window * window) / maximum(power(r, decay), 0.01)) * cone
    irradiance = attenuation * dot(n, l)
    h = normalize(l + v)
    dot_nh = saturate(dot(n, h))
    dot_vh = saturate(dot(v, h))
    s = maximum(shininess, 1e-4)
    fresnel = power(2.0, multiply_add(dot_vh, -5.55473, -6.98316) * dot_vh)
    f = sc + fresnel * (WHITE - sc)
    d = multiply_add(s, 0.5 * RECIPROCAL_PI, RECIPROCAL_PI) * power(dot_nh, s)
    g.output("Diffuse Light", irradiance * dcol, "i·(n·ℓ)·light (Light Accumulation: max(·, 0))",
             color=True)
    g.output("Diffuse Color", RECIPROCAL_PI * c, "color/π (BRDF_Lambert)", color=True)
    g.output("Specular Light", (f * (irradiance * ((0.25 * strength) * d))) * scol,
             "i·(n·ℓ)·light ⊗ F·G·D·specular strength", color=True)
    g.output("Specular Color", maximum(sc, 1.0),
             "white (F is per light: in Specular Light), linked from the material's colour",
             color=True)


@_loop_model("threejs", (
    LoopParameter("diffuse", vector="Diffuse Light Color", alpha="Decay"),
    LoopParameter("specular", vector="Specular Light Color", alpha="Inverse Distance"),
    LoopParameter("cone_scale", factor="Cone Scale"),
    LoopParameter("cone_offset", factor="Cone Offset")),
    {"Diffuse": ("Diffuse Light", "Diffuse Color"), "Glossy": ("Specular Light", "Specular Color")})
def _pack_threejs(light):
    kind, s = light["type"], light.get("settings", {})
    i = float(s.get("intensity", 1.0))
    diffuse, specular = _light_colors(light, i, i)
    near = kind in ("POINT", "SPOT")
    decay = float(s.get("decay", 2.0)) if near else 0.0
    cutoff = float(s.get("distance", 0.0)) if near else 0.0
    scale, offset = 1.0, 2.0  # no cone: t = saturate(cos ω + 2) = 1
    if kind == "SPOT":
        angle = float(light.get("spot_size", math.pi)) / 2.0
        e0 = math.cos(angle)
        e1 = math.cos(angle * (1.0 - float(s.get("penumbra", 0.0))))
        scale = 1.0 / (e1 - e0) if e1 - e0 > 1.0 / LOOP_HARD_EDGE else LOOP_HARD_EDGE
        offset = -e0 * scale
    return {"diffuse": (*diffuse, decay),
            "specular": (*specular, 1.0 / cutoff if cutoff > 0.0 else 0.0),
            "cone_scale": scale, "cone_offset": offset}


@group("X3D Loop Light", "One light of the X3D / VRML97 model in Eevee's light loop: its "
       "diffuse, specular and ambient light (the standards' lighting equation)",
       into=RIG_GROUPS)
def _x3d_loop_light(g):
    """docs/x3d.md: one light's on · attenuation · spot · IL ⊗ (Ia·O_a + I·O_d·max(N·L, 0) +
    I·O_s·max(N·H, 0)^e), packed so that one formula serves every light: the attenuation
    1/max(a0 + a1·d + a2·d², 1) (a sun (1, 0, 0)) where d ≤ radius (a sun's radius -1:
    everywhere); the spot ramp as saturate(ω·scale + offset), ω = acos(ℓ·axis) (scale =
    1/(beamWidth - cutOffAngle), offset = -cutOffAngle·scale; beamWidth ≥ cutOffAngle a hard
    edge of slope 1e7; no cone: scale 0, offset 1).  I, Ia and the light's colour are in the
    light colours.  The ambient light goes to Light Accumulation's Transmission, which no
    shadow darkens; Light Accumulation takes max(·, 0), which is max(N·L, 0)."""
    l = g.vector("Light Vector", ZERO, _LV)
    r = g.value("Distance", 1.0, _LD, min=0.0)
    axis = g.vector("Light Axis", (0.0, 0.0, 1.0), _LA)
    a0 = g.value("Constant", 1.0, "a0 of 1/max(a0 + a1·d + a2·d², 1) (1 for a sun)", min=0.0)
    a1 = g.value("Linear", 0.0, "a1 (0 for a sun)", min=0.0)
    a2 = g.value("Quadratic", 0.0, "a2 (0 for a sun)", min=0.0)
    radius = g.value("Radius", X3D_RADIUS, "The light reaches the points within this distance "
                     "(negative: everywhere, a sun)")
    dcol = g.color("Diffuse Light Color", WHITE,
                   "I·IL / the light's Diffuse factor (Light Accumulation's)")
    scale = g.value("Cone Scale", 0.0, "1/(beamWidth - cutOffAngle) (0: no cone)")
    scol = g.color("Specular Light Color", WHITE,
                   "I·IL / the light's Specular factor (Light Accumulation's)")
    offset = g.value("Cone Offset", 1.0, "-cutOffAngle·Cone Scale (1: no cone)")
    acol = g.color("Ambient Light Color", ZERO,
                   "Ia·IL / the light's Transmission factor (Light Accumulation's)")
    oc = g.color("Object Color", GREY, "O_d, the material's diffuseColor")
    sc = g.color("Specular Color", WHITE, "O_s, the material's specularColor")
    e = g.value("Exponent", 25.6, "128 × the X3D shininess", min=0.0, max=10000.0)
    ka = g.color("Ambient Object Color", GREY, "O_a = ambientIntensity × diffuseColor")
    n = g.vector("Normal", (0.0, 0.0, 1.0), _UN)
    v = g.vector("View Vector", (0.0, 0.0, 1.0), _UV)
    reach = maximum(at_least(radius, r), less_than(radius, 0.0))
    spot = saturate(multiply_add(acos(dot(l, normalize(axis))), scale, offset))
    factor = (x3d_attenuation(r, a0, a1, a2) * reach) * spot
    highlight = power(maximum(dot(normalize(l + v), n), 0.0), maximum(e, 0.0))
    g.output("Diffuse Light", (factor * dot(l, n)) * dcol,
             "on·att·spot·(N·L)·I·IL (Light Accumulation takes max(·, 0))", color=True)
    g.output("Diffuse Color", oc, "O_d", color=True)
    g.output("Specular Light", (factor * highlight) * scol, "on·att·spot·max(N·H, 0)^e·I·IL",
             color=True)
    g.output("Specular Color", sc, "O_s", color=True)
    g.output("Ambient Light", factor * acol, "on·att·spot·Ia·IL", color=True)
    g.output("Ambient Color", ka, "O_a", color=True)


@_loop_model("x3d", (
    LoopParameter("attenuation", components=("Constant", "Linear", "Quadratic"), alpha="Radius"),
    LoopParameter("diffuse", vector="Diffuse Light Color", alpha="Cone Scale"),
    LoopParameter("specular", vector="Specular Light Color", alpha="Cone Offset"),
    LoopParameter("ambient", vector="Ambient Light Color")),
    {"Diffuse": ("Diffuse Light", "Diffuse Color"), "Glossy": ("Specular Light", "Specular Color"),
     "Transmission": ("Ambient Light", "Ambient Color")},
    unshadowed=("Transmission",))
def _pack_x3d(light):
    kind, s = light["type"], light.get("settings", {})
    i = float(s.get("intensity", 1.0))
    diffuse, specular = _light_colors(light, i, i)
    color = tuple(light.get("color", (1.0, 1.0, 1.0)))[:3]
    ia = _over(float(s.get("ambient", 0.0)), float(light.get("transmission_factor", 1.0)))
    near = kind in ("POINT", "SPOT")
    attenuation = ((float(s.get("constant", 1.0)), float(s.get("linear", 0.0)),
                    float(s.get("quadratic", 0.0)), float(s.get("radius", X3D_RADIUS)))
                   if near else (1.0, 0.0, 0.0, -1.0))
    scale, offset = 0.0, 1.0  # no cone: saturate(1) = 1
    if kind == "SPOT":
        cut = float(light.get("spot_size", math.pi)) / 2.0
        beam = float(s.get("beam_width", X3D_BEAM_WIDTH))
        scale = 1.0 / (beam - cut) if cut - beam > 1.0 / LOOP_HARD_EDGE else -LOOP_HARD_EDGE
        offset = -cut * scale
    return {"attenuation": attenuation, "diffuse": (*diffuse, scale),
            "specular": (*specular, offset), "ambient": (*(c * ia for c in color), 0.0)}


NAMES = tuple(GROUPS)

__all__ = ["GROUPS", "NAMES", "LIBRARY_VERSION", "GroupDef", "Socket", "lambert",
           "phong_factor", "blinn_factor", "falloff", "clamp_add"]
