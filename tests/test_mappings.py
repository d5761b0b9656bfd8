# SPDX-License-Identifier: GPL-3.0-or-later
"""Each format's Phong mapping, both directions, without Blender: the project's values → the
format's fields (``core/fbx/phong.py``, ``core/x3d/phong.py``, ``core/threejs.py``) → the
values the importer gives back; and a lighting model as one object that answers every question
about it outside Blender: a throw-away fourth model, registered here, goes through the
mappings and the reference without any other file naming it."""

from __future__ import annotations

import math

import numpy as np
import pytest

from phong_nodes.core import compare, fbx, scenes, threejs, x3d
from phong_nodes.node_groups import models

#: Every setting a light holds (each model reads some), at values off every default.
SETTINGS = {"intensity": 2.5, "quadratic": 0.0, "linear": 0.0, "constant": 0.5,
            "edge_exponent": 3.0, "diffuse": 0.75, "specular": 1.5, "distance": 12.0,
            "decay": 1.5, "penumbra": 0.25, "power_k": 2.0, "ambient": 0.3, "radius": 40.0,
            "beam_width": 0.4}
#: The defaults a light takes for what a file does not give (the light panel's defaults).
DEFAULTS = {"intensity": 1.0, "quadratic": 1.0, "linear": 0.0, "constant": 0.0,
            "edge_exponent": 0.0, "diffuse": 1.0, "specular": 1.0, "distance": 0.0,
            "decay": 2.0, "penumbra": 0.0, "power_k": 2.0, "ambient": 0.0, "radius": 100.0,
            "beam_width": 0.7854}


# -- FBX -------------------------------------------------------------------------------------

@pytest.mark.parametrize("model", models.NAMES)
@pytest.mark.parametrize("kind", ["POINT", "SUN", "SPOT", "AREA"])
@pytest.mark.parametrize("falloff", ["QUADRATIC", "POWER"])
def test_fbx_light_values_come_back_through_the_file_s_values(model, kind, falloff):
    """values → FBX Light → the importer's settings: every setting back (the written values
    and the user properties together), in every model, an Area light as a spot."""
    size = math.radians(70.0)
    out, _notes = fbx.light_of(kind, (0.2, 0.4, 0.6), SETTINGS, falloff, size, False,
                               models.get(model), DEFAULTS, "Lamp")
    assert out.type == ("SPOT" if kind == "AREA" else kind)
    back = fbx.light_settings(out)
    assert back["color"] == (0.2, 0.4, 0.6) and back["cast_shadows"] is False
    settings = dict(DEFAULTS, **back["settings"])
    for attr, value in SETTINGS.items():
        assert settings[attr] == pytest.approx(value, rel=1e-6), attr
    if kind != "SUN":
        assert settings["falloff"] == falloff
    if kind in ("SPOT", "AREA"):
        assert back["spot_size"] == pytest.approx(size, rel=1e-12)


def test_fbx_light_single_term_falloff_is_said_by_the_file_alone():
    """i0/γ with γ = 1 and no other term is FBX's DecayType 0 with Intensity 100 × i0: no user
    property; with γ = 0.5 the file says i0/γ (Intensity 500 for i0 2.5), and keeps i0 and γ."""
    settings = dict(DEFAULTS, intensity=2.5, quadratic=0.0, constant=1.0)
    out, notes = fbx.light_of("POINT", (1, 1, 1), settings, "QUADRATIC", math.pi, True,
                              models.get("seeds"), DEFAULTS)
    assert (out.decay, out.intensity) == (0, 2.5)
    assert out.user == {} and notes == []
    assert fbx.light_props(out)[2] == ("Intensity", "Number", "", "A", (250.0,), "D")
    out, notes = fbx.light_of("POINT", (1, 1, 1), dict(settings, constant=0.5), "QUADRATIC",
                              math.pi, True, models.get("seeds"), DEFAULTS)
    assert (out.decay, out.intensity) == (0, 5.0)
    assert out.user == {"intensity": 2.5, "constant": 0.5} and len(notes) == 1


def test_fbx_area_light_is_the_model_s_spot():
    """An Area light: a 180° spot; the seeds' edge exponent 1 (cosθ_light) is the InnerAngle
    at which (cos ω)^1 = ½ halfway between the half angles: ω = 60° → Inner = 4·60° − 180°."""
    seeds = dict(DEFAULTS, edge_exponent=models.AREA_EDGE_EXPONENT)
    out, _ = fbx.light_of("AREA", (1, 1, 1), seeds, "QUADRATIC", math.pi, False,
                          models.get("seeds"), DEFAULTS)
    assert (out.type, out.outer_angle) == ("SPOT", 180.0)
    assert out.inner_angle == pytest.approx(60.0, abs=1e-9)
    assert fbx.light_settings(out)["settings"]["edge_exponent"] == pytest.approx(1.0)
    x3d_area = dict(DEFAULTS, beam_width=models.AREA_HALF_ANGLE)
    out, _ = fbx.light_of("AREA", (1, 1, 1), x3d_area, "QUADRATIC", math.pi, False,
                          models.get("x3d"), DEFAULTS)
    assert out.inner_angle == pytest.approx(180.0)


@pytest.mark.parametrize("specular", [(0.0, 0.0, 0.0), (0.5, 0.25, 0.125)])
def test_fbx_material_values_come_back(specular):
    values = {"Object Color": (0.1, 0.2, 0.3), "Ambient Object Color": (0.05, 0.1, 0.15),
              "Specular Color": specular, "Irradiant Color": (0.0, 0.01, 0.02),
              "Exponent": 42.0, "Opacity": 0.8}
    out = fbx.material_of(values, name="Paint")
    assert out.kind == ("LAMBERT" if not any(specular) else "PHONG")
    fbx.keep_unsaid(out, 0.5, 0.7)
    back = fbx.material_values(out)
    for key, value in values.items():
        assert back[key] == pytest.approx(value), key
    assert (back["Blinn"], back["Specular Strength"]) == (0.5, 0.7)
    props = dict((p[0], p[4]) for p in fbx.material_props(out))
    assert props["ShadingModel"] == ("Lambert" if not any(specular) else "Phong",)
    assert props["DiffuseColor"] == (0.1, 0.2, 0.3) and props["Opacity"] == (0.8,)
    assert props["TransparencyFactor"] == pytest.approx((0.2,))


def test_fbx_ambient_comes_back():
    colour, user = fbx.ambient_of(0.5, (0.2, 0.4, 0.8))
    assert colour == pytest.approx((0.1, 0.2, 0.4))
    assert fbx.world_ambient(colour, user) == (0.5, (0.2, 0.4, 0.8))
    colour, user = fbx.ambient_of(1.0, (0.2, 0.4, 0.8))
    assert user == {} and fbx.world_ambient(colour, user) == (1.0, (0.2, 0.4, 0.8))


# -- X3D -------------------------------------------------------------------------------------

@pytest.mark.parametrize("kind", ["directional", "point", "spot"])
def test_x3d_light_values_come_back_in_the_x3d_model(kind):
    """values → X3D Light fields → the reader's light values → values (the X3D model's
    settings), and the cut-off angle half the spot size."""
    fields, notes = x3d.light_fields(models.get("x3d"), SETTINGS, "QUADRATIC", kind, 1.2)
    assert notes == []
    light = x3d.Light(kind=kind, name="L", **fields)
    values = x3d.light_values(x3d.Document(path="", encoding="x3d-xml", meter=1.0), light)
    back = x3d.light_settings(values)
    keep = ("intensity", "ambient") + (() if kind == "directional" else
                                        ("constant", "linear", "quadratic", "radius"))
    for attr in keep + (("beam_width",) if kind == "spot" else ()):
        assert back[attr] == pytest.approx(SETTINGS[attr]), attr
    if kind == "spot":
        assert values["cut_off_angle"] == pytest.approx(0.6, rel=1e-6)


def test_x3d_light_of_other_models_is_mapped_with_notes():
    """The seeds' power falloff 1/d² is X3D's a2; no radius; a soft edge and the diffuse
    and specular factors named; three.js's penumbra narrows the beam."""
    fields, notes = x3d.light_fields(models.get("seeds"), SETTINGS, "POWER", "spot", 1.0)
    assert fields["attenuation"] == (0.0, 0.0, 1.0)
    assert fields["radius"] == x3d.NO_RADIUS and fields["beam_width"] == fields["cut_off_angle"]
    assert len(notes) == 2 and "Edge Exponent" in notes[0] and "Diffuse" in notes[1]
    fields, notes = x3d.light_fields(models.get("threejs"), SETTINGS, "QUADRATIC", "spot", 1.0)
    assert fields["beam_width"] == pytest.approx(0.5 * 0.75) and notes == []
    assert x3d.model_note(models.get("x3d"), "S") is None
    assert "seeds lighting model" in x3d.model_note(models.get("seeds"), "S")


def test_x3d_material_values_come_back():
    """values → X3D Material fields → the reader's Phong values → values (float32)."""
    values = {"Kd": (0.5, 0.25, 0.125), "Ka": (0.1, 0.05, 0.025), "Ks": (0.3, 0.3, 0.3),
              "Ke": (0.0, 0.1, 0.0), "exponent": 64.0, "opacity": 0.75}
    fields, notes = x3d.material_fields(values)
    assert notes == []
    back = x3d.phong_values(x3d.Material(name="M", **fields))
    for key in ("Kd", "Ka", "Ks", "Ke"):
        assert back[key] == pytest.approx(values[key], rel=1e-6), key
    assert back["exponent"] == pytest.approx(64.0) and back["opacity"] == pytest.approx(0.75)
    assert back["blinn"] == 1.0


def test_x3d_material_mapping_says_what_x3d_cannot():
    shininess, note = x3d.shininess_of(200.0)
    assert shininess == 1.0 and "above X3D's 128" in note
    assert x3d.shininess_of(64.0, kept=0.5) == (0.5, None)
    value, note = x3d.ambient_intensity_of((0.5, 0.5, 0.5), (0.1, 0.2, 0.1))
    assert "nearest multiple" in note and value == pytest.approx(0.2 / 0.75, rel=1e-7)
    assert x3d.ambient_intensity_of((0.0, 0.0, 0.0), (0.1, 0.1, 0.1))[0] == 0.0
    assert x3d.highlight_note(models.get("x3d"), 0.0, (1, 1, 1)) is None
    assert x3d.highlight_note(models.get("seeds"), 0.0, (1, 1, 1))
    assert x3d.highlight_note(models.get("seeds"), 0.0, (0, 0, 0)) is None


def test_x3d_world_ambient_comes_back():
    """The World's Phong ambient (which X3D lacks) → a DirectionalLight of intensity 0 →
    the same ambient read back; a black one is no light."""
    light = x3d.world_ambient_light(0.25, (0.5, 1.0, 0.75))
    assert (light.kind, light.intensity, light.is_global) == ("directional", 0.0, True)
    assert x3d.is_world_ambient(light)
    doc = x3d.Document(path="", encoding="x3d-xml", meter=1.0)
    assert x3d.world_ambient(doc, light) == (0.25, (0.5, 1.0, 0.75))
    assert x3d.world_ambient_light(0.0, (1, 1, 1)) is None
    assert x3d.world_ambient_light(0.5, (0, 0, 0)) is None
    assert not x3d.is_world_ambient(x3d.Light(kind="directional", name=x3d.WORLD_AMBIENT,
                                              intensity=0.5))


# -- three.js --------------------------------------------------------------------------------

def test_threejs_light_of_a_spot():
    light = {"name": "S", "type": "spot", "color": [1, 1, 1], "intensity": 2.0,
             "position": [0.0, 0.0, 2.0], "direction": [0.0, 0.0, -4.0], "half_angle": 30.0,
             **SETTINGS}
    out = threejs.light_of(light, models.get("threejs"))
    assert out["target"] == [0.0, 0.0, 1.0]
    assert out["angle"] == pytest.approx(math.pi / 6.0)
    assert (out["distance"], out["decay"], out["penumbra"]) == (12.0, 1.5, 0.25)
    sun = threejs.light_of({"name": "D", "type": "directional", "color": [1, 1, 1],
                            "intensity": 1.0, "direction": [0.0, -3.0, 0.0]},
                           models.get("seeds"))
    assert sun["position"] == [0.0, 1.0, 0.0]
    assert threejs.model_note(models.get("threejs"), "S") is None
    assert threejs.model_note(models.get("seeds"), "S")


def test_threejs_material_of():
    values = {"color": [0.5, 0.4, 0.3], "specular": [1, 1, 1], "shininess": 30.0,
              "emissive": [0, 0, 0], "specular_strength": 1.5, "ambient": [0.5, 0.4, 0.3],
              "blinn": 0.0}
    out, notes = threejs.material_of("M", values)
    assert (out["type"], out["specular_strength"], notes) == ("phong", 1.0, [])
    out, notes = threejs.material_of("M", dict(values, specular_strength=0.0, blinn=1.0,
                                               ambient=[0.1, 0.1, 0.1]))
    assert out["type"] == "lambert" and "specular" not in out and len(notes) == 2


# -- a fourth lighting model: one entry and its class --------------------------------------

class _Halves(models.Seeds):
    """A throw-away model: the seeds' lights at half their intensity, X3D's radius 7, an FBX
    spot's inner cone always half its outer, three.js lights without decay."""

    def reference_light(self, light, P, width):
        ell, intensity, ambient, edge = super().reference_light(light, P, width)
        return ell, 0.5 * intensity, ambient, edge

    def x3d_light(self, settings, falloff, kind, cut):
        out, notes = super().x3d_light(settings, falloff, kind, cut)
        return dict(out, radius=7.0), notes + ["halved"]

    def fbx_inner_angle(self, settings, outer):
        return 0.5 * outer

    def threejs_light(self, settings):
        return dict(super().threejs_light(settings), decay=0.0)


@pytest.fixture
def fourth(monkeypatch):
    seeds = models.get("seeds")
    model = _Halves(**{**{f: getattr(seeds, f) for f in seeds.__dataclass_fields__},
                       "name": "halves", "label": "Halves", "prefix": "Halves"})
    monkeypatch.setitem(models.MODELS, "halves", model)   # restored after the test
    assert models.check() == []
    return model


def test_a_fourth_model_goes_through_every_mapping_and_the_reference(fourth):
    from test_compare import SCENE, aovs   # the synthetic probes of the comparison's tests

    assert models.get("halves") is fourth
    fields, notes = x3d.light_fields(models.get("halves"), SETTINGS, "QUADRATIC", "point", 0.0)
    assert fields["radius"] == 7.0 and notes[-1] == "halved"
    assert "halves lighting model" in x3d.model_note(fourth, "S")
    out, _ = fbx.light_of("SPOT", (1, 1, 1), SETTINGS, "QUADRATIC", math.radians(80.0), False,
                          fourth, DEFAULTS)
    assert out.inner_angle == pytest.approx(40.0)
    page = threejs.light_of({"name": "P", "type": "point", "color": [1, 1, 1],
                             "intensity": 1.0, "position": [0, 0, 1], **SETTINGS}, fourth)
    assert page["decay"] == 0.0 and page["distance"] == 12.0
    # the reference: the sun's diffuse light on the lit pixel is half the seeds'
    seeds = compare.reference_image(SCENE, aovs())
    halves = compare.reference_image(dict(SCENE, model="halves"), aovs())
    np.testing.assert_allclose(halves["Diffuse"][0, 0], 0.5 * seeds["Diffuse"][0, 0],
                               rtol=1e-12)
    assert seeds["Diffuse"][0, 0].max() > 0.0
    np.testing.assert_array_equal(halves["Ambient"], seeds["Ambient"])
    # its scene files: its class reads them as the seeds' do (their keys and defaults)
    scene = scenes.parse({"title": "t", "model": "halves",
                          "camera": {"location": [0, -5, 1], "look_at": [0, 0, 0]},
                          "lights": [{"name": "key", "type": "point", "position": [0, 0, 2]}],
                          "objects": [{"name": "ball"}]})
    assert scene["model"] == "halves"
    assert (scene["lights"][0]["diffuse"], scene["lights"][0]["quadratic"]) == (1.0, 1.0)


def test_the_fourth_model_is_gone_after_its_test():
    assert "halves" not in models.MODELS and models.get("halves").name == models.DEFAULT
