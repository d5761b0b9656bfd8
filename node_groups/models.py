# SPDX-License-Identifier: GPL-3.0-or-later
"""The lighting models (seeds, three.js, X3D), one table entry each: written once here, read
by every part of the project that differs by model.

An entry says what a model is made of; its groups' formulas are in ``library.py``:

* ``name``, ``label``, ``description``: the value of ``scene["phong_model"]`` (and of the scene
  files' ``model``) and the Lighting Model menu's item (``addon/lighting/properties.py``);
* ``prefix``: the first word of a scene's lights group ("Phong Lights Scene");
* ``light_groups``: the light group of each Blender light type (POINT, SUN, SPOT), read by the
  lights group (``addon/lighting/rig.py``) and the Per Vertex / Per Face expressions
  (``shading_modes.py``);
* ``spot_angle``: the spot light group's input driven by half the light's Spot Size, and
  ``spot_note``: what the light panel says of it (None: nothing);
* ``settings``: what the model reads of a light, (setting, the light types that read it, the
  falloff under which it is read (None: any), the input of the model's light group that it
  drives (None: read elsewhere: the falloff chooses nodes, power_k drives the Power
  Falloff's Exponent, diffuse and specular the Phong Light Terms' strengths)), in the light
  panel's order (``properties.model_settings``);
* ``composition``: how the lights group sums the light groups' parts into the material's
  colour, one of ``COMPOSITIONS``; the lights group (``rig.py``) and the Per Vertex / Per Face
  expression (``shading_modes.py``) each hold one builder per composition, so a model that
  composes as an existing one is this table's entry and its light groups;
* ``loop``: its group in Eevee's light loop on Blender 5.3+ (``library.LOOP_MODELS``; None: the
  model's Eevee side is its lights group, as before 5.3).

No ``bpy`` here.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

#: How a lights group composes the material's colour (docs/contract.md, "Several lights").
COMPOSITIONS = {
    "phong": "per light a Phong Light Terms (diffuse and specular light; a Power Falloff where "
             "the light's falloff is POWER); Σ diffuse ⊗ Object Color + Σ specular ⊗ Specular "
             "Color + the World's Phong Ambient + the irradiant, min(…, 1)",
    "chain": "three.js: the ambient (three.js Ambient) ⊕ the emissive ⊕ each light's three.js "
             "Phong, a Phong Color Add chain",
    "phong_light_ambient": "as phong, with X3D Light Terms, and each light's own ambient "
                           "light: + Σ ambient light ⊗ Ambient Object Color",
}

#: Light types of Blender that a Phong lights group reads.
EVERY = ("POINT", "SUN", "SPOT")
NEAR = ("POINT", "SPOT")
#: Every light type of Blender that drives Phong materials: an Area light is drawn as the
#: model's spot light (``drawn_as``), the far field of a Lambertian emitter.
RENDERED = EVERY + ("AREA",)

#: The i0 of a light that takes it from Blender's Power, per watt (Point, Spot, Area) or per
#: unit of a Sun's Strength: what Blender's own light gives a Lambertian surface of colour
#: Kd, measured in Cycles (docs/model.md, "A light's Power"): a point or spot of P watts
#: Kd·P/(4π²)·cosθ/r², a sun of strength S Kd·S/π·cosθ, a small area light of P watts
#: Kd·P/π²·cosθ_light·cosθ/r².  Blender's Exposure multiplies the Power by 2^exposure, and
#: an Area light whose Normalize is off emits P per square metre of its shape.
POWER_TO_INTENSITY = {"POINT": 1.0 / (4.0 * math.pi ** 2), "SPOT": 1.0 / (4.0 * math.pi ** 2),
                      "SUN": 1.0 / math.pi, "AREA": 1.0 / math.pi ** 2}
#: An Area light as a spot: the half angle of its cone (a hemisphere) in radians, and the
#: edge exponent of the seeds' spot that gives a Lambertian emitter's cosθ_light.
AREA_HALF_ANGLE = math.pi / 2.0
AREA_EDGE_EXPONENT = 1.0


def drawn_as(light_type: str) -> str:
    """The light type whose light group draws a Blender light of *light_type*: an Area light
    is a spot (a 90° cone around its -Z axis, cosθ_light for the seeds' model), every other
    type itself."""
    return "SPOT" if light_type == "AREA" else light_type


@dataclass(frozen=True)
class LightingModel:
    """One lighting model (see the module's docstring)."""

    name: str
    label: str
    description: str
    prefix: str
    light_groups: dict
    spot_angle: str
    settings: tuple
    composition: str
    spot_note: str | None = None
    loop: str | None = None
    #: the spot settings an Area light takes (it is drawn as a spot: ``drawn_as``), by
    #: setting; a spot setting not named here keeps its default
    area: tuple = ()

    @property
    def power_falloff(self) -> bool:
        """Whether the model reads a light's falloff (Quadratic or Power i0/d^k)."""
        return any(row[0] == "falloff" for row in self.settings)


_TABLE = (
    LightingModel(
        name="seeds", label="Seeds (textbook Phong)",
        description="The lecture notes' Phong model: i0/(αr²+βr+γ) lights, (r·v)^e or (h·n)^e "
                    "highlights",
        prefix="Phong",
        light_groups={"POINT": "Phong Point Light", "SUN": "Phong Directional Light",
                      "SPOT": "Phong Spot Light"},
        spot_angle="Half Angle",
        settings=(("intensity", EVERY, None, "Intensity"),
                  ("falloff", NEAR, None, None),
                  ("quadratic", NEAR, "QUADRATIC", "Quadratic"),
                  ("linear", NEAR, "QUADRATIC", "Linear"),
                  ("constant", NEAR, "QUADRATIC", "Constant"),
                  ("power_k", NEAR, "POWER", None),
                  ("edge_exponent", ("SPOT",), None, "Edge Exponent"),
                  ("diffuse", EVERY, None, None),
                  ("specular", EVERY, None, None)),
        composition="phong", loop="Phong Loop Light",
        area=(("edge_exponent", AREA_EDGE_EXPONENT),)),
    LightingModel(
        name="threejs", label="three.js",
        description="What three.js r181's MeshPhongMaterial / MeshLambertMaterial show: "
                    "Lambert/π, normalised Blinn-Phong with Fresnel, distance/decay lights, "
                    "smoothstep penumbra",
        prefix="three.js",  # docs/threejs.md
        light_groups={"POINT": "three.js Point Light", "SUN": "Phong Directional Light",
                      "SPOT": "three.js Spot Light"},
        spot_angle="Angle",
        settings=(("intensity", EVERY, None, "Intensity"),
                  ("distance", NEAR, None, "Distance"),
                  ("decay", NEAR, None, "Decay"),
                  ("penumbra", ("SPOT",), None, "Penumbra")),
        composition="chain", spot_note="Angle: half the spot size", loop="three.js Loop Light",
        area=(("penumbra", 0.0),)),
    LightingModel(
        name="x3d", label="X3D / VRML97",
        description="The ISO lighting equation of X3D and VRML97: per-light ambient, "
                    "attenuation 1/max(a0 + a1·d + a2·d², 1) within a radius, a linear spot "
                    "ramp, Blinn highlights",
        prefix="X3D",  # docs/x3d.md
        light_groups={"POINT": "X3D Point Light", "SUN": "X3D Directional Light",
                      "SPOT": "X3D Spot Light"},
        spot_angle="Cut Off Angle",
        # the X3D attenuation 1/max(a0 + a1·d + a2·d², 1): a0, a1, a2 are the seeds' γ, β, α
        settings=(("intensity", EVERY, None, "Intensity"),
                  ("ambient", EVERY, None, "Ambient Intensity"),
                  ("constant", NEAR, None, "Constant"),
                  ("linear", NEAR, None, "Linear"),
                  ("quadratic", NEAR, None, "Quadratic"),
                  ("radius", NEAR, None, "Radius"),
                  ("beam_width", ("SPOT",), None, "Beam Width")),
        composition="phong_light_ambient", spot_note="Cut-off angle: half the spot size",
        loop="X3D Loop Light", area=(("beam_width", AREA_HALF_ANGLE),)),
)

#: name -> LightingModel, the default (a scene without a model) first.
MODELS: dict = {m.name: m for m in _TABLE}
#: The models' names, the default first.
NAMES: tuple = tuple(MODELS)
DEFAULT: str = NAMES[0]


def get(name) -> LightingModel:
    """The model *name*; the default one for anything else (a file's unknown value)."""
    return MODELS.get(name, MODELS[DEFAULT]) if isinstance(name, str) else MODELS[DEFAULT]


def check(table=None) -> list:
    """What is wrong with *table* (default ``MODELS``): every light type has a group, every
    composition is known; a list of messages (empty: nothing)."""
    problems = []
    for name, model in (MODELS if table is None else table).items():
        if name != model.name:
            problems.append(f"{name}: entry named {model.name!r}")
        if set(model.light_groups) != set(EVERY):
            problems.append(f"{name}: light groups for {sorted(model.light_groups)}")
        if model.composition not in COMPOSITIONS:
            problems.append(f"{name}: unknown composition {model.composition!r}")
    return problems


__all__ = ["COMPOSITIONS", "EVERY", "NEAR", "RENDERED", "POWER_TO_INTENSITY", "AREA_HALF_ANGLE",
           "AREA_EDGE_EXPONENT", "drawn_as", "LightingModel", "MODELS", "NAMES", "DEFAULT",
           "get", "check"]
