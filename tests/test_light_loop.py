# SPDX-License-Identifier: GPL-3.0-or-later
"""Eevee's light loop (issue 38): the loop groups of node_groups/library.py, evaluated per
light on what Blender 5.3's Light Evaluation gives (the unit vector toward the light, the
distance, 1 for a sun), the light's packed settings (``library.loop_parameters``) and what
Light Accumulation then does (max(Light, 0) ⊗ clamp(Color, 0, 1) × the light's Blender
factor), equal the independent reference's terms (node_groups/reference.py) for every
light type and falloff of the seeds' and the three.js models.  Pure numpy: no Blender.

The render tests of the loop (Eevee against the reference and Cycles on 5.3) are in
tests/test_light_loop_render.py."""

from __future__ import annotations

import math
import zlib

import numpy as np
import pytest

from phong_nodes.node_groups import library, reference

import seeded

N_POINTS = 4000


def _unit(v):
    return v / np.linalg.norm(v, axis=-1, keepdims=True)


def _geometry(rng):
    P = rng.uniform(-2.0, 2.0, (N_POINTS, 3))
    P[:, 2] = rng.uniform(-0.5, 0.5, N_POINTS)
    N = _unit(rng.normal(size=(N_POINTS, 3)))
    N[:, 2] = np.abs(N[:, 2]) + 0.2  # mostly toward the lights above
    N = _unit(N)
    V = _unit(rng.normal(size=(N_POINTS, 3)) + np.array([0.0, 0.0, 1.5]))
    return P, N, V


def _light(rng, kind, falloff="QUADRATIC", model="seeds"):
    """A light as ``loop_parameters`` takes it, with its position and axis (-Z)."""
    position = np.array([rng.uniform(-1, 1), rng.uniform(-1, 1), rng.uniform(1.5, 3.0)])
    direction = _unit(np.array([rng.uniform(-0.4, 0.4), rng.uniform(-0.4, 0.4), -1.0]))
    settings = {"intensity": rng.uniform(0.5, 3.0), "quadratic": rng.uniform(0.2, 1.5),
                "linear": rng.uniform(0.0, 0.5), "constant": rng.uniform(0.0, 0.3),
                "power_k": rng.uniform(0.5, 3.0), "edge_exponent": rng.uniform(0.0, 6.0),
                "diffuse": rng.uniform(0.3, 1.5), "specular": rng.uniform(0.3, 1.5),
                "distance": rng.choice([0.0, rng.uniform(2.5, 6.0)]),
                "decay": rng.uniform(0.0, 2.5), "penumbra": rng.choice([0.0, rng.uniform(0, 1)])}
    return {"type": kind, "falloff": falloff, "color": tuple(rng.uniform(0.3, 1.0, 3)),
            "spot_size": rng.uniform(0.6, 2.4), "diffuse_factor": rng.uniform(0.3, 1.5),
            "specular_factor": rng.uniform(0.3, 1.5), "settings": settings,
            "position": position, "direction": direction}


def _material(rng):
    return {"Object Color": rng.uniform(0.1, 1.0, 3), "Specular Color": rng.uniform(0.1, 1.0, 3),
            "Exponent": rng.uniform(1.0, 60.0), "Blinn": rng.choice([0.0, 1.0, rng.uniform()]),
            "Specular Strength": rng.choice([0.0, 1.0, rng.uniform()])}


def _evaluation(light, P):
    """What Light Evaluation gives: the unit vector toward the light and the distance (a
    sun: its -axis and 1), and the light's +Z axis."""
    if light["type"] == "SUN":
        l = np.broadcast_to(-light["direction"], P.shape)
        r = np.ones(len(P))
    else:
        to = light["position"] - P
        r = np.linalg.norm(to, axis=-1)
        l = to / r[:, None]
    return l, r, -light["direction"]


def loop_terms(model, light, material, P, N, V):
    """(diffuse, specular) that Light Accumulation adds for one light of *model*."""
    spec = library.LOOP_MODELS[model]
    group = library.RIG_GROUPS[spec.group]
    packed = library.loop_parameters(model, light)
    l, r, axis = _evaluation(light, P)
    inputs = {"Light Vector": l, "Distance": r, "Light Axis": axis, "Normal": N,
              "View Vector": V, **material}
    for parameter in spec.parameters:
        value = packed[parameter.key(model)]
        if parameter.factor is not None:
            inputs[parameter.factor] = value
        if parameter.vector is not None:
            inputs[parameter.vector] = np.array(value[:3])
        if parameter.alpha is not None:
            inputs[parameter.alpha] = value[3]
        if parameter.components:
            for name, component in zip(parameter.components, value[:3]):
                inputs[name] = component
    out = group.evaluate({k: v for k, v in inputs.items()
                          if k in {s.name for s in group.inputs}})
    result = []
    for slot, factor in (("Diffuse", light["diffuse_factor"]),
                         ("Glossy", light["specular_factor"])):
        light_output, color_output = spec.slots[slot]
        result.append(library.accumulate(out[light_output], out[color_output], factor))
    return result


def reference_terms(model, light, material, P, N, V):
    """(diffuse, specular) of one light by the independent reference."""
    s, kind = light["settings"], light["type"]
    if model == "threejs":
        if kind == "SUN":
            out = reference.directional_light(light["direction"], s["intensity"],
                                              geometry_position=P)
        elif kind == "POINT":
            out = reference.threejs_point_light(light["position"], s["intensity"],
                                                s["distance"], s["decay"], geometry_position=P)
        else:
            out = reference.threejs_spot_light(light["position"], light["direction"],
                                               light["spot_size"] / 2.0, s["penumbra"],
                                               s["intensity"], s["distance"], s["decay"],
                                               geometry_position=P)
        terms = reference.threejs_phong(out["Light Vector"], out["Intensity"], light["color"],
                                        material["Object Color"], material["Specular Color"],
                                        material["Exponent"], material["Specular Strength"],
                                        N, V)
        return terms["Diffuse"], terms["Specular"]
    power = light["falloff"] == "POWER"
    falloff = (0.0, 0.0, 1.0) if power else (s["quadratic"], s["linear"], s["constant"])
    if kind == "SUN":
        out = reference.directional_light(light["direction"], s["intensity"],
                                          geometry_position=P)
    elif kind == "POINT":
        out = reference.point_light(light["position"], s["intensity"], *falloff,
                                    geometry_position=P)
    else:
        out = reference.spot_light(light["position"], light["direction"],
                                   light["spot_size"] / 2.0, s["edge_exponent"], s["intensity"],
                                   *falloff, geometry_position=P)
    intensity = out["Intensity"]
    if power and kind != "SUN":
        intensity = reference.power_falloff(out["Distance"], intensity, s["power_k"])["Intensity"]
    terms = reference.phong_shading(
        light_vector=out["Light Vector"], light_intensity=intensity, light_color=light["color"],
        object_color=material["Object Color"], ambient_intensity=0.0,
        diffuse_strength=s["diffuse"], specular_strength=s["specular"],
        specular_color=material["Specular Color"], exponent=material["Exponent"],
        blinn=material["Blinn"], normal=N, view_vector=V)
    return terms["Diffuse"], terms["Specular"]


def _cone_edge(light, P):
    """Points within 1e-5 of a spot's cone edge (the comparison leaves them out)."""
    if light["type"] != "SPOT":
        return np.zeros(len(P), bool)
    l = _unit(light["position"] - P)
    cos_w = -(l @ light["direction"])
    return np.abs(cos_w - math.cos(light["spot_size"] / 2.0)) < 1e-5


CASES = [("seeds", "POINT", "QUADRATIC"), ("seeds", "POINT", "POWER"), ("seeds", "SUN", None),
         ("seeds", "SPOT", "QUADRATIC"), ("seeds", "SPOT", "POWER"),
         ("threejs", "POINT", None), ("threejs", "SUN", None), ("threejs", "SPOT", None)]


@pytest.mark.parametrize("model,kind,falloff", CASES)
def test_the_loop_group_gives_the_reference_terms(model, kind, falloff):
    rng = seeded.rng((model, kind, falloff))
    P, N, V = _geometry(rng)
    worst = 0.0
    for _trial in range(6):
        light = _light(rng, kind, falloff or "QUADRATIC", model)
        material = _material(rng)
        got = loop_terms(model, light, material, P, N, V)
        want = reference_terms(model, light, material, P, N, V)
        keep = ~_cone_edge(light, P)
        for g, w in zip(got, want):
            err = np.abs(g - w).max(axis=-1)[keep]
            worst = max(worst, float(err.max()))
            # relative to the size of the term (a highlight of e = 60 is steep)
            assert np.all(err <= 1e-6 + 1e-5 * np.abs(w).max(axis=-1)[keep]), (light, material)
    assert worst < 1e-4


def test_a_light_the_loop_cannot_show_adds_nothing():
    """An Area light (or any other type) gets zeros: Light Accumulation adds nothing."""
    for model in library.LOOP_MODELS:
        packed = library.loop_parameters(model, {"type": "AREA", "color": (1, 1, 1)})
        assert all(v == 0.0 or v == (0.0, 0.0, 0.0, 0.0) for v in packed.values())
        assert all(k.startswith(library.LOOP_PREFIX + model) for k in packed)


def test_a_blender_factor_of_zero_gives_no_light_and_others_are_undone():
    """Light Accumulation multiplies by Blender's own Diffuse / Specular factor: the packed
    colours divide by it (a factor of 0 cannot be undone: the loop adds nothing)."""
    light = {"type": "POINT", "color": (1.0, 0.5, 0.25), "diffuse_factor": 0.5,
             "specular_factor": 0.0, "settings": {"intensity": 2.0}}
    packed = library.loop_parameters("seeds", light)
    assert packed["phong_eevee_seeds_diffuse"][:3] == pytest.approx((4.0, 2.0, 1.0))
    assert packed["phong_eevee_seeds_specular"][:3] == (0.0, 0.0, 0.0)


def test_light_accumulation_clamps_as_blender_does():
    """max(Light, 0) ⊗ clamp(Color, 0, 1) × factor (Blender 5.3's node_light_accumulation)."""
    got = library.accumulate(np.array([-1.0, 0.5, 2.0]), np.array([0.5, 1.5, -0.2]), 2.0)
    assert got == pytest.approx([0.0, 1.0, 0.0])


def test_the_table_rows_of_figure_10_state_the_goals():
    """benchmarks/table.py's rows of figure 10 (light_loop.py --merge): the F12 ratio at 4 and
    16 lights against 2x (none at 1 light), the worst light's drag against 1.3x."""
    from phong_nodes.benchmarks import table

    def f12(principled, phong, group):
        return {"median_s": {"principled": principled, "phong": phong,
                             "phong_lights_group": group},
                "render_s": {"principled": [principled], "phong": [phong],
                             "phong_lights_group": [group]},
                "ratio_to_principled": {"phong": phong / principled,
                                        "phong_lights_group": group / principled},
                "bpy": "5.3.0"}

    figure = {"objects": 1000, "goals": {"f12": 2.0, "drag": 1.3},
              "f12": {"1": f12(2.0, 3.0, 3.0), "4": f12(2.0, 3.8, 6.0),
                      "16": f12(2.0, 4.2, 20.0)},
              "drag": {"lights": 16, "objects": 1000, "moves": 21, "bpy": "5.3.0",
                       "update_s": {"principled": [1.0, 2.0, 3.0], "phong": [1.0, 2.2, 3.6]},
                       "ratio_to_principled": {"phong": [1.0, 1.1, 1.2]},
                       "worst_ratio": {"phong": 1.2, "lights_group": 6.8,
                                       "phong_again": 1.25}}}
    rows = table.loop_rows(figure)
    assert [r[1] for r in rows] == ["1.50×", "1.90×", "2.10×", "1.20×"]
    assert [r[3] for r in rows] == ["", "met", "missed by 1.1×", "met"]
    assert [r[2] for r in rows] == ["–", "≤ 2×", "≤ 2×", "≤ 1.3×"]
    assert "ratio of their medians 1.10×" in rows[3][4]
    assert "the lights groups of 5.2: worst 6.80×" in rows[3][4]
    assert "median of 21 moves each" in rows[3][4]
    figure["drag"].update(method="files", rounds=8, passes=2, moves=10)
    figure["drag"]["worst_ratio"]["phong_live"] = 1.45
    detail = table.loop_rows(figure)[3][4]
    assert "the World's copies live: worst 1.45×" in detail
    assert "each file in its own process, 8 rounds of 2 x 10 moves per light" in detail
    assert table.loop_rows(None) == []


# -- the X3D / VRML97 model's loop (X3D Loop Light) -----------------------------------------

def _x3d_light(rng, kind, hard=False):
    light = _light(rng, kind)
    cut = light["spot_size"] / 2.0
    light["settings"] = {"intensity": rng.uniform(0.3, 1.5), "ambient": rng.uniform(0.0, 1.0),
                         "constant": rng.uniform(0.0, 1.5), "linear": rng.uniform(0.0, 0.5),
                         "quadratic": rng.uniform(0.0, 0.8), "radius": rng.uniform(3.0, 4.5),
                         "beam_width": cut + 0.2 if hard else rng.uniform(0.05, cut - 0.05)}
    light["transmission_factor"] = rng.uniform(0.3, 1.5)
    return light


def _x3d_reference(light, material, P, N, V):
    """(diffuse, specular, ambient) of one X3D light by the standards' equation (reference)."""
    s, kind = light["settings"], light["type"]
    near = (s["intensity"], s["ambient"], s["constant"], s["linear"], s["quadratic"], s["radius"])
    if kind == "SUN":
        out = reference.x3d_directional_light(light["direction"], s["intensity"], s["ambient"],
                                              geometry_position=P)
    elif kind == "POINT":
        out = reference.x3d_point_light(light["position"], *near, geometry_position=P)
    else:
        out = reference.x3d_spot_light(light["position"], light["direction"], s["beam_width"],
                                       light["spot_size"] / 2.0, *near, geometry_position=P)
    terms = reference.x3d_light_terms(out["Light Vector"], out["Intensity"], out["Ambient"],
                                      light["color"], material["Exponent"], N, V)
    return (terms["Diffuse Light"] * material["Object Color"],
            terms["Specular Light"] * material["Specular Color"],
            terms["Ambient Light"] * material["Ambient Object Color"]), out


@pytest.mark.parametrize("kind", ["POINT", "SUN", "SPOT", "SPOT hard"])
def test_the_x3d_loop_group_gives_the_standards_terms(kind):
    """X3D Loop Light, packed and accumulated as Eevee does, against the reference's X3D
    equation: the attenuation clamp, the radius, the spot ramp (and a hard edge where
    beamWidth ≥ cutOffAngle), Blinn without the N·L condition (e = 0 included) and each
    light's own ambient light, which goes to Transmission and is divided by Blender's
    Transmission factor."""
    rng = np.random.default_rng(zlib.crc32(kind.encode()))
    P, N, V = _geometry(rng)
    spec = library.LOOP_MODELS["x3d"]
    assert spec.unshadowed == ("Transmission",)
    worst = 0.0
    for trial in range(6):
        light = _x3d_light(rng, kind.split()[0], hard=kind.endswith("hard"))
        material = {"Object Color": rng.uniform(0.1, 1.0, 3),
                    "Specular Color": rng.uniform(0.1, 1.0, 3),
                    "Exponent": 0.0 if trial == 0 else rng.uniform(1.0, 100.0),
                    "Ambient Object Color": rng.uniform(0.0, 1.0, 3)}
        packed = library.loop_parameters("x3d", light)
        group = library.RIG_GROUPS[spec.group]
        l, r, axis = _evaluation(light, P)
        inputs = {"Light Vector": l, "Distance": r, "Light Axis": axis, "Normal": N,
                  "View Vector": V, **material}
        for parameter in spec.parameters:
            value = packed[parameter.key("x3d")]
            if parameter.vector is not None:
                inputs[parameter.vector] = np.array(value[:3])
            if parameter.alpha is not None:
                inputs[parameter.alpha] = value[3]
            for name, component in zip(parameter.components or (), value[:3]):
                inputs[name] = component
        out = group.evaluate(inputs)
        got = [library.accumulate(out[spec.slots[slot][0]], out[spec.slots[slot][1]],
                                  light[factor])
               for slot, factor in (("Diffuse", "diffuse_factor"), ("Glossy", "specular_factor"),
                                    ("Transmission", "transmission_factor"))]
        want, ref_light = _x3d_reference(light, material, P, N, V)
        keep = np.ones(len(P), bool)
        if kind != "SUN":
            keep &= np.abs(ref_light["Distance"] - light["settings"]["radius"]) > 1e-5
        if kind.endswith("hard"):
            keep &= np.abs(ref_light["Spot Angle"] - light["spot_size"] / 2.0) > 1e-5
        assert keep.mean() > 0.95
        for g, w in zip(got, want):
            err = np.abs(g - w).max(axis=-1)[keep]
            worst = max(worst, float(err.max()))
            assert np.all(err <= 1e-6 + 1e-5 * np.abs(w).max(axis=-1)[keep]), (light, material)
        lit = want[0].max(axis=-1) > 1e-3
        assert lit.mean() > 0.002 and (kind == "SUN" or lit.mean() < 0.99), lit.mean()
    assert worst < 1e-4
