# SPDX-License-Identifier: GPL-3.0-or-later
"""The reader: the generic nodes of a file into the data model, each node built once
(:func:`build`: DEF/USE is identity, a node used twice gives the same object), the dispatch
by node type, the scene-graph nodes (groups, shapes, appearances, materials, textures,
lights, viewpoints, bindable nodes, Inline) and the warnings at the end (:func:`finish`).
Each function is handed the reading context (:class:`~.context._Reading`); typed fields are
``fields``, PROTO expansion ``protos``, files ``files``, geometry nodes ``geometry``.
"""

from __future__ import annotations

import os

import numpy as np

from .numeric import transform_matrix
from .model import (
    MAX_DEPTH, SPOT_DEFAULTS, Appearance, Light, Material, Shape, Texture, TextureTransform,
    Transform, Viewpoint)
from .graph import (
    _BINDABLES, _FACE_SETS, _GEOMETRY, _GEOMETRY_SKIPPED, _GROUPS, _IGNORED, _LIGHTS,
    _MATERIALS, _MISSING, _TEXTURES, _TRANSFORM_LIKE, _VIEWPOINTS)
from .fields import (
    angle, field, flag, ints, node_value, node_values, num, numbers, rotation, string, strings,
    type_of, vec, where)
from .files import parse_file
from .protos import lookup
from .geometry import _default_uvs, geometry_node


# nodes --------------------------------------------------------------------------------

def build(ctx, value, depth, hint, want):
    """The model object of a node (memoised: a node USE'd twice gives the same object),
    None when it is not one of *want* ("child", "geometry", "appearance", "material",
    "texture", "texture_transform") or cannot be built."""
    n = lookup(ctx, value)
    if n is None:
        return None
    key = id(n)
    if key in ctx.memo:
        return ctx.memo[key][1]
    if key in ctx.busy:
        ctx.notes.add("nodes used inside themselves (a USE within its own DEF, a PROTO "
                      "instance within its own PROTO): left out", n.name or n.type)
        return None
    if depth > MAX_DEPTH:
        ctx.too_deep += 1
        return None
    ctx.busy.add(key)
    try:
        obj = dispatch(ctx, n, depth, hint, want)
    finally:
        ctx.busy.discard(key)
    ctx.memo[key] = (n, obj)
    return obj


def dispatch(ctx, n, depth, hint, want):
    t = type_of(ctx, n)
    if t is None:
        if want == "child" or want is None:
            ctx.unknown[n.type] = ctx.unknown.get(n.type, 0) + 1
            kids = node_values(ctx, n, "children")
            if kids:
                return group(ctx, n, n.type, depth, hint)
        else:
            ctx.unknown[n.type] = ctx.unknown.get(n.type, 0) + 1
        return None
    if t in _IGNORED:
        ctx.ignored[t] = ctx.ignored.get(t, 0) + 1
        return None
    if t in _GEOMETRY_SKIPPED:
        ctx.notes.add("geometry nodes not read (not tessellated here): left out", t)
        return None
    if want == "child":
        if t in _GROUPS:
            return group(ctx, n, t, depth, hint)
        if t == "Shape":
            return shape(ctx, n, depth, hint)
        if t in _LIGHTS:
            return light(ctx, n, t)
        if t in _VIEWPOINTS:
            return viewpoint(ctx, n, t)
        if t in _BINDABLES:
            bindable(ctx, n, t)
            return None
        if t == "Inline":
            return inline(ctx, n, depth, hint)
    elif want == "geometry" and t in _GEOMETRY:
        return geometry_node(ctx, n, t, hint)
    elif want == "appearance" and t == "Appearance":
        return appearance(ctx, n, depth, hint)
    elif want == "material" and t in _MATERIALS:
        return material(ctx, n, t, hint)
    elif want == "texture" and t in _TEXTURES:
        return texture(ctx, n, t, depth)
    elif want == "texture_transform" and t == "TextureTransform":
        return TextureTransform(
            name=n.name or "", center=vec(ctx, n, "center", (0.0, 0.0)),
            rotation=angle(ctx, n, "rotation", 0.0), scale=vec(ctx, n, "scale", (1.0, 1.0)),
            translation=vec(ctx, n, "translation", (0.0, 0.0)))
    ctx.notes.add("nodes where the standard allows none of their type: left out",
                  f"{t} as {want}")
    return None


def group(ctx, n, t, depth, hint):
    name = n.name or ""
    obj = Transform(name=name, kind=t)
    if t in _TRANSFORM_LIKE:
        obj.matrix = transform_matrix(
            vec(ctx, n, "translation", (0.0, 0.0, 0.0)), rotation(ctx, n, "rotation"),
            vec(ctx, n, "scale", (1.0, 1.0, 1.0)), rotation(ctx, n, "scaleOrientation"),
            vec(ctx, n, "center", (0.0, 0.0, 0.0)))
    elif t == "MatrixTransform":
        obj.matrix = matrix_field(ctx, n)
    if t == "Switch":
        kids = node_values(ctx, n, "choice") or node_values(ctx, n, "children")
        which = int(num(ctx, n, "whichChoice", -1.0))
        kids = [kids[which]] if 0 <= which < len(kids) else []
    elif t == "LOD":
        kids = (node_values(ctx, n, "level") or node_values(ctx, n, "children"))[:1]
    elif t == "CADFace":        # XML files often leave the Shape's containerField out
        kids = node_values(ctx, n, "shape") or node_values(ctx, n, "children")
    elif t == "HAnimHumanoid":
        kids = (node_values(ctx, n, "skeleton") + node_values(ctx, n, "skin")
                or node_values(ctx, n, "children"))
    else:
        kids = node_values(ctx, n, "children")
        if t == "Billboard":
            ctx.notes.add("Billboards read as Groups (a browser turns them towards the "
                          "viewer)", name or None)
    hint = name or hint
    for kid in kids:
        child = build(ctx, kid, depth + 1, hint, "child")
        if child is not None:
            obj.children.append(child)
    return obj


def matrix_field(ctx, n):
    """MatrixTransform's ``matrix`` (16 numbers): written as in Inventor and X3D's
    SFMatrix4f, translation in the 13th to 15th numbers (M = values as 4×4, transposed);
    a matrix written the other way (translation in the 4th, 8th, 12th) is read as such."""
    arr = numbers(ctx, n, "matrix")
    if arr is None or len(arr) < 16:
        if arr is not None:
            ctx.notes.add("fields with too few numbers: defaults used",
                          where(n, "matrix"))
        return np.eye(4)
    m = arr[:16].reshape(4, 4)
    if m[0, 3] == m[1, 3] == m[2, 3] == 0.0 or (m[3, :3] != 0).any():
        m = m.T
    return m.copy()


def shape(ctx, n, depth, hint):
    name = n.name or ""
    hint = name or hint
    appearance = build(ctx, node_value(ctx, n, "appearance"), depth + 1, hint, "appearance")
    geometry = build(ctx, node_value(ctx, n, "geometry"), depth + 1, hint, "geometry")
    if appearance is not None and appearance.texture is not None and geometry is not None \
            and geometry.uvs is None and len(geometry.corners) \
            and geometry.kind in _FACE_SETS:
        geometry.uvs = _default_uvs(geometry)
    return Shape(name=name, geometry=geometry, appearance=appearance)


def appearance(ctx, n, depth, hint):
    name = n.name or ""
    hint = name or hint
    for shader in node_values(ctx, n, "shaders"):
        found = lookup(ctx, shader)
        if found is not None:
            kind = type_of(ctx, found) or found.type
            ctx.ignored[kind] = ctx.ignored.get(kind, 0) + 1
    if node_value(ctx, n, "backMaterial") is not None:
        ctx.notes.add("Appearance backMaterial (X3D 4) not read: the front material is "
                      "used on both sides", name or None)
    return Appearance(
        name=name,
        material=build(ctx, node_value(ctx, n, "material"), depth + 1, hint, "material"),
        texture=build(ctx, node_value(ctx, n, "texture"), depth + 1, hint, "texture"),
        texture_transform=build(ctx, node_value(ctx, n, "textureTransform"), depth + 1, hint,
                                     "texture_transform"))


def material(ctx, n, t, hint):
    mat = Material(name=n.name or hint or "Material")
    if t == "UnlitMaterial":
        mat.kind = "unlit"
        mat.diffuse, mat.ambient_intensity, mat.shininess = (0.0, 0.0, 0.0), 0.0, 0.0
        mat.emissive = vec(ctx, n, "emissiveColor", (1.0, 1.0, 1.0))
        mat.transparency = num(ctx, n, "transparency", 0.0)
        return mat
    if t == "PhysicalMaterial":
        mat.kind = "physical"
        mat.diffuse = vec(ctx, n, "baseColor", (1.0, 1.0, 1.0))
        mat.emissive = vec(ctx, n, "emissiveColor", (0.0, 0.0, 0.0))
        mat.transparency = num(ctx, n, "transparency", 0.0)
        mat.metallic = num(ctx, n, "metallic", 1.0)
        mat.roughness = num(ctx, n, "roughness", 1.0)
        mat.ambient_intensity, mat.specular, mat.shininess = 0.0, (0.0, 0.0, 0.0), 0.0
        ctx.notes.add("PhysicalMaterials (X3D 4) read as their baseColor (diffuse) and "
                      "emissiveColor; metallic and roughness kept, not mapped", mat.name)
        return mat
    mat.diffuse = vec(ctx, n, "diffuseColor", (0.8, 0.8, 0.8))
    mat.ambient_intensity = num(ctx, n, "ambientIntensity", 0.2)
    mat.specular = vec(ctx, n, "specularColor", (0.0, 0.0, 0.0))
    mat.emissive = vec(ctx, n, "emissiveColor", (0.0, 0.0, 0.0))
    mat.shininess = num(ctx, n, "shininess", 0.2)
    mat.transparency = num(ctx, n, "transparency", 0.0)
    textures = [f for f in ("diffuseTexture", "emissiveTexture", "specularTexture",
                            "shininessTexture", "ambientTexture", "normalTexture",
                            "occlusionTexture") if node_value(ctx, n, f) is not None]
    if textures:
        ctx.notes.add("X3D 4 material textures not read", f"{mat.name}: {', '.join(textures)}")
    if t == "TwoSidedMaterial":
        mat.kind = "two_sided"
        if flag(ctx, n, "separateBackColor", False):
            mat.back = Material(
                name=mat.name + " (back)",
                diffuse=vec(ctx, n, "backDiffuseColor", (0.8, 0.8, 0.8)),
                ambient_intensity=num(ctx, n, "backAmbientIntensity", 0.2),
                specular=vec(ctx, n, "backSpecularColor", (0.0, 0.0, 0.0)),
                emissive=vec(ctx, n, "backEmissiveColor", (0.0, 0.0, 0.0)),
                shininess=num(ctx, n, "backShininess", 0.2),
                transparency=num(ctx, n, "backTransparency", 0.0))
    return mat


def texture(ctx, n, t, depth):
    if t == "MultiTexture":
        ctx.notes.add("MultiTextures read as their first texture", n.name or None)
        return build(ctx, next(iter(node_values(ctx, n, "texture")), None), depth + 1, "",
                          "texture")
    tex = Texture(name=n.name or "", kind=t, repeat_s=flag(ctx, n, "repeatS", True),
                  repeat_t=flag(ctx, n, "repeatT", True))
    if t == "PixelTexture":
        pixels(ctx, n, tex)
        return tex
    tex.urls = strings(ctx, n, "url")
    base = n.src.base if n.src is not None else os.getcwd()
    for url in tex.urls:
        path = ctx.resolver(url, base)
        if path is None:
            continue
        candidates = [path]
        beside = os.path.join(base, os.path.basename(path))
        if beside != path:
            candidates.append(beside)
        for candidate in candidates:
            if candidate not in tex.paths:
                tex.paths.append(candidate)
            if tex.path is None and os.path.isfile(candidate):
                tex.path = candidate
    if tex.path is None:
        ctx.notes.add("texture files not found", (tex.urls or ["(no url)"])[0])
    return tex


def pixels(ctx, n, tex):
    """PixelTexture's SFImage: width height components, then one integer a pixel."""
    arr = ints(ctx, n, "image")
    if len(arr) < 3:
        return
    width, height, comps = (int(v) for v in arr[:3])
    if not (0 < width <= 16384 and 0 < height <= 16384 and 1 <= comps <= 4) \
            or len(arr) < 3 + width * height:
        ctx.notes.add("PixelTexture images that could not be read", tex.name or None)
        return
    values = arr[3:3 + width * height].astype(np.uint64)
    shifts = np.arange(comps - 1, -1, -1, dtype=np.uint64) * np.uint64(8)
    tex.image = ((values[:, None] >> shifts[None, :]) & np.uint64(255)).astype(
        np.uint8).reshape(height, width, comps)
    tex.components = comps


def light(ctx, n, t):
    kind = _LIGHTS[t]
    light = Light(kind=kind, name=n.name or "")
    light.on = flag(ctx, n, "on", True)
    light.shadows = flag(ctx, n, "shadows", False)
    light.intensity = num(ctx, n, "intensity", 1.0)
    light.ambient_intensity = num(ctx, n, "ambientIntensity", 0.0)
    light.color = vec(ctx, n, "color", (1.0, 1.0, 1.0))
    if kind != "directional":
        light.location = vec(ctx, n, "location", (0.0, 0.0, 0.0))
        light.attenuation = vec(ctx, n, "attenuation", (1.0, 0.0, 0.0))
        light.radius = num(ctx, n, "radius", 100.0)
    if kind != "point":
        light.direction = vec(ctx, n, "direction", (0.0, 0.0, -1.0))
    if kind == "spot":
        beam, cut = SPOT_DEFAULTS["vrml97" if n.src.vrml97 else "x3d"]
        light.beam_width = angle(ctx, n, "beamWidth", beam)
        light.cut_off_angle = angle(ctx, n, "cutOffAngle", cut)
    light.is_global = flag(ctx, n, "global", kind != "directional")
    return light


def viewpoint(ctx, n, t):
    vp = Viewpoint(name=n.name or "", kind=t)
    vp.position = vec(ctx, n, "position", (0.0, 0.0, 10.0))
    vp.orientation = rotation(ctx, n, "orientation")
    if t == "OrthoViewpoint":
        vp.ortho_field = vec(ctx, n, "fieldOfView", (-1.0, -1.0, 1.0, 1.0))
    else:
        vp.field_of_view = angle(ctx, n, "fieldOfView", 0.785398)
    vp.center_of_rotation = vec(ctx, n, "centerOfRotation", (0.0, 0.0, 0.0))
    vp.description = string(ctx, n, "description", "")
    if n.src is ctx.main and ctx.doc.viewpoint is None:
        ctx.doc.viewpoint = vp
    return vp


def bindable(ctx, n, t):
    """The first NavigationInfo, Background and WorldInfo of the main file (an inlined
    file's are not bound, as the standard says)."""
    if n.src is not ctx.main or t in ctx.bound:
        return
    ctx.bound.add(t)
    doc = ctx.doc
    if t == "NavigationInfo":
        doc.headlight = flag(ctx, n, "headlight", True)
        if field(ctx, n, "type") is not _MISSING:
            doc.navigation_types = strings(ctx, n, "type")
    elif t == "Background":
        sky = numbers(ctx, n, "skyColor")
        doc.background = tuple(float(v) for v in sky[:3]) if sky is not None \
            and len(sky) >= 3 else (0.0, 0.0, 0.0)
    elif t == "WorldInfo":
        doc.title = string(ctx, n, "title", "")
        doc.info = strings(ctx, n, "info")


def inline(ctx, n, depth, hint):
    group = Transform(name=n.name or "", kind="Inline")
    if not flag(ctx, n, "load", True):
        return group
    urls = strings(ctx, n, "url")
    path = None
    for url in urls:
        candidate = ctx.resolver(url, n.src.base)
        if candidate and os.path.isfile(candidate):
            path = candidate
            break
    if path is None:
        ctx.notes.add("Inline files not found: left out", urls[0] if urls else "(no url)")
        return group
    real = os.path.realpath(path)
    if real in ctx.loading or real == os.path.realpath(ctx.main.path or "."):
        ctx.notes.add("Inline files that include themselves: left out",
                      os.path.basename(path))
        return group
    src = parse_file(ctx, real, len(ctx.loading) + 1)
    if src is None:
        return group
    if src.meter != n.src.meter:
        ratio = src.meter / n.src.meter
        group.matrix = np.diag([ratio, ratio, ratio, 1.0])
    ctx.loading.append(real)
    try:
        for kid in src.nodes:
            child = build(ctx, kid, depth + 1, hint, "child")
            if child is not None:
                group.children.append(child)
    finally:
        ctx.loading.pop()
    return group


# the end ------------------------------------------------------------------------------

def finish(ctx, doc):
    """The counts and notes of the reading *ctx* into the warnings of *doc*, a kind once."""
    if ctx.ignored:
        shown = ", ".join(f"{k} ×{v}" if v > 1 else k for k, v in sorted(ctx.ignored.items()))
        doc.warn("not imported (animation, interaction, scripts, sound, shaders, fog): "
                 + shown)
    if ctx.unknown:
        shown = ", ".join(f"{k} ×{v}" if v > 1 else k for k, v in sorted(ctx.unknown.items()))
        doc.warn(f"unknown node types skipped (their children read where they have them): "
                 f"{shown}")
    if ctx.too_deep:
        doc.warn(f"nodes nested deeper than {MAX_DEPTH} levels left out ({ctx.too_deep})")
    for line in ctx.notes.lines():
        doc.warn(line)
