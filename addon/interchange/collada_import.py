# SPDX-License-Identifier: GPL-3.0-or-later
"""COLLADA (.dae) imported as exact Phong materials, Phong lights and the file's scene.

``core/collada.py`` reads the whole file first (nothing is added when it cannot be read);
this module builds the Blender side:

* every node an object (an Empty when it holds several instances or none), its transform
  the file's matrix with the translation in metres and, at the roots, the up axis turned to
  Blender's Z; ``instance_node`` copies the node tree it names;
* meshes (triangles, polylist, polygons, tristrips, trifans) with their normals (custom
  split normals), texture coordinates ("UVMap", "UVMap1" ... by set) and vertex colours,
  positions times ``<unit meter>``; each ``bind_material`` symbol its material slot;
* every material a Phong material with the file's values (the table of
  ``docs/interchange.md``): emission → Irradiant Color, ambient → Ambient Object Color (Ka),
  diffuse → Object Color, specular → Specular Color, shininess → Exponent, blinn → Blinn 1;
  a term the effect leaves out is black; a texture feeds its input instead of the colour;
  opacity from the spec's transparency formulas (``phong_opacity``);
* lights: ambient → the World's Phong ambient (the sum of the file's ambient lights),
  directional → Sun, point → Point with 1/(c + l·d + q·d²) rescaled to metres, spot → Spot
  with ``spot_size`` = ``falloff_angle`` (the full cone) and Edge Exponent =
  ``falloff_exponent``; Phong Intensity 1 and the light colour the file's;
* cameras, the first one the scene's camera when the scene has none.

:func:`import_file` is the plain entry point (``phong compare FILE.dae``); it raises
:class:`ColladaImportError` and leaves the scene as it was when the import fails.
"""

from __future__ import annotations

import math

import bpy
import numpy as np
from mathutils import Matrix

from ...core import collada
from .. import compat
from ..lighting import opacity as opacity_nodes
from ..lighting import properties, recipe, writer
from ..lighting import sync as sync_mod
from . import keys, native

#: Custom properties of an imported material, so that export writes the file's technique
#: and transparency back.
TECHNIQUE_KEY = keys.COLLADA_TECHNIQUE
OPAQUE_KEY = keys.COLLADA_OPAQUE
TRANSPARENT_KEY = keys.COLLADA_TRANSPARENT
TRANSPARENCY_KEY = keys.COLLADA_TRANSPARENCY
SYMBOLS_KEY = "phong_collada_symbols"   # a mesh's material symbols, while importing
TEXTURE_NODE = keys.COLLADA_TEXTURE_NODE   # + lights-group input
UVMAP_NODE = "phong_dae_uv:"      # + lights-group input
#: lights-group input -> COLLADA element
INPUTS = keys.COLLADA_INPUTS
#: The most objects one import makes: the file's nodes with their ``instance_node`` copies
#: (and an object per instance of a node that holds several).  A file whose instances would
#: make more (a few kilobytes can ask for 2^40: each library node instantiating the next one
#: twice) imports the first MAX_NODES, with one warning giving the number it asks for;
#: counted before anything is made (:func:`object_count`), so such a file ends in seconds.
MAX_NODES = 10_000
#: The deepest nesting of nodes (children and instance_node) that is imported.
MAX_DEPTH = 256
class ColladaImportError(native.InterchangeError):
    """The import failed; nothing was added to the file."""


def import_file(context, filepath, literal_transparency=False) -> native.ImportResult:
    """Import the COLLADA file *filepath* into *context*'s scene (``formats.import_file``):
    its objects, Phong materials and warnings.  Raises ColladaImportError (the scene
    unchanged) when it cannot be imported."""
    try:
        doc = collada.load(filepath)
    except collada.ColladaError as error:
        raise ColladaImportError(str(error)) from None
    builder = _Builder(context, doc, literal_transparency)
    try:
        builder.build()
    except Exception as error:   # leave the file as it was
        builder.undo()
        raise ColladaImportError(f"{filepath}: import failed ({type(error).__name__}: "
                                 f"{error}); nothing imported") from error
    return native.ImportResult(builder.objects, list(builder.materials.values()),
                               doc.warnings, builder.sync)


def object_count(doc, by_id) -> int:
    """How many nodes the visual scene makes with every ``instance_node`` copy (and the extra
    object of each instance where a node holds several), counted once per library node
    (memoised: a 2^40 fan-out is 40 look-ups); an instance of a node on its own path (a cycle,
    left out by the import) counts nothing."""
    memo, busy = {}, set()

    def count(node, depth):
        key = id(node)
        if key in memo:
            return memo[key]
        if depth > MAX_DEPTH or key in busy:
            return 0
        busy.add(key)
        shown = [i for i in node.instances if i.kind != "node"]
        total = 1 + (len(shown) if len(shown) > 1 else 0)
        total += sum(count(child, depth + 1) for child in node.children)
        for inst in node.instances:
            target = by_id.get(inst.url) if inst.kind == "node" else None
            if target is not None:
                total += count(target, depth + 1)
        busy.discard(key)
        memo[key] = total
        return total

    return sum(count(node, 0) for node in doc.nodes)


class _Builder:
    def __init__(self, context, doc, literal):
        self.context = context
        self.scene = context.scene
        self.doc = doc
        self.literal = literal
        self.objects = []
        self.meshes = {}           # geometry id -> mesh
        self.lights = {}           # light id -> light data
        self.cameras = {}
        self.materials = {}        # material id -> Phong material
        self.uses = []             # (object, instance, mesh)
        self.images = {}
        self.uv_names = {}         # mesh -> {texture coordinate set: its UV map's name}
        self.sync = None
        self.world_before = None
        self.camera_before = self.scene.camera
        self.count = 0
        #: every data block that existed before: whatever else exists after a failure is
        #: the import's (materials the Sync copies, lights groups, images included)
        self.before = native.snapshot()

    def _new(self, collection, *args):
        return collection.new(*args)

    def undo(self):
        native.remove_added(self.before)
        if self.world_before is not None:
            world, values = self.world_before
            native.restore_keys(world, values)
        self.scene.camera = self.camera_before

    # -- the scene ----------------------------------------------------------------------
    def build(self):
        doc = self.doc
        by_id = dict(doc.library_nodes)
        stack = list(doc.nodes)
        while stack:
            node = stack.pop()
            if node.id:
                by_id.setdefault(node.id, node)
            stack.extend(node.children)
        self.by_id = by_id
        target = self.context.collection or self.scene.collection
        self.collection = target
        wanted = object_count(doc, by_id)
        if wanted > MAX_NODES:
            self.doc.warn(f"the file's nodes and instance_node copies would make {wanted:,} "
                          f"objects, more than {MAX_NODES:,}; the first {MAX_NODES:,} imported")
        for node in doc.nodes:
            self.node(node, None, True, ())
        self.ambient()
        with sync_mod.session(self.scene, self.context.view_layer) as self.sync:
            self.bind_materials()
            for mesh in self.meshes.values():
                if SYMBOLS_KEY in mesh.keys():
                    del mesh[SYMBOLS_KEY]
        camera = next((o for o in self.objects if o.type == "CAMERA"), None)
        if camera is not None and self.scene.camera is None:
            self.scene.camera = camera

    def node(self, node, parent, root, seen, depth=0):
        self.count += 1
        if self.count > MAX_NODES:
            return   # (named in one warning: build)
        if depth > MAX_DEPTH:
            self.doc.warn(f"nodes nested more than {MAX_DEPTH} deep (through instance_node); "
                          "the deeper ones left out")
            return
        shown = [i for i in node.instances if i.kind != "node"]
        data_of = [self.data(i, node) for i in shown]
        pairs = [(i, d) for i, d in zip(shown, data_of) if d is not None]
        ambient_only = node.instances and not node.children and all(
            i.kind == "light" and getattr(self.doc.lights.get(i.url), "kind", "") == "ambient"
            for i in node.instances)
        if ambient_only:   # the light is the World's: no object (export writes it back so)
            return
        own = pairs[0] if len(pairs) == 1 else None
        data = own[1] if own is not None else None
        obj = self._new(bpy.data.objects, node.name, data)
        self.collection.objects.link(obj)
        self.objects.append(obj)
        if parent is not None:
            obj.parent = parent
        local = collada.to_blender(self.doc, node.matrix, root)
        self.set_matrix(obj, local, node.name)
        if own is not None and own[0].kind == "geometry":
            self.uses.append((obj, own[0]))
        if own is None:
            for inst, data in pairs:
                child = self._new(bpy.data.objects, f"{node.name} {inst.url}", data)
                self.collection.objects.link(child)
                self.objects.append(child)
                child.parent = obj
                if inst.kind == "geometry":
                    self.uses.append((child, inst))
        for child in node.children:
            self.node(child, obj, False, seen, depth + 1)
        for inst in node.instances:
            if inst.kind != "node":
                continue
            target = self.by_id.get(inst.url)
            if target is None:
                self.doc.warn(f"node {node.name}: <instance_node url=\"#{inst.url}\"> not "
                              "found; left out")
            elif inst.url in seen:
                self.doc.warn(f"node {node.name}: <instance_node url=\"#{inst.url}\"> "
                              "instantiates itself; left out")
            else:
                self.node(target, obj, False, seen + (inst.url,), depth + 1)

    def set_matrix(self, obj, matrix, name):
        """*matrix* as *obj*'s transform relative to its parent.  A shear (``<skew>``, a
        sheared ``<matrix>``), which an object's location, rotation and scale cannot hold,
        goes into its parent inverse matrix instead (world = parent · parent inverse ·
        basis), exact; a root gets an Empty parent at the origin for it."""
        blender = Matrix([list(map(float, row)) for row in matrix])
        obj.matrix_basis = blender
        back = np.array(obj.matrix_basis, dtype=np.float64)
        linear = np.asarray(matrix, dtype=np.float64)[:3, :3]
        size = max(float(np.abs(linear).max()), 1e-30)
        if np.allclose(back[:3, :3], linear, rtol=0.0, atol=1e-5 * size) and \
                np.allclose(back[:3, 3], matrix[:3, 3], rtol=1e-6, atol=1e-6) and \
                np.allclose(matrix[3], (0.0, 0.0, 0.0, 1.0)):
            return
        if obj.parent is None:
            frame = self._new(bpy.data.objects, f"{name} (shear frame)", None)
            self.collection.objects.link(frame)
            self.objects.append(frame)
            obj.parent = frame
        obj.matrix_basis = Matrix.Identity(4)
        obj.matrix_parent_inverse = blender

    def data(self, inst, node):
        if inst.kind == "geometry":
            source = self.doc.meshes.get(inst.url)
            if source is None:
                self.doc.warn(f"node {node.name}: geometry #{inst.url} not found or not a "
                              "mesh; left out")
                return None
            if inst.url not in self.meshes:
                self.meshes[inst.url] = self.mesh(source)
            return self.meshes[inst.url]
        if inst.kind == "light":
            source = self.doc.lights.get(inst.url)
            if source is None:
                self.doc.warn(f"node {node.name}: light #{inst.url} not found; left out")
                return None
            if source.kind == "ambient":
                return None
            if inst.url not in self.lights:
                self.lights[inst.url] = self.light(source)
            return self.lights[inst.url]
        if inst.kind == "camera":
            source = self.doc.cameras.get(inst.url)
            if source is None:
                self.doc.warn(f"node {node.name}: camera #{inst.url} not found; left out")
                return None
            if inst.url not in self.cameras:
                self.cameras[inst.url] = self.camera(source)
            return self.cameras[inst.url]
        return None

    # -- meshes -------------------------------------------------------------------------
    def mesh(self, source: collada.Mesh):
        dropped = collada.drop_degenerate(source)
        if dropped and not source.from_strips:
            self.doc.warn(f"geometry {source.name}: {dropped} face(s) using a vertex twice "
                          "left out")
        mesh = self._new(bpy.data.meshes, source.name)
        m = self.doc.meter
        positions = np.asarray(source.positions, dtype=np.float64) * m
        mesh.vertices.add(len(positions))
        mesh.vertices.foreach_set("co", positions.astype(np.float32).reshape(-1))
        if source.edges is not None and len(source.edges):   # <lines>: loose edges
            mesh.edges.add(len(source.edges))
            mesh.edges.foreach_set("vertices", source.edges.astype(np.int32).reshape(-1))
        sizes = np.asarray(source.face_sizes, dtype=np.int64)
        if len(sizes):
            mesh.loops.add(int(sizes.sum()))
            native.set_attribute(mesh, ".corner_vert", "INT", "CORNER", "value",
                           source.corners.astype(np.int32),
                           lambda values: mesh.loops.foreach_set("vertex_index", values))
            mesh.polygons.add(len(sizes))
            starts = np.concatenate([[0], np.cumsum(sizes)[:-1]]).astype(np.int32)
            mesh.polygons.foreach_set("loop_start", starts)
            symbols = np.asarray(source.face_symbols, dtype=np.int32)
            if symbols.any():
                native.set_attribute(mesh, "material_index", "INT", "FACE", "value", symbols,
                               lambda values: mesh.polygons.foreach_set("material_index",
                                                                        values))
        self.uv_names[mesh] = {}
        for index, channel in enumerate(sorted(source.uvs)):
            layer = mesh.uv_layers.new(name="UVMap" if index == 0 else f"UVMap{channel}")
            if layer is not None:
                self.uv_names[mesh][channel] = layer.name
                values = source.uvs[channel].astype(np.float32).reshape(-1)
                native.set_attribute(mesh, layer.name, "FLOAT2", "CORNER", "vector", values,
                               lambda values, layer=layer: layer.data.foreach_set("uv", values))
        for index, channel in enumerate(sorted(source.colors)):
            name = "Col" if index == 0 else f"Col{channel}"
            attribute = mesh.color_attributes.new(name, "FLOAT_COLOR", "CORNER")
            attribute.data.foreach_set("color",
                                       source.colors[channel].astype(np.float32).reshape(-1))
        mesh.update(calc_edges=True)
        if mesh.validate(verbose=False):
            self.doc.warn(f"geometry {source.name}: invalid faces (repeated faces or edges) "
                          "repaired by Blender")
        if source.normals is not None and len(mesh.loops) != len(source.corners):
            self.doc.warn(f"geometry {source.name}: its normals left out (Blender repaired "
                          "its faces)")
        elif source.normals is not None and len(sizes):
            normals = np.asarray(source.normals, dtype=np.float64)
            length = np.sqrt(np.einsum("ij,ij->i", normals, normals))[:, None]
            normals = np.where(length > 0, normals / np.where(length > 0, length, 1), 0.0)
            sharp = mesh.attributes.get("sharp_face")
            if sharp is not None:   # smooth faces: the custom normals are used
                mesh.attributes.remove(sharp)
            compat.set_corner_normals(mesh, normals.astype(np.float32))
        mesh[SYMBOLS_KEY] = list(source.symbols)
        return mesh

    # -- lights and cameras -----------------------------------------------------------------
    def light(self, source: collada.Light):
        kind = {"directional": "SUN", "point": "POINT", "spot": "SPOT"}[source.kind]
        light = self._new(bpy.data.lights, source.name, kind)
        if min(source.color) < 0.0:
            self.doc.warn(f"light {source.name}: negative colour {source.color} read as 0")
        light.color = tuple(max(0.0, c) for c in source.color)
        values = {"intensity": 1.0}
        if source.kind in ("point", "spot"):
            constant, linear, quadratic = collada.attenuation(self.doc, source)
            values.update(constant=constant, linear=linear, quadratic=quadratic)
        if source.kind == "spot":
            angle = source.falloff_angle
            if not 1.0 <= angle <= 180.0:
                self.doc.warn(f"light {source.name}: falloff_angle {angle:g}° outside Blender's "
                              "1°-180°; clamped")
                angle = min(max(angle, 1.0), 180.0)
            light.spot_size = math.radians(angle)
            light.spot_blend = 0.0
            values["edge_exponent"] = max(source.falloff_exponent, 0.0)
        properties.write_light(light, values)
        return light

    def camera(self, source: collada.Camera):
        camera = self._new(bpy.data.cameras, source.name)
        m = self.doc.meter
        if source.kind == "orthographic":
            camera.type = "ORTHO"
            if source.xmag is not None:
                camera.sensor_fit = "HORIZONTAL"
                camera.ortho_scale = 2.0 * source.xmag * m
            elif source.ymag is not None:
                camera.sensor_fit = "VERTICAL"
                camera.ortho_scale = 2.0 * source.ymag * m
        else:
            camera.type = "PERSP"
            if source.xfov is not None:
                camera.sensor_fit = "HORIZONTAL"
                camera.angle = math.radians(min(max(source.xfov, 0.37), 175.0))
            elif source.yfov is not None:
                camera.sensor_fit = "VERTICAL"
                camera.angle = math.radians(min(max(source.yfov, 0.37), 175.0))
        camera.clip_start = max(source.znear * m, 1e-6)
        camera.clip_end = max(source.zfar * m, camera.clip_start * 1.001)
        return camera

    def ambient(self):
        used = set()
        stack = list(self.doc.nodes) + list(self.doc.library_nodes.values())
        while stack:
            node = stack.pop()
            stack.extend(node.children)
            used |= {i.url for i in node.instances if i.kind == "light"}
        ambients = [light for key, light in self.doc.lights.items()
                    if light.kind == "ambient" and key in used]
        if not ambients:
            return
        world = self.scene.world
        if world is None:
            world = self._new(bpy.data.worlds, "World")
            self.scene.world = world
        keys = (properties.AMBIENT_INTENSITY[0], properties.AMBIENT_COLOR[0])
        self.world_before = (world, {k: (world[k] if k in world.keys() else None) for k in keys})
        total = np.sum([light.color for light in ambients], axis=0)
        properties.write_world(world, 1.0, tuple(float(c) for c in total))

    # -- materials ------------------------------------------------------------------------
    def bind_materials(self):
        for obj, inst in self.uses:
            mesh = obj.data
            symbols = list(mesh.get(SYMBOLS_KEY, []))
            key, reach = self.sync.light_set(obj)
            group = self.sync.group(key, reach)
            wanted = []
            for symbol in symbols:
                target = inst.bindings.get(symbol)
                source = self.doc.materials.get(target) if target else None
                if source is None:   # liberal: an unbound symbol naming a material
                    source = self.doc.materials.get(symbol) or next(
                        (m for m in self.doc.materials.values() if m.name == symbol), None)
                    if source is None and symbol:
                        self.doc.warn(f"geometry {mesh.name}: material symbol {symbol!r} "
                                      "bound to no material; a default Phong material used")
                uv_names = self.uv_names.get(mesh, {})
                binding = {semantic: uv_names.get(channel, f"UVMap{channel}" if channel
                                                  else "UVMap")
                           for semantic, channel in inst.uv_bindings.get(symbol, {}).items()}
                wanted.append(self.material(source, group, binding))
            if not symbols:
                wanted.append(self.material(None, group, {}))
            if len(mesh.materials) == 0:
                for material in wanted:
                    mesh.materials.append(material)
            if [s.material for s in obj.material_slots] != wanted:
                for slot, material in zip(obj.material_slots, wanted):
                    slot.link = "OBJECT"
                    slot.material = material
            self.sync.apply(obj)

    def material(self, source, group, uv_binding):
        key = source.id if source is not None else None
        if key in self.materials:
            return self.materials[key]
        name = source.name if source is not None else "COLLADA default"
        material = writer.new_material(name, group)
        if source is not None:
            self.values(material, source, uv_binding)
        self.materials[key] = material
        return material

    def values(self, material, source: collada.Material, uv_binding):
        tree = material.node_tree
        lights = tree.nodes[recipe.LIGHTS_NODE]
        specular = source.technique in ("phong", "blinn")
        negative = source.shininess is not None and source.shininess < 0.0
        writer.write(material, writer.Values(
            {socket_name: source.color(element) for socket_name, element in INPUTS.items()},
            exponent=source.shininess if specular and source.shininess is not None
            and not negative else 0.0,
            blinn=1.0 if source.technique == "blinn" else 0.0,
            specular_strength=1.0 if specular else 0.0))
        for index, (socket_name, element) in enumerate(INPUTS.items()):
            texture = source.texture(element)
            image = self.image(texture, source) if texture is not None else None
            if image is not None:
                tree.links.new(self.texture_node(tree, socket_name, image, texture, uv_binding,
                                                 index), lights.inputs[socket_name])
        if negative:
            self.doc.warn(f"material {source.name}: shininess {source.shininess:g} read as 0")
        material[TECHNIQUE_KEY] = source.technique
        material[OPAQUE_KEY] = source.opaque
        if source.transparent is not None:
            material[TRANSPARENT_KEY] = [float(c) for c in source.transparent]
        if source.transparency is not None:
            material[TRANSPARENCY_KEY] = float(source.transparency)
        opacity = source.opacity()
        channels = source.opacity_channels()
        mapped = self.transparent_map(material, source, uv_binding)
        if mapped:   # the texture's opacity per pixel; the control keeps a white texel's
            opacity_nodes.set_opacity(material, opacity)
            return
        if max(channels) - min(channels) > 1e-6:
            self.doc.warn(f"material {source.name}: {source.opaque} opacity differs per "
                          f"channel {tuple(round(c, 4) for c in channels)}; their mean "
                          f"{opacity:.4g} used")
        if opacity <= 0.0 and not self.literal:
            self.doc.warn(f"material {source.name}: its transparency makes it wholly "
                          f"invisible ({source.opaque}, transparency "
                          f"{1.0 if source.transparency is None else source.transparency:g}); "
                          "imported opaque, as its exporter most likely meant")
            opacity = 1.0
        opacity_nodes.set_opacity(material, opacity)  # clamped to [0, 1] there

    def transparent_map(self, material, source, uv_binding) -> bool:
        """A ``<transparent><texture>`` as the material's opacity map, the spec's formula of
        its mode with the texel for the colour: A_ONE a·t, A_ZERO 1 − a·t, RGB_ZERO
        1 − mean(rgb)·t, RGB_ONE mean(rgb)·t (``Material.opacity_of_texel``); returns whether
        the map was made.  With t = 0 the texture changes nothing (the formula is constant:
        the scalar path reads it), and a missing image is named in the texture warning."""
        texture = source.transparent_texture
        t = 1.0 if source.transparency is None else float(source.transparency)
        if texture is None or t == 0.0:
            return False
        image = self.image(texture, source)
        if image is None:
            return False
        tree = material.node_tree
        node = self.texture_node(tree, "transparent", image, texture, uv_binding, 5).node
        if source.opaque.startswith("A_"):
            value = compat.output_socket(node, "Alpha")
        else:
            native.straight(image)   # the spec's RGB, not multiplied by the texel's alpha
            value = native.mean_rgb(tree, "transparent mean", compat.output_socket(node, "Color"),
                                    (-900.0, -1300.0))
        scaled = native.math(tree, native.MAP_NODE + "transparent x t", "MULTIPLY", value, t,
                             (-700.0, -1300.0))
        if source.opaque.endswith("_ZERO"):
            scaled = native.math(tree, native.MAP_NODE + "1 - transparent", "SUBTRACT", 1.0,
                                 scaled, (-550.0, -1300.0))
        native.opacity_map(material, scaled)
        return True

    def image(self, texture, source):
        if texture.resolved in self.images:
            return self.images[texture.resolved]
        image = native.load_image(texture.resolved) if texture.exists else None
        if image is None:
            self.doc.warn(f"material {source.name}: texture {texture.path} not found or not "
                          f"readable (looked for {texture.resolved}); left out")
        self.images[texture.resolved] = image
        return image

    def texture_node(self, tree, socket_name, image, texture, uv_binding, index):
        node = tree.nodes.new("ShaderNodeTexImage")
        node.name = TEXTURE_NODE + socket_name
        node.label = f"{socket_name} texture"
        node.image = image
        node.location = (-1150.0, 200.0 - 300.0 * index)
        layer = uv_binding.get(texture.texcoord)   # the UV map of the bound set
        if layer and layer != "UVMap":   # not the mesh's first (active) map: its own node
            uv = tree.nodes.new("ShaderNodeUVMap")
            uv.name = UVMAP_NODE + socket_name
            uv.uv_map = layer
            uv.location = (-1450.0, 200.0 - 300.0 * index)
            tree.links.new(uv.outputs["UV"], node.inputs["Vector"])
        return node.outputs["Color"]
