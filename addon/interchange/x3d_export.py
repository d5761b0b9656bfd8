# SPDX-License-Identifier: GPL-3.0-or-later
"""The scene written as VRML97 / X3D (``core/x3d.save``: ``.x3d`` XML, ``.x3dv`` ClassicVRML,
``.wrl`` VRML97, gzipped as ``.x3dz``, ``.x3dvz``, ``.wrz``, ``.gz``), in metres, Y up.

The inverse of ``x3d_import`` (docs/interchange.md, "X3D / VRML97"):

* every mesh object a Transform (its world matrix, Z up turned to Y up) named after it,
  holding a Shape per material slot it uses: an IndexedFaceSet of the slot's faces (``solid``
  the material's Backface Culling; corner normals unless every face is flat, texture
  coordinates where its material has a texture, colours where its material shows the colour
  attribute), loose edges an IndexedLineSet, a mesh of bare vertices a PointSet; objects
  that share a mesh share its geometry (DEF/USE);
* each Phong material a Material from its controls: diffuseColor = Object Color, specularColor
  = Specular Color, emissiveColor = Irradiant Color, shininess = Exponent / 128 (clamped to
  [0, 1], with a warning above 128), ambientIntensity = Ka / Kd where the Ambient Object Color
  is a multiple of the Object Color (else the best multiple, with a warning), transparency = 1
  − Opacity; an Image Texture feeding Object Color an ImageTexture (with its TextureTransform;
  its alpha × Opacity as the opacity map is what X3D says with the texture's alpha), or a
  PixelTexture of its texels where the image has no file (packed or generated: an imported
  PixelTexture comes back as one),
  a colour attribute a Color node; a material imported from a shape without Material (Kd, Ka,
  Ks black) a Shape without Material again;
* lights with their X3D values: ``on`` (hidden from render: FALSE), intensity, ambient
  intensity, colour, location and direction in the world, attenuation (a0, a1, a2) =
  (Constant, Linear, Quadratic), radius, beamWidth, cutOffAngle = half the spot size; a
  light-linked light a ``global FALSE`` light in a Group of exactly the objects it reaches
  (VRML97: directional lights only; its point and spot lights are global, with a warning);
  the headlight (a Sun that follows the camera) ``NavigationInfo { headlight TRUE }``;
* the scene camera the Viewpoint (fieldOfView the angle of the view's smaller side) or an
  OrthoViewpoint.

A scene in another lighting model is written with its values mapped as well as X3D allows,
and one warning says so.  Values are written as the shortest decimals that read back as the
same float32 (Blender's precision), and the file's own ambientIntensity, shininess and
cutOffAngle that an import kept are written back where the controls still hold them:
import → export → import keeps names and values.
"""

from __future__ import annotations

import math
import os

import bpy
import numpy as np

from ...core import x3d
from ...node_groups import models
from .. import compat
from ..lighting import feeds as feed_reader
from ..lighting import headlight as headlight_mod
from ..lighting import lights as lights_mod
from ..lighting import properties, recipe, rig
from ..lighting import sources as source_materials
from . import keys, native

#: Blender's Z up to the file's Y up (the inverse of x3d.Y_UP_TO_Z_UP: a rotation).
Z_UP_TO_Y_UP = x3d.Y_UP_TO_Z_UP.T.copy()
#: The largest image without a file written as a PixelTexture (texels: 1024 × 1024, about
#: 10 MB of text); a larger one is left out with a warning.
MAX_PIXELS = 1 << 20


#: The shortest decimal that reads back as the same float32 (the mapping's, core/x3d/phong).
f32 = x3d.f32
_colour = x3d.colour32


def encoding_of(path: str) -> str:
    """The encoding *path*'s extension asks for; ValueError for another name."""
    lower = path.lower()
    stem = lower[:-3] if lower.endswith(".gz") else lower
    for packed, plain in ((".x3dz", ".x3d"), (".x3dvz", ".x3dv"), (".wrz", ".wrl")):
        if stem.endswith(packed):
            stem = stem[:-len(packed)] + plain
    for ending, encoding in ((".x3dv", "x3d-classic"), (".x3d", "x3d-xml"), (".wrl", "vrml97"),
                             (".vrml", "vrml97")):
        if stem.endswith(ending):
            return encoding
    raise ValueError(f"{path}: not an X3D or VRML file name (.x3d, .x3dv, .wrl; gzipped .x3dz, "
                     ".x3dvz, .wrz or .gz)")


def export(context, filepath, use_selection=False, shadows=True) -> list:
    """Write *context*'s scene to *filepath* (the encoding by its extension); returns the
    warnings.  ValueError for a file name of no X3D encoding, OSError when it cannot be
    written (nothing half-written: ``core.outputs.write_file``).  *shadows*: a light whose
    Cast Shadow is on gets ``shadows TRUE`` (X3D files only; where this Blender casts Phong
    shadows); False leaves every light at X3D's default, none."""
    warnings: list = []
    encoding_of(filepath)
    doc = document(context, filepath, use_selection, warnings)
    if not shadows:
        for light in doc.lights:
            light.light.shadows = False
    x3d.save(doc, filepath)
    return warnings


class _Warnings(list):
    def add(self, text):
        if text not in self:
            self.append(text)


def document(context, filepath, use_selection, warnings) -> x3d.Document:
    """The scene as a ``core.x3d.Document`` (world coordinates, Y up, metres)."""
    out = _Warnings()
    writer = _Writer(context, filepath, use_selection, out)
    doc = writer.build()
    warnings.extend(out)
    return doc


class _Writer:
    def __init__(self, context, filepath, use_selection, warnings):
        self.context = context
        self.scene = context.scene
        self.layer = context.view_layer
        self.collections = lights_mod.render_collections(self.layer)  # once, not per object
        self.path = os.path.abspath(filepath)
        self.folder = os.path.dirname(self.path)
        self.selection = use_selection
        self.warnings = warnings
        self.pixel_textures = {}    # (image name, extension) -> x3d.Texture, written once
        self.encoding = encoding_of(filepath)
        self.model = models.get(rig.model_of(self.scene))   # its mapping to X3D's values
        self.appearances = {}     # material name -> (Appearance or None, uses colours, attr)
        self.geometries = {}      # (mesh name, slot, UVs, colours attr) -> x3d.Mesh
        self.materials = {}       # material name -> x3d.Material

    def chosen(self, obj) -> bool:
        return not self.selection or obj.select_get()

    def build(self) -> x3d.Document:
        scene = self.scene
        doc = x3d.Document(path=self.path, encoding=self.encoding, version="3.3",
                           profile="Immersive", meter=1.0, title=scene.name,
                           navigation_types=["EXAMINE", "ANY"])
        note = x3d.model_note(self.model, scene.name)
        if note:
            self.warnings.add(note)
        meshes = [o for o in scene.objects if o.type == "MESH" and self.chosen(o)
                  and lights_mod.visible(o, self.layer, self.collections) and not o.hide_render]
        lights = [o for o in scene.objects if o.type == "LIGHT" and self.chosen(o)]
        other = sorted({o.type for o in scene.objects if self.chosen(o) and o.type not in
                        ("MESH", "LIGHT", "CAMERA", "EMPTY", "ARMATURE") and not o.hide_render})
        if other:
            self.warnings.add(f"objects of other types left out (convert them to meshes "
                              f"first): {', '.join(other)}")
        heads = [o for o in lights if headlight_mod.is_headlight(o, scene)]
        doc.headlight = False
        for obj in heads:
            if obj.hide_render or not lights_mod.visible(obj, self.layer, self.collections):
                continue
            doc.headlight = True
            read = properties.light_values(obj.data)
            values = (read["settings"]["intensity"], read["settings"]["ambient"],
                      read["color"])
            if values[0] != 1.0 or values[1] != 0.0 or any(c != 1.0 for c in values[2]):
                self.warnings.add(f"headlight {obj.name}: X3D's headlight is white with "
                                  "intensity 1 and no ambient light; written as that")
        transforms = {obj.name: self.transform(obj) for obj in sorted(meshes,
                                                                      key=lambda o: o.name)}
        placed = self.lights([o for o in lights if o not in heads], meshes)
        root = doc.root.children
        vp = self.viewpoint()
        if vp is not None:
            root.append(vp)
            doc.viewpoint = vp
            near = float(self.scene.camera.data.clip_start)
            if 0.0 < near < 0.125:  # X3D browsers clip nearer than avatarSize[0] / 2
                doc.avatar_size = (f32(2.0 * near), 1.6, 0.75)
        root.extend(placed["root"])
        grouped = set()
        for group, members in placed["groups"]:
            group.children.extend(transforms[o.name] for o in members)
            grouped.update(o.name for o in members)
            root.append(group)
        root.extend(t for name, t in transforms.items() if name not in grouped)
        self.world_ambient(root)
        return doc

    # -- meshes -----------------------------------------------------------------------------
    def transform(self, obj) -> x3d.Transform:
        matrix = Z_UP_TO_Y_UP @ np.array(obj.matrix_world, dtype=np.float64)
        out = x3d.Transform(name=obj.name, kind="Transform", matrix=matrix)
        mesh = obj.data
        if [m for m in obj.modifiers if m.show_render and m.name != "Phong Shading"]:
            self.warnings.add(f"modifiers not applied (the mesh itself written): {obj.name}")
        slots = [slot.material for slot in obj.material_slots] or [None]
        used = self.used_slots(mesh, len(slots))
        for index in used:
            material = slots[index] if index < len(slots) else None
            appearance, colours, texture = self.appearance(material)
            # solid: the material's Backface Culling (Blender draws both sides without it)
            solid = bool(material is not None and material.use_backface_culling)
            key = (mesh.name, index if len(used) > 1 else -1, texture, colours, solid)
            geometry = self.geometries.get(key)
            if geometry is None:
                geometry = self.geometries[key] = self.geometry(
                    mesh, index if len(used) > 1 else None, texture, colours, solid)
            if geometry is None:
                continue
            out.children.append(x3d.Shape(name="", geometry=geometry, appearance=appearance))
        edges = self.loose_edges(mesh)
        if edges is not None:
            material = slots[0] if slots else None
            appearance, _colours, _texture = self.appearance(material)
            out.children.append(x3d.Shape(name="", geometry=edges, appearance=appearance))
        return out

    @staticmethod
    def used_slots(mesh, count) -> list:
        faces = len(mesh.polygons)
        if not faces:
            return [0] if not len(mesh.edges) else []
        index = np.zeros(faces, dtype=np.int32)
        mesh.polygons.foreach_get("material_index", index)
        index = np.clip(index, 0, max(count - 1, 0))
        return sorted(set(np.unique(index).tolist()))

    def geometry(self, mesh, slot, texture, colours, solid=False):
        """The faces of *mesh* (of material slot *slot*, or all) as an x3d.Mesh (*solid*:
        its back faces not drawn)."""
        n = len(mesh.vertices)
        positions = np.zeros(n * 3, dtype=np.float32)
        mesh.vertices.foreach_get("co", positions)
        positions = positions.reshape(-1, 3).astype(np.float64)
        faces = len(mesh.polygons)
        if not faces:   # bare vertices: a PointSet
            if not n:
                return None
            return x3d.Mesh(name=mesh.name, kind="PointSet", positions=positions,
                            point_colors=self.point_colours(mesh, colours))
        sizes = np.zeros(faces, dtype=np.int32)
        mesh.polygons.foreach_get("loop_total", sizes)
        loops = len(mesh.loops)
        corners = np.zeros(loops, dtype=np.int32)
        mesh.loops.foreach_get("vertex_index", corners)
        keep = np.ones(faces, bool)
        if slot is not None:
            index = np.zeros(faces, dtype=np.int32)
            mesh.polygons.foreach_get("material_index", index)
            keep = index == slot
        corner_keep = np.repeat(keep, sizes)
        smooth = np.zeros(faces, dtype=bool)
        mesh.polygons.foreach_get("use_smooth", smooth)
        normals = None
        crease = 0.0
        if mesh.has_custom_normals or smooth[keep].any():
            normals = np.zeros(loops * 3, dtype=np.float32)
            mesh.corner_normals.foreach_get("vector", normals) if hasattr(
                mesh, "corner_normals") else mesh.loops.foreach_get("normal", normals)
            normals = normals.reshape(-1, 3)[corner_keep].astype(np.float64)
        used = np.unique(corners[corner_keep])
        remap = np.full(n, -1, dtype=np.int64)
        remap[used] = np.arange(len(used))
        name = mesh.name if slot is None else f"{mesh.name} {slot}"
        out = x3d.Mesh(name=name, kind="IndexedFaceSet", positions=positions[used],
                       face_sizes=sizes[keep].astype(np.int64),
                       corners=remap[corners[corner_keep]], normals=normals, solid=solid,
                       crease_angle=crease)
        if texture:
            layer = mesh.uv_layers.get(keys.X3D_UV_MAP) or mesh.uv_layers.active
            if layer is not None:
                uv = np.zeros(loops * 2, dtype=np.float32)
                layer.data.foreach_get("uv", uv)
                out.uvs = uv.reshape(-1, 2)[corner_keep].astype(np.float64)
        if colours:
            values = self.corner_colours(mesh, colours, corners)
            if values is not None:
                out.colors = values[corner_keep]
        return out

    def loose_edges(self, mesh):
        """The edges of *mesh* that no face uses, as an IndexedLineSet (or None)."""
        count = len(mesh.edges)
        if not count:
            return None
        used = np.zeros(len(mesh.loops), dtype=np.int32)
        mesh.loops.foreach_get("edge_index", used)
        loose = np.ones(count, dtype=bool)
        loose[used] = False
        if not loose.any():
            return None
        pairs = np.zeros(count * 2, dtype=np.int32)
        mesh.edges.foreach_get("vertices", pairs)
        pairs = pairs.reshape(-1, 2)[loose]
        positions = np.zeros(len(mesh.vertices) * 3, dtype=np.float32)
        mesh.vertices.foreach_get("co", positions)
        used = np.unique(pairs)
        remap = np.full(len(mesh.vertices), -1, dtype=np.int64)
        remap[used] = np.arange(len(used))
        name = f"{mesh.name} lines" if len(mesh.polygons) else mesh.name
        return x3d.Mesh(name=name, kind="IndexedLineSet",
                        positions=positions.reshape(-1, 3)[used].astype(np.float64),
                        edges=remap[pairs])

    @staticmethod
    def _attribute(mesh, name):
        attribute = mesh.color_attributes.get(name) if name else None
        if attribute is None and len(mesh.color_attributes):
            attribute = mesh.color_attributes[0] if not name else None
        return attribute

    def corner_colours(self, mesh, name, corners):
        attribute = self._attribute(mesh, name)
        if attribute is None:
            return None
        values = np.zeros(len(attribute.data) * 4, dtype=np.float32)
        attribute.data.foreach_get("color", values)
        values = values.reshape(-1, 4).astype(np.float64)
        return values[corners] if attribute.domain == "POINT" else values

    def point_colours(self, mesh, name):
        attribute = self._attribute(mesh, name) if name else None
        if attribute is None or attribute.domain != "POINT":
            return None
        values = np.zeros(len(attribute.data) * 4, dtype=np.float32)
        attribute.data.foreach_get("color", values)
        return values.reshape(-1, 4).astype(np.float64)

    # -- materials --------------------------------------------------------------------------
    def appearance(self, material):
        """(Appearance or None, colour attribute name or "", whether it has a texture)."""
        key = material.name if material is not None else None
        if key in self.appearances:
            return self.appearances[key]
        if material is None:
            result = (x3d.Appearance(material=x3d.Material(name="Material")), "", False)
        elif not recipe.is_phong_material(material):
            color = source_materials.base_color(material) or (0.8, 0.8, 0.8)
            self.warnings.add(f"materials that are not Phong materials written as a Material "
                              f"of their base colour: {material.name}")
            result = (x3d.Appearance(material=x3d.Material(name=material.name,
                                                            diffuse=_colour(color))), "", False)
        else:
            result = self.phong(material)
        self.appearances[key] = result
        return result

    def phong(self, material):
        tree = material.node_tree
        name = material.name
        feeds = feed_reader.feeds(material)
        kd_feed = _feed(feeds["Object Color"])
        ka_feed = _feed(feeds[recipe.AMBIENT_INPUT])
        ks_feed = _feed(feeds["Specular Color"])
        ke_feed = _feed(feeds["Irradiant Color"])
        exponent = float(feeds["Exponent"].value)
        opacity = float(feeds["Opacity"].value)
        unlit = bool(material.get(keys.X3D_UNLIT))
        black = all(f.constant == (0.0, 0.0, 0.0) and f.texture is None and not f.colours
                    for f in (kd_feed, ka_feed, ks_feed))
        if unlit and black:   # a shape without Material: its texture / colours / white
            glow = ke_feed.control if ke_feed.control is not None else ke_feed.constant
            white = tuple(glow) == (1.0, 1.0, 1.0)
            texture = self.texture(ke_feed.texture, material, not white)
            transform = self.texture_transform(material) if texture is not None else None
            out = None
            if not white:
                if texture is not None or ke_feed.colours:
                    self.warnings.add(f"material {name}: an unlit texture or colours times a "
                                      "colour (X3D 3 has no unlit colour that multiplies); "
                                      "written as the colour")
                out = x3d.Material(name=name, diffuse=(0.0, 0.0, 0.0), ambient_intensity=0.0,
                                   specular=(0.0, 0.0, 0.0), emissive=_colour(glow),
                                   shininess=0.0, transparency=f32(1.0 - opacity))
            elif opacity < 1.0:
                self.warnings.add(f"material {name}: the opacity of a shape without Material "
                                  "left out")
            appearance = x3d.Appearance(name="", material=out, texture=texture,
                                        texture_transform=transform)
            return appearance, ke_feed.attribute if ke_feed.colours else "", texture is not None
        for what, feed in (("Specular Color", ks_feed), ("Irradiant Color", ke_feed)):
            if feed.texture is not None or feed.colours or feed.unknown:
                self.warnings.add(f"material {name}: {what} fed by nodes X3D cannot say "
                                  "(only the diffuse colour takes a texture or colours); "
                                  "its colour control written")
        if kd_feed.unknown:
            self.warnings.add(f"material {name}: Object Color fed by nodes X3D cannot say; "
                              "its colour control written")
        # the Object Color control keeps the file's diffuseColor where a texture or the
        # colours replace it (X3D writes it all the same)
        control = feeds["Object Color"].value
        diffuse = _colour(kd_feed.control if kd_feed.control is not None else
                          control if (kd_feed.texture is not None or kd_feed.colours) else
                          kd_feed.constant)
        texture = self.texture(kd_feed.texture, material, kd_feed.control is not None)
        if texture is None and kd_feed.texture is None and not kd_feed.colours:
            texture = self.missing_texture(material)
        if texture is not None and kd_feed.control is None and not kd_feed.colours and \
                _grey(texture):
            diffuse = (1.0, 1.0, 1.0)   # a grey texture alone: X3D multiplies diffuseColor
        if kd_feed.colours and kd_feed.control is not None and \
                tuple(kd_feed.control) != (1.0, 1.0, 1.0) and texture is None:
            self.warnings.add(f"material {name}: colours times a colour: X3D's colours replace "
                              "the diffuse colour; the colours written")
        transform = self.texture_transform(material) if texture is not None else None
        shininess, note = x3d.shininess_of(exponent, material.get(keys.X3D_SHININESS))
        if note:
            self.warnings.add(f"material {name}: {note}")
        out = x3d.Material(name=name, diffuse=diffuse,
                           ambient_intensity=self.ambient(material, kd_feed, ka_feed,
                                                          control),
                           specular=_colour(ks_feed.control if ks_feed.control is not None
                                            else ks_feed.constant),
                           emissive=_colour(ke_feed.control if ke_feed.control is not None
                                            else ke_feed.constant),
                           shininess=shininess, transparency=f32(1.0 - opacity))
        if feeds["Opacity"].other is not None and not (
                texture is not None and _texture_alpha(feeds["Opacity"].other,
                                                       kd_feed.texture)):
            self.warnings.add(f"material {name}: its opacity map left out (X3D 3's "
                              "transparency is one number)")
        note = x3d.highlight_note(self.model, float(feeds["Blinn"].value), out.specular)
        if note:
            self.warnings.add(f"material {name}: {note}")
        appearance = x3d.Appearance(name="", material=out, texture=texture,
                                    texture_transform=transform)
        return appearance, kd_feed.attribute if kd_feed.colours else "", texture is not None

    def ambient(self, material, kd_feed, ka_feed, control) -> float:
        """ambientIntensity: Ka / Kd (one number for the three channels); *control*: the
        Object Color control's colour."""
        name = material.name
        if ka_feed.same_as(kd_feed):   # the seeds' Ka = Kd
            return 1.0
        if ka_feed.scale is not None:   # × ambientIntensity of a texture or the colours
            return f32(ka_feed.scale)
        kd = np.array(kd_feed.control if kd_feed.control is not None else
                      control[:3] if kd_feed.texture is not None or kd_feed.colours else
                      kd_feed.constant, dtype=np.float64)
        ka = np.array(ka_feed.control if ka_feed.control is not None else ka_feed.constant,
                      dtype=np.float64)
        value, note = x3d.ambient_intensity_of(kd, ka, material.get(keys.X3D_AMBIENT))
        if note:
            self.warnings.add(f"material {name}: {note}")
        return value

    def texture(self, node, material, multiplied):
        """The x3d.Texture of an Image Texture node: an ImageTexture of its file (relative to
        the written file), or a PixelTexture of its texels where the image has no file of its
        own (packed, or generated: an image imported from a PixelTexture), or None."""
        if node is None:
            return None
        image = node.image
        path = bpy.path.abspath(image.filepath, library=image.library) if image.filepath else ""
        inline = not path or not os.path.isfile(path)
        if inline and (image.packed_file is not None or image.source == "GENERATED"):
            key = (image.name, node.extension)
            if key not in self.pixel_textures:   # one PixelTexture, USE'd by the others
                self.pixel_textures[key] = self.pixel_texture(image)
            texture = self.pixel_textures[key]
        elif inline:
            self.warnings.add(f"textures without an image file left out (pack or save them "
                              f"first): {image.name}")
            return None
        else:
            try:
                url = os.path.relpath(path, self.folder)
            except ValueError:   # another drive
                url = path
            url = url.replace(os.sep, "/")
            texture = x3d.Texture(name=image.name, urls=[url], paths=[path], path=path)
            texture.components = native.image_components(path)
        if texture is None:
            return None
        texture.repeat_s = texture.repeat_t = node.extension == "REPEAT"
        if multiplied and not _grey(texture):
            self.warnings.add(f"material {material.name}: an RGB texture times a colour: X3D's "
                              "RGB textures replace the diffuse colour; the texture written")
        return texture

    def missing_texture(self, material):
        """The ImageTexture whose file was not there when *material* was imported
        (``keys.X3D_MISSING_TEXTURE``): its reference written again, relative to the written
        file (X3D browsers show the diffuse colour while the file is missing, as the
        import did), or None."""
        entry = material.get(keys.X3D_MISSING_TEXTURE)
        paths = [str(p) for p in (entry or {}).get("paths", ())]
        if not paths:
            return None
        urls = []
        for path in paths:
            try:
                url = os.path.relpath(path, self.folder)
            except ValueError:   # another drive
                url = path
            url = url.replace(os.sep, "/")
            if url not in urls:
                urls.append(url)
        self.warnings.add(f"texture files that were not there at import: their references "
                          f"written: {os.path.basename(paths[0])}")
        return x3d.Texture(name=str(entry.get("name", "")), urls=urls, paths=paths,
                           repeat_s=bool(entry.get("repeat_s", True)),
                           repeat_t=bool(entry.get("repeat_t", True)))

    def pixel_texture(self, image):
        """A PixelTexture of *image*'s texels (bottom row first, as both hold them): the
        bytes round(255 × value) of its channels as the image holds them (an imported
        PixelTexture's exactly), its components those it was imported with, else grey where
        every texel is, with alpha where any is not opaque.  None, with a warning, for an
        image larger than :data:`MAX_PIXELS` texels or without pixels."""
        width, height = image.size
        if width * height > MAX_PIXELS:
            self.warnings.add(f"images without a file larger than {MAX_PIXELS:,} texels left "
                              f"out (save them as files first): {image.name}")
            return None
        channels = image.channels
        values = np.empty(width * height * channels, dtype=np.float32)
        try:
            image.pixels.foreach_get(values)
        except (RuntimeError, ValueError):
            values = np.zeros(0, dtype=np.float32)
        if width * height == 0 or values.size != width * height * channels or channels < 1:
            self.warnings.add(f"images without a file or pixels left out: {image.name}")
            return None
        rgba = np.ones((height, width, 4), dtype=np.float32)
        texels = values.reshape(height, width, channels)
        rgba[..., :3] = texels[..., :1] if channels < 3 else texels[..., :3]
        if channels in (2, 4):
            rgba[..., 3] = texels[..., -1]
        data = np.clip(np.rint(rgba * 255.0), 0, 255).astype(np.uint8)
        comps = image.get(keys.X3D_COMPONENTS)
        if comps not in (1, 2, 3, 4):
            grey = bool((data[..., 0] == data[..., 1]).all() and
                        (data[..., 0] == data[..., 2]).all())
            alpha = bool((data[..., 3] < 255).any())
            comps = (1 if grey else 3) + (1 if alpha else 0)
        comps = int(comps)
        pick = {1: [0], 2: [0, 3], 3: [0, 1, 2], 4: [0, 1, 2, 3]}[comps]
        return x3d.Texture(name=image.name, kind="PixelTexture", image=data[..., pick],
                           components=comps)

    @staticmethod
    def texture_transform(material):
        node = material.node_tree.nodes.get(keys.X3D_MAPPING_NODE)
        values = material.get(keys.X3D_TRANSFORM)
        if node is None or values is None or len(values) != 7:
            return None
        values = [float(v) for v in values]
        return x3d.TextureTransform(center=tuple(values[0:2]), rotation=values[2],
                                    scale=tuple(values[3:5]), translation=tuple(values[5:7]))

    # -- lights ---------------------------------------------------------------------------
    def lights(self, objects, meshes) -> dict:
        """{"root": lights at the root, "groups": [(Group, its mesh objects)]}."""
        root, scoped = [], []
        for obj in sorted(objects, key=lambda o: o.name):
            if models.drawn_as(obj.data.type) not in keys.X3D_LIGHT_TYPES.values():
                self.warnings.add(f"lights of a type X3D has not left out: {obj.name} "
                                  f"({obj.data.type})")
                continue
            light = self.light(obj)
            rule = lights_mod.receivers(obj)
            reached = None if rule is None else [m for m in meshes
                                                 if lights_mod.reaches(rule, m)]
            if reached is not None and len(reached) == len(meshes) and meshes:
                reached = None   # it reaches everything written: global
            if obj.get(keys.X3D_LIGHTS_NOTHING):   # an imported scope without shapes
                reached = []
                if self.encoding == "vrml97" and light.kind != "directional":
                    light.on = False   # VRML97 cannot scope it: off shows the same
            if reached is None:
                light.is_global = True
                root.append(light)
            elif self.encoding == "vrml97" and light.kind != "directional":
                self.warnings.add(f"light-linked point and spot lights written global (VRML97's "
                                  f"point and spot lights light everything): {obj.name}")
                light.is_global = True
                root.append(light)
            else:
                light.is_global = False
                scoped.append((light, {m.name for m in reached}))
        if self.encoding == "vrml97":   # its DirectionalLight lights only its group
            for light in root:
                if light.kind == "directional":
                    light.is_global = True
        groups = {}
        for mesh in meshes:
            lights = tuple(light for light, names in scoped if mesh.name in names)
            if lights:
                groups.setdefault(lights, []).append(mesh)
        out = []
        for lights, members in groups.items():
            out.append((x3d.Transform(name="", kind="Group", children=list(lights)), members))
        for light, names in scoped:
            if not names:   # lights nothing: a group of its own
                out.append((x3d.Transform(name="", kind="Group", children=[light]), []))
        return {"root": root, "groups": out}

    def light(self, obj) -> x3d.Light:
        data = obj.data
        # an Area light is the spot that draws it (a 90° cut-off; the X3D model's beam width)
        kind = {v: k for k, v in keys.X3D_LIGHT_TYPES.items()}[models.drawn_as(data.type)]

        read = properties.light_values(data)  # i0 its own or its Power's
        nothing = bool(obj.get(keys.X3D_LIGHTS_NOTHING))   # hidden: its scope is empty
        on = ((not obj.hide_render or nothing)
              and lights_mod.visible(obj, self.layer, self.collections))
        name = obj.name.removesuffix(keys.X3D_OFF) if not on else obj.name
        matrix = Z_UP_TO_Y_UP @ np.array(obj.matrix_world, dtype=np.float64)
        direction = -matrix[:3, 2]
        length = float(np.linalg.norm(direction))
        direction = direction / length if length > 0 else np.array([0.0, 0.0, -1.0])
        fields, notes = x3d.light_fields(self.model, read["settings"], read["falloff"], kind,
                                         read["spot_size"], data.get(keys.X3D_CUT_OFF))
        for note in notes:
            self.warnings.add(f"light {obj.name}: {note}")
        return x3d.Light(kind=kind, name=name, on=on,
                         shadows=bool(data.use_shadow) and compat.HAS_RAYCAST,
                         color=_colour(read["color"]),
                         location=tuple(f32(v) for v in matrix[:3, 3]),
                         direction=tuple(f32(v) for v in direction), **fields)

    def world_ambient(self, root) -> None:
        """The World's Phong ambient light (which X3D lacks) as a DirectionalLight of
        intensity 0 whose ambientIntensity and colour give the same ambient term."""
        world = self.scene.world
        if world is None:
            return
        light = x3d.world_ambient_light(
            float(world.get(properties.AMBIENT_INTENSITY[0], properties.AMBIENT_INTENSITY[1])),
            world.get(properties.AMBIENT_COLOR[0], properties.AMBIENT_COLOR[1]))
        if light is not None:
            root.insert(0, light)

    # -- the camera -------------------------------------------------------------------------
    def viewpoint(self):
        obj = self.scene.camera
        if obj is None or obj.type != "CAMERA":
            return None
        camera = obj.data
        matrix = Z_UP_TO_Y_UP @ np.array(obj.matrix_world, dtype=np.float64)
        u, _s, vt = np.linalg.svd(matrix[:3, :3])
        rotation = u @ vt
        if np.linalg.det(rotation) < 0:
            u[:, -1] *= -1.0
            rotation = u @ vt
        frame = np.eye(4)
        frame[:3, :3] = rotation
        orientation = x3d.decompose(frame)["rotation"]
        render = self.scene.render
        width = render.resolution_x * render.pixel_aspect_x
        height = render.resolution_y * render.pixel_aspect_y
        if camera.shift_x or camera.shift_y:
            self.warnings.add(f"camera {obj.name}: its lens shift has no X3D counterpart; "
                              "left out")
        vp = x3d.Viewpoint(name=obj.name, position=tuple(f32(v) for v in matrix[:3, 3]),
                           orientation=tuple(float(v) for v in orientation))
        fit = camera.sensor_fit
        if fit == "AUTO":
            fit = "HORIZONTAL" if width >= height else "VERTICAL"
        if camera.type == "ORTHO":
            size = float(camera.ortho_scale)
            w, h = (size, size * height / width) if fit == "HORIZONTAL" else \
                (size * width / height, size)
            vp.kind = "OrthoViewpoint"
            vp.ortho_field = (f32(-w / 2), f32(-h / 2), f32(w / 2), f32(h / 2))
            if self.encoding == "vrml97":
                self.warnings.add(f"camera {obj.name}: VRML97 has no orthographic viewpoint; "
                                  "written as a perspective Viewpoint (.x3d and .x3dv keep it)")
            return vp
        if camera.type != "PERSP":
            self.warnings.add(f"camera {obj.name}: a {camera.type} camera written as a "
                              "perspective Viewpoint")
        sensor = camera.sensor_width if fit == "HORIZONTAL" else camera.sensor_height
        half = math.atan(sensor / (2.0 * camera.lens))   # of the fit side
        other = (height / width) if fit == "HORIZONTAL" else (width / height)
        half_other = math.atan(math.tan(half) * other)
        fov = 2.0 * min(half, half_other)   # X3D: the angle of the smaller side
        vp.field_of_view = f32(fov)
        return vp


class _Feed:
    """What X3D can say of a lights-group input's ``feeds.Feed``: a constant colour (a
    control's or the socket's), an Image Texture, the colour attribute, their product, × a
    scale."""

    __slots__ = ("socket", "constant", "control", "texture", "colours", "attribute", "scale",
                 "unknown")

    def __init__(self, socket):
        self.socket = socket
        self.constant = (1.0, 1.0, 1.0)
        self.control = None
        self.texture = None
        self.colours = False
        self.attribute = ""
        self.scale = None
        self.unknown = False

    def same_as(self, other) -> bool:
        return self.socket is not None and self.socket == other.socket


def _feed(feed) -> _Feed:
    """The _Feed of the ``feeds.Feed`` *feed*."""
    out = _Feed(feed.socket)
    if feed.other is None:   # a value: the socket's own, or an RGB node's (a control)
        value = feed.value if isinstance(feed.value, tuple) else (float(feed.value),) * 3
        out.constant = tuple(float(c) for c in value[:3])
        if feed.socket is not None:
            out.control = out.constant
        return out
    chain = feed.chain
    out.control = chain.colour
    if chain.colour is not None:
        out.constant = chain.colour
    out.texture = chain.texture
    if chain.attribute is not None:
        out.colours = True
        out.attribute = chain.attribute.layer_name
    out.scale = chain.scale
    out.unknown = chain.unknown
    return out


def _texture_alpha(product, node) -> bool:
    """Whether the opacity map *product* (``recipe.OPACITY_MAP``) is the alpha of the Image
    Texture *node* (the one written) times the Opacity control: what X3D says with the
    texture's alpha and transparency (``x3d_import._Builder.texture_alpha``)."""
    if node is None or product is None or product.operation != "MULTIPLY":
        return False
    sources = set()
    for identifier in ("Value", "Value_001"):
        socket = compat.input_socket(product, identifier)
        if not socket.is_linked:
            return False
        link = socket.links[0]
        sources.add((link.from_node.name, link.from_socket.identifier))
    return sources == {(node.name, "Alpha"), (recipe.OPACITY, "Value")}


def _grey(texture) -> bool:
    """Whether a written texture's image has one or two channels (X3D multiplies then)."""
    return texture.components in (1, 2)
