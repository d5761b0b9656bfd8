# SPDX-License-Identifier: GPL-3.0-or-later
"""FBX's Phong mapping, both directions, pure: the project's Phong values of a light, a
material and the scene ambient to the FBX data model (``model``: what ``write`` splices into
a file) and back (what ``read`` gives, as the importer applies it).

Lights (the export, :func:`light_of`; the import, :func:`light_settings`):

    LightType       POINT, SUN, SPOT (an Area light: the spot that draws it, a 180° cone)
    Intensity       100 × i0 (÷ c where the falloff is one term c·r^k)
    DecayType       k of 1/d^k: a single term c·r^k of i0/(αr²+βr+γ) exactly; a mixed one
                    as its highest term; the power falloff's k rounded into 0-3
    OuterAngle      the spot size (full cone, degrees)
    InnerAngle      the lighting model's rule (``LightingModel.fbx_inner_angle``; read back as
                    the seeds' edge exponent, :func:`spot_edge_exponent`, and three.js's
                    penumbra 1 − Inner / Outer)
    CastShadows     Cast Shadow

What the written values do not give back is kept as user properties (``PhongNodes|key``).
Materials (:func:`material_of`, :func:`material_values`): DiffuseColor = Object Color,
AmbientColor = Ambient Object Color, SpecularColor = Specular Color, EmissiveColor =
Irradiant Color, ShininessExponent = Exponent, Opacity; a Lambert where the specular colour is
black and unmapped; Blinn, Specular Strength and a Lambert's exponent as user properties.  The
World's Phong ambient (:func:`ambient_of`, :func:`world_ambient`): AmbientColor = intensity ×
colour, the intensity and colour kept as user properties where the intensity is not 1.

No ``bpy``: the exporter reads Blender and calls these; the tests run them on numbers.
"""

from __future__ import annotations

import math

from ...node_groups import models
from .model import SURFACE_DEFAULTS, Light, Material

#: FbxLight::EType of the light types written (an Area light is written as a spot).
WRITTEN_TYPES = {"POINT": 0, "SUN": 1, "SPOT": 2}
#: Blender's light types an export writes: every type that lights Phong materials.
EXPORTED = models.RENDERED
#: The Phong settings a light's user property may give back: every setting some model reads.
SETTINGS = tuple(dict.fromkeys(row[0] for model in models.MODELS.values()
                               for row in model.settings if row[0] != "falloff"))


def _close(a, b) -> bool:
    return abs(a - b) <= 1e-6 * max(1.0, abs(a), abs(b))


# -- lights: FBX -> Phong ------------------------------------------------------------------------

def spot_edge_exponent(outer_deg: float, inner_deg: float) -> float:
    """The seeds' soft edge exponent e_att for an FBX spot (full angles in degrees): 0 (hard
    edge) when InnerAngle ≥ OuterAngle, else the e for which (cos ω)^e = 1/2 halfway between
    the inner and the outer half-angles (the FBX spot fades from the inner to the outer cone);
    capped at 100 (the control's range)."""
    if outer_deg <= 0.0 or inner_deg >= outer_deg:
        return 0.0
    middle = math.radians((max(inner_deg, 0.0) + outer_deg) / 4.0)
    cos = math.cos(min(middle, math.radians(89.9)))
    return min(math.log(0.5) / math.log(cos), 100.0) if cos < 1.0 else 100.0


def falloff(k: int) -> dict:
    """Phong light settings of the decay 1/d^k: k = 0, 1, 2 as i₀/(αr² + βr + γ), others
    as the power falloff (``falloff`` "POWER", ``power_k``)."""
    if k == 0:
        return {"quadratic": 0.0, "linear": 0.0, "constant": 1.0}
    if k == 1:
        return {"quadratic": 0.0, "linear": 1.0, "constant": 0.0}
    if k == 2:
        return {"quadratic": 1.0, "linear": 0.0, "constant": 0.0}
    return {"quadratic": 1.0, "linear": 0.0, "constant": 0.0, "falloff": "POWER",
            "power_k": float(k)}


def light_settings(light: Light) -> dict:
    """What the FBX *light* gives a Blender light: {"type", "color", "cast_shadows",
    "spot_size" (radians) and "spot_blend" (a spot's), "settings": the Phong settings (i0,
    the falloff, a spot's edge exponent and penumbra; then what the user properties kept)}."""
    settings = {"intensity": light.intensity}
    out = {"type": light.type, "color": tuple(light.color),
           "cast_shadows": bool(light.cast_shadows), "settings": settings}
    if light.type != "SUN":
        settings.update(falloff(light.decay))
        settings.setdefault("falloff", "QUADRATIC")
    if light.type == "SPOT":
        out["spot_size"] = math.radians(min(max(light.outer_angle, 1.0), 180.0))
        share = 1.0 - light.inner_angle / light.outer_angle if light.outer_angle > 0 else 0.0
        out["spot_blend"] = min(max(share, 0.0), 1.0)
        settings["edge_exponent"] = spot_edge_exponent(light.outer_angle, light.inner_angle)
        settings["penumbra"] = min(max(share, 0.0), 1.0)
    for key, value in light.user.items():   # what Phong Nodes' export kept
        if key == "falloff_power":
            settings["falloff"] = "POWER" if value else "QUADRATIC"
        elif key in SETTINGS:
            settings[key] = value
    return out


# -- lights: Phong -> FBX ------------------------------------------------------------------------

def light_of(light_type: str, color, settings: dict, falloff_kind: str, spot_size: float,
             cast_shadows: bool, model, defaults: dict, name: str = "") -> tuple:
    """(the FBX :class:`Light`, warnings) of a Blender light of *light_type* (POINT, SUN, SPOT,
    AREA: drawn as its spot) with its *color*, Phong *settings* ({setting: value}), falloff
    ("QUADRATIC" or "POWER"), *spot_size* (radians, full cone) and Cast Shadow, in the
    lighting *model* (``models.LightingModel``); *defaults*: every setting's default, what a
    light takes that the file does not give.  The settings that the written values do not
    give back (:func:`light_settings`) are kept as user properties."""
    warnings = []
    kind = models.drawn_as(light_type)
    out = Light(type=kind, color=tuple(color), intensity=settings["intensity"], decay=0,
                cast_shadows=bool(cast_shadows))
    power = False
    if kind != "SUN":
        if falloff_kind == "POWER":
            power = True
            k = settings["power_k"]
            out.decay = int(min(max(round(k), 0), 3))
            if k != out.decay:
                warnings.append(f"light {name}: power falloff k = {k:g} written as the nearest "
                                f"FBX DecayType (1/d^{out.decay})")
        else:
            terms = [(2, settings["quadratic"]), (1, settings["linear"]),
                     (0, settings["constant"])]
            used = [(k, c) for k, c in terms if c != 0.0]
            if not used:
                warnings.append(f"light {name}: falloff 1/0 (every coefficient 0) written "
                                "without decay")
            else:
                out.decay, c = used[0]
                out.intensity = settings["intensity"] / c
                if len(used) > 1:
                    warnings.append(f"light {name}: mixed falloff i0/(αr²+βr+γ) written as "
                                    f"its highest term, FBX DecayType 1/d^{out.decay}")
    if kind == "SPOT":
        out.outer_angle = math.degrees(spot_size)
        inner = model.fbx_inner_angle(settings, out.outer_angle)
        out.inner_angle = min(max(inner, 0.0), out.outer_angle)
    # what the importer derives from the written values
    derived = dict(defaults)
    read = light_settings(out)["settings"]
    if (read.get("falloff") == "POWER") != power:
        out.user["falloff_power"] = 1.0 if power else 0.0
    derived.update({k: v for k, v in read.items() if k in derived})
    for attr, value in settings.items():
        if attr in derived and not _close(value, derived[attr]):
            out.user[attr] = value
    if out.user:
        warnings.append(f"light {name}: Phong settings kept as FBX user properties: "
                        + ", ".join("PhongNodes|" + k for k in sorted(out.user)))
    return out, warnings


# -- materials -----------------------------------------------------------------------------------

#: The Phong values of a material that FBX's colours hold: lights-group input, by slot.
COLOURS = ("Object Color", "Ambient Object Color", "Specular Color", "Irradiant Color")


def material_of(values: dict, maps: dict | None = None, name: str = "") -> Material:
    """The FBX Phong (or Lambert: a black Specular Color without a map) :class:`Material` of
    the Phong *values* ({lights-group input: value}: the four colours, "Exponent",
    "Opacity"); *maps*: the :class:`Texture` on each input (:data:`model.PROPERTY_OF`'s
    keys).  :func:`keep_unsaid` adds what FBX cannot say."""
    maps = dict(maps or {})
    specular = tuple(values["Specular Color"])
    lambert = all(c == 0.0 for c in specular) and "Specular Color" not in maps
    return Material(name=name, kind="LAMBERT" if lambert else "PHONG",
                    colors={slot: tuple(values[slot]) for slot in COLOURS},
                    exponent=max(float(values["Exponent"]), 0.0),
                    opacity=min(max(float(values["Opacity"]), 0.0), 1.0), textures=maps)


def keep_unsaid(out: Material, blinn: float, strength: float | None) -> list:
    """*out*'s user properties for what FBX's Phong cannot say: the *blinn* share (0: Phong's
    highlight), the Specular *strength* (None: the model has none; 1: nothing), a Lambert's
    own exponent; their names (for one warning)."""
    if blinn != 0.0:
        out.user["Blinn"] = blinn
    if strength is not None and strength != 1.0:
        out.user["SpecularStrength"] = strength
    if out.lambert and out.exponent != SURFACE_DEFAULTS["ShininessExponent"]:
        out.user["Exponent"] = out.exponent
    return sorted(out.user)


def material_values(material: Material) -> dict:
    """The Phong values of a read FBX *material*: its colours by the lights group's input,
    "Exponent", "Opacity", "Blinn" (the user property, else 1 for a Blinn shading model) and
    "Specular Strength" where the file keeps one."""
    out = {slot: tuple(material.colors[slot]) for slot in COLOURS}
    out["Exponent"] = material.exponent
    out["Opacity"] = material.opacity
    out["Blinn"] = material.user.get("Blinn", 1.0 if material.blinn else 0.0)
    if "SpecularStrength" in material.user:
        out["Specular Strength"] = material.user["SpecularStrength"]
    return out


# -- the scene's ambient -------------------------------------------------------------------------

def ambient_of(intensity: float, color) -> tuple:
    """(GlobalSettings' AmbientColor, its user properties) of the World's Phong ambient
    *intensity* × *color*: the two kept apart where the intensity is not 1."""
    color = tuple(float(c) for c in tuple(color)[:3])
    user = {}
    if intensity != 1.0:
        user = {"AmbientIntensity": intensity, "AmbientR": color[0], "AmbientG": color[1],
                "AmbientB": color[2]}
    return tuple(intensity * c for c in color), user


def world_ambient(ambient, user: dict) -> tuple:
    """(intensity, colour) of the World's Phong ambient from a file's AmbientColor and
    GlobalSettings' user properties (the intensity and colour Phong Nodes' export kept)."""
    if "AmbientIntensity" in user and all(f"Ambient{c}" in user for c in "RGB"):
        return user["AmbientIntensity"], tuple(user[f"Ambient{c}"] for c in "RGB")
    return 1.0, tuple(ambient)
