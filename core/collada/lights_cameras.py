# SPDX-License-Identifier: GPL-3.0-or-later
"""Lights and cameras: ``<light>`` (ambient, directional, point, spot with their attenuation
and falloff) into a :class:`~.model.Light`, ``<camera>`` (perspective or orthographic optics)
into a :class:`~.model.Camera`.  Each function is handed the reading context
(``context._Reading``).
"""

from __future__ import annotations

from .model import LIGHT_KINDS, Camera, Light
from .context import _name
from .numbers import floats, number


def read_light(ctx, element):
    ident = element.get("id", "")
    name = _name(element, ident)
    common = element.find("technique_common")
    kind_element = next((c for c in common if c.tag in LIGHT_KINDS), None) \
        if common is not None else None
    if kind_element is None:
        ctx.doc.warn(f"light {name}: no ambient, directional, point or spot; left out")
        return None
    where = f"light {name}"
    out = Light(ident, name, kind_element.tag)
    color = kind_element.find("color")
    values = floats(ctx, color, f"{where}: <color>") if color is not None else None
    if values is not None and len(values) >= 3:
        out.color = tuple(float(v) for v in values[:3])
    for attr, tag in (("constant", "constant_attenuation"),
                      ("linear", "linear_attenuation"),
                      ("quadratic", "quadratic_attenuation"),
                      ("falloff_angle", "falloff_angle"),
                      ("falloff_exponent", "falloff_exponent")):
        child = kind_element.find(tag)
        if child is not None:
            value = number(ctx, child, f"{where}: <{tag}>")
            if value is not None:
                setattr(out, attr, value)
    if out.kind in ("point", "spot"):
        if min(out.constant, out.linear, out.quadratic) < 0.0:
            ctx.doc.warn(f"{where}: negative attenuation read as 0")
            out.constant, out.linear, out.quadratic = (max(v, 0.0) for v in (
                out.constant, out.linear, out.quadratic))
    return out


def read_camera(ctx, element):
    ident = element.get("id", "")
    name = _name(element, ident)
    common = element.find("optics/technique_common")
    kind = next((c for c in common if c.tag in ("perspective", "orthographic")), None) \
        if common is not None else None
    if kind is None:
        ctx.doc.warn(f"camera {name}: no perspective or orthographic optics; left out")
        return None
    out = Camera(ident, name, kind.tag)
    for attr in ("xfov", "yfov", "xmag", "ymag", "aspect_ratio", "znear", "zfar"):
        child = kind.find(attr)
        if child is not None:
            value = number(ctx, child, f"camera {name}: <{attr}>")
            if value is not None:
                setattr(out, attr, value)
    return out
