# SPDX-License-Identifier: GPL-3.0-or-later
"""The reader: the generic nodes of a file into the data model.  :class:`_Reader` holds one
reading's state and builds each node once (DEF/USE is identity: a node used twice gives
the same object); its jobs are its parts: :class:`.files._Files` (sniffing and parsing),
:class:`.fields._Fields` (typed fields), :class:`.graph._Protos` (PROTO expansion),
:class:`.geometry._Geometry` (geometry nodes), and here the dispatch by node type, the
scene-graph nodes (groups, shapes, appearances, materials, textures, lights, viewpoints,
bindable nodes, Inline) and the warnings at the end.
"""

from __future__ import annotations

import os

import numpy as np

from .numeric import transform_matrix
from .model import (
    MAX_DEPTH, SPOT_DEFAULTS, Appearance, Light, Material, _Notes, Shape, Texture,
    TextureTransform, Transform, Viewpoint)
from .graph import (
    _BINDABLES, _CASE, _FACE_SETS, _GEOMETRY, _GEOMETRY_SKIPPED, _GROUPS, _IGNORED, _KNOWN,
    _KNOWN_LOWER, _LIGHTS, _MATERIALS, MAX_PROTO_DEPTH, _MISSING, _N, _TEXTURES, _TRANSFORM_LIKE,
    _VIEWPOINTS, _Protos, _Use)
from .fields import _Fields
from .files import _Files, resolve_local
from .geometry import _Geometry, _default_uvs


class _Reader(_Files, _Fields, _Protos, _Geometry):
    """One reading: its state, and each node of the graph built once into the model."""

    def __init__(self, resolver=None):
        self.resolver = resolver or resolve_local
        self.notes = _Notes()
        self.ignored = {}           # node type → count (behaviour, sound, shaders, ROUTE)
        self.unknown = {}           # unknown node types → count
        self.too_deep = 0
        self.memo = {}              # id(_N) → (_N, built object); the _N is kept alive
        self.busy = set()
        self.copies = 0
        self.expanded = {}          # id(instance) → (instance, copied body root)
        self.files = {}             # real path → _Source (None: failed or being read)
        self.loading = []           # Inline files being built (recursion)
        self.canon = {}             # type as written → canonical type (or None)
        self.doc = None
        self.main = None
        self.bound = set()
        self.arrays = {}
        self.tessellated = {}

    # nodes --------------------------------------------------------------------------------
    def lookup(self, value):
        """A field's node: a _Use resolved in its scope, a PROTO instance expanded to the node
        it stands for (its body's first node), None when there is none."""
        for _ in range(MAX_PROTO_DEPTH + 2):
            if isinstance(value, _Use):
                found = value.scope.defs.get(value.name)
                if found is None:
                    self.notes.add("USE of names never DEF'd: left out", value.name)
                    return None
                value = found
            if not isinstance(value, _N):
                return None
            if value.proto is None:
                return value
            value = self.expand(value)
        return None

    def type_of(self, n):
        written = n.type
        if written in self.canon:
            return self.canon[written]
        if written in _KNOWN:
            canonical = written
        else:
            canonical = _KNOWN_LOWER.get((written or "").lower())
            if canonical is not None:
                self.notes.add(_CASE, f"{written} → {canonical}")
        self.canon[written] = canonical
        return canonical

    def build(self, value, depth, hint, want):
        """The model object of a node (memoised: a node USE'd twice gives the same object),
        None when it is not one of *want* ("child", "geometry", "appearance", "material",
        "texture", "texture_transform") or cannot be built."""
        n = self.lookup(value)
        if n is None:
            return None
        key = id(n)
        if key in self.memo:
            return self.memo[key][1]
        if key in self.busy:
            self.notes.add("nodes used inside themselves (a USE within its own DEF, a PROTO "
                           "instance within its own PROTO): left out", n.name or n.type)
            return None
        if depth > MAX_DEPTH:
            self.too_deep += 1
            return None
        self.busy.add(key)
        try:
            obj = self.dispatch(n, depth, hint, want)
        finally:
            self.busy.discard(key)
        self.memo[key] = (n, obj)
        return obj

    def dispatch(self, n, depth, hint, want):
        t = self.type_of(n)
        if t is None:
            if want == "child" or want is None:
                self.unknown[n.type] = self.unknown.get(n.type, 0) + 1
                kids = self.node_values(n, "children")
                if kids:
                    return self.group(n, n.type, depth, hint)
            else:
                self.unknown[n.type] = self.unknown.get(n.type, 0) + 1
            return None
        if t in _IGNORED:
            self.ignored[t] = self.ignored.get(t, 0) + 1
            return None
        if t in _GEOMETRY_SKIPPED:
            self.notes.add("geometry nodes not read (not tessellated here): left out", t)
            return None
        if want == "child":
            if t in _GROUPS:
                return self.group(n, t, depth, hint)
            if t == "Shape":
                return self.shape(n, depth, hint)
            if t in _LIGHTS:
                return self.light(n, t)
            if t in _VIEWPOINTS:
                return self.viewpoint(n, t)
            if t in _BINDABLES:
                self.bindable(n, t)
                return None
            if t == "Inline":
                return self.inline(n, depth, hint)
        elif want == "geometry" and t in _GEOMETRY:
            return self.geometry(n, t, hint)
        elif want == "appearance" and t == "Appearance":
            return self.appearance(n, depth, hint)
        elif want == "material" and t in _MATERIALS:
            return self.material(n, t, hint)
        elif want == "texture" and t in _TEXTURES:
            return self.texture(n, t, depth)
        elif want == "texture_transform" and t == "TextureTransform":
            return TextureTransform(
                name=n.name or "", center=self.vec(n, "center", (0.0, 0.0)),
                rotation=self.angle(n, "rotation", 0.0), scale=self.vec(n, "scale", (1.0, 1.0)),
                translation=self.vec(n, "translation", (0.0, 0.0)))
        self.notes.add("nodes where the standard allows none of their type: left out",
                       f"{t} as {want}")
        return None

    def group(self, n, t, depth, hint):
        name = n.name or ""
        obj = Transform(name=name, kind=t)
        if t in _TRANSFORM_LIKE:
            obj.matrix = transform_matrix(
                self.vec(n, "translation", (0.0, 0.0, 0.0)), self.rotation(n, "rotation"),
                self.vec(n, "scale", (1.0, 1.0, 1.0)), self.rotation(n, "scaleOrientation"),
                self.vec(n, "center", (0.0, 0.0, 0.0)))
        elif t == "MatrixTransform":
            obj.matrix = self.matrix_field(n)
        if t == "Switch":
            kids = self.node_values(n, "choice") or self.node_values(n, "children")
            which = int(self.num(n, "whichChoice", -1.0))
            kids = [kids[which]] if 0 <= which < len(kids) else []
        elif t == "LOD":
            kids = (self.node_values(n, "level") or self.node_values(n, "children"))[:1]
        elif t == "CADFace":        # XML files often leave the Shape's containerField out
            kids = self.node_values(n, "shape") or self.node_values(n, "children")
        elif t == "HAnimHumanoid":
            kids = (self.node_values(n, "skeleton") + self.node_values(n, "skin")
                    or self.node_values(n, "children"))
        else:
            kids = self.node_values(n, "children")
            if t == "Billboard":
                self.notes.add("Billboards read as Groups (a browser turns them towards the "
                               "viewer)", name or None)
        hint = name or hint
        for kid in kids:
            child = self.build(kid, depth + 1, hint, "child")
            if child is not None:
                obj.children.append(child)
        return obj

    def matrix_field(self, n):
        """MatrixTransform's ``matrix`` (16 numbers): written as in Inventor and X3D's
        SFMatrix4f, translation in the 13th to 15th numbers (M = values as 4×4, transposed);
        a matrix written the other way (translation in the 4th, 8th, 12th) is read as such."""
        arr = self.numbers(n, "matrix")
        if arr is None or len(arr) < 16:
            if arr is not None:
                self.notes.add("fields with too few numbers: defaults used",
                               self.where(n, "matrix"))
            return np.eye(4)
        m = arr[:16].reshape(4, 4)
        if m[0, 3] == m[1, 3] == m[2, 3] == 0.0 or (m[3, :3] != 0).any():
            m = m.T
        return m.copy()

    def shape(self, n, depth, hint):
        name = n.name or ""
        hint = name or hint
        appearance = self.build(self.node_value(n, "appearance"), depth + 1, hint, "appearance")
        geometry = self.build(self.node_value(n, "geometry"), depth + 1, hint, "geometry")
        if appearance is not None and appearance.texture is not None and geometry is not None \
                and geometry.uvs is None and len(geometry.corners) \
                and geometry.kind in _FACE_SETS:
            geometry.uvs = _default_uvs(geometry)
        return Shape(name=name, geometry=geometry, appearance=appearance)

    def appearance(self, n, depth, hint):
        name = n.name or ""
        hint = name or hint
        for shader in self.node_values(n, "shaders"):
            found = self.lookup(shader)
            if found is not None:
                kind = self.type_of(found) or found.type
                self.ignored[kind] = self.ignored.get(kind, 0) + 1
        if self.node_value(n, "backMaterial") is not None:
            self.notes.add("Appearance backMaterial (X3D 4) not read: the front material is "
                           "used on both sides", name or None)
        return Appearance(
            name=name,
            material=self.build(self.node_value(n, "material"), depth + 1, hint, "material"),
            texture=self.build(self.node_value(n, "texture"), depth + 1, hint, "texture"),
            texture_transform=self.build(self.node_value(n, "textureTransform"), depth + 1, hint,
                                         "texture_transform"))

    def material(self, n, t, hint):
        mat = Material(name=n.name or hint or "Material")
        if t == "UnlitMaterial":
            mat.kind = "unlit"
            mat.diffuse, mat.ambient_intensity, mat.shininess = (0.0, 0.0, 0.0), 0.0, 0.0
            mat.emissive = self.vec(n, "emissiveColor", (1.0, 1.0, 1.0))
            mat.transparency = self.num(n, "transparency", 0.0)
            return mat
        if t == "PhysicalMaterial":
            mat.kind = "physical"
            mat.diffuse = self.vec(n, "baseColor", (1.0, 1.0, 1.0))
            mat.emissive = self.vec(n, "emissiveColor", (0.0, 0.0, 0.0))
            mat.transparency = self.num(n, "transparency", 0.0)
            mat.metallic = self.num(n, "metallic", 1.0)
            mat.roughness = self.num(n, "roughness", 1.0)
            mat.ambient_intensity, mat.specular, mat.shininess = 0.0, (0.0, 0.0, 0.0), 0.0
            self.notes.add("PhysicalMaterials (X3D 4) read as their baseColor (diffuse) and "
                           "emissiveColor; metallic and roughness kept, not mapped", mat.name)
            return mat
        mat.diffuse = self.vec(n, "diffuseColor", (0.8, 0.8, 0.8))
        mat.ambient_intensity = self.num(n, "ambientIntensity", 0.2)
        mat.specular = self.vec(n, "specularColor", (0.0, 0.0, 0.0))
        mat.emissive = self.vec(n, "emissiveColor", (0.0, 0.0, 0.0))
        mat.shininess = self.num(n, "shininess", 0.2)
        mat.transparency = self.num(n, "transparency", 0.0)
        textures = [f for f in ("diffuseTexture", "emissiveTexture", "specularTexture",
                                "shininessTexture", "ambientTexture", "normalTexture",
                                "occlusionTexture") if self.node_value(n, f) is not None]
        if textures:
            self.notes.add("X3D 4 material textures not read", f"{mat.name}: {', '.join(textures)}")
        if t == "TwoSidedMaterial":
            mat.kind = "two_sided"
            if self.flag(n, "separateBackColor", False):
                mat.back = Material(
                    name=mat.name + " (back)",
                    diffuse=self.vec(n, "backDiffuseColor", (0.8, 0.8, 0.8)),
                    ambient_intensity=self.num(n, "backAmbientIntensity", 0.2),
                    specular=self.vec(n, "backSpecularColor", (0.0, 0.0, 0.0)),
                    emissive=self.vec(n, "backEmissiveColor", (0.0, 0.0, 0.0)),
                    shininess=self.num(n, "backShininess", 0.2),
                    transparency=self.num(n, "backTransparency", 0.0))
        return mat

    def texture(self, n, t, depth):
        if t == "MultiTexture":
            self.notes.add("MultiTextures read as their first texture", n.name or None)
            return self.build(next(iter(self.node_values(n, "texture")), None), depth + 1, "",
                              "texture")
        tex = Texture(name=n.name or "", kind=t, repeat_s=self.flag(n, "repeatS", True),
                      repeat_t=self.flag(n, "repeatT", True))
        if t == "PixelTexture":
            self.pixels(n, tex)
            return tex
        tex.urls = self.strings(n, "url")
        base = n.src.base if n.src is not None else os.getcwd()
        for url in tex.urls:
            path = self.resolver(url, base)
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
            self.notes.add("texture files not found", (tex.urls or ["(no url)"])[0])
        return tex

    def pixels(self, n, tex):
        """PixelTexture's SFImage: width height components, then one integer a pixel."""
        arr = self.ints(n, "image")
        if len(arr) < 3:
            return
        width, height, comps = (int(v) for v in arr[:3])
        if not (0 < width <= 16384 and 0 < height <= 16384 and 1 <= comps <= 4) \
                or len(arr) < 3 + width * height:
            self.notes.add("PixelTexture images that could not be read", tex.name or None)
            return
        values = arr[3:3 + width * height].astype(np.uint64)
        shifts = np.arange(comps - 1, -1, -1, dtype=np.uint64) * np.uint64(8)
        tex.image = ((values[:, None] >> shifts[None, :]) & np.uint64(255)).astype(
            np.uint8).reshape(height, width, comps)
        tex.components = comps

    def light(self, n, t):
        kind = _LIGHTS[t]
        light = Light(kind=kind, name=n.name or "")
        light.on = self.flag(n, "on", True)
        light.shadows = self.flag(n, "shadows", False)
        light.intensity = self.num(n, "intensity", 1.0)
        light.ambient_intensity = self.num(n, "ambientIntensity", 0.0)
        light.color = self.vec(n, "color", (1.0, 1.0, 1.0))
        if kind != "directional":
            light.location = self.vec(n, "location", (0.0, 0.0, 0.0))
            light.attenuation = self.vec(n, "attenuation", (1.0, 0.0, 0.0))
            light.radius = self.num(n, "radius", 100.0)
        if kind != "point":
            light.direction = self.vec(n, "direction", (0.0, 0.0, -1.0))
        if kind == "spot":
            beam, cut = SPOT_DEFAULTS["vrml97" if n.src.vrml97 else "x3d"]
            light.beam_width = self.angle(n, "beamWidth", beam)
            light.cut_off_angle = self.angle(n, "cutOffAngle", cut)
        light.is_global = self.flag(n, "global", kind != "directional")
        return light

    def viewpoint(self, n, t):
        vp = Viewpoint(name=n.name or "", kind=t)
        vp.position = self.vec(n, "position", (0.0, 0.0, 10.0))
        vp.orientation = self.rotation(n, "orientation")
        if t == "OrthoViewpoint":
            vp.ortho_field = self.vec(n, "fieldOfView", (-1.0, -1.0, 1.0, 1.0))
        else:
            vp.field_of_view = self.angle(n, "fieldOfView", 0.785398)
        vp.center_of_rotation = self.vec(n, "centerOfRotation", (0.0, 0.0, 0.0))
        vp.description = self.string(n, "description", "")
        if n.src is self.main and self.doc.viewpoint is None:
            self.doc.viewpoint = vp
        return vp

    def bindable(self, n, t):
        """The first NavigationInfo, Background and WorldInfo of the main file (an inlined
        file's are not bound, as the standard says)."""
        if n.src is not self.main or t in self.bound:
            return
        self.bound.add(t)
        doc = self.doc
        if t == "NavigationInfo":
            doc.headlight = self.flag(n, "headlight", True)
            if self.field(n, "type") is not _MISSING:
                doc.navigation_types = self.strings(n, "type")
        elif t == "Background":
            sky = self.numbers(n, "skyColor")
            doc.background = tuple(float(v) for v in sky[:3]) if sky is not None \
                and len(sky) >= 3 else (0.0, 0.0, 0.0)
        elif t == "WorldInfo":
            doc.title = self.string(n, "title", "")
            doc.info = self.strings(n, "info")

    def inline(self, n, depth, hint):
        group = Transform(name=n.name or "", kind="Inline")
        if not self.flag(n, "load", True):
            return group
        urls = self.strings(n, "url")
        path = None
        for url in urls:
            candidate = self.resolver(url, n.src.base)
            if candidate and os.path.isfile(candidate):
                path = candidate
                break
        if path is None:
            self.notes.add("Inline files not found: left out", urls[0] if urls else "(no url)")
            return group
        real = os.path.realpath(path)
        if real in self.loading or real == os.path.realpath(self.main.path or "."):
            self.notes.add("Inline files that include themselves: left out",
                           os.path.basename(path))
            return group
        src = self.parse_file(real, len(self.loading) + 1)
        if src is None:
            return group
        if src.meter != n.src.meter:
            ratio = src.meter / n.src.meter
            group.matrix = np.diag([ratio, ratio, ratio, 1.0])
        self.loading.append(real)
        try:
            for kid in src.nodes:
                child = self.build(kid, depth + 1, hint, "child")
                if child is not None:
                    group.children.append(child)
        finally:
            self.loading.pop()
        return group

    # the end ------------------------------------------------------------------------------
    def finish(self, doc):
        if self.ignored:
            shown = ", ".join(f"{k} ×{v}" if v > 1 else k for k, v in sorted(self.ignored.items()))
            doc.warn("not imported (animation, interaction, scripts, sound, shaders, fog): "
                     + shown)
        if self.unknown:
            shown = ", ".join(f"{k} ×{v}" if v > 1 else k for k, v in sorted(self.unknown.items()))
            doc.warn(f"unknown node types skipped (their children read where they have them): "
                     f"{shown}")
        if self.too_deep:
            doc.warn(f"nodes nested deeper than {MAX_DEPTH} levels left out ({self.too_deep})")
        for line in self.notes.lines():
            doc.warn(line)
