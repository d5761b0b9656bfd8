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
  Falloff's Exponent, diffuse and specular the light's terms' strengths)), in the light
  panel's order (``properties.model_settings``);
* ``composition``: how the lights group sums the light groups' parts into the material's
  colour, one of ``COMPOSITIONS``; the lights group (``rig.py``) and the Per Vertex / Per Face
  expression (``shading_modes.py``) each hold one builder per composition, so a model that
  composes as an existing one is this table's entry and its light groups;
* ``loop``: its group in Eevee's light loop on Blender 5.3+ (``library.LOOP_MODELS``; None: the
  model's Eevee side is its lights group, as before 5.3);
* ``native``: the interchange formats whose own lighting equation the model is ("x3d",
  "threejs"): a scene in another model is written mapped, with one warning;
* ``rig``, ``rig_material``, ``ambient``: the groups its lights group is built of, one a light
  (``library.rig_light_group``), the material's colours and the World's ambient.

Each entry is an object of its model's class, which answers what the model means outside
Blender (no exporter or comparison asks for a model by name): its scene files' schema
(:attr:`LightingModel.scene_schema`, read by ``core/scenes.py``), its reference
(:meth:`LightingModel.reference_ambient`, :meth:`~LightingModel.reference_light`: the
formulas of ``reference.py`` with its settings) and its mappings to the formats' values
(:meth:`~LightingModel.x3d_light`, :meth:`~LightingModel.fbx_inner_angle`,
:meth:`~LightingModel.threejs_light`), read by ``core/x3d/phong.py``, ``core/fbx/phong.py``,
``core/threejs.py`` and ``core/compare.py``.  A new model is one entry of its class.

No ``bpy`` here.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from . import reference as ref

#: How a lights group composes the material's colour (docs/contract.md, "Several lights").
COMPOSITIONS = {
    "phong": "per light one group of its type, falloff and shadow ray (its diffuse and "
             "specular light added to the sums; i0/d^k where the light's falloff is POWER); "
             "Σ diffuse ⊗ Object Color + Σ specular ⊗ Specular "
             "Color + the World's Phong Ambient + the irradiant, min(…, 1)",
    "chain": "three.js: the ambient (three.js Ambient) ⊕ the emissive ⊕ each light's three.js "
             "Phong, as one sum clamped once (per light one group: its irradiance and its "
             "highlight's sums, times the material's colours once)",
    "phong_light_ambient": "as phong, with X3D's lights, and each light's own ambient "
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
    #: the interchange formats whose own lighting equation this model is ("x3d", "threejs")
    native: tuple = ()
    #: the first words of the lights group's light groups, one a light (``library``:
    #: "<rig> Point", "<rig> Spot (i0/d^k) with Shadow", …)
    rig: str = "Phong Rig"
    #: the lights group's group that multiplies its lights' sums by the material's colours
    #: (None: the diffuse sum times the Object Color, the specular sum times the Specular
    #: Color)
    rig_material: str | None = None
    #: the World's ambient light: its group and the input the Ambient Object Color feeds
    ambient: tuple = ("Phong Ambient", "Object Color")
    #: whether its light groups blend Phong's and Blinn-Phong's highlights by the material's
    #: Blinn; they then have a variant with each highlight alone (``library.HIGHLIGHTS``)
    blinn: bool = False

    @property
    def power_falloff(self) -> bool:
        """Whether the model reads a light's falloff (Quadratic or Power i0/d^k)."""
        return any(row[0] == "falloff" for row in self.settings)

    @property
    def scene_schema(self) -> str:
        """The scene files' schema its lights and materials are read with (``core/scenes.py``'s
        readers of that name): its class's."""
        return self.name

    # -- what the model means outside Blender: each model's class says it -----------------
    # *settings* is a light's {setting: value} (every model's settings, as
    # ``addon/lighting/properties.settings_of`` reads them); *light* a light of a scene as
    # plain data ("type" point / directional / spot, "position", "direction", "half_angle" in
    # degrees and the settings); *P* (N, 3) points.

    def reference_ambient(self, intensity, color, object_color):
        """The scene's ambient term (the World's Phong ambient) on *object_color*."""
        return ref.ambient(intensity, color, object_color)["Color"]

    def reference_light(self, light, P, width):
        """(ℓ, intensity, ambient intensity or None, ambiguous) of *light* at the points *P*
        in this model; ambiguous: within *width* of a discontinuity of its light."""
        raise NotImplementedError(f"{self.name}: no reference light")

    def reference_terms(self, light, ell, intensity, ambient, edge, on, seen, px, width):
        """(diffuse, specular, ambient light (or None), ambiguous) of *light*'s light at the
        pixels *px* (``core.compare``'s probes: color, spec_color, ambient_color, exponent,
        blinn, strength, normal, view, N, I, n, v), from :meth:`reference_light`'s ℓ,
        intensity, ambient intensity and edge; *on*: the pixels it reaches, *seen*: its
        visibility there (0 in shadow); ambiguous: pixels within *width* of a discontinuity.
        """
        raise NotImplementedError(f"{self.name}: no reference terms")

    def x3d_light(self, settings, falloff, kind, cut) -> tuple:
        """({"attenuation": (a0, a1, a2), "radius": metres or None (none), "beam_width":
        radians} of a light of *kind* ("point", "spot"; *cut*: a spot's cut-off angle), notes:
        what X3D cannot say, each a sentence after "light NAME: ")."""
        raise NotImplementedError(f"{self.name}: no X3D mapping")

    def fbx_inner_angle(self, settings, outer) -> float:
        """The FBX InnerAngle (degrees, full cone) of a spot whose OuterAngle is *outer*."""
        raise NotImplementedError(f"{self.name}: no FBX mapping")

    def threejs_light(self, settings) -> dict:
        """The three.js page's distance, decay and (a spot's) penumbra of a light, of those
        *settings* holds: the light's own three.js settings (the page shows three.js's model
        whatever the scene's)."""
        return {key: float(settings[key]) for key in ("distance", "decay", "penumbra")
                if key in settings}


def _hard_edge(cos_angle, theta, width):
    """Where a hard cone's edge makes a point's light ambiguous."""
    return np.abs(cos_angle - math.cos(theta)) < width


class Seeds(LightingModel):
    """The seeds' textbook model: i0/(αr²+βr+γ) or i0/d^k, a cone with a cos^e edge, diffuse
    and specular factors per light."""

    @property
    def scene_schema(self) -> str:
        return "seeds"

    def reference_light(self, light, P, width):
        kind = light["type"]
        if kind == "directional":
            out = ref.directional_light(light["direction"], light["intensity"],
                                        geometry_position=P)
            return out["Light Vector"], out["Intensity"], None, np.zeros(len(P), bool)
        # the power falloff i0/d^k (docs/model.md §Power falloff): no quadratic falloff, then
        # the power's
        power = light.get("falloff", "quadratic") == "power"
        quadratic = (0.0, 0.0, 1.0) if power else (light["quadratic"], light["linear"],
                                                   light["constant"])
        if kind == "point":
            out = ref.point_light(light["position"], light["intensity"], *quadratic,
                                  geometry_position=P)
            edge = np.zeros(len(P), bool)
        else:
            theta = math.radians(light["half_angle"])
            out = ref.spot_light(light["position"], light["direction"], theta,
                                 light["edge_exponent"], light["intensity"], *quadratic,
                                 geometry_position=P)
            edge = _hard_edge(out["Cos Angle"], theta, width)
        intensity = (ref.power_falloff(out["Distance"], out["Intensity"],
                                       light.get("power_k", 2.0))["Intensity"]
                     if power else out["Intensity"])
        return out["Light Vector"], intensity, None, edge

    def reference_terms(self, light, ell, intensity, ambient, edge, on, seen, px, width):
        dif = np.where(on, light["diffuse"], 0.0)
        spe = np.where(on, light["specular"], 0.0)
        ambiguous = edge & (dif + spe > 0)
        ambiguous |= (np.abs(ref.dot(ell, px["n"])) < width) & (spe > 0)
        out = ref.phong_shading(
            light_vector=ell, light_intensity=intensity * seen, light_color=light["color"],
            object_color=px["color"], irradiant_color=(0.0, 0.0, 0.0), ambient_intensity=0.0,
            diffuse_strength=dif, specular_strength=spe, specular_color=px["spec_color"],
            exponent=px["exponent"], blinn=px["blinn"], normal=px["normal"],
            view_vector=px["view"], geometry_normal=px["N"], incoming=px["I"])
        return out["Diffuse"], out["Specular"], None, ambiguous

    def x3d_light(self, settings, falloff, kind, cut) -> tuple:
        notes = []
        out = {"attenuation": (settings["constant"], settings["linear"], settings["quadratic"]),
               "radius": None, "beam_width": cut}
        if kind != "directional" and falloff == "POWER":
            k = settings["power_k"]
            terms = {0.0: (1.0, 0.0, 0.0), 1.0: (0.0, 1.0, 0.0), 2.0: (0.0, 0.0, 1.0)}
            if k not in terms:
                notes.append(f"falloff 1/d^{k:g} has no X3D counterpart; written as 1/d²")
            out["attenuation"] = terms.get(k, (0.0, 0.0, 1.0))
        if kind == "spot" and settings["edge_exponent"] > 0.0:
            notes.append("the soft edge (Edge Exponent) written as a hard cone")
        if (settings["diffuse"], settings["specular"]) != (1.0, 1.0):
            notes.append("Diffuse / Specular factors have no X3D counterpart; written as 1")
        return out, notes

    def fbx_inner_angle(self, settings, outer) -> float:
        # (cos ω)^e = ½ at ω = (Inner + Outer) / 4: the inverse of the importer's rule
        # (core/fbx/phong.spot_edge_exponent)
        e = settings["edge_exponent"]
        return outer if e <= 0.0 else 4.0 * math.degrees(math.acos(0.5 ** (1.0 / e))) - outer


class ThreeJS(LightingModel):
    """three.js r181's MeshPhongMaterial: distance/decay lights, a smoothstep penumbra,
    Lambert/π and normalised Blinn-Phong with Fresnel."""

    @property
    def scene_schema(self) -> str:
        return "threejs"

    def reference_ambient(self, intensity, color, object_color):
        return ref.threejs_ambient(intensity, color, object_color)["Color"]

    def reference_light(self, light, P, width):
        kind = light["type"]
        if kind == "directional":  # the seeds' directional light
            out = ref.directional_light(light["direction"], light["intensity"],
                                        geometry_position=P)
            return out["Light Vector"], out["Intensity"], None, np.zeros(len(P), bool)
        if kind == "point":
            out = ref.threejs_point_light(light["position"], light["intensity"],
                                          light["distance"], light["decay"],
                                          geometry_position=P)
            return out["Light Vector"], out["Intensity"], None, np.zeros(len(P), bool)
        theta = math.radians(light["half_angle"])
        out = ref.threejs_spot_light(light["position"], light["direction"], theta,
                                     light["penumbra"], light["intensity"], light["distance"],
                                     light["decay"], geometry_position=P)
        edge = _hard_edge(out["Cos Angle"], theta, width) & (light["penumbra"] == 0)
        return out["Light Vector"], out["Intensity"], None, edge

    def reference_terms(self, light, ell, intensity, ambient, edge, on, seen, px, width):
        out = ref.threejs_phong(ell, np.where(on, intensity, 0.0) * seen, light["color"],
                                px["color"], px["spec_color"], px["exponent"], px["strength"],
                                px["normal"], px["view"], px["N"], px["I"])
        return out["Diffuse"], out["Specular"], None, edge & on

    def x3d_light(self, settings, falloff, kind, cut) -> tuple:
        penumbra = settings["penumbra"]
        return {"attenuation": (settings["constant"], settings["linear"],
                                settings["quadratic"]),
                "radius": None,
                "beam_width": cut * (1.0 - penumbra) if penumbra > 0.0 else cut}, []

    def fbx_inner_angle(self, settings, outer) -> float:
        return outer * (1.0 - settings["penumbra"])


class X3D(LightingModel):
    """The ISO lighting equation of X3D and VRML97 (docs/x3d.md)."""

    @property
    def scene_schema(self) -> str:
        return "x3d"

    def reference_light(self, light, P, width):
        kind = light["type"]
        if kind == "directional":
            out = ref.x3d_directional_light(light["direction"], light["intensity"],
                                            light.get("ambient", 0.0), geometry_position=P)
            return (out["Light Vector"], out["Intensity"], out["Ambient"],
                    np.zeros(len(P), bool))
        falloff = (light.get("ambient", 0.0), light["constant"], light["linear"],
                   light["quadratic"], light.get("radius", 100.0))
        if kind == "point":
            out = ref.x3d_point_light(light["position"], light["intensity"], *falloff,
                                      geometry_position=P)
            edge = np.zeros(len(P), bool)
        else:   # a hard edge where beamWidth ≥ cutOffAngle
            cut = math.radians(light["half_angle"])
            beam = light.get("beam_width", cut)
            out = ref.x3d_spot_light(light["position"], light["direction"], beam, cut,
                                     light["intensity"], *falloff, geometry_position=P)
            edge = (np.abs(out["Spot Angle"] - cut) < width) & (beam >= cut)
        edge |= np.abs(out["Distance"] - falloff[-1]) < width   # the radius
        return out["Light Vector"], out["Intensity"], out["Ambient"], edge

    def reference_terms(self, light, ell, intensity, ambient, edge, on, seen, px, width):
        # per-light ambient, Blinn highlights without the N·L condition
        out = ref.x3d_light_terms(ell, np.where(on, intensity, 0.0) * seen,
                                  np.where(on, ambient, 0.0), light["color"], px["exponent"],
                                  px["n"], px["v"])
        return (out["Diffuse Light"] * px["color"], out["Specular Light"] * px["spec_color"],
                out["Ambient Light"] * px["ambient_color"], edge & on)

    def x3d_light(self, settings, falloff, kind, cut) -> tuple:
        return {"attenuation": (settings["constant"], settings["linear"],
                                settings["quadratic"]),
                "radius": settings["radius"], "beam_width": settings["beam_width"]}, []

    def fbx_inner_angle(self, settings, outer) -> float:
        return 2.0 * math.degrees(settings["beam_width"])


_TABLE = (
    Seeds(
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
        area=(("edge_exponent", AREA_EDGE_EXPONENT),), blinn=True),
    ThreeJS(
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
        area=(("penumbra", 0.0),), native=("threejs",), rig="three.js Rig",
        rig_material="three.js Rig Material", ambient=("three.js Ambient", "Diffuse Color")),
    X3D(
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
        loop="X3D Loop Light", area=(("beam_width", AREA_HALF_ANGLE),), native=("x3d",),
        rig="X3D Rig"),
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
           "AREA_EDGE_EXPONENT", "drawn_as", "LightingModel", "Seeds", "ThreeJS", "X3D",
           "MODELS", "NAMES", "DEFAULT", "get", "check"]
