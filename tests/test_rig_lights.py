# SPDX-License-Identifier: GPL-3.0-or-later
"""The lights group's light groups of the seeds' model (node_groups/library.py,
``rig_light_group``: one group per light type, falloff and shadow ray, the fewest exact
nodes a light costs) evaluated on numpy agree with the independent reference: the light
model of their type, then Phong Diffuse and the highlight (Phong, Blinn-Phong or their
blend), added to the sums they are given.  numpy has no scene, so the shadow ray hits
nothing there: a light with its ray gives its light unshadowed (the rays themselves are
rendered by tests/test_shadows.py).  No Blender here."""

import itertools
import math

import numpy as np
import pytest

from phong_nodes.node_groups import library, reference

import seeded

N = 4000


def _unit(v):
    return v / np.linalg.norm(v, axis=-1, keepdims=True)


def _setting(rng, low, high):
    x = rng.uniform(low, high, N)
    x[rng.random(N) < 0.05] = 0.0  # zeros: α = β = γ = 0, exponents 0, i0 = 0
    return x


def _case(rng, kind, falloff):
    """Random inputs of the light group and the reference's light for them."""
    p = rng.uniform(-4, 4, (N, 3))
    n, v = _unit(rng.normal(size=(N, 3))), _unit(rng.normal(size=(N, 3)))
    inputs = {"Surface Position": p, "Normal": n, "View Vector": v,
              "Reflected View": 2.0 * np.sum(n * v, axis=-1, keepdims=True) * n - v,
              "Light Gate Normal": library.GATE_SCALE * n,
              "Intensity": _setting(rng, -0.5, 4.0), "Light Color": rng.uniform(-0.2, 1.5, (N, 3)),
              "Diffuse Strength": _setting(rng, -0.5, 2.0),
              "Specular Strength": _setting(rng, -0.5, 2.0),
              "Exponent": _setting(rng, -1.0, 200.0), "Blinn": rng.uniform(0.0, 1.0, N),
              "Diffuse Sum": rng.uniform(0, 1, (N, 3)), "Specular Sum": rng.uniform(0, 1, (N, 3)),
              "True Normal": n, "Ray Lift": 1e-5 * n, "Cast Shadow": np.ones(N)}
    inputs["Plain Diffuse Sum"], inputs["Plain Specular Sum"] = (
        inputs["Diffuse Sum"] + 1.0, inputs["Specular Sum"] + 2.0)
    if kind != "SUN":
        inputs["Position"] = p + rng.normal(size=(N, 3)) * rng.choice([0.3, 2.0, 6.0], (N, 1))
    if kind != "POINT":
        inputs["Direction"] = rng.normal(size=(N, 3)) * rng.choice([0.5, 1.0, 3.0], (N, 1))
        inputs["Reversed Axis"] = -_unit(inputs["Direction"])  # the group's: the unit +Z axis
    if kind == "SPOT":  # Blender's Spot Size is at most 180°: θ ≤ 90°
        inputs["Half Angle"] = rng.uniform(0.0, math.pi / 2.0, N)
        inputs["Edge Exponent"] = _setting(rng, -1.0, 40.0)
    quadratic = dict(quadratic=1.0, linear=0.0, constant=0.0)
    if falloff == "QUADRATIC" and kind != "SUN":
        for name in ("Quadratic", "Linear", "Constant"):
            inputs[name] = _setting(rng, -0.5, 4.0)
        quadratic = {name.lower(): inputs[name] for name in ("Quadratic", "Linear", "Constant")}
    elif kind != "SUN":
        inputs["Falloff Exponent"] = _setting(rng, -1.0, 4.0)
        quadratic = dict(quadratic=0.0, linear=0.0, constant=1.0)
    i0 = inputs["Intensity"]
    if kind == "SUN":
        light = reference.directional_light(inputs["Direction"], i0, p)
    elif kind == "POINT":
        light = reference.point_light(inputs["Position"], i0, geometry_position=p, **quadratic)
    else:
        light = reference.spot_light(inputs["Position"], inputs["Direction"],
                                     inputs["Half Angle"], inputs["Edge Exponent"], i0,
                                     geometry_position=p, **quadratic)
    if falloff == "POWER" and kind != "SUN":
        light["Intensity"] = reference.power_falloff(light["Distance"], light["Intensity"],
                                                     inputs["Falloff Exponent"])["Intensity"]
    return inputs, light


@pytest.mark.parametrize("switched", [False, True])
@pytest.mark.parametrize("blinn", ["between", 0.0, 1.0])
@pytest.mark.parametrize("shadows", [False, True])
@pytest.mark.parametrize("kind, falloff", [("POINT", "QUADRATIC"), ("POINT", "POWER"),
                                           ("SPOT", "QUADRATIC"), ("SPOT", "POWER"),
                                           ("SUN", "QUADRATIC")])
def test_a_light_adds_what_the_reference_gives(kind, falloff, shadows, blinn, switched):
    rng = seeded.rng((kind, falloff, shadows, str(blinn)))
    inputs, light = _case(rng, kind, falloff)
    if blinn != "between":
        inputs["Blinn"] = np.full(N, blinn)
    name = library.rig_light_group("seeds", kind, falloff, shadows)
    group = library.definition(name, (library.SWITCH_FEATURE,) if switched else ())
    assert (group is library.RIG_GROUPS[name]) == (not switched)
    got = group.evaluate(inputs)
    ell, i = light["Light Vector"], light["Intensity"]
    common = dict(light_color=inputs["Light Color"], normal=inputs["Normal"])
    diffuse = reference.diffuse(ell, i * inputs["Diffuse Strength"], object_color=(1.0, 1.0, 1.0),
                                **common)["Color"]
    spec = dict(intensity=i * inputs["Specular Strength"], specular_color=(1.0, 1.0, 1.0),
                exponent=inputs["Exponent"], view_vector=inputs["View Vector"], **common)
    b = inputs["Blinn"][:, None]
    specular = ((1.0 - b) * reference.specular(ell, **spec)["Color"]
                + b * reference.blinn_specular(ell, **spec)["Color"])
    sums = ("Diffuse Sum", "Specular Sum") + (
        ("Plain Diffuse Sum", "Plain Specular Sum") if shadows else ())
    assert set(got) == set(sums)
    for output in sums:
        term = diffuse if "Diffuse" in output else specular
        assert np.abs(term).max() > 0.01 and np.mean(np.abs(term).max(axis=-1) > 1e-6) > 0.002
        np.testing.assert_allclose(got[output] - inputs[output], term, rtol=1e-9, atol=1e-9,
                                   err_msg=output)


@pytest.mark.parametrize("highlight, blinn", [(library.PHONG, 0.0), (library.BLINN, 1.0)])
@pytest.mark.parametrize("shadows", [False, True])
@pytest.mark.parametrize("kind, falloff", [("POINT", "QUADRATIC"), ("POINT", "POWER"),
                                           ("SPOT", "QUADRATIC"), ("SUN", "QUADRATIC")])
def test_a_light_with_one_highlight_adds_what_the_reference_gives(kind, falloff, shadows,
                                                                  highlight, blinn):
    """The variant of one highlight (what a lights group before 5.3 gives a material whose
    Blinn is exactly 0 or 1) reads no Blinn and adds that highlight alone: the reference's
    Phong (r·v)^e or Blinn-Phong (h·n)^e, not a blend."""
    rng = seeded.rng((kind, falloff, shadows, highlight))
    inputs, light = _case(rng, kind, falloff)
    del inputs["Blinn"]
    name = library.rig_light_group("seeds", kind, falloff, shadows, highlight)
    assert name != library.rig_light_group("seeds", kind, falloff, shadows)
    group = library.definition(name)
    assert "Blinn" not in [s.name for s in group.inputs]
    got = group.evaluate(inputs)
    ell, i = light["Light Vector"], light["Intensity"]
    spec = dict(intensity=i * inputs["Specular Strength"], specular_color=(1.0, 1.0, 1.0),
                exponent=inputs["Exponent"], view_vector=inputs["View Vector"],
                light_color=inputs["Light Color"], normal=inputs["Normal"])
    specular = (reference.blinn_specular if blinn else reference.specular)(ell, **spec)["Color"]
    other = (reference.specular if blinn else reference.blinn_specular)(ell, **spec)["Color"]
    assert np.abs(specular - other).max() > 0.01  # the two highlights differ here
    for output in ("Specular Sum",) + (("Plain Specular Sum",) if shadows else ()):
        np.testing.assert_allclose(got[output] - inputs[output], specular, rtol=1e-9,
                                   atol=1e-9, err_msg=output)
    blend = library.definition(library.rig_light_group("seeds", kind, falloff, shadows))
    want = blend.evaluate({**inputs, "Blinn": np.full(N, blinn)})
    for output in got:  # the diffuse light too: what the blend gives at that Blinn
        np.testing.assert_allclose(got[output], want[output], rtol=1e-12, atol=0.0,
                                   err_msg=output)


def _x3d_case(rng, kind, facts=None):
    """Random inputs of the X3D light group and the reference's light for them."""
    p = rng.uniform(-4, 4, (N, 3))
    n, v = _unit(rng.normal(size=(N, 3))), _unit(rng.normal(size=(N, 3)))
    inputs = {"Surface Position": p, "Normal": n, "View Vector": v,
              "Intensity": _setting(rng, -0.5, 4.0), "Ambient Intensity": _setting(rng, 0.0, 1.0),
              "Light Color": rng.uniform(-0.2, 1.5, (N, 3)), "Exponent": _setting(rng, -1.0, 128.0),
              "True Normal": n, "Ray Lift": 1e-5 * n, "Cast Shadow": np.ones(N)}
    for name in ("Diffuse Sum", "Specular Sum", "Ambient Sum", "Plain Diffuse Sum",
                 "Plain Specular Sum"):
        inputs[name] = rng.uniform(0, 1, (N, 3))
    if kind != "SUN":
        inputs["Position"] = p + rng.normal(size=(N, 3)) * rng.choice([0.3, 2.0, 6.0], (N, 1))
        for name in ("Constant", "Linear", "Quadratic"):
            inputs[name] = _setting(rng, 0.0, 2.0)
        inputs["Radius"] = rng.choice([-1.0, 2.0, 5.0, 100.0], N)
    if kind != "POINT":
        inputs["Direction"] = rng.normal(size=(N, 3)) * rng.choice([0.5, 1.0, 3.0], (N, 1))
        inputs["Reversed Axis"] = -_unit(inputs["Direction"])  # the group's: the unit +Z axis
    if kind == "SPOT":  # both orders: a ramp, or a hard edge at the cut-off
        inputs["Beam Width"] = rng.uniform(0.0, math.pi / 2.0, N)
        inputs["Cut Off Angle"] = rng.uniform(0.0, math.pi / 2.0, N)
    for fact, holds in (facts or {}).items():  # inputs that hold *facts* (LIGHT_FACTS)
        if fact == "ramp":
            low, high = np.sort([inputs["Beam Width"], inputs["Cut Off Angle"]], axis=0)
            high = high + 0.01
            inputs["Beam Width"], inputs["Cut Off Angle"] = (low, high) if holds else (high, low)
        elif fact == "ambient 0":
            inputs["Ambient Intensity"] = np.zeros(N) if holds else rng.uniform(0.1, 1.0, N)
    near = {k: inputs[k] for k in ("Constant", "Linear", "Quadratic", "Radius")} \
        if kind != "SUN" else {}
    args = dict(intensity=inputs["Intensity"], ambient_intensity=inputs["Ambient Intensity"],
                geometry_position=p)
    if kind == "SUN":
        light = reference.x3d_directional_light(inputs["Direction"], **args)
    elif kind == "POINT":
        light = reference.x3d_point_light(inputs["Position"], radius=near["Radius"],
                                          constant=near["Constant"], linear=near["Linear"],
                                          quadratic=near["Quadratic"], **args)
    else:
        light = reference.x3d_spot_light(inputs["Position"], inputs["Direction"],
                                         inputs["Beam Width"], inputs["Cut Off Angle"],
                                         radius=near["Radius"], constant=near["Constant"],
                                         linear=near["Linear"], quadratic=near["Quadratic"],
                                         **args)
    return inputs, light


@pytest.mark.parametrize("switched", [False, True])
@pytest.mark.parametrize("shadows", [False, True])
@pytest.mark.parametrize("kind", ["POINT", "SPOT", "SUN"])
def test_an_x3d_light_adds_what_the_reference_gives(kind, shadows, switched):
    rng = seeded.rng(("x3d", kind, shadows))
    inputs, light = _x3d_case(rng, kind)
    name = library.rig_light_group("x3d", kind, "QUADRATIC", shadows)
    group = library.definition(name, (library.SWITCH_FEATURE,) if switched else ())
    _check_x3d(group, inputs, light, shadows)


def _check_x3d(group, inputs, light, shadows, ambient=True):
    got = group.evaluate(inputs)
    terms = reference.x3d_light_terms(light["Light Vector"], light["Intensity"],
                                      light["Ambient"], inputs["Light Color"],
                                      inputs["Exponent"], inputs["Normal"], inputs["View Vector"])
    expected = {"Diffuse Sum": terms["Diffuse Light"], "Specular Sum": terms["Specular Light"],
                "Ambient Sum": terms["Ambient Light"]}
    if shadows:
        expected.update({"Plain Diffuse Sum": terms["Diffuse Light"],
                         "Plain Specular Sum": terms["Specular Light"]})
    assert set(got) == set(expected)
    for output, term in expected.items():
        if ambient or output != "Ambient Sum":  # (an ambientIntensity of 0 adds nothing)
            assert np.abs(term).max() > 0.01 and \
                np.mean(np.abs(term).max(axis=-1) > 1e-6) > 0.002
        np.testing.assert_allclose(got[output] - inputs[output], term, rtol=1e-9, atol=1e-9,
                                   err_msg=output)


def _threejs_case(rng, kind, facts=None):
    """Random inputs of the three.js light group and the reference's light for them (*facts*:
    the inputs made to hold them, ``library.LIGHT_FACTS``)."""
    p = rng.uniform(-4, 4, (N, 3))
    n, v = _unit(rng.normal(size=(N, 3))), _unit(rng.normal(size=(N, 3)))
    inputs = {"Surface Position": p, "Normal": n, "View Vector": v,
              "Lambert Normal": n / 128.0, "Intensity": _setting(rng, 0.0, 4.0),
              "Light Color": rng.uniform(0.0, 1.5, (N, 3)), "Exponent": _setting(rng, -1.0, 200.0),
              "Specular Strength": rng.choice([0.0, 0.3, 1.0], N),
              "True Normal": n, "Ray Lift": 1e-5 * n, "Cast Shadow": np.ones(N)}
    if kind != "SUN":
        inputs["Position"] = p + rng.normal(size=(N, 3)) * rng.choice([0.3, 2.0, 6.0], (N, 1))
        inputs["Distance"] = rng.choice([0.0, 3.0, 8.0], N)
        inputs["Decay"] = _setting(rng, 0.0, 3.0)
    if kind != "POINT":
        inputs["Direction"] = rng.normal(size=(N, 3)) * rng.choice([0.5, 1.0, 3.0], (N, 1))
        inputs["Reversed Axis"] = -_unit(inputs["Direction"])  # the group's: the unit +Z axis
    if kind == "SPOT":
        inputs["Angle"] = rng.uniform(0.0, math.pi / 2.0, N)
        inputs["Penumbra"] = rng.choice([0.0, 0.2, 1.0], N)
    for fact, holds in (facts or {}).items():
        if fact == "cut-off":
            inputs["Distance"] = rng.choice([3.0, 8.0], N) if holds else np.zeros(N)
        elif fact == "decay 2":
            inputs["Decay"] = np.full(N, 2.0) if holds else rng.uniform(0.0, 3.0, N)
        elif fact == "penumbra":
            inputs["Angle"] = rng.uniform(0.1, math.pi / 2.0, N)
            inputs["Penumbra"] = rng.choice([0.2, 1.0], N) if holds else np.zeros(N)
    args = dict(intensity=inputs["Intensity"], geometry_position=p)
    if kind == "SUN":
        light = reference.directional_light(inputs["Direction"], **args)
    elif kind == "POINT":
        light = reference.threejs_point_light(inputs["Position"], distance=inputs["Distance"],
                                              decay=inputs["Decay"], **args)
    else:
        light = reference.threejs_spot_light(inputs["Position"], inputs["Direction"],
                                             inputs["Angle"], inputs["Penumbra"],
                                             distance=inputs["Distance"], decay=inputs["Decay"],
                                             **args)
    return inputs, light


@pytest.mark.parametrize("switched", [False, True])
@pytest.mark.parametrize("shadows", [False, True])
@pytest.mark.parametrize("kind", ["POINT", "SPOT", "SUN"])
def test_a_threejs_light_gives_what_the_reference_gives(kind, shadows, switched):
    """The light group's sums (from zero) times the material's colours (three.js Rig
    Material) are the reference's three.js Phong Diffuse and Specular of the light."""
    rng = seeded.rng(("threejs", kind, shadows))
    inputs, light = _threejs_case(rng, kind)
    group = library.definition(library.rig_light_group("threejs", kind, "QUADRATIC", shadows),
                               (library.SWITCH_FEATURE,) if switched else ())
    _check_threejs(rng, group, inputs, light, shadows)


def _check_threejs(rng, group, inputs, light, shadows):
    got = group.evaluate(inputs)
    colours = {"Diffuse Color": rng.uniform(0, 1, (N, 3)),
               "Specular Color": rng.uniform(0, 1, (N, 3)), "Shininess": inputs["Exponent"],
               "Specular Strength": inputs["Specular Strength"]}
    want = reference.threejs_phong(light["Light Vector"], light["Intensity"],
                                   inputs["Light Color"], colours["Diffuse Color"],
                                   colours["Specular Color"], inputs["Exponent"],
                                   inputs["Specular Strength"], inputs["Normal"],
                                   inputs["View Vector"])
    material = library.RIG_GROUPS["three.js Rig Material"]
    for prefix in ("", "Plain ") if shadows else ("",):
        terms = material.evaluate({**colours, **{name: got[prefix + name] for name in (
            "Diffuse Sum", "Specular Sum", "Fresnel Sum")}})
        for output in ("Diffuse", "Specular"):
            term = want[output]
            assert np.abs(term).max() > 0.01 and np.mean(np.abs(term).max(axis=-1) > 1e-6) > 0.002
            np.testing.assert_allclose(terms[output], term, rtol=1e-9, atol=1e-9,
                                       err_msg=prefix + output)


def _operations(group, outputs) -> int:
    """The nodes *group* computes its *outputs* with (each formula once: ``Expr.key``)."""
    seen = set()

    def walk(expr):
        if expr.is_leaf or expr.key in seen:
            return
        seen.add(expr.key)
        for arg in expr.args:
            walk(arg)

    for name in outputs:
        walk(group.expressions[name])
    return len(seen)


_FACT_CASES = [(model, kind, shadows, dict(zip(facts, values)))
               for model in ("threejs", "x3d") for kind in ("POINT", "SPOT", "SUN")
               for facts in [library.light_facts(model, kind)] if facts
               for shadows in (False, True)
               for values in itertools.product((False, True), repeat=len(facts))]


@pytest.mark.parametrize("model, kind, shadows, facts", _FACT_CASES,
                         ids=[f"{m}-{k}-{s}-{sorted(f.items())}" for m, k, s, f in _FACT_CASES])
def test_a_light_of_known_constants_gives_the_reference_with_fewer_nodes(model, kind, shadows,
                                                                         facts):
    """Before 5.3 (no Switch), a three.js or X3D light whose constants hold *facts*
    (``library.LIGHT_FACTS``: a cut-off distance, decay 2, a penumbra; an X3D ramp, an
    ambientIntensity of 0) gets the group of those facts: the reference's light for every
    input that holds them, with fewer nodes than the general group, which computes both
    branches and selects one."""
    rng = seeded.rng((model, kind, shadows, tuple(facts.items())))
    name = library.rig_light_group(model, kind, "QUADRATIC", shadows, facts=facts)
    general = library.rig_light_group(model, kind, "QUADRATIC", shadows)
    assert name != general and name in library.RIG_GROUPS
    group = library.definition(name)
    if model == "threejs":
        inputs, light = _threejs_case(rng, kind, facts)
        _check_threejs(rng, group, inputs, light, shadows)
    else:
        inputs, light = _x3d_case(rng, kind, facts)
        _check_x3d(group, inputs, light, shadows, ambient=not facts["ambient 0"])
    sums = [s for s in library.RIG_MODELS[model].sums]
    fewer, more = (_operations(library.definition(n), sums) for n in (name, general))
    assert fewer <= more, f"{name}: {fewer} nodes, the general group {more}"
    if facts == {f: _USUAL[model][f] for f in facts}:  # a light as Blender makes it: nodes fewer
        assert fewer < more, f"{name}: {fewer} nodes, the general group {more}"


#: The facts of a light as Blender makes it, in each model (no three.js cut-off, decay 2, no
#: penumbra; X3D: a Spot Size of 45° is a cut-off angle below the default beamWidth, no
#: ambientIntensity).
_USUAL = {"threejs": {"cut-off": False, "decay 2": True, "penumbra": False},
          "x3d": {"ramp": False, "ambient 0": True}}
