# SPDX-License-Identifier: GPL-3.0-or-later
"""FBX Phong and Lambert materials, lights and the scene ambient, read without ``bpy``
(issue 27).

The file is read by ufbx (PyPI ``ufbx``, bundled with the extension as wheels); this module
turns what it reads into plain data, by the FBX SDK's rules:

* every value comes from the object itself, else from the file's ``PropertyTemplate`` (the
  ``Definitions`` section), else from the FBX SDK class default (:data:`SURFACE_DEFAULTS`,
  :data:`LIGHT_DEFAULTS`: the values the FBX SDK writes in its own templates, e.g. Maya's
  ``FbxSurfacePhong`` and ``FbxLight`` templates); :attr:`Material.sources` says which;
* Object Color = DiffuseColor × DiffuseFactor, Ka = AmbientColor × AmbientFactor, Specular =
  SpecularColor × SpecularFactor (Lambert: black), Exponent = ShininessExponent (else the
  legacy Shininess), Irradiant = EmissiveColor × EmissiveFactor, opacity = the stored
  ``Opacity``, else 1 − TransparencyFactor × mean(TransparentColor) (the FBX SDK's rule);
* a light's colour, Intensity / 100, DecayType as the falloff 1/dᵏ (k = 0, 1, 2, 3) and a
  spot's OuterAngle / InnerAngle (FBX 6.1: ``Cone angle`` / ``HotSpot``), full cone angles in
  degrees;
* the scene ambient is GlobalSettings' AmbientColor.

ufbx 0.0.5 gives every property of an element (``props.props``) and finds a property through
the template (``props.find_prop``); ``props.defaults`` is not used: it crashes the process on
an element whose type has no template.  A file ufbx cannot read raises :class:`FbxError`, the
one exception class of this module.
"""

from __future__ import annotations

import math
import os
from dataclasses import dataclass, field

#: FBX SDK class defaults of FbxSurfaceLambert / FbxSurfacePhong (what the SDK writes in its
#: own PropertyTemplate "FbxSurfacePhong"; Lambert's are the same without the specular ones).
SURFACE_DEFAULTS = {
    "EmissiveColor": (0.0, 0.0, 0.0), "EmissiveFactor": 1.0,
    "AmbientColor": (0.2, 0.2, 0.2), "AmbientFactor": 1.0,
    "DiffuseColor": (0.8, 0.8, 0.8), "DiffuseFactor": 1.0,
    "TransparentColor": (0.0, 0.0, 0.0), "TransparencyFactor": 0.0,
    "SpecularColor": (0.2, 0.2, 0.2), "SpecularFactor": 1.0,
    "ShininessExponent": 20.0,
    "ReflectionColor": (0.0, 0.0, 0.0), "ReflectionFactor": 1.0,
}
#: FBX SDK class defaults of FbxLight (its template as the SDK writes it: InnerAngle 0,
#: OuterAngle 45; fbxlight.h's comment says 45 for InnerAngle too, the SDK writes 0).
LIGHT_DEFAULTS = {"Color": (1.0, 1.0, 1.0), "Intensity": 100.0, "LightType": 0,
                  "DecayType": 0, "InnerAngle": 0.0, "OuterAngle": 45.0}
#: Older names of a property (FBX 6.1 and before), looked up after the current one.
ALIASES = {"InnerAngle": ("InnerAngle", "HotSpot"), "OuterAngle": ("OuterAngle", "Cone angle")}
#: FbxLight::EType and how a Blender light stands in for it.
LIGHT_TYPES = {0: "POINT", 1: "SUN", 2: "SPOT", 3: "AREA", 4: "VOLUME"}
#: The colour slots of the Phong model: lights-group input -> (colour, factor) properties.
SLOTS = {
    "Object Color": ("DiffuseColor", "DiffuseFactor"),
    "Ambient Object Color": ("AmbientColor", "AmbientFactor"),
    "Specular Color": ("SpecularColor", "SpecularFactor"),
    "Irradiant Color": ("EmissiveColor", "EmissiveFactor"),
}
#: Texture slots read (a texture on the colour multiplies colour × factor; one on the factor
#: too): property -> lights-group input.
TEXTURE_SLOTS = {"DiffuseColor": "Object Color", "AmbientColor": "Ambient Object Color",
                 "SpecularColor": "Specular Color", "EmissiveColor": "Irradiant Color"}
#: Embedded textures larger than this are left out (bounded memory), with a warning.
MAX_EMBEDDED = 256 * 1024 * 1024
_NO_VALUE = 0x4000 | 0x10000  # ufbx PropFlags NOT_FOUND | NO_VALUE


class FbxError(ValueError):
    """A file that cannot be read as FBX: names the file and what is wrong."""

    def __init__(self, path: str, message: str):
        self.path = path
        super().__init__(f"{path}: {message}")


@dataclass
class Texture:
    prop: str                 # the material property it is connected to (DiffuseColor ...)
    name: str                 # the file name as written in the file
    candidates: tuple         # where it is looked for, first existing wins
    content: bytes | None     # embedded data (FBX Video Content), or None
    element: str = ""         # the Texture element's name

    @property
    def resolved(self) -> str | None:
        for path in self.candidates:
            if path and os.path.isfile(path):
                return path
        return None


@dataclass
class Material:
    name: str
    model: str                # "PHONG", "LAMBERT" or "OTHER" (PBR, Arnold, ShaderFX ...)
    shading: str              # the file's ShadingModel (or ufbx's shader name)
    raw: dict = field(default_factory=dict)      # property -> value used (float or 3 floats)
    sources: dict = field(default_factory=dict)  # property -> "object" | "template" | "default"
    colors: dict = field(default_factory=dict)   # lights-group input -> (r, g, b)
    exponent: float = 20.0
    opacity: float = 1.0
    blinn: bool = False
    textures: dict = field(default_factory=dict)  # lights-group input -> Texture
    unsupported: list = field(default_factory=list)


@dataclass
class Light:
    name: str                 # the light (NodeAttribute) name
    nodes: tuple              # names of the nodes (objects) that hold it
    fbx_type: int             # FbxLight::EType
    type: str                 # POINT, SUN, SPOT (AREA and VOLUME become POINT, see warnings)
    color: tuple
    intensity: float          # Intensity / 100
    decay: int                # k of 1/d^k
    outer_angle: float        # degrees, full cone (spot)
    inner_angle: float        # degrees, full cone (spot)
    sources: dict = field(default_factory=dict)


@dataclass
class Scene:
    path: str
    version: int
    ascii: bool
    creator: str
    ambient: tuple
    materials: list
    lights: list
    warnings: list

    def material(self, name):
        return next((m for m in self.materials if m.name == name), None)

    def light(self, name):
        return next((l for l in self.lights if l.name == name or name in l.nodes), None)


def _ufbx():
    try:
        import ufbx
    except ImportError as error:  # the wheel is missing for this platform
        raise FbxError("ufbx", f"the ufbx module is not available ({error})") from None
    return ufbx


#: The last scenes loaded, kept alive: ufbx 0.0.5's element objects hold no reference to their
#: scene, and one used (or merely garbage-collected) after its scene was freed crashes the
#: process.  A scene is dropped two loads later, long after the plain data was taken from it.
_KEPT: list = []


def load(path: str, **options):
    """The ufbx scene of *path* (raises :class:`FbxError`).  *options* go to
    ``ufbx.load_file``.  The scene is never freed explicitly (see :data:`_KEPT`)."""
    ufbx = _ufbx()
    if not os.path.isfile(path):
        raise FbxError(path, "file not found")
    try:
        scene = ufbx.load_file(path, **options)
    except ufbx.UfbxError as error:
        raise FbxError(path, f"not readable as FBX ({type(error).__name__}: {error})") from None
    except (OSError, ValueError, MemoryError) as error:
        raise FbxError(path, f"not readable as FBX ({error})") from None
    _KEPT.append(scene)
    del _KEPT[:-2]
    return scene


def _finite(value) -> bool:
    return all(math.isfinite(v) for v in (value if isinstance(value, tuple) else (value,)))


def _value(prop, width):
    v = prop.value_vec4
    return (float(v.x), float(v.y), float(v.z)) if width == 3 else float(v.x)


def lookup(props, names, default, width, own=None):
    """(value, source) of the first of *names* on the element, else in its template, else
    *default* ("default").  A non-finite value counts as absent."""
    own = own if own is not None else {p.name: p for p in props.props}
    for name in names:
        prop = own.get(name)
        if prop is not None and not prop.flags & _NO_VALUE:
            value = _value(prop, width)
            if _finite(value):
                return value, "object"
    for name in names:
        prop = props.find_prop(name)
        if prop is not None and name not in own and not prop.flags & _NO_VALUE:
            value = _value(prop, width)
            if _finite(value):
                return value, "template"
    return default, "default"


def _texture(prop_name, texture, base) -> Texture:
    files = list(texture.file_textures) if texture.type.name != "FILE" else [texture]
    tex = files[0] if files else texture
    content = bytes(tex.content) if len(tex.content) else None
    if tex.video is not None and content is None and len(tex.video.content):
        content = bytes(tex.video.content)
    candidates = []
    for path in (tex.filename, tex.absolute_filename,
                 os.path.join(base, tex.relative_filename) if tex.relative_filename else "",
                 os.path.join(base, os.path.basename(tex.relative_filename.replace("\\", "/")))
                 if tex.relative_filename else "",
                 os.path.join(base, os.path.basename(tex.absolute_filename.replace("\\", "/")))
                 if tex.absolute_filename else ""):
            if path and path not in candidates:
                candidates.append(path)
    name = tex.relative_filename or tex.absolute_filename or tex.filename or tex.name
    return Texture(prop_name, name, tuple(candidates), content, tex.name)


def read_material(mat, base="") -> Material:
    """The Phong values of the ufbx material *mat* (``base``: the file's folder)."""
    ufbx = _ufbx()
    shading = mat.shading_model_name or ""
    kind = mat.shader_type
    if mat.shader is not None or kind not in (ufbx.ShaderType.FBX_LAMBERT,
                                              ufbx.ShaderType.FBX_PHONG):
        return Material(mat.name, "OTHER", shading or kind.name)
    lambert = kind == ufbx.ShaderType.FBX_LAMBERT
    out = Material(mat.name, "LAMBERT" if lambert else "PHONG", shading,
                   blinn=shading.strip().lower() == "blinn")
    own = {p.name: p for p in mat.props.props}

    def get(name, width):
        value, source = lookup(mat.props, (name,), SURFACE_DEFAULTS[name], width, own)
        out.raw[name], out.sources[name] = value, source
        return value

    for slot, (color_name, factor_name) in SLOTS.items():
        if lambert and slot == "Specular Color":
            out.colors[slot] = (0.0, 0.0, 0.0)
            continue
        color, factor = get(color_name, 3), get(factor_name, 1)
        out.colors[slot] = tuple(c * factor for c in color)
    if not lambert:
        exponent, source = lookup(mat.props, ("ShininessExponent",), None, 1, own)
        if source == "default":
            exponent, source = lookup(mat.props, ("Shininess",),
                                      SURFACE_DEFAULTS["ShininessExponent"], 1, own)
        out.raw["ShininessExponent"], out.sources["ShininessExponent"] = exponent, source
        out.exponent = max(float(exponent), 0.0)
    opacity, source = lookup(mat.props, ("Opacity",), None, 1, own)
    if opacity is None:
        tc, tf = get("TransparentColor", 3), get("TransparencyFactor", 1)
        opacity = 1.0 - tf * sum(tc) / 3.0
    else:
        out.raw["Opacity"], out.sources["Opacity"] = opacity, source
    out.opacity = min(max(float(opacity), 0.0), 1.0)
    if not lambert:
        rc, rf = get("ReflectionColor", 3), get("ReflectionFactor", 1)
        if rf * max(rc) > 0.0:
            out.unsupported.append("reflection (ReflectionColor × ReflectionFactor)")
    for link in mat.textures:
        prop = link.material_prop
        slot = TEXTURE_SLOTS.get(prop)
        if slot is None or (lambert and slot == "Specular Color"):
            out.unsupported.append(f"texture on {prop}")
            continue
        out.textures[slot] = _texture(prop, link.texture, base)
    return out


def read_light(light) -> Light:
    ufbx = _ufbx()
    own = {p.name: p for p in light.props.props}
    sources = {}

    def get(name, width):
        value, source = lookup(light.props, ALIASES.get(name, (name,)), LIGHT_DEFAULTS[name],
                               width, own)
        sources[name] = source
        return value

    fbx_type = int(round(get("LightType", 1)))
    decay = int(round(get("DecayType", 1)))
    del ufbx
    return Light(
        name=light.name, nodes=tuple(n.name for n in light.instances), fbx_type=fbx_type,
        type={0: "POINT", 1: "SUN", 2: "SPOT"}.get(fbx_type, "POINT"),
        color=tuple(get("Color", 3)), intensity=get("Intensity", 1) / 100.0,
        decay=decay if decay in (0, 1, 2, 3) else 2,
        outer_angle=get("OuterAngle", 1), inner_angle=get("InnerAngle", 1), sources=sources)


def read(path: str) -> Scene:
    """Materials, lights and ambient of the FBX file *path* (raises :class:`FbxError`)."""
    return from_scene(load(path, ignore_geometry=True, ignore_animation=True), path)


def from_scene(scene, path: str) -> Scene:
    """Plain data of a loaded ufbx *scene* (see :func:`read`)."""
    base = os.path.dirname(os.path.abspath(path))
    warnings = []
    materials = [read_material(m, base) for m in scene.materials]
    lights = []
    for light in scene.lights:
        item = read_light(light)
        if item.fbx_type not in (0, 1, 2):
            what = LIGHT_TYPES.get(item.fbx_type, f"type {item.fbx_type}")
            warnings.append(f"{path}: light {item.name}: {what.lower()} light imported as a "
                            "point light (the Phong model has point, directional and spot)")
        if item.decay != int(round(lookup(light.props, ("DecayType",), 0, 1)[0])):
            warnings.append(f"{path}: light {item.name}: unknown DecayType, read as quadratic")
        lights.append(item)
    ambient = tuple(float(c) for c in scene.settings.ambient_color)
    if not _finite(ambient):
        ambient = (0.0, 0.0, 0.0)
    meta = scene.metadata
    return Scene(path, int(meta.version), bool(meta.ascii), meta.creator, ambient,
                 materials, lights, warnings)


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
