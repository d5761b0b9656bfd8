# SPDX-License-Identifier: GPL-3.0-or-later
"""X3D's Phong mapping, both directions, and the data model's to Blender's axes: the import
(:func:`to_blender_matrix`, :func:`phong_values`, :func:`light_values`,
:func:`counter_clockwise`, :func:`apply_texture_transform`) and the export (:func:`light_fields`
in a lighting model, :func:`material_fields`, :func:`shininess_of`,
:func:`ambient_intensity_of`, the notes of what X3D cannot say); pure, so that a round trip
values → X3D fields → values is tested on numbers.
"""

from __future__ import annotations

import numpy as np

from .model import Y_UP_TO_Z_UP, Light, Material, Mesh, TextureTransform
from .document import Document


# -- mappings to the Phong model and to Blender's axes ----------------------------------------

def to_blender_matrix(doc: Document) -> np.ndarray:
    """4×4 matrix from the file's axes and units to Blender's (Z up, metres): a rotation of
    +90° about X (X3D's +Y becomes +Z, its +Z, towards the viewer, becomes -Y) times
    ``doc.meter``.  The Blender side puts it in front of every world matrix (or of the
    root); the parsed data is never converted."""
    return Y_UP_TO_Z_UP @ np.diag([doc.meter, doc.meter, doc.meter, 1.0])


def phong_values(material: Material | None, texture_components: int | None = None,
                 colors: bool = False) -> dict:
    """The project's Phong parameters of a VRML97 / X3D material (ISO/IEC 14772-1 §4.14 and
    19775-1 §17.2.2 "lighting model"):

    ============================  ==========================================================
    VRML97 / X3D                  Phong
    ============================  ==========================================================
    diffuseColor                  Kd (Object Color)
    ambientIntensity × diffuse    Ka (Ambient Object Color)
    specularColor                 Ks (Specular Color)
    emissiveColor                 Ke (Irradiant Color)
    128 × shininess               exponent
    (the standard's N·H)          blinn = 1: the half-vector highlight
    1 − transparency              opacity
    Material NULL (None)          unlit: Ke white, Kd = Ka = Ks = 0 ("lit" False)
    UnlitMaterial                 unlit: Ke = its colour
    an RGB(A) texture             replaces Kd (unlit: Ke) — VRML97 and X3D 3
    a 1- or 2-channel texture     multiplies Kd (unlit: Ke), or the colours when given
    a Color / ColorRGBA node      replaces Kd (unlit: Ke), unless an RGB texture is given
    ============================  ==========================================================

    *texture_components* is the number of channels of the shape's texture (None: no
    texture), *colors* whether its geometry has colours.  Returns Kd, Ka, Ks, Ke (RGB),
    exponent, blinn, opacity, lit, and "source": what colours the term the texture and
    colours act on ("material", "colors", "texture", "texture*material",
    "texture*colors")."""
    if texture_components is None:
        source = "colors" if colors else "material"
    elif texture_components >= 3:
        source = "texture"
    else:
        source = "texture*colors" if colors else "texture*material"
    if material is None or material.kind == "unlit":
        emissive = (1.0, 1.0, 1.0) if material is None else tuple(material.emissive)
        opacity = 1.0 if material is None else 1.0 - material.transparency
        return {"Kd": (0.0, 0.0, 0.0), "Ka": (0.0, 0.0, 0.0), "Ks": (0.0, 0.0, 0.0),
                "Ke": emissive, "exponent": 0.0, "blinn": 1.0, "opacity": opacity,
                "lit": False, "source": source}
    kd = tuple(float(c) for c in material.diffuse)
    return {"Kd": kd, "Ka": tuple(material.ambient_intensity * c for c in kd),
            "Ks": tuple(float(c) for c in material.specular),
            "Ke": tuple(float(c) for c in material.emissive),
            "exponent": 128.0 * material.shininess, "blinn": 1.0,
            "opacity": 1.0 - material.transparency, "lit": True, "source": source}


def light_values(doc: Document, light: Light) -> dict:
    """A light's values for the Phong lights, distances in metres: the standard's
    attenuation 1/max(a0 + a1·d + a2·d², 1) with d in the file's units equals
    1/max(a0 + a1'·d' + a2'·d'², 1) with d' = d·meter: a1' = a1/m, a2' = a2/m²; radius × m;
    beamWidth and cutOffAngle in radians (the half-angles of the cone: full intensity inside
    beamWidth, none beyond cutOffAngle, a linear ramp between as X3D says); ambient intensity
    and ``global`` as read; ``shadows`` (default false: X3D's lights cast none unless a file
    says so)."""
    m = doc.meter
    a0, a1, a2 = light.attenuation
    return {"kind": light.kind, "on": light.on, "intensity": light.intensity,
            "ambient_intensity": light.ambient_intensity, "color": tuple(light.color),
            "attenuation": (a0, a1 / m, a2 / (m * m)), "radius": light.radius * m,
            "beam_width": light.beam_width, "cut_off_angle": light.cut_off_angle,
            "global": light.is_global, "shadows": bool(light.shadows)}


def counter_clockwise(mesh: Mesh) -> Mesh:
    """A copy of *mesh* whose faces are counter-clockwise (``ccw`` True): each face of a
    ``ccw`` FALSE mesh reversed, keeping its first corner, with its per-corner values."""
    out = Mesh(**{k: getattr(mesh, k) for k in mesh.__dataclass_fields__})
    if mesh.ccw or not len(mesh.corners):
        return out
    sizes = np.asarray(mesh.face_sizes, dtype=np.int64)
    starts = np.repeat(np.r_[0, np.cumsum(sizes)[:-1]], sizes)
    local = np.arange(len(mesh.corners)) - starts
    order = starts + (np.repeat(sizes, sizes) - local) % np.repeat(sizes, sizes)
    out.corners = mesh.corners[order]
    for name in ("normals", "colors", "uvs"):
        values = getattr(mesh, name)
        if values is not None:
            setattr(out, name, values[order])
    out.ccw = True
    return out


def apply_texture_transform(uvs: np.ndarray, transform: TextureTransform | None) -> np.ndarray:
    """*uvs* (c, 2) transformed by a TextureTransform (the standard's Tc' = -C·S·R·C·T·Tc)."""
    if transform is None or uvs is None:
        return uvs
    m = transform.matrix()
    uvs = np.asarray(uvs, dtype=np.float64)
    return uvs @ m[:2, :2].T + m[:2, 2]


# -- the export: the project's Phong values to X3D's fields ------------------------------------

#: A light's radius where the scene's lighting model has none (X3D's radius bounds every
#: point and spot light): far beyond any scene.
NO_RADIUS = 1.0e6


def f32(value) -> float:
    """The shortest decimal that reads back as the same float32 (0.1 for float32(0.1)):
    Blender's precision, written as such."""
    return float(str(np.float32(value)))


def colour32(values) -> tuple:
    """The first three of *values* as :func:`f32` numbers."""
    return tuple(f32(v) for v in tuple(values)[:3])


def model_note(model, scene_name: str) -> str | None:
    """The one warning of a scene in a lighting model (``node_groups.models``) that is not
    X3D's own (None for X3D's): what its values become."""
    if "x3d" in model.native:
        return None
    return (f"scene {scene_name!r} is in the {model.name} lighting model, not X3D / VRML97: "
            "its values are written mapped to X3D's (lights' attenuation 1/(c + l·d + q·d²) "
            "as X3D's 1/max(a0 + a1·d + a2·d², 1), no radius, a spot's soft edge as "
            "beamWidth, Phong highlights as Blinn's, the World's ambient light as a "
            "DirectionalLight of intensity 0): the picture may differ")


def light_fields(model, settings: dict, falloff: str, kind: str, spot_size: float,
                 kept_cut=None) -> tuple:
    """({X3D Light field: value}, notes) of a light of *kind* ("directional", "point",
    "spot") with the Phong *settings* ({setting: value}: every model's, as a light holds
    them), *falloff* ("QUADRATIC" or "POWER") and *spot_size* (radians, the full cone) in
    the lighting *model*: intensity, ambientIntensity, attenuation (a0, a1, a2), radius,
    cutOffAngle = half the spot size (the file's own *kept_cut* where it still gives it) and
    beamWidth, as ``LightingModel.x3d_light`` maps the model's settings; notes: what X3D
    cannot say, each a sentence after "light NAME: "."""
    out = {"intensity": float(settings["intensity"]),
           "ambient_intensity": float(settings["ambient"])}
    notes = []
    cut = None
    if kind == "spot":
        cut = kept_cut if isinstance(kept_cut, float) and \
            np.float32(2.0 * kept_cut) == np.float32(spot_size) else f32(spot_size / 2.0)
        out["cut_off_angle"] = cut
    mapped, notes = model.x3d_light(settings, falloff, kind, cut)
    if kind != "directional":
        out["attenuation"] = tuple(mapped["attenuation"])
        out["radius"] = NO_RADIUS if mapped["radius"] is None else float(mapped["radius"])
    if kind == "spot":
        out["beam_width"] = mapped["beam_width"]
    return out, notes


def light_settings(values: dict) -> dict:
    """The Phong settings of an X3D light's values (:func:`light_values`), in the X3D
    model: the inverse of :func:`light_fields` there."""
    a0, a1, a2 = values["attenuation"]
    out = {"intensity": values["intensity"], "ambient": values["ambient_intensity"],
           "constant": a0, "linear": a1, "quadratic": a2, "radius": values["radius"]}
    if values["kind"] == "spot":
        out["beam_width"] = values["beam_width"]
    return out


def shininess_of(exponent: float, kept=None) -> tuple:
    """(X3D shininess, note or None) of a Phong exponent: exponent / 128, the file's own
    *kept* shininess where it still gives the exponent, 1 (with a note) above 128."""
    if isinstance(kept, float) and np.float32(128.0 * kept) == np.float32(exponent):
        return kept, None
    shininess = exponent / 128.0
    if shininess > 1.0:
        return 1.0, (f"Exponent {exponent:g} above X3D's 128 (shininess 1): written as "
                     "shininess 1")
    return max(f32(shininess), 0.0), None


def ambient_intensity_of(kd, ka, kept=None) -> tuple:
    """(X3D ambientIntensity, note or None) of the colours Kd and Ka: Ka / Kd where Ka is a
    multiple of Kd (the file's own *kept* value where it still gives Ka), else the nearest
    multiple (with a note); 0 for a black Ka, and (with a note) for a Ka without a Kd."""
    kd = np.asarray(kd, dtype=np.float64)
    ka = np.asarray(ka, dtype=np.float64)
    if isinstance(kept, float) and all(np.float32(kept * f32(d)) == np.float32(a)
                                       for d, a in zip(kd, ka)):
        return kept, None
    if not ka.any():
        return 0.0, None
    if not kd.any():
        return 0.0, ("an ambient colour without a diffuse colour, which X3D "
                     "(ambientIntensity × diffuseColor) cannot say: ambientIntensity 0 written")
    ratio = float(ka @ kd / (kd @ kd))
    note = None
    if np.abs(ka - ratio * kd).max() > 1e-6 * max(1.0, float(ka.max())):
        note = (f"Ambient Color {tuple(round(float(v), 4) for v in ka)} is not a multiple of "
                "Object Color as X3D's ambientIntensity × diffuseColor: the nearest multiple "
                f"{ratio:.4g} written")
    return f32(max(ratio, 0.0)), note


def highlight_note(model, blinn: float, specular) -> str | None:
    """The note of a material whose highlight X3D (Blinn's always) cannot say in *model*."""
    if "x3d" not in model.native and blinn < 1.0 and any(specular):
        return "Phong's (r·v)^e highlight written as X3D's Blinn highlight (n·h)^e"
    return None


def material_fields(values: dict, kept_shininess=None, kept_ambient=None) -> tuple:
    """({X3D Material field: value}, notes) of the Phong *values* ({"Kd", "Ka", "Ks", "Ke",
    "exponent", "opacity"}): the inverse of :func:`phong_values` for a lit material."""
    shininess, note = shininess_of(values["exponent"], kept_shininess)
    ambient, other = ambient_intensity_of(values["Kd"], values["Ka"], kept_ambient)
    fields = {"diffuse": colour32(values["Kd"]), "ambient_intensity": ambient,
              "specular": colour32(values["Ks"]), "emissive": colour32(values["Ke"]),
              "shininess": shininess, "transparency": f32(1.0 - values["opacity"])}
    return fields, [n for n in (note, other) if n]


# -- the World's Phong ambient light, which X3D lacks ------------------------------------------

#: The DEF of the DirectionalLight (intensity 0, global) that carries the World's Phong
#: ambient light: written by the export, read back into the World by the import.
WORLD_AMBIENT = "WorldAmbient"


def world_ambient_light(intensity: float, color) -> Light | None:
    """The DirectionalLight of intensity 0 whose ambientIntensity and colour give the World's
    Phong ambient term *intensity* × *color* (None where it is black)."""
    color = [float(c) for c in tuple(color)[:3]]
    if intensity <= 0.0 or not any(color):
        return None
    return Light(kind="directional", name=WORLD_AMBIENT, intensity=0.0,
                 ambient_intensity=f32(intensity), color=colour32(color), is_global=True)


def is_world_ambient(light: Light) -> bool:
    """Whether *light* is :func:`world_ambient_light`'s: a DirectionalLight DEF'd
    :data:`WORLD_AMBIENT` of intensity 0, on, without shadows (reached by the whole file:
    the caller checks that).  Its ambient term is the World's, exactly."""
    return (light.kind == "directional" and light.name == WORLD_AMBIENT
            and float(light.intensity) == 0.0 and bool(light.on) and not light.shadows)


def world_ambient(doc: Document, light: Light) -> tuple:
    """(intensity, colour) of the World's Phong ambient that :func:`world_ambient_light`
    wrote: the inverse of it."""
    values = light_values(doc, light)
    return (max(float(values["ambient_intensity"]), 0.0),
            tuple(max(float(c), 0.0) for c in values["color"]))
