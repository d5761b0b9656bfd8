# SPDX-License-Identifier: GPL-3.0-or-later
"""Per-light and per-world Phong settings.

The values are stored as plain ID custom properties (``light["phong_intensity"]``,
``world["phong_ambient_color"]`` ...), not inside an add-on PropertyGroup: the drivers of
Phong materials read those custom properties, and custom properties survive in a .blend
opened without the extension.  ``light.phong`` and ``world.phong`` are thin PropertyGroups
whose getters/setters forward to the custom properties, so the panels and scripts get
named, typed, range-checked properties with the documented defaults.  Their getters and
setters live in ``forwarding``, a module that holds no ``bpy`` (see there why).
"""

import math
import struct

import bpy
from bpy.props import BoolProperty, FloatProperty, FloatVectorProperty, PointerProperty

from ...node_groups import library, models
from ...node_groups.library import FALLOFF_DEFAULTS, X3D_BEAM_WIDTH, X3D_RADIUS
from .. import compat
from . import forwarding

#: (attribute, custom property key, label, default, min, soft max, description)
LIGHT_SETTINGS = (
    ("intensity", "phong_intensity", "Phong Intensity", 1.0, 0.0, 100.0,
     "Phong intensity i0 of the light (dimensionless), used when the light does not take "
     "its i0 from its Power"),
    ("quadratic", "phong_quadratic", "Quadratic", FALLOFF_DEFAULTS["quadratic"], 0.0, 10.0,
     "α in i0/(αr²+βr+γ): 1 gives the physical i0/r² (Point and Spot)"),
    ("linear", "phong_linear", "Linear", FALLOFF_DEFAULTS["linear"], 0.0, 10.0,
     "β in i0/(αr²+βr+γ) (Point and Spot)"),
    ("constant", "phong_constant", "Constant", FALLOFF_DEFAULTS["constant"], 0.0, 10.0,
     "γ in i0/(αr²+βr+γ) (Point and Spot)"),
    ("edge_exponent", "phong_edge_exponent", "Edge Exponent", 0.0, 0.0, 100.0,
     "Spot edge exponent e_att: 0 gives a hard cone edge, higher values a softer one"),
    ("diffuse", "phong_diffuse", "Diffuse", 1.0, 0.0, 10.0,
     "Diffuse factor i_source,diff / i_source (seed 000 §3.5)"),
    ("specular", "phong_specular", "Specular", 1.0, 0.0, 10.0,
     "Specular factor i_source,spec / i_source (seed 000 §3.5)"),
    # the three.js model (docs/threejs.md); intensity is shared
    ("distance", "phong_distance", "Distance", 0.0, 0.0, 1000.0,
     "three.js distance: the light fades smoothly to 0 there; 0 = no cut-off (Point and Spot)"),
    ("decay", "phong_decay", "Decay", 2.0, 0.0, 4.0,
     "three.js decay: intensity/d^decay, 2 physical (Point and Spot)"),
    ("penumbra", "phong_penumbra", "Penumbra", 0.0, 0.0, 1.0,
     "three.js penumbra: the share of the cone's angle that fades out (Spot)"),
    ("power_k", "phong_power_k", "Power k", 2.0, 0.0, 4.0,
     "k in i0/d^k when the falloff is Power: 2 physical, 1 softer, 0 none (Point and Spot)"),
    # the X3D / VRML97 model (docs/x3d.md); intensity and the three falloffs are shared
    ("ambient", "phong_light_ambient", "Ambient", 0.0, 0.0, 1.0,
     "X3D ambientIntensity: the light's own ambient light, attenuated and spotted like its "
     "direct light"),
    ("radius", "phong_radius", "Radius", X3D_RADIUS, 0.0, 1000.0,
     "X3D radius: the light reaches only the points within this distance (Point and Spot)"),
    ("beam_width", "phong_beam_width", "Beam Width", X3D_BEAM_WIDTH, 0.0, 3.14159265,
     "X3D beamWidth: full intensity within this angle of the axis, fading linearly to 0 at "
     "the cut-off angle (half the Spot Size) (Spot)"),
)
#: Whether a light takes its i0 from Blender's Power (1) or from its Phong Intensity (0): an
#: int custom property that the lights group's driver reads, so flipping it is live.  A light
#: without it reads as 1 unless it has a Phong Intensity of its own (a file of an earlier
#: version, an imported light, the seeds' scenes: ``write_light`` sets 0).
FROM_POWER_KEY = "phong_intensity_from_power"
#: Settings shown as angles (radians inside, degrees in the panel).
ANGLE_SETTINGS = ("beam_width",)
#: The seeds' distance falloff of a Point or Spot light: ``light["phong_falloff"]`` (a
#: string; missing means QUADRATIC).  It chooses the nodes of the light in its lights group,
#: so a change relinks the scene (``lights.signature`` holds it), as a change of light type.
FALLOFF_KEY = "phong_falloff"
FALLOFF_ITEMS = (
    ("QUADRATIC", "Quadratic", "i0/(αr²+βr+γ) (Quadratic, Linear, Constant)"),
    ("POWER", "Power", "i0/d^k (Power k): k = 2 physical, 1 softer, 0 no attenuation"),
)
FALLOFFS = tuple(item[0] for item in FALLOFF_ITEMS)


def falloff_of(light) -> str:
    """The falloff of *light* ("QUADRATIC" or "POWER"; anything else reads as QUADRATIC)."""
    value = light.get(FALLOFF_KEY, FALLOFFS[0])
    value = value.upper() if isinstance(value, str) else value
    return value if value in FALLOFFS else FALLOFFS[0]


# What each lighting model reads of a light is its ``settings`` in ``node_groups/models.py``
# ((setting, light types, falloff or None, light-group input or None)): the light panel shows
# these in this order, the rig drives the light groups' inputs from it, the description hands
# them to the reference.


def model_settings(model: str, light) -> list:
    """(setting, light-group input or None) of what *model* reads of *light*, by its type and
    falloff, in the panel's order.  An Area light reads what a spot reads but the spot
    settings that the model's ``area`` fixes."""
    kind = models.drawn_as(light.type)
    falloff = falloff_of(light) if kind in models.NEAR else None
    spec = models.MODELS[model]
    fixed = dict(spec.area) if light.type == "AREA" else {}
    return [(attr, target) for attr, types, when, target in spec.settings
            if kind in types and when in (None, falloff) and attr not in fixed]


def read_settings(light_type: str) -> set:
    """Every setting some model reads of a light of *light_type* (its falloff aside; an Area
    light reads what a spot reads)."""
    light_type = models.drawn_as(light_type)
    return {attr for model in models.MODELS.values() for attr, types, _when, _target
            in model.settings if light_type in types and attr != "falloff"}


# -- the one reader of a light's values ------------------------------------------------------

def from_power(light) -> bool:
    """Whether *light* takes its i0 from its Power (``FROM_POWER_KEY``; unset: unless it has
    a Phong Intensity of its own)."""
    return forwarding.flag(light, FROM_POWER_KEY, LIGHT_KEYS["intensity"][0])


def emitting_area(light) -> float:
    """The area of an Area light's shape in square metres (1 for any other light)."""
    if light.type != "AREA":
        return 1.0
    size = float(light.size)
    size_y = float(light.size_y) if light.shape in ("RECTANGLE", "ELLIPSE") else size
    return size * size_y * (math.pi / 4.0 if light.shape in ("DISK", "ELLIPSE") else 1.0)


def node_factor(light) -> float:
    """What *light*'s own node tree (Use Nodes) makes of its Power: 0 where its active Light
    Output has no surface (Cycles then gives no light), an Emission's Strength where one
    feeds it, else 1."""
    tree = light.node_tree if getattr(light, "use_nodes", False) else None
    if tree is None:
        return 1.0
    output = next((n for n in tree.nodes if n.bl_idname == "ShaderNodeOutputLight"
                   and n.is_active_output), None)
    if output is None:
        return 1.0
    surface = output.inputs.get("Surface")
    if surface is None or not surface.is_linked:
        return 0.0
    node = surface.links[0].from_node
    strength = node.inputs.get("Strength") if node.bl_idname == "ShaderNodeEmission" else None
    if strength is not None and not strength.is_linked:
        return max(0.0, float(strength.default_value))
    return 1.0


def power_scale(light) -> float:
    """i0 per unit of *light*'s Power (``models.POWER_TO_INTENSITY``; an Area light whose
    Normalize is off emits its Power per square metre; times ``node_factor``); 0 for a light
    type without one."""
    scale = models.POWER_TO_INTENSITY.get(light.type, 0.0)
    if light.type == "AREA" and not getattr(light, "normalize", True):
        scale *= emitting_area(light)
    return scale * node_factor(light)


def power_intensity(light) -> float:
    """The i0 that *light*'s Power gives (Blender's Exposure included)."""
    return float(light.energy) * 2.0 ** float(getattr(light, "exposure", 0.0)) * power_scale(light)


def intensity(light) -> float:
    """*light*'s i0: from its Power, or its Phong Intensity (``from_power``)."""
    if from_power(light):
        return power_intensity(light)
    key, default = LIGHT_KEYS["intensity"]
    return float(light.get(key, default))


def light_color(light) -> tuple:
    """The colour *light* emits: its Color, times its Temperature's where it uses one."""
    color = tuple(float(c) for c in light.color)
    if getattr(light, "use_temperature", False):
        color = tuple(c * float(t) for c, t in zip(color, light.temperature_color))
    return color


def settings_of(light) -> dict:
    """{setting of ``LIGHT_SETTINGS``: value} of *light* as it lights Phong materials: i0 as
    ``intensity`` says, and for an Area light the spot settings of every model's ``area``."""
    values = {attr: float(light.get(key, default)) for attr, (key, default) in LIGHT_KEYS.items()}
    values["intensity"] = intensity(light)
    if light.type == "AREA":
        for model in models.MODELS.values():
            values.update(model.area)
    return values


#: Before Blender 5.3 (no Switch node) a three.js or X3D light's group is chosen by its
#: constants (``library.LIGHT_FACTS``): what each fact reads of the light.
FACT_SETTINGS = {"cut-off": ("distance",), "decay 2": ("decay",), "penumbra": ("penumbra",),
                 "ramp": ("beam_width",), "ambient 0": ("ambient",)}
#: A penumbra that leaves the cone's two cosines closer than this (float32, as the light group
#: computes them) may read as none in Blender: such a light keeps the general group.
PENUMBRA_MARGIN = 1.0e-6


def facts_of(light, model: str):
    """{fact: bool} of ``library.LIGHT_FACTS`` that *light* (a Light) holds in *model*, as
    its light group's sockets carry them (float32: a fact holds where the condition of its
    Switch does), or None: the light takes its model's general group (Blender 5.3+, whose
    Switch chooses inside the one group; a model without facts for the light's type; a
    setting the facts read, or the Spot Size, animated or driven; a penumbra too small to
    tell, ``PENUMBRA_MARGIN``)."""
    kind = models.drawn_as(light.type)
    facts = library.light_facts(model, kind)
    if not facts or library.SWITCH_FEATURE in compat.NODE_FEATURES:
        return None
    animated = compat.animated_paths(light)
    keys = {f'["{LIGHT_KEYS[attr][0]}"]' for fact in facts for attr in FACT_SETTINGS[fact]}
    if animated is None or animated & (keys | {"spot_size"}):
        return None
    fixed = dict(models.MODELS[model].area) if light.type == "AREA" else {}
    values = {attr: float(fixed[attr]) if attr in fixed else float(light.get(*LIGHT_KEYS[attr]))
              for fact in facts for attr in FACT_SETTINGS[fact]}
    f32 = _float32
    half = f32(models.AREA_HALF_ANGLE if light.type == "AREA"
               else 0.5 * float(getattr(light, "spot_size", math.pi)))
    out = {}
    for fact in facts:
        if fact == "cut-off":  # less_than(0, distance)
            out[fact] = f32(values["distance"]) > 0.0
        elif fact == "decay 2":  # equal(decay, 2)
            out[fact] = f32(values["decay"]) == 2.0
        elif fact == "ambient 0":  # equal(ambientIntensity, 0)
            out[fact] = f32(values["ambient"]) == 0.0
        elif fact == "ramp":  # less_than(beamWidth, cutOffAngle)
            out[fact] = f32(values["beam_width"]) < half
        elif fact == "penumbra":  # less_than(cos angle, cos(angle·(1 - penumbra)))
            inner = f32(half * f32(1.0 - f32(values["penumbra"])))
            gap = math.cos(inner) - math.cos(half)
            if 0.0 < gap <= PENUMBRA_MARGIN:
                return None
            out[fact] = gap > PENUMBRA_MARGIN
    return out


def _float32(value) -> float:
    """*value* as a float32 socket holds it."""
    return struct.unpack("f", struct.pack("f", float(value)))[0]


def light_values(light) -> dict:
    """Everything the Phong models read of *light* (a Light), as plain values: "type" (the
    type of the light group that draws it, ``models.drawn_as``), "blender_type", "color"
    (``light_color``), "spot_size" (radians; a hemisphere for an Area light), Blender's
    "diffuse_factor", "specular_factor" and "transmission_factor", "falloff" and "settings"
    (``settings_of``)."""
    kind = models.drawn_as(light.type)
    spot_size = (2.0 * models.AREA_HALF_ANGLE if light.type == "AREA"
                 else float(getattr(light, "spot_size", math.pi)))
    return {"type": kind, "blender_type": light.type, "color": light_color(light),
            "spot_size": spot_size,
            "diffuse_factor": getattr(light, "diffuse_factor", 1.0),
            "specular_factor": getattr(light, "specular_factor", 1.0),
            "transmission_factor": getattr(light, "transmission_factor", 1.0),
            "falloff": falloff_of(light), "settings": settings_of(light)}


AMBIENT_INTENSITY = ("phong_ambient_intensity", 0.1)
AMBIENT_COLOR = ("phong_ambient_color", (1.0, 1.0, 1.0))
#: The ambient intensity of a scene without a World: Blender renders no world light there.
NO_WORLD_AMBIENT = 0.0

LIGHT_KEYS = {attr: (key, default) for attr, key, _l, default, *_ in LIGHT_SETTINGS}


def _light_annotations():
    ann = {}
    for attr, key, label, default, vmin, soft_max, desc in LIGHT_SETTINGS:
        angle = {"subtype": "ANGLE"} if attr in ANGLE_SETTINGS else {}
        ann[attr] = FloatProperty(
            name=label, description=desc, default=default, min=vmin, soft_max=soft_max,
            get=forwarding.float_getter(key, default),
            set=forwarding.float_setter(key, (FROM_POWER_KEY, 0) if attr == "intensity" else None),
            **angle)
    ann["falloff"] = bpy.props.EnumProperty(
        name="Falloff", items=FALLOFF_ITEMS,
        description="Distance falloff of a Point or Spot light in the seeds' model (changing "
                    "it relinks the scene's Phong materials)",
        get=forwarding.enum_getter(FALLOFF_KEY, FALLOFFS),
        set=forwarding.string_setter(FALLOFF_KEY, FALLOFFS))
    ann["from_power"] = BoolProperty(
        name="Intensity from Power",
        description="The light's i0 follows its Power (and Exposure) as Blender's own "
                    "light lights a diffuse surface; off: the Phong Intensity below",
        get=forwarding.bool_getter(FROM_POWER_KEY, LIGHT_KEYS["intensity"][0]),
        set=forwarding.int_setter(FROM_POWER_KEY))
    return ann


PhongLightSettings = type("PhongLightSettings", (bpy.types.PropertyGroup,), {
    "__doc__": "Phong settings of a light (stored as custom properties of the light data)",
    "__annotations__": _light_annotations(),
})


class PhongWorldSettings(bpy.types.PropertyGroup):
    """Phong ambient light of a world (stored as custom properties of the world)"""

    ambient_intensity: FloatProperty(
        name="Ambient Intensity", description="Intensity of the Phong ambient light (seed 000 §3.3)",
        default=AMBIENT_INTENSITY[1], min=0.0, soft_max=1.0,
        get=forwarding.float_getter(*AMBIENT_INTENSITY),
        set=forwarding.float_setter(AMBIENT_INTENSITY[0]))
    ambient_color: FloatVectorProperty(
        name="Ambient Color", description="Colour of the Phong ambient light", subtype="COLOR",
        size=3, default=AMBIENT_COLOR[1], min=0.0, soft_max=1.0,
        get=forwarding.color_getter(*AMBIENT_COLOR), set=forwarding.color_setter(AMBIENT_COLOR[0]))


#: (identifier, label, description) of the lighting models (``node_groups/models.py``);
#: identifiers are the values of ``scene["phong_model"]`` and of the scene files' ``model``.
MODEL_ITEMS = tuple((m.name, m.label, m.description) for m in models.MODELS.values())
MODEL_KEY = "phong_model"


def model_of(scene) -> str:
    """The lighting model of *scene*: a name of ``models.MODELS`` (default the seeds')."""
    model = scene.get(MODEL_KEY, models.DEFAULT) if scene is not None else models.DEFAULT
    return model if model in models.MODELS else models.DEFAULT


_MODEL_NAMES = tuple(item[0] for item in MODEL_ITEMS)


class PhongSceneSettings(bpy.types.PropertyGroup):
    """Phong settings of a scene (stored as custom properties of the scene)"""

    model: bpy.props.EnumProperty(
        name="Lighting Model", items=MODEL_ITEMS,
        get=forwarding.enum_getter(MODEL_KEY, _MODEL_NAMES),
        set=forwarding.model_setter(MODEL_KEY, _MODEL_NAMES),
        description="The lighting model of the scene's Phong materials (changing it "
                    "rebuilds the scene's lights groups; the materials keep their values)")


#: The seeds' light settings that a light met for the first time takes from Blender's own
#: factors of the light (an artist's Specular 0 light gives no highlight in Phong either).
BLENDER_FACTORS = {"diffuse": "diffuse_factor", "specular": "specular_factor"}


def ensure_light_props(light) -> None:
    """Write every missing Phong custom property of *light* (drivers need them to exist).  A
    light met for the first time takes its i0 from its Power (``from_power``); its Phong
    Intensity starts at the i0 its Power gives, so that turning Power off keeps the look, and
    its Phong Diffuse and Specular start at Blender's Diffuse and Specular factors of it
    (``BLENDER_FACTORS``; a light with an i0 of its own, as the seeds' scenes and imported
    files write, keeps 1 and 1)."""
    missing = False
    if FROM_POWER_KEY not in light.keys():
        power = from_power(light)
        light[FROM_POWER_KEY] = int(power)
        if power:
            light[LIGHT_KEYS["intensity"][0]] = power_intensity(light)
            for attr, blender in BLENDER_FACTORS.items():
                key = LIGHT_KEYS[attr][0]
                if key not in light.keys():
                    light[key] = float(getattr(light, blender, 1.0))
        missing = True
    for _attr, key, _label, default, vmin, soft_max, desc in LIGHT_SETTINGS:
        if key not in light.keys():
            light[key] = float(default)
            missing = True
        try:
            light.id_properties_ui(key).update(min=vmin, soft_min=vmin, soft_max=soft_max,
                                                 default=default, description=desc)
        except TypeError:
            pass
    if missing:
        light.update_tag()  # the evaluated copy that drivers read must get them too


def write_light(light, values: dict) -> None:
    """Set Phong settings of *light*: {attribute of LIGHT_SETTINGS, or "falloff": value}
    ("falloff": "QUADRATIC" or "POWER", any case; ValueError for anything else).  An
    "intensity" given here is the light's own i0 (it no longer follows the Power)."""
    if "intensity" in values:
        light[FROM_POWER_KEY] = 0
    for attr, value in values.items():
        if attr == "falloff":
            name = value.upper() if isinstance(value, str) else value
            if name not in FALLOFFS:
                raise ValueError(f"falloff must be one of {', '.join(FALLOFFS)}, not {value!r}")
            light[FALLOFF_KEY] = name
            continue
        light[LIGHT_KEYS[attr][0]] = float(value)
    ensure_light_props(light)
    light.update_tag()


def write_world(world, intensity: float, color) -> None:
    """Set the Phong ambient light of *world*."""
    world[AMBIENT_INTENSITY[0]] = float(intensity)
    world[AMBIENT_COLOR[0]] = [float(c) for c in tuple(color)[:3]]
    ensure_world_props(world)
    world.update_tag()


def ensure_world_props(world) -> None:
    """Write the world's missing Phong ambient custom properties: a world met for the first
    time (neither set) takes the light it gives Blender's own render (``world_light``); one
    where a script set one of them, the other's default."""
    key, default = AMBIENT_INTENSITY
    key_c, default_c = AMBIENT_COLOR
    have = world.keys()
    missing = key not in have or key_c not in have
    if key not in have and key_c not in have:  # no Phong ambient yet: the World's own light
        intensity, color, _note = world_light(world)
        world[key] = float(intensity)
        world[key_c] = [float(c) for c in color]
    elif missing:  # one of them set (by a script): the other's default
        if key not in have:
            world[key] = float(default)
        if key_c not in have:
            world[key_c] = list(default_c)
    try:
        world.id_properties_ui(key).update(min=0.0, soft_min=0.0, soft_max=1.0, default=default,
                                           description="Phong ambient intensity")
        world.id_properties_ui(key_c).update(min=0.0, soft_min=0.0, soft_max=1.0,
                                             subtype="COLOR", default=list(default_c),
                                             description="Phong ambient colour")
    except TypeError:
        pass
    if missing:
        world.update_tag()


def world_light(world) -> tuple:
    """(intensity, colour, note) of the ambient light that stands for *world*'s own light:
    its Background's Strength and Color (an unlit diffuse surface open to a uniform world
    of radiance L shows Kd·L in Blender, Ka·i·Cl in Phong).  An image on the Color: its mean
    radiance over the sphere, with a note saying so; any other node there: the World's
    viewport colour, with a note.  The note is None where the value is exact."""
    background = None
    if compat.uses_nodes(world) and world.node_tree is not None:
        output = next((n for n in world.node_tree.nodes
                       if n.bl_idname == "ShaderNodeOutputWorld" and n.is_active_output), None)
        surface = output.inputs["Surface"] if output is not None else None
        if surface is not None and surface.is_linked:
            node = surface.links[0].from_node
            background = node if node.bl_idname == "ShaderNodeBackground" else None
            if background is None:
                return 1.0, tuple(world.color), (
                    f"World '{world.name}': its surface is a {node.bl_label} node, not a "
                    "Background: the Phong ambient light is its viewport colour")
        elif output is not None:
            return 0.0, (1.0, 1.0, 1.0), None  # nothing on the output: no world light
    if background is None:
        return 1.0, tuple(world.color), None
    strength_socket = background.inputs["Strength"]
    strength = 1.0 if strength_socket.is_linked else float(strength_socket.default_value)
    color_socket = background.inputs["Color"]
    if not color_socket.is_linked:
        return strength, tuple(color_socket.default_value)[:3], None
    source = color_socket.links[0].from_node
    image = getattr(source, "image", None)
    mean = _image_mean(image) if image is not None else None
    if mean is not None:
        return strength, mean, (f"World '{world.name}': the Phong ambient light is the mean "
                                f"of its image '{image.name}' (Phong's ambient light is "
                                "uniform)")
    return strength, tuple(world.color), (
        f"World '{world.name}': its colour comes from a {source.bl_label} node: the Phong "
        "ambient light is its viewport colour")


def _image_mean(image):
    """The mean colour of an equirectangular *image* over the sphere (rows weighted by the
    solid angle they cover), from a 64 x 32 copy; None when it has no pixels."""
    import numpy as np  # noqa: PLC0415

    try:
        if not image.has_data and image.source in ("FILE", "SEQUENCE", "TILED"):
            image.reload()
        small = image.copy()
    except (RuntimeError, ReferenceError):
        return None
    try:
        small.scale(64, 32)
        pixels = np.empty(64 * 32 * small.channels, np.float32)
        small.pixels.foreach_get(pixels)
    except (RuntimeError, ValueError):
        return None
    finally:
        bpy.data.images.remove(small)
    rgb = pixels.reshape(32, 64, -1)[..., :3].astype(np.float64)
    weight = np.sin((np.arange(32) + 0.5) / 32 * np.pi)[:, None, None]
    mean = (rgb * weight).sum(axis=(0, 1)) / (weight.sum() * 64)
    return tuple(float(c) for c in mean) if np.all(np.isfinite(mean)) else None


classes = (PhongLightSettings, PhongWorldSettings, PhongSceneSettings)


_register_classes, _unregister_classes = bpy.utils.register_classes_factory(classes)


def register():
    # what a model switch calls (forwarding's model callback) is set by addon/__init__.py
    _register_classes()
    bpy.types.Light.phong = PointerProperty(type=PhongLightSettings)
    bpy.types.World.phong = PointerProperty(type=PhongWorldSettings)
    bpy.types.Scene.phong = PointerProperty(type=PhongSceneSettings)


def unregister():
    del bpy.types.Scene.phong
    del bpy.types.World.phong
    del bpy.types.Light.phong
    _unregister_classes()
