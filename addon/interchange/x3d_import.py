# SPDX-License-Identifier: GPL-3.0-or-later
"""VRML97 / X3D (.wrl, .x3dv, .x3d, gzipped too) imported as exact Phong materials in the
X3D / VRML97 lighting model (docs/x3d.md, docs/interchange.md).

``core/x3d.py`` reads the whole file first (nothing is added when it cannot be read); this
module builds the Blender side:

* every shape instance an object in a new collection named after the file, its world
  matrix the file's (Y up turned to Blender's Z up at the root, positions and translations in
  metres: ``UNIT length``), named after its Shape's DEF, else the nearest named group's, else
  its geometry's or material's name (KiCad's shapes have only the latter); a
  matrix that location, rotation and scale cannot hold (a shear: ``scaleOrientation``) goes
  into the parent inverse matrix under one Empty at the origin, exact.  One mesh per geometry
  node: DEF/USE'd geometry is one mesh shared by its objects;
* meshes through numpy at once (``foreach_set`` of the corner, face and attribute arrays):
  faces counter-clockwise, the file's normals as custom split normals, else smooth by the
  ``creaseAngle``; texture coordinates as "UVMap", colours per corner (per point for line and
  point sets) as the colour attribute "Col"; line sets loose edges, point sets vertices; an
  Extrusion its faces (``core.x3d.extrude``), a Text its strings set in Blender's built-in font
  (:func:`text_geometry`: a FONT curve converted to a mesh, then removed), one warning a file
  for the font families and styles it cannot match;
* every Material a Phong material from birth under the file's name, with
  ``core.x3d.phong_values``: Kd = diffuseColor, Ka = ambientIntensity × diffuseColor (the
  Ambient Object Color control), Ks = specularColor, Ke = emissiveColor, Exponent = 128 ×
  shininess, Opacity = 1 − transparency.  An RGB(A) texture or the Color node replaces the
  diffuse colour (Ka = ambientIntensity × it), a one- or two-channel texture multiplies it
  (the image's channels read from its file); ``solid`` its Backface Culling (a material
  whose shapes differ in it two variants); a two- or four-channel texture's alpha times
  1 − transparency the material's opacity (its opacity map); TextureTransform a Mapping
  node.  A shape without Material is unlit: a Phong material whose Irradiant Color is its
  texture, its colours or white and whose Kd, Ka and Ks are black, so the picture is that
  colour exactly (and the comparison's reference, which reads the material's inputs,
  predicts it);
* lights: DirectionalLight → Sun, PointLight → Point, SpotLight → Spot (``spot_size`` = 2 ×
  cutOffAngle), Phong Intensity, Ambient, attenuation (a0, a1, a2) and Radius through
  ``core.x3d.light_values``, both for distances in the world (the standard measures them in
  the light's coordinate system: under a scale s, a1 / s, a2 / s², radius × s), Beam
  Width; ``on FALSE`` hidden from render; a scoped light (VRML97's DirectionalLight, X3D's
  ``global FALSE``) Light-Linked to a receiver collection of exactly the objects of its
  scope; the headlight (``NavigationInfo { headlight TRUE }``, the default) a Sun that
  follows the camera (``lighting/headlight.py``);
* the bound Viewpoint (or OrthoViewpoint) the scene camera; X3D's default viewpoint
  (0 0 10, π/4) when the file has none and the scene no camera (marked
  ``DEFAULT_VIEWPOINT_KEY``: ``phong compare`` frames the objects with it);
* the scene in the X3D model (``scene.phong.model = "x3d"``: its lights groups rebuilt), the
  World's Phong ambient intensity 0 (X3D has no global ambient light).

:func:`import_file` is the plain entry point (``phong compare FILE.wrl``); it raises
:class:`X3DImportError` and leaves the scene as it was when the import fails.
"""

from __future__ import annotations

import math
import os

import bpy
import numpy as np
from mathutils import Matrix, Vector

from ...core import x3d
from .. import compat
from ..lighting import headlight as headlight_mod
from ..lighting import opacity as opacity_nodes
from ..lighting import properties, recipe, rig, writer
from ..lighting import sync as sync_mod
from ..lighting import world_copies
from . import keys, native
from .native import image_components

#: Custom properties an import leaves for the export (import → export → import keeps the
#: file's values exactly where the float32 controls round them).
AMBIENT_KEY = keys.X3D_AMBIENT                   # material: the file's ambientIntensity
SHININESS_KEY = keys.X3D_SHININESS                # material: the file's shininess
TRANSFORM_KEY = keys.X3D_TRANSFORM                # material: center, rotation, scale, translation
UNLIT_KEY = keys.X3D_UNLIT                        # material: a shape without Material
CUT_OFF_KEY = keys.X3D_CUT_OFF                    # spot light: the file's cutOffAngle
HEADLIGHT_OFF_KEY = "phong_x3d_no_headlight"      # scene: the file said headlight FALSE
LIGHTS_NOTHING_KEY = keys.X3D_LIGHTS_NOTHING      # light object: a scope without shapes
DEFAULT_VIEWPOINT_KEY = "phong_x3d_default_viewpoint"  # camera object: the file has no Viewpoint
#: Nodes of the texture and colour chains (the export reads them back).
TEXTURE_NODE = "phong_x3d_texture"
UV_NODE = "phong_x3d_uv"
MAPPING_NODE = keys.X3D_MAPPING_NODE
COLORS_NODE = "phong_x3d_colors"
CHAIN = "phong_x3d:"                              # + what: the Vector Math nodes
COLOR_ATTRIBUTE = "Col"
UV_MAP = keys.X3D_UV_MAP
OFF = keys.X3D_OFF
#: The Empty under which objects with a sheared matrix hang (their parent inverse holds it).
SHEAR_FRAME = "X3D shear frame"
LIGHT_TYPES = keys.X3D_LIGHT_TYPES
LIGHT_NAMES = {"directional": "DirectionalLight", "point": "PointLight", "spot": "SpotLight"}
#: Blender's range of a spot's size (the full cone) and of a perspective camera's angle.
SPOT_SIZE = (math.radians(1.0), math.pi)
CAMERA_ANGLE = (0.00640536, 3.01675)


class X3DImportError(native.InterchangeError):
    """The import failed; nothing was added to the file."""


def import_file(context, filepath) -> native.ImportResult:
    """Import the VRML97 / X3D file *filepath* into *context*'s scene
    (``formats.import_file``): its objects, Phong materials and warnings.  Raises
    X3DImportError (the scene unchanged) when it cannot be imported."""
    try:
        doc = x3d.load(filepath)
    except x3d.X3DError as error:
        raise X3DImportError(str(error)) from None
    except (OSError, MemoryError) as error:
        raise X3DImportError(f"{filepath}: cannot be read ({error})") from None
    builder = _Builder(context, doc)
    try:
        builder.build()
    except Exception as error:   # leave the file as it was
        builder.undo()
        raise X3DImportError(f"{filepath}: import failed ({type(error).__name__}: {error}); "
                             "nothing imported") from error
    return native.ImportResult(builder.objects, builder.made, builder.warnings(), builder.sync)


# -- pure helpers (no bpy) --------------------------------------------------------------------

def degenerate_faces(sizes: np.ndarray, corners: np.ndarray) -> np.ndarray:
    """Boolean per face: the face uses one vertex twice (Blender refuses such faces)."""
    sizes = np.asarray(sizes, dtype=np.int64)
    if not len(sizes):
        return np.zeros(0, bool)
    if np.all(sizes == 3):
        a, b, c = np.asarray(corners, dtype=np.int64).reshape(-1, 3).T
        return (a == b) | (b == c) | (a == c)
    face = np.repeat(np.arange(len(sizes)), sizes)
    order = np.lexsort((corners, face))
    f, c = face[order], np.asarray(corners)[order]
    same = (f[1:] == f[:-1]) & (c[1:] == c[:-1])
    bad = np.zeros(len(sizes), bool)
    bad[f[1:][same]] = True
    return bad


def file_matrix(doc, matrix) -> np.ndarray:
    """The Blender world matrix of a file matrix: Y up turned to Z up, its translation in
    metres (positions are scaled to metres in the meshes, so the matrix keeps the file's
    rotation and scale)."""
    out = np.array(matrix, dtype=np.float64)
    out[:3, 3] *= doc.meter
    return x3d.Y_UP_TO_Z_UP @ out


def _scale_of(matrix) -> tuple:
    """(the uniform scale of a 3×3 matrix: cube root of |det|, whether it is uniform)."""
    linear = np.asarray(matrix, dtype=np.float64)[:3, :3]
    values = np.linalg.svd(linear, compute_uv=False)
    scale = float(abs(np.linalg.det(linear))) ** (1.0 / 3.0)
    uniform = values.max() - values.min() <= 1e-6 * max(values.max(), 1e-30)
    return scale, uniform


#: FontStyle's major justification → Blender's horizontal alignment of a line.
ALIGN_X = {"BEGIN": "LEFT", "FIRST": "LEFT", "MIDDLE": "CENTER", "END": "RIGHT"}
#: The font families and styles Blender's built-in font (a sans serif, plain) shows.
BUILTIN_FAMILIES = {"SANS"}
BUILTIN_STYLES = {"PLAIN"}


def _glyphs(line: str, size: float, align: str):
    """(positions (n, 3), face sizes, corners) of one line of text in Blender's built-in
    font: baseline at y = 0, aligned at x = 0 (LEFT, CENTER, RIGHT), *size* the em."""
    fonts_before = set(bpy.data.fonts)
    curve = bpy.data.curves.new("X3D Text", "FONT")
    try:
        curve.body = line
        curve.size = size
        curve.align_x = align
        obj = bpy.data.objects.new("X3D Text", curve)
        try:
            mesh = bpy.data.meshes.new_from_object(obj)
        finally:
            bpy.data.objects.remove(obj)
    finally:
        bpy.data.curves.remove(curve)
        for font in set(bpy.data.fonts) - fonts_before:
            if not font.users:
                bpy.data.fonts.remove(font)
    try:
        positions = np.zeros(len(mesh.vertices) * 3)
        mesh.vertices.foreach_get("co", positions)
        sizes = np.zeros(len(mesh.polygons), np.int64)
        mesh.polygons.foreach_get("loop_total", sizes)
        corners = np.zeros(len(mesh.loops), np.int64)
        mesh.loops.foreach_get("vertex_index", corners)
    finally:
        bpy.data.meshes.remove(mesh)
    return positions.reshape(-1, 3), sizes, corners


def text_geometry(text: dict, notes: dict) -> x3d.Mesh:
    """A Text node's strings set in Blender's built-in font as a flat mesh in the node's
    local XY plane (+Y up, facing +Z): FontStyle ``size`` the em, lines ``size × spacing``
    apart (downward, upward with ``topToBottom`` FALSE), the major justification
    (BEGIN / FIRST at x = 0, MIDDLE centred, END ending there) per line, the minor one
    (FIRST: the first baseline at y = 0; BEGIN, MIDDLE, END: the glyphs' top, middle or
    bottom), ``length`` (each line's glyphs stretched or squeezed along x to it) and
    ``maxExtent`` (every line squeezed along x when the longest is longer).  What the
    font cannot follow is gathered in *notes* ({kind: set of values}) for one warning."""
    size = float(text["size"]) if text["size"] > 0 else 1.0
    spacing = float(text["spacing"])
    major, minor = text["justify"]
    align = ALIGN_X.get(major, "LEFT")
    for kind, values, known in (("family", text["family"], BUILTIN_FAMILIES),
                                ("style", [text["style"]], BUILTIN_STYLES)):
        notes.setdefault(kind, set()).update(str(v) for v in values if str(v).upper() not in known)
    if not text["horizontal"]:
        notes.setdefault("layout", set()).add("horizontal FALSE")
    if not text["left_to_right"]:
        notes.setdefault("layout", set()).add("leftToRight FALSE")
    if major not in ALIGN_X or minor not in ("BEGIN", "FIRST", "MIDDLE", "END"):
        notes.setdefault("layout", set()).add(f"justify {major} {minor}")
    direction = -1.0 if text["top_to_bottom"] else 1.0
    lines = []
    for index, line in enumerate(text["strings"]):
        positions, sizes, corners = _glyphs(line, size, align)
        positions[:, 1] += direction * index * size * spacing
        length = text["length"][index] if index < len(text["length"]) else 0.0
        if length > 0 and len(positions):
            width = positions[:, 0].max() - positions[:, 0].min()
            if width > 0:
                positions[:, 0] *= length / width
        lines.append((positions, sizes, corners))
    positions = np.concatenate([p for p, _, _ in lines]) if lines else np.zeros((0, 3))
    if text["max_extent"] > 0 and len(positions):
        widths = [p[:, 0].max() - p[:, 0].min() for p, _, _ in lines if len(p)]
        if max(widths) > text["max_extent"]:
            positions[:, 0] *= text["max_extent"] / max(widths)
    if len(positions) and minor in ("BEGIN", "MIDDLE", "END"):
        top, bottom = positions[:, 1].max(), positions[:, 1].min()
        positions[:, 1] -= {"BEGIN": top, "END": bottom, "MIDDLE": (top + bottom) / 2.0}[minor]
    offsets = np.cumsum([0] + [len(p) for p, _, _ in lines])
    corners = np.concatenate([c + offsets[k] for k, (_, _, c) in enumerate(lines)]) \
        if lines else np.zeros(0, np.int64)
    sizes = np.concatenate([s for _, s, _ in lines]) if lines else np.zeros(0, np.int64)
    positions[:, 2] = 0.0
    return x3d.Mesh(name="Text", kind="Text", positions=positions, face_sizes=sizes,
                    corners=corners.astype(np.int64), solid=text["solid"])


def font_warnings(notes: dict) -> list:
    """One warning for everything the Text nodes of a file asked that the font cannot
    show (*notes* of :func:`text_geometry`)."""
    parts = []
    unmatched = sorted(notes.get("family", set()) | notes.get("style", set()))
    if unmatched:
        parts.append("Blender's built-in font (a plain sans serif) used for " +
                     ", ".join(unmatched))
    if notes.get("layout"):
        parts.append("not followed: " + ", ".join(sorted(notes["layout"])) +
                     " (set left to right, top to bottom, BEGIN / FIRST)")
    return ["Text: " + "; ".join(parts)] if parts else []


def light_attenuation(attenuation, scale) -> tuple:
    """The attenuation (a0, a1, a2) of a light under a Transform of uniform *scale* s, for
    world distances: the standard's 1/max(a0 + a1·d + a2·d², 1) takes d in the light's
    coordinate system, d = d_world / s, so a1' = a1 / s and a2' = a2 / s² (a scale of 0,
    which the file cannot mean, is read as 1)."""
    a0, a1, a2 = (float(v) for v in attenuation)
    s = float(scale) if scale > 0.0 and math.isfinite(scale) else 1.0
    return a0, a1 / s, a2 / (s * s)


class _Builder:
    def __init__(self, context, doc):
        self.context = context
        self.scene = context.scene
        self.layer = context.view_layer
        self.doc = doc
        self.own = []               # warnings of the Blender side, each once
        self.objects = []
        self.made = []              # the Phong materials made, in order
        self.meshes = {}            # id(core Mesh) -> Blender mesh
        self.images = {}            # id(core Texture) -> (image or None, components)
        self.materials = {}         # variant key -> material
        self.first = {}             # id(core Material) or None -> its first variant key
        self.uses = []              # (object, ShapeInstance)
        self.by_instance = {}       # instance id -> object
        self.frame = None           # the Empty that carries sheared matrices
        self.sync = None
        self.camera = None
        self.before = native.snapshot()
        self.camera_before = self.scene.camera
        self.model_before = self.scene.get(rig.MODEL_KEY)
        self.world_before = None    # (world, {key: value or None})
        self.world_ambient = None   # (intensity, colour) of the export's WorldAmbient light
        self.scene_keys = {HEADLIGHT_OFF_KEY: self.scene.get(HEADLIGHT_OFF_KEY)}
        self.retargeted = []        # (a scene's own headlight, the camera it followed)
        self.font_notes = {}        # what the Text nodes asked of the font: {kind: {value}}

    def warn(self, text: str) -> None:
        if text not in self.own:
            self.own.append(text)

    def warnings(self) -> list:
        return list(self.doc.warnings) + [w for w in self.own if w not in self.doc.warnings]

    # -- rollback -------------------------------------------------------------------------
    def undo(self):
        native.remove_added(self.before)
        if self.world_before is not None:
            world, values = self.world_before
            if world.name in bpy.data.worlds:
                native.restore_keys(world, values)
                world_copies.prune([world])   # the removed lights groups' light keys
        native.restore_keys(self.scene, self.scene_keys)
        self.scene.camera = self.camera_before
        for obj, target in self.retargeted:
            try:
                constraint = obj.constraints.get(headlight_mod.CONSTRAINT)
                if constraint is not None:
                    constraint.target = target
            except ReferenceError:
                pass
        if self.scene.get(rig.MODEL_KEY) != self.model_before:
            self.scene.phong.model = self.model_before or rig.MODELS[0]  # relinks the scene
            if self.model_before is None and rig.MODEL_KEY in self.scene.keys():
                del self.scene[rig.MODEL_KEY]

    # -- the scene ------------------------------------------------------------------------
    def build(self):
        doc, scene = self.doc, self.scene
        stem = os.path.splitext(os.path.basename(doc.path))[0]
        for ending in (".wrl", ".x3d", ".x3dv"):   # "model.wrl.gz"
            stem = stem.removesuffix(ending)
        self.collection = bpy.data.collections.new(stem or "X3D")
        target = self.context.collection or scene.collection
        target.children.link(self.collection)
        if not doc.instances:
            self.warn("the file has no shape with geometry")
        for inst in doc.instances:
            self.shape(inst)
        for line in font_warnings(self.font_notes):
            self.warn(line)
        self.make_camera()
        lights = self.lights()
        if doc.headlight:   # the viewer has one headlight: a scene's own follows the camera
            existing = headlight_mod.headlights(scene)
            for obj in existing:
                constraint = obj.constraints.get(headlight_mod.CONSTRAINT)
                self.retargeted.append((obj, constraint.target if constraint else None))
                headlight_mod.follow(obj, scene.camera)
            if not existing:
                lights.append(headlight_mod.add(scene, scene.camera, self.collection))
        else:
            scene[HEADLIGHT_OFF_KEY] = 1
        self.objects.extend(lights)
        if scene.get(rig.MODEL_KEY) != "x3d":
            if rig.groups_of(scene):
                self.warn(f"scene {scene.name!r} switched from the {rig.model_of(scene)} lighting "
                          "model to X3D / VRML97: its other Phong materials show that model too")
            scene.phong.model = "x3d"      # relinks the scene's Phong materials, if any
        self.no_world_ambient()
        with sync_mod.session(scene, self.layer) as self.sync:
            for obj, inst in self.uses:   # each material made for its objects' light set
                self.bind(obj, inst)

    def shape(self, inst):
        geometry = inst.shape.geometry
        material = inst.shape.material
        # the reader names a geometry by its DEF, else its shape's or group's, else its type
        given = geometry.name if geometry.name != geometry.kind else ""
        name = inst.shape.name or (inst.path[-1] if inst.path else "") or given \
            or (material.name if material is not None else "") or geometry.kind
        mesh = self.meshes.get(id(geometry))
        if mesh is None:
            mesh = self.meshes[id(geometry)] = self.mesh(geometry, given or name)
        obj = bpy.data.objects.new(name, mesh)
        self.collection.objects.link(obj)
        self.place(obj, file_matrix(self.doc, inst.matrix), name)
        self.objects.append(obj)
        self.uses.append((obj, inst))
        self.by_instance[inst.id] = obj

    def place(self, obj, matrix, name):
        """*matrix* as *obj*'s world matrix; a shear (which location, rotation and scale
        cannot hold) goes into its parent inverse matrix under an Empty at the origin."""
        blender = Matrix(matrix.tolist())
        obj.rotation_mode = "QUATERNION"   # exact where Euler angles lose digits (gimbal)
        obj.matrix_basis = blender
        back = np.array(obj.matrix_basis, dtype=np.float64)
        size = max(float(np.abs(matrix[:3, :3]).max()), 1e-30)
        error = np.abs(back[:3] - matrix[:3])
        if error[:, :3].max() <= 1e-5 * size and \
                error[:, 3].max() <= 1e-6 * (1.0 + float(np.abs(matrix[:3, 3]).max())):
            return
        if self.frame is None:
            self.frame = bpy.data.objects.new(SHEAR_FRAME, None)
            self.collection.objects.link(self.frame)
            self.objects.append(self.frame)
        obj.parent = self.frame
        obj.matrix_basis = Matrix.Identity(4)
        obj.matrix_parent_inverse = blender

    # -- meshes -----------------------------------------------------------------------------
    def mesh(self, source, name):
        if source.text is not None:
            return self.mesh(text_geometry(source.text, self.font_notes), name)
        source = x3d.counter_clockwise(source)
        mesh = bpy.data.meshes.new(name)
        positions = np.asarray(source.positions, dtype=np.float64) * self.doc.meter
        mesh.vertices.add(len(positions))
        mesh.vertices.foreach_set("co", positions.astype(np.float32).reshape(-1))
        if source.edges is not None and len(source.edges):   # line sets: loose edges
            edges = np.asarray(source.edges, dtype=np.int64).reshape(-1, 2)
            edges = edges[edges[:, 0] != edges[:, 1]]
            mesh.edges.add(len(edges))
            mesh.edges.foreach_set("vertices", edges.astype(np.int32).reshape(-1))
        sizes = np.asarray(source.face_sizes, dtype=np.int64)
        corners = np.asarray(source.corners, dtype=np.int64)
        per_corner = {key: getattr(source, key) for key in ("normals", "colors", "uvs")}
        bad = degenerate_faces(sizes, corners)
        if bad.any():
            self.warn(f"faces using a vertex twice left out (Blender refuses them): "
                      f"{name} ({int(bad.sum())})")
            keep = np.repeat(~bad, sizes)
            sizes, corners = sizes[~bad], corners[keep]
            per_corner = {k: (v[keep] if v is not None else None) for k, v in per_corner.items()}
        if len(sizes):
            mesh.loops.add(len(corners))
            native.set_attribute(mesh, ".corner_vert", "INT", "CORNER", "value",
                           corners.astype(np.int32),
                           lambda values: mesh.loops.foreach_set("vertex_index", values))
            mesh.polygons.add(len(sizes))
            starts = np.concatenate([[0], np.cumsum(sizes)[:-1]]).astype(np.int32)
            mesh.polygons.foreach_set("loop_start", starts)
        uvs = per_corner["uvs"]
        if uvs is not None and len(sizes):
            layer = mesh.uv_layers.new(name=UV_MAP)
            values = np.asarray(uvs, dtype=np.float32).reshape(-1)
            native.set_attribute(mesh, layer.name, "FLOAT2", "CORNER", "vector", values,
                           lambda values: layer.data.foreach_set("uv", values))
        colors = per_corner["colors"]
        if colors is not None and len(sizes):
            attribute = mesh.color_attributes.new(COLOR_ATTRIBUTE, "FLOAT_COLOR", "CORNER")
            attribute.data.foreach_set("color", np.asarray(colors, np.float32).reshape(-1))
        elif source.point_colors is not None and len(positions):
            attribute = mesh.color_attributes.new(COLOR_ATTRIBUTE, "FLOAT_COLOR", "POINT")
            attribute.data.foreach_set("color",
                                       np.asarray(source.point_colors, np.float32).reshape(-1))
        mesh.update(calc_edges=True)
        if mesh.validate(verbose=False):
            self.warn(f"invalid faces (repeated faces or edges) repaired by Blender: {name}")
        normals = per_corner["normals"]
        if normals is not None and len(mesh.loops) != len(corners):
            self.warn(f"normals left out where Blender repaired the faces: {name}")
            normals = None
        if normals is not None and len(sizes):
            normals = np.asarray(normals, dtype=np.float64)
            length = np.sqrt(np.einsum("ij,ij->i", normals, normals))[:, None]
            normals = np.where(length > 0, normals / np.where(length > 0, length, 1.0), 0.0)
            mesh.shade_smooth()   # the custom normals are used on smooth faces
            compat.set_corner_normals(mesh, normals.astype(np.float32))
        elif len(sizes):
            compat.smooth_by_angle(mesh, float(source.crease_angle))
        return mesh

    # -- lights -----------------------------------------------------------------------------
    def lights(self) -> list:
        """The file's lights as Blender lights; instances of one light at one place (a
        scoped light USE'd in several groups) are one Blender light reaching the union of
        their scopes.  Returns the light objects."""
        merged = {}
        for inst in self.doc.lights:
            location = (x3d.to_blender_matrix(self.doc) @ inst.matrix
                        @ np.append(np.asarray(inst.light.location, float), 1.0))[:3]
            direction = x3d.Y_UP_TO_Z_UP[:3, :3] @ inst.world_direction()
            place = None if inst.light.kind == "directional" else tuple(np.round(location, 9))
            key = (id(inst.light), place, tuple(np.round(direction, 9)))
            entry = merged.setdefault(key, [inst, location, direction, set(), False])
            if inst.scope is None:
                entry[4] = True
            else:
                entry[3].update(inst.scope)
        out = []
        total = len(self.doc.instances)
        for inst, location, direction, scope, is_global in merged.values():
            scope = None if is_global or len(scope) >= total else scope
            if self.world_ambient is None and scope is None and \
                    x3d.is_world_ambient(inst.light):
                self.world_ambient = x3d.world_ambient(self.doc, inst.light)
                continue
            out.append(self.light(inst, location, direction, scope))
        return out

    def light(self, inst, location, direction, scope):
        source = inst.light
        values = x3d.light_values(self.doc, source)
        name = source.name or LIGHT_NAMES[source.kind]
        shown = name if source.on or name.endswith(OFF) else name + OFF
        light = bpy.data.lights.new(name, LIGHT_TYPES[source.kind])
        light.use_shadow = values["shadows"]  # X3D's shadows field: Cast Shadow (default off)
        color = tuple(float(c) for c in values["color"])
        if min(color) < 0.0:
            self.warn(f"negative light colours read as 0: {name}")
        light.color = tuple(max(0.0, c) for c in color)
        intensity = float(values["intensity"])
        ambient = float(values["ambient_intensity"])
        if min(intensity, ambient) < 0.0:
            self.warn(f"negative light intensities read as 0: {name}")
        settings = {"intensity": max(intensity, 0.0), "ambient": max(ambient, 0.0)}
        if source.kind != "directional":
            # the standard measures d (attenuation and radius) in the light's coordinate
            # system: under a scale s, d_local = d_world / s (light_attenuation)
            scale, uniform = _scale_of(inst.matrix)
            if not uniform:
                self.warn(f"lights under a non-uniform scale: their attenuation and radius "
                          f"measured with the cube root of the volume scale: {name}")
            a0, a1, a2 = light_attenuation(values["attenuation"], scale)
            settings.update(constant=a0, linear=a1, quadratic=a2,
                            radius=values["radius"] * scale)
        if source.kind == "spot":
            cut = float(values["cut_off_angle"])
            size = min(max(2.0 * cut, SPOT_SIZE[0]), SPOT_SIZE[1])
            if size != 2.0 * cut:
                self.warn(f"spot cut-off angles outside Blender's spot size of 1°-180° "
                          f"clamped: {name} ({math.degrees(cut):g}°)")
            light.spot_size = size
            light.spot_blend = 0.0
            light[CUT_OFF_KEY] = cut
            settings["beam_width"] = float(values["beam_width"])
        properties.write_light(light, settings)
        obj = bpy.data.objects.new(shown, light)
        self.collection.objects.link(obj)
        rotation = Vector(direction.tolist()).to_track_quat("-Z", "Y")
        obj.rotation_mode = "QUATERNION"
        obj.matrix_basis = Matrix.LocRotScale(Vector(location.tolist()), rotation, None)
        if not source.on:
            obj.hide_render = True
        if scope is not None:
            receivers = [self.by_instance[i] for i in sorted(scope) if i in self.by_instance]
            if not receivers:   # Light Linking without receivers would light everything
                obj.hide_render = True
                obj[LIGHTS_NOTHING_KEY] = 1
                self.warn(f"scoped lights whose group holds no shape (they light nothing): "
                          f"hidden from render: {obj.name}")
            else:
                collection = bpy.data.collections.new(f"{obj.name} scope")
                for receiver in receivers:
                    collection.objects.link(receiver)
                obj.light_linking.receiver_collection = collection
        return obj

    # -- the camera -------------------------------------------------------------------------
    def make_camera(self):
        doc, scene = self.doc, self.scene
        vp = doc.viewpoint
        if vp is None and scene.camera is not None:
            return   # X3D's default viewpoint only where the scene has no camera
        if vp is None:
            vp = x3d.Viewpoint(name="Viewpoint")
            world = x3d.to_blender_matrix(doc) @ vp.matrix()
        else:
            world = x3d.to_blender_matrix(doc) @ np.asarray(doc.viewpoint_matrix) @ vp.matrix()
        name = vp.name or vp.description or "Viewpoint"
        camera = bpy.data.cameras.new(name)
        linear = world[:3, :3]
        scale, _uniform = _scale_of(world)
        u, _s, vt = np.linalg.svd(linear)
        rotation = u @ vt
        if np.linalg.det(rotation) < 0:   # a mirrored frame: the nearest rotation
            u[:, -1] *= -1.0
            rotation = u @ vt
        location = world[:3, 3].copy()
        render = scene.render
        aspect = (render.resolution_x * render.pixel_aspect_x) / max(
            render.resolution_y * render.pixel_aspect_y, 1e-9)
        if vp.kind == "OrthoViewpoint":
            lo_x, lo_y, hi_x, hi_y = vp.ortho_field or (-1.0, -1.0, 1.0, 1.0)
            width, height = abs(hi_x - lo_x) * scale, abs(hi_y - lo_y) * scale
            camera.type = "ORTHO"
            if width / max(height, 1e-30) <= aspect:   # the height limits the view
                camera.sensor_fit, camera.ortho_scale = "VERTICAL", max(height, 1e-6)
            else:
                camera.sensor_fit, camera.ortho_scale = "HORIZONTAL", max(width, 1e-6)
            centre = np.array([(lo_x + hi_x) / 2.0, (lo_y + hi_y) / 2.0, 0.0]) * scale
            location = location + rotation @ centre
        else:
            camera.type = "PERSP"
            # X3D's fieldOfView is the angle of the smaller side of the view
            camera.sensor_fit = "VERTICAL" if aspect >= 1.0 else "HORIZONTAL"
            fov = float(vp.field_of_view)
            angle = min(max(fov, CAMERA_ANGLE[0]), CAMERA_ANGLE[1])
            if angle != fov:
                self.warn(f"viewpoint fieldOfView {fov:g} outside Blender's camera angles; "
                          f"{angle:g} used")
            camera.angle = angle
        reach = self.extent(location)
        camera.clip_end = max(reach * 2.0, 1.0)
        camera.clip_start = min(0.1, camera.clip_end * 1e-4)
        obj = bpy.data.objects.new(name, camera)
        if doc.viewpoint is None:   # a viewer frames such a file (``phong compare`` does)
            obj[DEFAULT_VIEWPOINT_KEY] = 1
        self.collection.objects.link(obj)
        matrix = np.eye(4)
        matrix[:3, :3] = rotation
        matrix[:3, 3] = location
        obj.rotation_mode = "QUATERNION"
        obj.matrix_basis = Matrix(matrix.tolist())
        self.objects.append(obj)
        self.camera = obj
        scene.camera = obj

    def extent(self, point) -> float:
        """The largest distance from *point* to the imported objects' bounding boxes."""
        far = 0.0
        for obj in self.objects:
            if obj.type != "MESH" or not len(obj.data.vertices):
                continue
            corners = np.array([tuple(c) for c in obj.bound_box], dtype=np.float64)
            matrix = np.array(obj.matrix_world, dtype=np.float64)
            world = corners @ matrix[:3, :3].T + matrix[:3, 3]
            far = max(far, float(np.linalg.norm(world - point, axis=1).max()))
        return far

    # -- the world ------------------------------------------------------------------------
    def no_world_ambient(self):
        world = self.scene.world
        if world is None:
            world = bpy.data.worlds.new("World")
            compat.black_world(world)
            self.scene.world = world
        keys = (properties.AMBIENT_INTENSITY[0], properties.AMBIENT_COLOR[0])
        self.world_before = (world, {k: (world[k] if k in world.keys() else None)
                                     for k in keys})
        color = world.get(keys[1], properties.AMBIENT_COLOR[1])
        if self.world_ambient is not None:   # the export's World ambient, read back
            properties.write_world(world, *self.world_ambient)
        else:
            properties.write_world(world, 0.0, tuple(color))

    # -- materials ------------------------------------------------------------------------
    def bind(self, obj, inst):
        shape = inst.shape
        geometry = shape.geometry
        texture = shape.texture
        image, components = self.image(texture) if texture is not None else (None, None)
        colors = geometry.colors is not None or geometry.point_colors is not None
        key, reach = self.sync.light_set(obj)
        material = shape.material
        transform = shape.texture_transform if image is not None else None
        # a material of equal texture, transform, colours, light set and ``solid`` is made
        # once; lines and points (which have no back) take any variant of the rest
        faces = geometry.edges is None and geometry.kind != "PointSet"
        solid = bool(geometry.solid) if faces else None
        missing = texture is not None and image is None and texture.image is None and \
            bool(texture.paths)   # an ImageTexture whose file is not there: its reference
        variant = (id(material) if material is not None else None,
                   (image.name, texture.repeat_s, texture.repeat_t) if image is not None
                   else ("missing", tuple(texture.paths), texture.repeat_s, texture.repeat_t)
                   if missing else None,
                   (tuple(transform.center), transform.rotation, tuple(transform.scale),
                    tuple(transform.translation)) if transform is not None else None,
                   colors, key, solid)
        made = self.materials.get(variant)
        if made is None and solid is None:
            made = next((m for v, m in self.materials.items() if v[:5] == variant[:5]), None)
        if made is None:
            group = self.sync.group(key, reach)
            name = self.name_of(material, variant,
                                texture if image is not None or missing else None, reach, key)
            made = self.material(name, group, material, image, components, colors,
                                 shape.texture_transform if image is not None else None,
                                 texture)
            # solid TRUE: the back of a face is not drawn (Eevee, Workbench; Cycles draws
            # both sides whatever the setting: docs/x3d.md)
            made.use_backface_culling = bool(solid)
            if missing:   # left out of the picture, its reference kept for the export
                made[keys.X3D_MISSING_TEXTURE] = {
                    "name": texture.name, "paths": list(texture.paths),
                    "repeat_s": bool(texture.repeat_s), "repeat_t": bool(texture.repeat_t)}
            self.materials[variant] = made
            self.made.append(made)
        mesh = obj.data
        if len(mesh.materials) == 0:
            mesh.materials.append(made)
        elif obj.material_slots[0].material is not made:
            slot = obj.material_slots[0]
            slot.link = "OBJECT"
            slot.material = made

    def name_of(self, material, variant, texture, reach, key) -> str:
        """The file's name for the first variant of a material; for the others (another
        texture, colours, light set or ``solid``) the first variant's Blender name and what
        differs, in brackets: a file that defines a name twice (two ``DEF PIN-01``, a PROTO's
        Material in each instance) gives ``PIN-01 [...]`` and ``PIN-01.001 [...]``, each
        variant named after its own material."""
        base = material.name if material is not None else "Unlit"
        first = self.first.setdefault(variant[0], variant)
        if first == variant:
            return base
        made = self.materials.get(first)
        if made is not None:
            base = made.name
        parts = []
        if variant[1:3] != first[1:3]:
            parts.append(texture.name or os.path.basename(
                texture.path or (texture.paths[0] if texture.paths else "")) if texture
                else "no texture")
        if variant[3] != first[3]:
            parts.append("colours" if variant[3] else "no colours")
        if variant[4] != first[4]:
            parts.append(", ".join(o.name for o in reach) or "no light")
        if variant[5] != first[5]:
            parts.append("solid" if variant[5] else "two-sided")
        return f"{base} [{'; '.join(parts)}]"

    def material(self, name, group, source, image, components, colors, transform, texture):
        values = x3d.phong_values(source, components, colors)
        material = writer.new_material(name, group)
        tree = material.node_tree
        lights = tree.nodes[recipe.LIGHTS_NODE]
        controls = writer.write(material, writer.Values(
            {"Object Color": values["Kd"], "Specular Color": values["Ks"],
             "Irradiant Color": values["Ke"], recipe.AMBIENT_INPUT: values["Ka"]},
            exponent=values["exponent"], blinn=values["blinn"]))
        if source is not None:
            material[AMBIENT_KEY] = float(source.ambient_intensity)
            material[SHININESS_KEY] = float(source.shininess)
            if source.kind == "two_sided" and source.back is not None:
                self.warn("TwoSidedMaterial back colours not shown (Blender shows the front "
                          f"values on both sides): {source.name}")
            if source.kind == "physical":
                self.warn("PhysicalMaterial read as a Phong material of its base colour "
                          f"(metallic and roughness not used): {source.name}")
        if not values["lit"]:
            material[UNLIT_KEY] = 1
        # the texture and colours act on Kd (lit) or Ke (unlit), as phong_values says
        socket_name = "Object Color" if values["lit"] else "Irradiant Color"
        base = None     # what replaces the term: the texture, the colours or their product
        if image is not None:
            base = self.texture_chain(material, image, texture, transform)
        if colors and values["source"] in ("colors", "texture*colors"):
            attribute = recipe.named_node(tree, COLORS_NODE, "ShaderNodeVertexColor",
                                          (-1150.0, 500.0))
            attribute.layer_name = COLOR_ATTRIBUTE
            attribute.label = "Colours (Color node)"
            colour = compat.output_socket(attribute, "Color")
            base = colour if base is None else self.vector(
                tree, "texture x colours", "MULTIPLY", base, colour, (-700.0, 500.0))
        if base is None:
            return self.finish(material, values)
        if image is not None and components in (2, 4) and self.has_alpha(image):
            self.texture_alpha(material, values["opacity"])
        if values["source"] == "texture*material":   # a grey texture multiplies the term
            feed = self.vector(tree, "texture x colour", "MULTIPLY", base,
                               controls[socket_name], (-700.0, 300.0))
        else:
            feed = base
        tree.links.new(feed, lights.inputs[socket_name])
        if values["lit"]:
            if values["source"] == "texture*material":   # Ka = texture × the Ka control
                ambient = self.vector(tree, "texture x ambient", "MULTIPLY", base,
                                      controls[recipe.AMBIENT_INPUT], (-700.0, 100.0))
            else:   # Ka = ambientIntensity × the colour that replaces diffuseColor
                node = recipe.named_node(tree, CHAIN + "ambient", "ShaderNodeVectorMath",
                                         (-500.0, 100.0))
                node.operation = "SCALE"
                node.label = "x ambientIntensity"
                tree.links.new(base, compat.input_socket(node, "Vector"))
                compat.input_socket(node, "Scale").default_value = float(
                    source.ambient_intensity)
                ambient = compat.output_socket(node, "Vector")
            tree.links.new(ambient, lights.inputs[recipe.AMBIENT_INPUT])
        return self.finish(material, values)

    @staticmethod
    def finish(material, values):
        if values["opacity"] < 1.0 and material.node_tree.nodes.get(recipe.OPACITY_MAP) is None:
            opacity_nodes.set_opacity(material, values["opacity"])
        return material

    @staticmethod
    def texture_alpha(material, opacity):
        """A two- or four-channel texture's alpha as the material's opacity (cut-out leaves,
        labels): the opacity map (``recipe.OPACITY_MAP``) = the texture's alpha × the
        Opacity control, which keeps the file's 1 − transparency (X3D 4's texturing table:
        A × (1 − transparency); VRML97 and X3D 3 say A alone, the same where transparency
        is 0, as it mostly is)."""
        tree = material.node_tree
        opacity_nodes.set_opacity(material, opacity)   # the control: kept for the export
        alpha = compat.output_socket(tree.nodes[TEXTURE_NODE], "Alpha")
        control = compat.value_output(tree.nodes[recipe.OPACITY])
        native.math(tree, recipe.OPACITY_MAP, "MULTIPLY", alpha, control, (-400.0, 600.0),
                    clamp=True)
        tree.nodes[recipe.OPACITY_MAP].label = "texture alpha x Opacity"
        opacity_nodes.apply_opacity(material)

    @staticmethod
    def has_alpha(image) -> bool:
        """Whether *image* has a texel whose alpha is below 1 (an RGBA file of opaque texels
        blends nothing: it stays an opaque material).  Images over 16 Mpixels, or whose
        pixels cannot be read, are taken as having one (as the file's channels say)."""
        width, height = image.size
        if width * height > (1 << 24) or width * height == 0:
            return True
        try:
            pixels = np.empty(len(image.pixels), dtype=np.float32)
            image.pixels.foreach_get(pixels)
        except (RuntimeError, ValueError, TypeError):
            return True
        return not len(pixels) or float(pixels[3::4].min()) < 1.0

    @staticmethod
    def vector(tree, what, operation, a, b, location):
        node = recipe.named_node(tree, CHAIN + what, "ShaderNodeVectorMath", location)
        node.operation = operation
        node.label = what
        tree.links.new(a, compat.input_socket(node, "Vector"))
        tree.links.new(b, compat.input_socket(node, "Vector_001"))
        return compat.output_socket(node, "Vector")

    def texture_chain(self, material, image, texture, transform):
        """Image Texture (UVMap, through a Mapping node for a TextureTransform); returns its
        Color output."""
        tree = material.node_tree
        node = recipe.named_node(tree, TEXTURE_NODE, "ShaderNodeTexImage", (-1150.0, 250.0))
        node.image = image
        node.label = texture.name or "ImageTexture"
        if not texture.repeat_s and not texture.repeat_t:
            node.extension = "EXTEND"
        elif not (texture.repeat_s and texture.repeat_t):
            self.warn("textures that repeat along one axis only shown repeating along both "
                      f"(Blender's images repeat or clamp both): {texture.name or image.name}")
        if transform is not None:
            mapping = self.mapping(tree, transform)
            if mapping is not None:
                uv = recipe.named_node(tree, UV_NODE, "ShaderNodeUVMap", (-1650.0, 250.0))
                uv.uv_map = UV_MAP
                tree.links.new(compat.output_socket(uv, "UV"),
                               compat.input_socket(mapping, "Vector"))
                tree.links.new(compat.output_socket(mapping, "Vector"),
                               compat.input_socket(node, "Vector"))
                material[TRANSFORM_KEY] = [*map(float, transform.center),
                                           float(transform.rotation), *map(float, transform.scale),
                                           *map(float, transform.translation)]
        return compat.output_socket(node, "Color")

    def mapping(self, tree, transform):
        """A Mapping node giving the standard's Tc' = −C·S·R·C·T·Tc = S·R(θ)·Tc + S·R(θ)·(C + T)
        − C.  Blender's Texture mapping gives R(r)ᵀ(v − L) / s, so r = −θ, s = 1/scale and
        L = −(C + T) + R(−θ)·(C / scale).  None (with a warning) for a zero scale, which no
        Mapping node can give."""
        sx, sy = (float(v) for v in transform.scale)
        if sx == 0.0 or sy == 0.0:
            self.warn(f"TextureTransform with a zero scale left out: {transform.name or '-'}")
            return None
        theta = float(transform.rotation)
        cx, cy = (float(v) for v in transform.center)
        tx, ty = (float(v) for v in transform.translation)
        c, s = math.cos(-theta), math.sin(-theta)
        qx, qy = cx / sx, cy / sy
        location = (-(cx + tx) + c * qx - s * qy, -(cy + ty) + s * qx + c * qy, 0.0)
        node = recipe.named_node(tree, MAPPING_NODE, "ShaderNodeMapping", (-1400.0, 250.0))
        node.vector_type = "TEXTURE"
        node.label = "TextureTransform"
        compat.input_socket(node, "Location").default_value = location
        compat.input_socket(node, "Rotation").default_value = (0.0, 0.0, -theta)
        compat.input_socket(node, "Scale").default_value = (1.0 / sx, 1.0 / sy, 1.0)
        return node

    # -- images -----------------------------------------------------------------------------
    def image(self, texture):
        """(Blender image or None, its components) of a core Texture, each loaded once, as
        data (Non-Color: the texel's value is the colour in the standard's equation, as the
        numbers of diffuseColor are) with its colour apart from its alpha."""
        # one image per file (or PixelTexture): ImageTexture nodes naming one file share it
        key = texture.path if texture.image is None and texture.path else id(texture)
        if key in self.images:
            return self.images[key]
        image, components = None, None
        name = texture.name or (os.path.basename(texture.path) if texture.path else "")
        if texture.image is not None:
            pixels = np.asarray(texture.image, dtype=np.float32) / 255.0
            height, width, comps = pixels.shape
            rgba = np.ones((height, width, 4), dtype=np.float32)
            rgba[..., :3] = pixels[..., :1] if comps < 3 else pixels[..., :3]
            if comps in (2, 4):
                rgba[..., 3] = pixels[..., -1]
            image = bpy.data.images.new(name or "PixelTexture", width, height,
                                        alpha=comps in (2, 4))
            image.colorspace_settings.name = native.NON_COLOR
            image.pixels.foreach_set(rgba.reshape(-1))
            image.update()
            image.pack()
            image[keys.X3D_COMPONENTS] = comps   # (the export writes it back as it was)
            components = comps
        elif texture.path is not None:   # its own image (renamed below), as data
            image = native.load_image(texture.path, non_color=True, existing=False)
            if image is None:
                self.warn(f"texture files that Blender cannot read left out: {texture.path}")
            else:
                if texture.name:
                    image.name = texture.name
                components = image_components(texture.path) or \
                    {8: 1, 16: 2, 24: 3, 32: 4, 96: 3, 128: 4}.get(image.depth, 3)
        if image is not None:
            image.colorspace_settings.name = native.NON_COLOR
            native.straight(image)
        self.images[key] = (image, components)
        return self.images[key]
