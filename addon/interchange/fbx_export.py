# SPDX-License-Identifier: GPL-3.0-or-later
"""FBX with Phong materials (issue 45): Blender's own exporter writes the file, then the Phong
parts are rewritten (``core/fbx_write.py``) and the file is put in place atomically.

Each Phong material (read by ``materials.feeds``, the one reader of a Phong material) becomes
an FBX Phong material, or a Lambert where its Specular Color is black (as a Lambert imports):

    DiffuseColor = Object Color        AmbientColor = Ambient Object Color
    SpecularColor = Specular Color     ShininessExponent = Shininess = Exponent
    EmissiveColor = Irradiant Color    every factor 1, ReflectionFactor 0
    Opacity o, TransparencyFactor 1 − o, TransparentColor white

Each Phong light (Point, Sun, Spot): LightType; Color; Intensity = 100 × Phong intensity (the
importer's Intensity / 100); DecayType k of the falloff (1/d^k: a single term c·r^k of
i₀/(αr²+βr+γ) is exact, with Intensity = 100·i₀/c; a mixed one is written as its highest
term, with a warning; the power falloff's k, rounded into 0-3); a spot's OuterAngle = Spot
Size and InnerAngle per the scene's lighting model (seeds: where the edge factor
(cos ω)^e_att is ½, the inverse of the importer's rule; three.js: (1 − penumbra) × Outer;
X3D: the beam width); CastShadows = Cast Shadow.  The World's Phong ambient (colour ×
intensity) is GlobalSettings' AmbientColor.

What FBX cannot say is kept as user properties ``PhongNodes|<key>`` that the importer reads
back, so that import ∘ export gives every control again, each kind named in one warning: a
material's Blinn, Specular Strength and a Lambert's Exponent; a light's settings that the
written FBX values do not give back (coefficients of a mixed falloff, the power falloff, the
other models' settings ...); the World's ambient intensity.  An image texture feeding a
colour (alone, or times a colour control as the importers make it) is an FBX Texture (and
Video) on its property, the colour white or that control's (the importer reads colour ×
texture back).  Principled and other materials are written as Blender writes them.
"""

from __future__ import annotations

import math
import os
import tempfile

import bpy

from ...core import fbx as fbx_read
from ...core import fbx_write, outputs
from ..lighting import materials as recipe
from ..lighting import properties, rig
from .native import ensure_fbx_addon

#: The importer's reading of a material's user properties: key -> lights-group input.
MATERIAL_USER = {"Blinn": "Blinn", "SpecularStrength": "Specular Strength"}
BLACK = (0.0, 0.0, 0.0)


def _close(a, b) -> bool:
    return abs(a - b) <= 1e-6 * max(1.0, abs(a), abs(b))


#: The colour inputs that take a texture, and the FBX property it is written on.
TEXTURE_PROPS = {"Object Color": "DiffuseColor", recipe.AMBIENT_INPUT: "AmbientColor",
                 "Specular Color": "SpecularColor", "Irradiant Color": "EmissiveColor"}


def _texture(node, folder):
    """The fbx_write.Texture of the Image Texture *node* (its file), or None for an image
    without a file (packed or generated)."""
    image = node.image
    if image.packed_file is not None or image.source != "FILE":
        return None
    path = os.path.abspath(bpy.path.abspath(image.filepath, library=image.library))
    try:
        relative = os.path.relpath(path, folder)
    except ValueError:   # another drive (Windows)
        relative = path
    return fbx_write.Texture(path, relative, os.path.basename(path) or image.name)


def material_of(material, warnings: list, folder: str = "") -> fbx_write.Material:
    """The FBX Phong (or Lambert) values of the Phong material *material* (*folder*: the
    FBX file's, for the textures' relative paths).  A colour fed by an image texture (alone:
    colour white, or times a colour: that colour) is that colour with the texture on its
    property, as the importer reads it back (colour × texture)."""
    feeds = recipe.feeds(material)
    name = material.name
    textures, values = {}, {}
    for key, prop in TEXTURE_PROPS.items():
        feed = feeds[key]
        values[key] = feed.value
        if feed.texture is None:
            continue
        texture = _texture(feed.texture, folder)
        if texture is None:
            warnings.append(f"material {name}: {key}'s image {feed.texture.image.name!r} has "
                            "no file (packed or generated): the colour written without it")
            continue
        textures[prop] = texture
        if feed.other is feed.texture:   # the texture alone: white × texture
            values[key] = (1.0, 1.0, 1.0)
    fed = [k for k, f in feeds.items() if f.other is not None and f.texture is None
           and k != "Opacity"]
    if fed:
        warnings.append(f"material {name}: {', '.join(fed)} fed by nodes FBX cannot say; "
                        "the control's value written")
    if feeds["Opacity"].other is not None:
        warnings.append(f"material {name}: its opacity map left out (the Opacity control's "
                        "value written)")
    specular = values["Specular Color"]
    lambert = all(c == 0.0 for c in specular) and "SpecularColor" not in textures
    out = fbx_write.Material(
        lambert=lambert, diffuse=values["Object Color"], ambient=values[recipe.AMBIENT_INPUT],
        specular=specular, emissive=values["Irradiant Color"],
        exponent=max(feeds["Exponent"].value, 0.0),
        opacity=min(max(feeds["Opacity"].value, 0.0), 1.0), textures=textures)
    blinn = feeds["Blinn"].value
    if blinn != 0.0:
        out.user["Blinn"] = blinn
    strength = feeds.get("Specular Strength")
    if strength is not None and strength.value != 1.0:
        out.user["SpecularStrength"] = strength.value
    if lambert and out.exponent != fbx_read.SURFACE_DEFAULTS["ShininessExponent"]:
        out.user["Exponent"] = out.exponent
    if out.user:
        warnings.append(f"material {name}: kept as FBX user properties (FBX's Phong cannot "
                        "say them): " + ", ".join(fbx_write.USER + k for k in out.user))
    return out


def _spot_inner(light, model, outer) -> float:
    """The FBX InnerAngle (degrees, full cone) of a spot whose OuterAngle is *outer*."""
    if model == "threejs":
        inner = outer * (1.0 - float(light.get("phong_penumbra", 0.0)))
    elif model == "x3d":
        key, default = properties.LIGHT_KEYS["beam_width"]
        inner = 2.0 * math.degrees(float(light.get(key, default)))
    else:   # seeds: (cos ω)^e = ½ at ω = (Inner + Outer) / 4 (fbx.spot_edge_exponent)
        e = float(light.get("phong_edge_exponent", 0.0))
        inner = outer if e <= 0.0 else 4.0 * math.degrees(math.acos(0.5 ** (1.0 / e))) - outer
    return min(max(inner, 0.0), outer)


def light_of(light, scene, warnings: list) -> fbx_write.Light:
    """The FBX values of the Blender light *light* (Point, Sun, Spot) and, as user properties,
    its Phong settings that those values do not give back."""
    name = light.name
    values = {attr: float(light.get(key, default))
              for attr, (key, default) in properties.LIGHT_KEYS.items()}
    out = fbx_write.Light(type=light.type, color=tuple(float(c) for c in light.color),
                          intensity=100.0 * values["intensity"], decay=0,
                          cast_shadows=bool(light.use_shadow))
    power = False
    if light.type != "SUN":
        falloff = properties.falloff_of(light)
        if falloff == "POWER":
            power = True
            k = values["power_k"]
            out.decay = int(min(max(round(k), 0), 3))
            if k != out.decay:
                warnings.append(f"light {name}: power falloff k = {k:g} written as the nearest "
                                f"FBX DecayType (1/d^{out.decay})")
        else:
            terms = [(2, values["quadratic"]), (1, values["linear"]), (0, values["constant"])]
            used = [(k, c) for k, c in terms if c != 0.0]
            if not used:
                warnings.append(f"light {name}: falloff 1/0 (every coefficient 0) written "
                                "without decay")
            else:
                out.decay, c = used[0]
                out.intensity = 100.0 * values["intensity"] / c
                if len(used) > 1:
                    warnings.append(f"light {name}: mixed falloff i0/(αr²+βr+γ) written as "
                                    f"its highest term, FBX DecayType 1/d^{out.decay}")
    if light.type == "SPOT":
        out.outer_angle = math.degrees(light.spot_size)
        out.inner_angle = _spot_inner(light, rig.model_of(scene), out.outer_angle)
    # what the importer derives from the written values (fbx_import.apply_light)
    derived = {attr: default for attr, (_key, default) in properties.LIGHT_KEYS.items()}
    derived["intensity"] = out.intensity / 100.0
    if light.type != "SUN":
        rule = fbx_read.falloff(out.decay)
        derived.update({k: v for k, v in rule.items() if k in derived})
        if (rule.get("falloff") == "POWER") != power:
            out.user["falloff_power"] = 1.0 if power else 0.0
    if light.type == "SPOT" and out.outer_angle > 0.0:
        derived["edge_exponent"] = fbx_read.spot_edge_exponent(out.outer_angle,
                                                               out.inner_angle)
        derived["penumbra"] = min(max(1.0 - out.inner_angle / out.outer_angle, 0.0), 1.0)
    for attr, value in values.items():
        if not _close(value, derived[attr]):
            out.user[attr] = value
    if out.user:
        warnings.append(f"light {name}: Phong settings kept as FBX user properties: "
                        + ", ".join(fbx_write.USER + k for k in sorted(out.user)))
    return out


def _ambient(scene):
    """(GlobalSettings AmbientColor, user properties) of the World's Phong ambient."""
    world = scene.world
    key, default = properties.AMBIENT_INTENSITY
    color_key, default_color = properties.AMBIENT_COLOR
    if world is None:
        return None, {}
    intensity = float(world.get(key, default))
    color = tuple(float(c) for c in tuple(world.get(color_key, default_color))[:3])
    user = {}
    if intensity != 1.0:
        user = {"AmbientIntensity": intensity, "AmbientR": color[0], "AmbientG": color[1],
                "AmbientB": color[2]}
    return tuple(intensity * c for c in color), user


def export(context, filepath, use_selection=False, **options) -> list:
    """Write *context*'s scene to the FBX file *filepath* (Blender's exporter with *options*,
    its keyword arguments, then the Phong parts); returns the warnings.  Raises OSError or
    ValueError (the file is then left as it was)."""
    if not ensure_fbx_addon():
        raise ValueError("Blender's FBX exporter (io_scene_fbx) is not available")
    path = os.path.abspath(bpy.path.abspath(filepath))
    warnings = []
    scene = context.scene
    layer = context.view_layer
    objects = [o for o in layer.objects if not use_selection or o.select_get()]
    phong, lights = {}, {}
    for obj in objects:
        for slot in getattr(obj, "material_slots", ()):
            material = slot.material
            if material is not None and material.name not in phong and \
                    recipe.is_phong_material(material):
                phong[material.name] = material
        if obj.type == "LIGHT" and obj.data.type in fbx_write.LIGHT_TYPES and \
                obj.data.name not in lights:
            lights[obj.data.name] = obj.data
    values = {n: material_of(m, warnings, os.path.dirname(path)) for n, m in phong.items()}
    light_values = {n: light_of(l, scene, warnings) for n, l in lights.items()}
    ambient, ambient_user = _ambient(scene)
    folder = os.path.dirname(path)
    fd, first = tempfile.mkstemp(prefix=outputs.temp_prefix("partial", "blender_fbx"),
                                 suffix=".fbx", dir=folder)
    os.close(fd)
    try:
        try:
            result = bpy.ops.export_scene.fbx(filepath=first, use_selection=use_selection,
                                              **options)
        except (RuntimeError, TypeError) as error:   # its own error, or an unknown option
            last = [line for line in str(error).splitlines() if line.strip()][-1:] or [""]
            raise ValueError(f"Blender's FBX exporter failed ({last[0][:200]})") from None
        if result != {"FINISHED"}:
            raise ValueError(f"Blender's FBX exporter did not finish ({result})")
        with open(first, "rb") as handle:
            data = handle.read()
        new, _missing = fbx_write.rewrite(data, values, light_values, ambient, ambient_user)
        outputs.write_file(path, new)
    except fbx_write.FbxWriteError as error:
        raise ValueError(f"the file Blender's exporter wrote cannot be rewritten ({error})") \
            from None
    finally:
        if os.path.exists(first):
            os.remove(first)
    if ambient_user:
        warnings.append("the World's Phong ambient intensity kept as FBX user properties "
                        "(AmbientColor = intensity × colour)")
    return warnings
