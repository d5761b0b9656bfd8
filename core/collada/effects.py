# SPDX-License-Identifier: GPL-3.0-or-later
"""Materials and their effects: ``profile_COMMON``'s technique (constant, lambert, phong,
blinn) into a :class:`~.model.Material`, its colours, floats and textures through the
effect's parameters (``newparam``, ``setparam``) and the sampler → surface → image chain.
Each function is handed the reading context (``context._Reading``); *scope* is an effect's
(parameters, parameters set by the material, where: the name in warnings).
"""

from __future__ import annotations

import os

from .model import OPAQUE_MODES, TECHNIQUES, Material, Texture, _uri_path
from .context import _name, _ref
from .numbers import floats, number


def newparams(ctx, *scopes):
    """{sid: newparam element} of *scopes* (later scopes win)."""
    out = {}
    for scope in scopes:
        if scope is None:
            continue
        for param in scope.findall("newparam"):
            if param.get("sid"):
                out[param.get("sid")] = param
    return out


def read_material(ctx, element):
    ident = element.get("id", "")
    name = _name(element, ident)
    where = f"material {name}"
    out = Material(ident, name)
    inst = element.find("instance_effect")
    effect = ctx.ids.get(_ref(inst.get("url"))) if inst is not None else None
    if effect is None or effect.tag != "effect":
        ctx.doc.warn(f"{where}: effect {inst.get('url') if inst is not None else '(none)'} "
                     "not found; imported black")
        out.technique = "lambert"
        return out
    out.effect_id = effect.get("id", "")
    profile = effect.find("profile_COMMON")
    if profile is None:
        profiles = [c.tag for c in effect if c.tag.startswith("profile_")]
        ctx.doc.warn(f"{where}: no profile_COMMON ({', '.join(profiles) or 'no profile'}); "
                     "imported black")
        out.technique = "lambert"
        return out
    technique_element = profile.find("technique")
    shading = None
    if technique_element is not None:
        shading = next((c for c in technique_element if c.tag in TECHNIQUES), None)
    if shading is None:
        ctx.doc.warn(f"{where}: no constant, lambert, phong or blinn technique; "
                     "imported black")
        out.technique = "lambert"
        return out
    out.technique = shading.tag
    params = newparams(ctx, effect, profile, technique_element)
    setparams = {}
    if inst is not None:
        for setparam in inst.findall("setparam"):
            if setparam.get("ref"):
                setparams[setparam.get("ref")] = setparam
    scope = (params, setparams, where)
    for child in shading:
        tag = child.tag
        if tag in ("emission", "ambient", "diffuse", "specular", "transparent"):
            color, texture = color_or_texture(ctx, child, scope)
            if tag == "transparent":
                mode = (child.get("opaque") or "A_ONE").strip().upper()
                if mode not in OPAQUE_MODES:
                    ctx.doc.warn(f"{where}: <transparent opaque=\"{mode}\"> unknown; "
                                 "read as A_ONE")
                    mode = "A_ONE"
                out.opaque = mode
                if texture is not None:
                    out.transparent_texture = texture
                elif color is not None:
                    out.transparent = color
                continue
            if color is not None:
                out.colors[tag] = color
            if texture is not None:
                out.textures[tag] = texture
                out.colors.setdefault(tag, (1.0, 1.0, 1.0, 1.0))
        elif tag in ("shininess", "transparency"):
            value = float_value(ctx, child, scope)
            if value is not None:
                setattr(out, tag, value)
    return out


def _param_value(ctx, ref, scope, kinds):
    params, setparams, where = scope
    source = setparams.get(ref) if ref in setparams else params.get(ref)
    if source is None:
        return None
    for kind in kinds:
        value = source.find(kind)
        if value is not None:
            return floats(ctx, value, f"{where}: <{kind}> of {ref}")
    return None


def color_or_texture(ctx, element, scope):
    where = scope[2]
    color = element.find("color")
    if color is not None:
        values = floats(ctx, color, f"{where}: <{element.tag}>")
        if values is not None and len(values) >= 3:
            a = float(values[3]) if len(values) >= 4 else 1.0
            return (float(values[0]), float(values[1]), float(values[2]), a), None
        ctx.doc.warn(f"{where}: <{element.tag}> colour that cannot be read; left out")
        return None, None
    param = element.find("param")
    if param is not None:
        values = _param_value(ctx, param.get("ref", ""), scope,
                                   ("float4", "float3", "color", "float"))
        if values is not None and len(values) >= 3:
            a = float(values[3]) if len(values) >= 4 else 1.0
            return (float(values[0]), float(values[1]), float(values[2]), a), None
        if values is not None and len(values) == 1:
            v = float(values[0])
            return (v, v, v, 1.0), None
        ctx.doc.warn(f"{where}: <{element.tag}> parameter {param.get('ref')} not found; "
                     "left out")
        return None, None
    texture = element.find("texture")
    if texture is not None:
        found = texture_of(ctx, texture.get("texture", ""), texture.get("texcoord", ""),
                           scope)
        if found is None:
            ctx.doc.warn(f"{where}: <{element.tag}> texture {texture.get('texture')} not "
                         "resolved to an image; left out")
        return None, found
    return None, None


def float_value(ctx, element, scope):
    where = scope[2]
    value = element.find("float")
    if value is not None:
        return number(ctx, value, f"{where}: <{element.tag}>")
    param = element.find("param")
    if param is not None:
        values = _param_value(ctx, param.get("ref", ""), scope, ("float",))
        if values is not None and len(values):
            return float(values[0])
        ctx.doc.warn(f"{where}: <{element.tag}> parameter {param.get('ref')} not found; "
                     "left out")
    return None


def texture_of(ctx, name, texcoord, scope, depth=0):
    """The Texture a ``<texture texture=...>`` names: the spec's sampler → surface →
    image chain (setparam first), 1.5's instance_image, or (as other readers accept)
    an image id, image name or a file name."""
    params, setparams, where = scope
    if depth > 8:
        return None
    param = setparams.get(name) if name in setparams else params.get(name)
    if param is not None:
        sampler = next((c for c in param if c.tag.startswith("sampler")), None)
        surface = param.find("surface")
        if sampler is not None:
            inst = sampler.find("instance_image")
            if inst is not None:
                return image(ctx, _ref(inst.get("url")), texcoord, where)
            src = sampler.find("source")
            if src is not None and src.text:
                return texture_of(ctx, src.text.strip(), texcoord, scope, depth + 1)
        if surface is not None:
            init = surface.find("init_from")
            if init is not None and init.text and init.text.strip():
                return image(ctx, init.text.strip(), texcoord, where)
            inst = surface.find("init_from/ref")
            if inst is not None and inst.text:
                return image(ctx, inst.text.strip(), texcoord, where)
            # init_planar / init_volume / init_cube: <all ref="image"/> (or the first face)
            ref = next((e.get("ref") for e in surface.iter() if e.get("ref")), None)
            if ref:
                return image(ctx, ref, texcoord, where)
    return image(ctx, name, texcoord, where, liberal=True)


def image(ctx, ident, texcoord, where, liberal=False):
    element = ctx.ids.get(ident)
    if element is None or element.tag != "image":
        element = next((i for i in ctx.root.iter("image") if i.get("name") == ident), None)
    if element is None:
        if liberal and os.path.splitext(ident)[1]:
            return texture_file(ctx, ident, texcoord, ident)
        return None
    init = element.find("init_from")
    text = None
    if init is not None:
        ref = init.find("ref")
        text = ref.text if ref is not None else init.text
    if not text or not text.strip():
        ctx.doc.warn(f"{where}: image {ident} has no file; left out")
        return None
    return texture_file(ctx, text.strip(), texcoord, element.get("id", ident))


def texture_file(ctx, written, texcoord, image_id):
    folder = os.path.dirname(os.path.abspath(ctx.doc.path))
    path = _uri_path(written)
    candidates = []
    if os.path.isabs(path):
        candidates.append(path)
    candidates.append(os.path.normpath(os.path.join(folder, path.replace("\\", "/"))))
    candidates.append(os.path.join(folder, os.path.basename(path.replace("\\", "/"))))
    resolved = next((c for c in candidates if os.path.isfile(c)), candidates[0])
    return Texture(written, resolved, texcoord, image_id)
