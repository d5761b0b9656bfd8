# SPDX-License-Identifier: GPL-3.0-or-later
"""FBX with Phong materials: Blender's own exporter writes the file, then the Phong parts are
rewritten (``core/fbx``: ``phong`` the mapping, ``write`` the splice) and the file is put in
place atomically.  This module reads Blender; what each value becomes is ``core/fbx/phong``'s.

Each Phong material (read by ``feeds.feeds``, the one reader of a Phong material) becomes
an FBX Phong material, or a Lambert where its Specular Color is black (as a Lambert imports):

    DiffuseColor = Object Color        AmbientColor = Ambient Object Color
    SpecularColor = Specular Color     ShininessExponent = Shininess = Exponent
    EmissiveColor = Irradiant Color    every factor 1, ReflectionFactor 0
    Opacity o, TransparencyFactor 1 − o, TransparentColor white

Each Phong light (Point, Sun, Spot; an Area light as the spot that draws it, a 180° cone):
LightType; Color; Intensity = 100 × Phong intensity (the importer's Intensity / 100); DecayType k of the falloff (1/d^k: a single term c·r^k of
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
colour (alone, times a colour control as the importers make it, or in another chain of
products such as X3D's texture × diffuseColor) is an FBX Texture (and Video) on its
property, the colour white, that control's or the chain's numbers (the importer reads colour ×
texture back; a colour map read as data marked ``NonColor<property>``); an exponent map
(Exponent × mean(texel)) on ShininessExponent; an opacity map
on TransparencyFactor / TransparentColor (a texel's alpha as Blender's exporter writes it,
else the FBX SDK's rule: ``_opacity_map``).  An image file's path is written whether or not
the file is there; a packed image is written beside the FBX file.  Principled and other
materials are written as Blender writes them.
"""

from __future__ import annotations

import os
import tempfile

import bpy

from ...core import fbx, outputs
from ...node_groups import models
from .. import compat
from ..lighting import feeds as feed_reader
from ..lighting import properties, recipe, rig
from . import keys, native
from .native import ensure_fbx_addon

#: The colour inputs that take a texture (each written on its FBX property: fbx.PROPERTY_OF).
TEXTURE_INPUTS = ("Object Color", recipe.AMBIENT_INPUT, "Specular Color", "Irradiant Color")
#: The file name suffix of a packed image written beside the FBX file, by its format.
SUFFIXES = {"PNG": ".png", "JPEG": ".jpg", "TARGA": ".tga", "TARGA_RAW": ".tga", "BMP": ".bmp",
            "TIFF": ".tif", "OPEN_EXR": ".exr", "OPEN_EXR_MULTILAYER": ".exr", "HDR": ".hdr",
            "WEBP": ".webp", "JPEG2000": ".jp2", "CINEON": ".cin", "DPX": ".dpx"}
WHITE = (1.0, 1.0, 1.0)
#: The FBX properties whose maps are colours (read in the image's colour space, sRGB for
#: 8-bit files); a map of one of them whose image is data (Non-Color: X3D's texels, which
#: enter the equation as numbers) is marked ``NonColor<property>`` for the importer.
COLOUR_MAPS = ("DiffuseColor", "AmbientColor", "SpecularColor", "EmissiveColor",
               "TransparentColor")
NON_COLOR_USER = fbx.NON_COLOR_USER
MEAN = 1.0 / 3.0


class Textures:
    """The image files of one export: a file image's own path (whether or not the file is
    there: a scene received without its textures keeps its references, as Blender's
    exporter writes them), a packed image's bytes written beside the FBX file once
    (:attr:`pending`: written once the rewrite has succeeded, just before the FBX file is
    put in place; each file atomically)."""

    def __init__(self, folder: str, embed: bool = False, copy: bool = False):
        self.folder = folder
        self.embed = embed    # Blender's embed_textures (with path_mode COPY): Video Content
        self.copy = copy      # Blender's path_mode COPY: image files copied beside the FBX
        self.made = {}        # image name -> fbx.Texture
        self.pending = {}     # path beside the FBX -> bytes
        self.taken = set()

    def __call__(self, node, warnings, where):
        """The fbx.Texture of the Image Texture *node*, or None (a warning says why)."""
        image = node.image
        if image.name in self.made:
            return self.made[image.name]
        content = None
        if image.packed_file is not None:
            content = bytes(image.packed_file.data)
            path = self._beside(image, content)
            if not self.embed:
                self.pending[path] = content
                warnings.append(f"{where}: packed image {image.name!r} written beside the FBX "
                                f"file as {os.path.basename(path)}")
        elif image.source == "FILE" and image.filepath:
            path = os.path.abspath(bpy.path.abspath(image.filepath, library=image.library))
            if (self.embed or self.copy) and os.path.isfile(path):
                try:
                    with open(path, "rb") as handle:
                        content = handle.read()
                except OSError:
                    content = None
            if self.copy and not self.embed and content is not None and \
                    os.path.dirname(path) != self.folder:   # Blender's COPY: beside the FBX
                path = self._beside(image, content)
                self.pending[path] = content
        else:
            warnings.append(f"{where}: image {image.name!r} has no file (generated): left "
                            "out")
            return None
        try:
            relative = os.path.relpath(path, self.folder)
        except ValueError:   # another drive (Windows)
            relative = path
        texture = fbx.Texture(name=os.path.basename(path) or image.name, candidates=(path,),
                              relative=relative,
                              data=image.colorspace_settings.name == native.NON_COLOR,
                              content=content if self.embed else None)
        self.made[image.name] = texture
        return texture

    def _beside(self, image, data: bytes) -> str:
        """A file name beside the FBX for the bytes *data* of *image* (its own file's name,
        else its name with the suffix of its format), one not taken by another image of the
        export nor by a different file already there."""
        base = bpy.path.basename(image.filepath) or image.name
        base = "".join(c if c.isalnum() or c in "._- " else "_" for c in base).strip(". ") \
            or "texture"
        stem, suffix = os.path.splitext(base)
        if not suffix:
            suffix = SUFFIXES.get(image.file_format, ".png")
        for n in range(1000):
            name = stem + ("" if n == 0 else f"_{n}") + suffix
            path = os.path.join(self.folder, name)
            if path in self.taken:
                continue
            if os.path.exists(path):
                try:
                    with open(path, "rb") as handle:
                        if handle.read() != data:
                            continue
                except OSError:
                    continue
            self.taken.add(path)
            return path
        raise ValueError(f"no free file name beside the FBX file for the image {image.name!r}")

    def write(self) -> None:
        for path, data in self.pending.items():
            outputs.write_file(path, data)


# -- the chains of the opacity and exponent maps ----------------------------------------------

def _walk(socket, depth=0):
    """The number the output *socket* gives, as the importers build a map's chain: a
    product ("prod", k, maps) of a constant k and maps, each ("alpha", image node, None) or
    ("mean", image node, colour): mean(colour ⊗ texel); or one minus such a product
    ("one_minus", k, maps).  None for any other node."""
    node = socket.node
    kind = node.bl_idname
    if depth > 12:
        return None
    if kind == "ShaderNodeValue":
        return ("prod", float(compat.value_output(node).default_value), [])
    if kind == "ShaderNodeTexImage" and node.image is not None and \
            socket.identifier == "Alpha":
        return ("prod", 1.0, [("alpha", node, None)])
    if kind == "ShaderNodeVectorMath" and node.operation == "DOT_PRODUCT":
        a, b = (compat.input_socket(node, k) for k in ("Vector", "Vector_001"))
        if b.is_linked and not a.is_linked:
            a, b = b, a
        if not a.is_linked or b.is_linked or \
                any(abs(v - MEAN) > 1e-6 for v in tuple(b.default_value)[:3]):
            return None
        colour = _colour(a.links[0].from_socket, depth + 1)
        return None if colour is None else ("prod", 1.0, [("mean", *colour)])
    if kind != "ShaderNodeMath" or node.operation not in ("MULTIPLY", "SUBTRACT"):
        return None
    terms = []
    for identifier in ("Value", "Value_001"):
        inp = compat.input_socket(node, identifier)
        terms.append(_walk(inp.links[0].from_socket, depth + 1) if inp.is_linked
                     else ("prod", float(inp.default_value), []))
    if None in terms:
        return None
    (a, ka, ma), (b, kb, mb) = terms
    if node.operation == "SUBTRACT":
        if a == "prod" and not ma and ka == 1.0 and b == "prod":
            return ("one_minus", kb, mb)
        return None
    if a == b == "prod":
        return ("prod", ka * kb, ma + mb)
    if a == "one_minus" and b == "prod" and kb == 1.0 and not mb:   # one minus ... times 1
        return ("one_minus", ka, ma)
    if b == "one_minus" and a == "prod" and ka == 1.0 and not ma:
        return ("one_minus", kb, mb)
    return None


def _colour(socket, depth):
    """(image node, colour) of a texel's colour times a constant colour, or None."""
    node = socket.node
    if node.bl_idname == "ShaderNodeTexImage" and node.image is not None and \
            socket.identifier == "Color":
        return node, WHITE
    if node.bl_idname == "ShaderNodeVectorMath" and node.operation == "MULTIPLY" and \
            depth < 12:
        a, b = (compat.input_socket(node, k) for k in ("Vector", "Vector_001"))
        if b.is_linked and not a.is_linked:
            a, b = b, a
        if a.is_linked and not b.is_linked:
            inner = _colour(a.links[0].from_socket, depth + 1)
            if inner is not None:
                return inner[0], tuple(x * float(y) for x, y in
                                       zip(inner[1], tuple(b.default_value)[:3]))
    return None


def _is_data(node) -> bool:
    return node.image.colorspace_settings.name == native.NON_COLOR


def _exponent_map(feed, textures, out, warnings, where) -> bool:
    """The exponent map Exponent = k × mean(texel) (the importers' chain) as a texture on
    ShininessExponent with the exponent k; False where the Exponent is fed otherwise."""
    if feed.other is None or feed.socket is None:
        return False
    form = _walk(feed.socket)
    if form is None or form[0] != "prod" or len(form[2]) != 1 or \
            form[2][0][0] != "mean" or form[2][0][2] != WHITE:
        return False
    texture = textures(form[2][0][1], warnings, where)
    if texture is not None:
        out.textures["Exponent"] = texture
        out.exponent = max(form[1], 0.0)
    return True


def _opacity_map(node, textures, out, warnings, where) -> None:
    """The opacity map *node* (``recipe.OPACITY_MAP``) as FBX textures: a texel's alpha
    times k (X3D's texture alpha × Opacity, COLLADA's A_ONE) on TransparencyFactor, as
    Blender's exporter writes its alpha texture (k kept as ``OpacityAlphaScale`` where it is
    not 1); 1 − k × mean(TC ⊗ t_c) × mean(t_f) (the FBX SDK's rule, COLLADA's RGB_ZERO) on
    TransparentColor (a colour map) and TransparencyFactor (a data map) with
    TransparencyFactor k (``TransparencyMaps`` 1: read by the SDK's rule, not as an alpha).
    Any other chain: a warning, the Opacity control's value written."""
    form = _walk(compat.output_socket(node, "Value")) \
        if node.bl_idname == "ShaderNodeMath" else None
    written = False
    if form is not None and form[0] == "prod" and len(form[2]) == 1 and \
            form[2][0][0] == "alpha":
        texture = textures(form[2][0][1], warnings, where)
        if texture is not None:
            out.textures["TransparencyFactor"] = texture
            if form[1] != 1.0:
                out.user["OpacityAlphaScale"] = form[1]
        written = True
    elif form is not None and form[0] == "one_minus" and 1 <= len(form[2]) <= 2 and \
            all(kind == "mean" for kind, _n, _c in form[2]):
        slots = {}
        for _kind, image, colour in sorted(form[2], key=lambda m: _is_data(m[1])):
            prop = "TransparencyFactor" if colour == WHITE and _is_data(image) and \
                "TransparencyFactor" not in slots else "TransparentColor"
            if prop in slots:
                slots = None
                break
            slots[prop] = (image, colour)
        if slots is not None:
            for prop, (image, colour) in slots.items():
                texture = textures(image, warnings, where)
                if texture is not None:
                    out.textures[prop] = texture
                    if prop == "TransparentColor":
                        out.transparent_color = colour
            out.transparency_factor = form[1]
            if out.transparent_color is None:
                out.transparent_color = WHITE
            out.user["TransparencyMaps"] = 1.0
            written = True
    if not written:
        warnings.append(f"{where}: its opacity map is a chain FBX cannot say: left out (the "
                        "Opacity control's value written)")


def material_of(material, warnings: list, folder: str = "", textures=None) -> fbx.Material:
    """The FBX Phong (or Lambert) values of the Phong material *material* (*folder*: the
    FBX file's, for the textures' relative paths; *textures*: the export's
    :class:`Textures`).  A colour fed by an image texture (alone: colour white, or times a
    colour: that colour) is that colour with the texture on its property, as the importer
    reads it back (colour × texture); the exponent and opacity maps as ``_exponent_map`` and
    ``_opacity_map`` say.  The values become FBX's by ``fbx.material_of``."""
    if textures is None:
        textures = Textures(folder)
    feeds = feed_reader.feeds(material)
    name = material.name
    where = f"material {name}"
    maps, values, mapped = {}, {}, set()
    for key in TEXTURE_INPUTS:
        feed = feeds[key]
        values[key] = feed.value
        node, colour, chain = feed.texture, None, feed.chain
        if node is None and chain is not None and chain.texture is not None and \
                not chain.unknown and chain.attribute is None:
            # another chain of products: colours × a scale × the texel (X3D's texture ×
            # diffuseColor, ambientIntensity × texel ...): the product of the numbers
            node = chain.texture
            scale = 1.0 if chain.scale is None else chain.scale
            colour = tuple(c * scale for c in (chain.colour or WHITE))
        if node is None:
            continue
        mapped.add(key)
        texture = textures(node, warnings, where)
        if texture is None:
            continue
        maps[key] = texture
        if colour is not None:
            values[key] = colour
        elif feed.other is feed.texture:   # the texture alone: white × texture
            values[key] = WHITE
    values["Exponent"] = feeds["Exponent"].value
    values["Opacity"] = feeds["Opacity"].value
    out = fbx.material_of(values, maps, name)
    lambert = out.lambert
    exponent_mapped = not lambert and _exponent_map(feeds["Exponent"], textures, out,
                                                    warnings, where)
    fed = [k for k, f in feeds.items() if f.other is not None and k not in mapped
           and k != "Opacity" and not (k == "Exponent" and exponent_mapped)]
    if fed:
        warnings.append(f"{where}: {', '.join(fed)} fed by nodes FBX cannot say; "
                        "the control's value written")
    if feeds["Opacity"].other is not None:
        _opacity_map(feeds["Opacity"].other, textures, out, warnings, where)
    for key, texture in out.textures.items():
        prop = fbx.PROPERTY_OF[key]
        if prop in COLOUR_MAPS and texture.data:   # a colour map read as data (X3D's texels)
            out.user[NON_COLOR_USER + prop] = 1.0
    kept = []
    taken = {fbx.PROPERTY_OF[key] for key in out.textures}
    by_property = {prop: key for key, prop in fbx.PROPERTY_OF.items()}
    for prop, entry in (material.get(keys.FBX_MISSING_MAPS) or {}).items():
        if prop in taken or prop not in by_property or \
                (lambert and prop in ("SpecularColor", "ShininessExponent")):
            continue   # the material has its own map there now
        path, near = str(entry.get("path", "")), str(entry.get("near", ""))
        if not path and not near:
            continue
        try:
            relative = os.path.relpath(near or path, textures.folder)
        except ValueError:   # another drive (Windows)
            relative = near or path
        out.textures[by_property[prop]] = fbx.Texture(
            name=os.path.basename(path or near), candidates=(path or near,), relative=relative)
        kept.append(prop)
    if kept:
        warnings.append(f"{where}: the file's references kept for the maps whose files were "
                        f"not there at import: {', '.join(kept)}")
    strength = feeds.get("Specular Strength")
    if fbx.keep_unsaid(out, feeds["Blinn"].value,
                       None if strength is None else strength.value):
        warnings.append(f"{where}: kept as FBX user properties (FBX's Phong cannot "
                        "say them): " + ", ".join(fbx.USER + k for k in out.user))
    return out


def light_of(light, scene, warnings: list) -> fbx.Light:
    """The FBX values of the Blender light *light* (Point, Sun, Spot; an Area light as the
    spot that draws it) and, as user properties, its Phong settings that those values do not
    give back: what the light holds, read by ``properties.light_values``, mapped by
    ``fbx.light_of`` in the scene's lighting model."""
    values = properties.light_values(light)   # i0 its own or its Power's
    defaults = {attr: default for attr, (_key, default) in properties.LIGHT_KEYS.items()}
    out, notes = fbx.light_of(light.type, values["color"], values["settings"],
                              values["falloff"], values["spot_size"], light.use_shadow,
                              models.get(rig.model_of(scene)), defaults, light.name)
    warnings.extend(notes)
    return out


def _ambient(scene):
    """(GlobalSettings AmbientColor, user properties) of the World's Phong ambient."""
    world = scene.world
    if world is None:
        return None, {}
    key, default = properties.AMBIENT_INTENSITY
    color_key, default_color = properties.AMBIENT_COLOR
    return fbx.ambient_of(float(world.get(key, default)), world.get(color_key, default_color))


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
        if obj.type == "LIGHT" and obj.data.type in fbx.EXPORTED and \
                obj.data.name not in lights:
            lights[obj.data.name] = obj.data
    textures = Textures(os.path.dirname(path), embed=bool(options.get("embed_textures"))
                        and options.get("path_mode") == "COPY",
                        copy=options.get("path_mode") == "COPY")
    values = {n: material_of(m, warnings, textures=textures) for n, m in phong.items()}
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
        new, _missing = fbx.rewrite(data, values, light_values, ambient, ambient_user)
        textures.write()
        outputs.write_file(path, new)
    except fbx.FbxWriteError as error:
        raise ValueError(f"the file Blender's exporter wrote cannot be rewritten ({error})") \
            from None
    finally:
        if os.path.exists(first):
            os.remove(first)
    if ambient_user:
        warnings.append("the World's Phong ambient intensity kept as FBX user properties "
                        "(AmbientColor = intensity × colour)")
    return warnings
