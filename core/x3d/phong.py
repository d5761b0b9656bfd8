# SPDX-License-Identifier: GPL-3.0-or-later
"""The mappings of the data model to the project's Phong model and to Blender's axes:
:func:`to_blender_matrix`, :func:`phong_values`, :func:`light_values`,
:func:`counter_clockwise` and :func:`apply_texture_transform`.
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
