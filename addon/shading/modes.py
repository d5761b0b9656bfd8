# SPDX-License-Identifier: GPL-3.0-or-later
"""Per Vertex and Per Face shading, live, without Python at render time (docs/shading_modes.md).

A Phong material's Shading (``material["phong_shading"]``: PIXEL, VERTEX, FACE) says where
the model is evaluated.  PIXEL is the lights group in the shader (``lighting/rig.py``).
VERTEX and FACE evaluate the same model (``node_groups/shading_modes.py``: the library's own
group expressions, composed as the lights group composes them) in the shader too, but at the
vertices of the pixel's triangle or at the centre of its face:

* a Geometry Nodes group that does not depend on lights or camera, **Phong Shading
  Geometry**, runs as the last modifier of every mesh object with such a material: it stores
  on each face the centre and normal of the face (Per Face), then triangulates and stores on
  each triangle the positions and normals of its three vertices, and on each corner its
  barycentric basis vector (Per Vertex), all in object space;
* the material shows a shader group of its light set and mode, **Phong Per Vertex ⟨lights
  group⟩** / **Phong Per Face ⟨lights group⟩**, made once per lights group: it reads those
  attributes (taken to world space by the shaded object's transform, so instances are lit
  where they stand), evaluates the model at each of the triangle's vertices (or at the face
  centre) and mixes the three colours by the interpolated basis (Gouraud) or shows the one
  colour (flat).  The viewer is the eye of the pixel's ray (position + incoming × view
  distance), so the camera, and the viewport's view, are followed at render time;
* the lights reach it as they reach the lights group: world transforms from the World's
  properties (View Layer attributes, where the lights group reads them) or drivers, their
  settings, the world's ambient by drivers without Python expressions.

Moving a light or the camera evaluates no Geometry Nodes and, where the lights group reads the
lights' transforms from the World, re-evaluates no material either: a light drag costs what it
costs Per Pixel (issue 28).  Everything is data of the file: a saved file renders the same
without the extension.
"""

from __future__ import annotations

import contextlib

import bpy
from bpy.app.handlers import persistent

from ...node_groups import models
from ...node_groups import shading_modes as model
from ...node_groups.expr import VECTOR, input_
from .. import compat, loader
from ..lighting import drivers, materials, properties, rig, world_copies
from ..lighting.lights import SUPPORTED

#: Custom property of the material: its shading mode (docs/contract.md).
SHADING_KEY = "phong_shading"
MODES = model.MODES
PIXEL, VERTEX, FACE = MODES
MODIFIER_NAME = "Phong Shading"
#: The Geometry Nodes group of the modifier: its custom property holds its layout version.
GEOMETRY_TREE = "Phong Shading Geometry"
GEOMETRY_KEY = "phong_shading_geometry"
GEOMETRY_VERSION = 1
#: The attributes it stores (object space): face centre and normal (FACE domain, of the
#: faces before triangulation), the triangle's vertex positions and normals (FACE domain,
#: after it), each corner's barycentric basis (CORNER domain).
FACE_CENTRE, FACE_NORMAL = "phong_face_p", "phong_face_n"
VERTEX_POSITIONS = ("phong_p0", "phong_p1", "phong_p2")
VERTEX_NORMALS = ("phong_n0", "phong_n1", "phong_n2")
WEIGHTS = "phong_w"
#: Outputs of a Per Vertex shading group besides Color: the model at the triangle's k-th
#: vertex (constant over the triangle).
VERTEX_OUTPUTS = ("Vertex 0", "Vertex 1", "Vertex 2")
_POINT_NORMAL = "phong_vertex_normal"  # temporary, removed by the group
#: Custom properties of a shading group: its lights group (an ID pointer), its mode and the
#: fingerprint of what it was built for.
GROUP_LIGHTS_KEY = "phong_shading_lights"
GROUP_MODE_KEY = "phong_shading_mode"
GROUP_SIGNATURE_KEY = "phong_shading_signature"
GROUP_VERSION = 3  # bump when the layout of the shading groups changes
#: Nodes of the material in these modes: the shading group and the Emission it feeds.
SHADING_NODE = "phong_shading_group"
EMISSION_NODE = materials.SHADING_EMISSION  # "phong_shading_emission"
#: The design before (a Geometry Nodes group per material storing a colour attribute that an
#: Attribute node showed): removed on load and by Relink.
LEGACY_TREE_KEY = "phong_shading_material"
LEGACY_ATTRIBUTE_NODE = "phong_shading_attribute"
#: The material's inputs of the shading group (those of the lights group that the model reads).
CONTROL_INPUTS = tuple(i for i in rig.INPUTS if i[0] in model.CONTROLS)


def mode_of(material) -> str:
    """The material's shading mode (PIXEL when unset or unknown)."""
    value = material.get(SHADING_KEY, PIXEL) if material is not None else PIXEL
    return value if value in MODES else PIXEL


def set_mode(material, mode: str) -> None:
    """Set *material*'s shading mode and put it into effect."""
    if mode not in MODES:
        raise ValueError(f"unknown shading {mode!r}: expected one of {', '.join(MODES)}")
    material[SHADING_KEY] = mode
    update(material)


def group_of(material):
    """The shading group *material* shows (Per Vertex / Per Face), or None."""
    tree = material.node_tree if material is not None else None
    node = tree.nodes.get(SHADING_NODE) if tree is not None else None
    return node.node_tree if node is not None and node.bl_idname == "ShaderNodeGroup" else None


def geometry_tree():
    """The modifier's Geometry Nodes group, or None."""
    for tree in bpy.data.node_groups:
        if tree.bl_idname == "GeometryNodeTree" and GEOMETRY_KEY in tree.keys() \
                and tree.library is None:
            return tree
    return None


def users(material) -> list:
    """The mesh objects whose material slots hold *material*."""
    return [o for o in bpy.data.objects if o.type == "MESH" and o.library is None
            and any(slot.material == material for slot in o.material_slots)]


def needs_modifier(obj) -> bool:
    """Whether a material of *obj* is a Phong material shaded Per Vertex or Per Face."""
    return obj.type == "MESH" and any(
        mode_of(s.material) != PIXEL and materials.is_phong_material(s.material)
        for s in obj.material_slots)


# -- putting a mode into effect ----------------------------------------------------------

def update(material, objects=None, groups=None) -> None:
    """Make *material* and its objects show its shading mode; *objects* (its users) when the
    caller has looked them up, *groups* a cache of shading groups shared by the calls of one
    refresh."""
    if not materials.is_phong_material(material):
        return
    _remove_legacy_nodes(material)
    mode = mode_of(material)
    objects = users(material) if objects is None else objects
    if mode == PIXEL:
        had, geometry = group_of(material), geometry_tree()
        _surface_per_pixel(material)
        if geometry is not None:
            for obj in objects:
                if not needs_modifier(obj):
                    _remove_modifier(obj, geometry)
        _remove_unused(had, geometry)
        return
    group = shading_group(material, mode, groups)
    _surface_per_mesh(material, group)
    geometry = ensure_geometry_tree()
    for obj in objects:
        _ensure_modifier(obj, geometry)
    world_copies.follow_readers()  # Eevee compiles the group: it reads the World's copies


def refresh(scene=None) -> int:
    """Update every Phong material that is not Per Pixel (or still shows a shading group);
    remove what no material needs any more; returns how many materials.  Run after the lights
    groups changed (``sync``) and on load."""
    legacy = _remove_legacy_trees()
    todo = [m for m in materials.phong_materials()
            if mode_of(m) != PIXEL or group_of(m) is not None
            or (legacy and LEGACY_ATTRIBUTE_NODE in m.node_tree.nodes)]
    if todo:
        wanted = {m.as_pointer() for m in todo}
        uses = {pointer: [] for pointer in wanted}
        for obj in bpy.data.objects:
            if obj.type != "MESH" or obj.library is not None:
                continue
            for pointer in {s.material.as_pointer() for s in obj.material_slots
                            if s.material is not None} & wanted:
                uses[pointer].append(obj)
        groups: dict = {}
        for material in todo:
            update(material, uses[material.as_pointer()], groups)
    _prune()
    return len(todo)


def _prune() -> None:
    """Remove the modifiers of objects that need them no more, the shading groups no material
    shows and the geometry group no modifier runs."""
    geometry = geometry_tree()
    if geometry is not None:
        for obj in bpy.data.objects:
            if obj.library is None and obj.type == "MESH" and not needs_modifier(obj):
                _remove_modifier(obj, geometry)
    _remove_unused(geometry, *[t for t in bpy.data.node_groups
                               if GROUP_MODE_KEY in t.keys() and t.library is None])


_BUSY: list = []


@persistent
def follow_objects(_scene, depsgraph=None) -> None:
    """After an edit of mesh objects: one that got a Per Vertex / Per Face material (a slot
    assigned by hand) gets the modifier, and a modifier the user added after Phong Shading
    puts Phong Shading last again.  Only the updated objects are looked at."""
    if _BUSY or depsgraph is None or not (depsgraph.id_type_updated("OBJECT")
                                          or depsgraph.id_type_updated("MESH")):
        return
    geometry = geometry_tree()
    if geometry is None:
        return  # no Per Vertex / Per Face material was set up in the file: nothing to follow
    objects, meshes = set(), set()
    for change in depsgraph.updates:
        if not change.is_updated_geometry:  # a slot or a modifier changed: geometry is tagged
            continue  # (a light move re-shades every object: not looked at)
        original = getattr(change.id, "original", None)
        if isinstance(original, bpy.types.Object):
            if original.type == "MESH":
                objects.add(original)
        elif isinstance(original, bpy.types.Mesh):  # a slot of the mesh was assigned
            meshes.add(original.as_pointer())
    if meshes:
        objects.update(o for o in bpy.data.objects
                       if o.type == "MESH" and o.data.as_pointer() in meshes)
    todo = []
    for obj in objects:
        if obj.library is not None or not needs_modifier(obj):
            continue
        modifiers = obj.modifiers
        if not len(modifiers) or modifiers[-1].type != "NODES" \
                or modifiers[-1].node_group != geometry:
            todo.append(obj)
    if not todo:
        return
    _BUSY.append(True)
    try:
        for obj in todo:
            for slot in obj.material_slots:  # a material set up in another file or by hand
                if mode_of(slot.material) != PIXEL and group_of(slot.material) is None:
                    update(slot.material)
            _ensure_modifier(obj, geometry)
    finally:
        _BUSY.pop()


@persistent
def upgrade_on_load(*_args) -> None:
    """A file of the design before (a Geometry Nodes group per material): refreshed into
    this one, nothing lost (the materials keep their Shading)."""
    if any(LEGACY_TREE_KEY in t.keys() for t in bpy.data.node_groups if t.library is None):
        refresh()


#: The shading room's handlers, (event of ``bpy.app.handlers``, function) in the order they
#: run (``addon/__init__.py`` registers them, before the lighting room's relink).
HANDLERS = (("depsgraph_update_post", follow_objects), ("load_post", upgrade_on_load))


def _lights_group(material):
    """The lights group *material* uses, or None."""
    node = material.node_tree.nodes.get(materials.LIGHTS_NODE)
    return node.node_tree if node is not None else None


def _light_set(group):
    """(light objects, world, model) of the lights group *group* (None: no light)."""
    scene = rig.owner(group) if group is not None else None
    if scene is None:
        return [], None, rig.MODELS[0]
    names = list(group.get("phong_lights", []))
    lights = [scene.objects.get(n) for n in names]
    lights = [o for o in lights if o is not None and o.type == "LIGHT"
              and o.data.type in SUPPORTED]
    light_model = group.get(rig.MODEL_KEY, rig.MODELS[0])
    return lights, scene.world, models.get(light_model).name


def _modifiers(obj, tree) -> list:
    """The modifiers of *obj* that run the Geometry Nodes group *tree*."""
    return [m for m in obj.modifiers if m.type == "NODES" and m.node_group == tree]


def _ensure_modifier(obj, tree) -> None:
    if obj.type != "MESH" or obj.library is not None:
        return
    modifier = next(iter(_modifiers(obj, tree)), None)
    if modifier is None:
        modifier = obj.modifiers.new(MODIFIER_NAME, "NODES")
        modifier.node_group = tree
    index = list(obj.modifiers).index(modifier)
    if index != len(obj.modifiers) - 1:
        obj.modifiers.move(index, len(obj.modifiers) - 1)  # last: the lit mesh is the one seen


@contextlib.contextmanager
def modifiers_off(objects):
    """The Phong Shading modifiers of *objects* switched off inside the block (Cycles' bake
    to vertex colours needs the mesh's own topology, which the modifier triangulates)."""
    tree = geometry_tree()
    off = []
    if tree is not None:
        for obj in objects:
            for modifier in _modifiers(obj, tree):
                if modifier.show_viewport or modifier.show_render:
                    off.append((modifier, modifier.show_viewport, modifier.show_render))
                    modifier.show_viewport = modifier.show_render = False
    try:
        yield
    finally:
        for modifier, viewport, render in off:
            modifier.show_viewport, modifier.show_render = viewport, render


def _remove_modifier(obj, tree) -> None:
    for modifier in _modifiers(obj, tree):
        obj.modifiers.remove(modifier)


def _remove_unused(*trees) -> None:
    """Remove those of *trees* (None skipped) that nothing uses."""
    for tree in trees:
        if tree is not None and tree.users == 0:
            bpy.data.node_groups.remove(tree)


def _remove_legacy_trees() -> bool:
    """Remove the Geometry Nodes groups (and their modifiers) of the design before."""
    legacy = [t for t in bpy.data.node_groups
              if LEGACY_TREE_KEY in t.keys() and t.library is None]
    for tree in legacy:
        for obj in bpy.data.objects:
            if obj.library is None and obj.type == "MESH":
                _remove_modifier(obj, tree)
        bpy.data.node_groups.remove(tree)
    return bool(legacy)


def _remove_legacy_nodes(material) -> None:
    node = material.node_tree.nodes.get(LEGACY_ATTRIBUTE_NODE)
    if node is not None:
        material.node_tree.nodes.remove(node)


# -- the material's surface -----------------------------------------------------------

def _surface_per_pixel(material) -> None:
    tree = material.node_tree
    for name in (SHADING_NODE, EMISSION_NODE):
        node = tree.nodes.get(name)
        if node is not None:
            tree.nodes.remove(node)
    lights = tree.nodes.get(materials.LIGHTS_NODE)
    output = tree.nodes.get(materials.OUTPUT)
    if lights is None or output is None:
        return
    materials.apply_opacity(material)  # the lights group's Shader into the output (or mix)
    for aov_name, socket in materials.AOVS.items():  # every AOV from the lights group again
        aov = tree.nodes.get(f"phong_aov:{aov_name}")
        if aov is not None:
            tree.links.new(lights.outputs[socket], aov.inputs["Color"])


def _surface_per_mesh(material, group) -> None:
    tree = material.node_tree
    node = materials.named_node(tree, SHADING_NODE, "ShaderNodeGroup", (-20.0, 420.0))
    if node.node_tree != group:
        node.node_tree = group
    node.label = "Phong Per Vertex" if group.get(GROUP_MODE_KEY) == VERTEX else "Phong Per Face"
    node.width = 200.0
    lights = tree.nodes.get(materials.LIGHTS_NODE)
    for socket in node.inputs:  # the material's controls, as its lights group node has them
        source = lights.inputs.get(socket.name) if lights is not None else None
        for link in list(socket.links):
            if source is None or not source.is_linked \
                    or link.from_socket != source.links[0].from_socket:
                tree.links.remove(link)
        if source is None:
            continue
        if source.is_linked:
            if not socket.is_linked:
                tree.links.new(source.links[0].from_socket, socket)
        else:
            socket.default_value = source.default_value
    emission = materials.named_node(tree, EMISSION_NODE, "ShaderNodeEmission", (260.0, 420.0))
    emission.inputs["Strength"].default_value = 1.0
    if not any(l.from_socket == node.outputs["Color"] for l in emission.inputs["Color"].links):
        tree.links.new(node.outputs["Color"], emission.inputs["Color"])
    materials.apply_opacity(material)  # the emission into the output (or the opacity mix)
    for aov_name in materials.AOVS:
        aov = tree.nodes.get(f"phong_aov:{aov_name}")
        if aov is None:
            continue
        if aov_name == materials.AOV_NAME:  # Phong Color: the colour shown
            tree.links.new(node.outputs["Color"], aov.inputs["Color"])
        else:  # the per-pixel terms are not computed in this mode (and not compiled by Eevee)
            for link in list(aov.inputs["Color"].links):
                tree.links.remove(link)
            aov.inputs["Color"].default_value = (0.0, 0.0, 0.0, 1.0)


# -- the Geometry Nodes group (no light, no camera: evaluated when the mesh changes) -------

def ensure_geometry_tree():
    """The modifier's group, made (or remade when its layout is older) once per file."""
    tree = geometry_tree()
    if tree is not None and tree.get(GEOMETRY_KEY) == GEOMETRY_VERSION:
        return tree
    if tree is None:
        tree = bpy.data.node_groups.new(GEOMETRY_TREE, "GeometryNodeTree")
    build_geometry_tree(tree)
    tree[GEOMETRY_KEY] = GEOMETRY_VERSION
    return tree


def build_geometry_tree(tree) -> None:
    """Store the attributes the shading groups read (module docstring), in object space."""
    tree.nodes.clear()
    tree.interface.clear()
    tree.interface.new_socket("Geometry", in_out="INPUT", socket_type="NodeSocketGeometry")
    tree.interface.new_socket("Geometry", in_out="OUTPUT", socket_type="NodeSocketGeometry")
    if hasattr(tree, "is_modifier"):
        tree.is_modifier = True
    tree.description = ("Phong Per Vertex / Per Face shading: each face's centre and normal, "
                        "each triangle's vertex positions and normals, each corner's "
                        "barycentric basis (object space), for the shading groups")
    nodes, links = tree.nodes, tree.links
    x = [0.0]

    def new(kind, **settings):
        node = nodes.new(kind)
        for key, value in settings.items():
            setattr(node, key, value)
        node.location = (x[0], -200.0 * (len(nodes) % 4))
        return node

    def store(geometry, name, domain, value):
        node = new("GeometryNodeStoreNamedAttribute", data_type="FLOAT_VECTOR", domain=domain)
        node.inputs["Name"].default_value = name
        links.new(geometry, node.inputs["Geometry"])
        socket = next(s for s in node.inputs if s.name == "Value" and s.enabled)
        links.new(value, socket)
        x[0] += 200.0
        return node.outputs["Geometry"]

    geometry = compat.output_socket(new("NodeGroupInput"), "Geometry")
    x[0] += 200.0
    position = compat.output_socket(new("GeometryNodeInputPosition"), "Position")
    normal = compat.output_socket(new("GeometryNodeInputNormal"), "Normal")
    # the face: its centre (the mean of its corners) and normal, before triangulation
    geometry = store(geometry, FACE_CENTRE, "FACE", position)
    geometry = store(geometry, FACE_NORMAL, "FACE", normal)
    geometry = store(geometry, _POINT_NORMAL, "POINT", normal)  # the vertex normal
    triangulate = new("GeometryNodeTriangulate")
    links.new(geometry, compat.input_socket(triangulate, "Mesh"))
    geometry = compat.output_socket(triangulate, "Mesh")
    x[0] += 200.0
    vertex_normal = new("GeometryNodeInputNamedAttribute", data_type="FLOAT_VECTOR")
    vertex_normal.inputs["Name"].default_value = _POINT_NORMAL
    vertex_normal = next(s for s in vertex_normal.outputs if s.enabled and s.name == "Attribute")
    for k in range(3):  # the triangle's k-th corner's vertex
        corners = new("GeometryNodeCornersOfFace")
        corners.inputs["Sort Index"].default_value = k
        vertex = new("GeometryNodeVertexOfCorner")
        links.new(corners.outputs["Corner Index"], vertex.inputs["Corner Index"])
        for name, value in ((VERTEX_POSITIONS[k], position), (VERTEX_NORMALS[k], vertex_normal)):
            at = new("GeometryNodeFieldAtIndex", domain="POINT", data_type="FLOAT_VECTOR")
            links.new(vertex.outputs["Vertex Index"], at.inputs["Index"])
            links.new(value, next(s for s in at.inputs if s.name == "Value" and s.enabled))
            geometry = store(geometry, name, "FACE",
                             next(s for s in at.outputs if s.name == "Value" and s.enabled))
    # each corner: its barycentric basis vector (1, 0, 0), (0, 1, 0) or (0, 0, 1)
    index_in_face = new("GeometryNodeFaceOfCorner").outputs["Index in Face"]
    basis = new("ShaderNodeCombineXYZ")
    for k in range(3):
        equal = new("ShaderNodeMath", operation="COMPARE")
        links.new(index_in_face, compat.input_socket(equal, "Value"))
        compat.input_socket(equal, "Value_001").default_value = float(k)
        compat.input_socket(equal, "Value_002").default_value = 0.25
        links.new(compat.output_socket(equal, "Value"), compat.input_socket(basis, "XYZ"[k]))
    geometry = store(geometry, WEIGHTS, "CORNER", compat.output_socket(basis, "Vector"))
    remove = new("GeometryNodeRemoveAttribute")
    links.new(geometry, remove.inputs["Geometry"])
    remove.inputs["Name"].default_value = _POINT_NORMAL
    x[0] += 200.0
    links.new(remove.outputs["Geometry"], compat.input_socket(new("NodeGroupOutput"), "Geometry"))


# -- the shading group (per lights group and mode) ------------------------------------------

def shading_group(material, mode, cache=None):
    """The shading group of *material*'s lights group for *mode*, made or rebuilt when its
    lights, world or model changed; *cache*: (lights group, mode) -> group, for the calls of
    one refresh."""
    lights_group = _lights_group(material)
    key = (lights_group.as_pointer() if lights_group is not None else None, mode)
    if cache is not None and key in cache:
        return cache[key]
    lights, world, light_model = _light_set(lights_group)
    world_keys = world_copies.listed(lights_group)
    signature = repr((GROUP_VERSION, mode, light_model, world.name if world else None,
                      [(o.name, o.data.type, properties.falloff_of(o.data)) for o in lights],
                      world_keys))
    group = next((t for t in bpy.data.node_groups
                  if t.get(GROUP_MODE_KEY) == mode and t.library is None
                  and t.bl_idname == "ShaderNodeTree"
                  and t.get(GROUP_LIGHTS_KEY) == lights_group), None)
    name = (f"Phong {'Per Vertex' if mode == VERTEX else 'Per Face'} "
            f"{lights_group.name if lights_group is not None else 'no lights'}")
    if group is None:
        group = bpy.data.node_groups.new(name, "ShaderNodeTree")
        group[GROUP_MODE_KEY] = mode
        if lights_group is not None:
            group[GROUP_LIGHTS_KEY] = lights_group
    if group.get(GROUP_SIGNATURE_KEY) != signature:
        scene = rig.owner(lights_group) if lights_group is not None else None
        group = rig.rewrite(group, lambda tree: build_shading_group(
            tree, mode, lights, world, light_model, world_keys, scene))
        group[GROUP_SIGNATURE_KEY] = signature
    if not (group.name == name or group.name.startswith(name + ".")):
        group.name = name
    if cache is not None:
        cache[key] = group
    return group


class _Writer(loader.NodeWriter):
    """The node writer of the library groups, its leaves mapped to sockets of this tree."""

    def __init__(self, tree, sockets):
        super().__init__(tree, None)
        self.leaf_sockets = sockets

    def _leaf(self, expression):
        self.depth[expression.key] = 0
        return self.leaf_sockets[expression.value]


class _Builder:
    def __init__(self, tree):
        self.tree = tree
        self.row = 0

    def node(self, kind, name=None, x=-900.0):
        node = self.tree.nodes.new(kind)
        if name:
            node.name = node.label = name
        node.location = (x, -self.row * 160.0)
        self.row += 1
        return node

    def value(self, name, id_type, id_block, path, scale=None):
        node = self.node("ShaderNodeValue", name)
        drivers.prop(compat.value_output(node), None, id_type, id_block, path, scale)
        return compat.value_output(node)

    def constant(self, name, value):
        node = self.node("ShaderNodeValue", name)
        compat.value_output(node).default_value = float(value)
        return compat.value_output(node)

    def vector(self, name, id_type, id_block, path):
        """A vector of three driven channels: path[0], path[1], path[2]."""
        node = self.node("ShaderNodeCombineXYZ", name)
        for index, axis in enumerate("XYZ"):
            drivers.prop(compat.input_socket(node, axis), None, id_type, id_block,
                         f"{path}[{index}]")
        return compat.output_socket(node, "Vector")

    def constant_vector(self, name, value):
        node = self.node("ShaderNodeCombineXYZ", name)
        for index, axis in enumerate("XYZ"):
            compat.input_socket(node, axis).default_value = float(value[index])
        return compat.output_socket(node, "Vector")

    def attribute(self, name, attribute_type="GEOMETRY"):
        node = self.node("ShaderNodeAttribute", name, x=-1300.0)
        node.attribute_type = attribute_type
        node.attribute_name = name
        return node.outputs["Vector"]

    def to_world(self, socket, vector_type="POINT"):
        node = self.node("ShaderNodeVectorTransform", x=-1100.0)
        node.vector_type = vector_type
        node.convert_from, node.convert_to = "OBJECT", "WORLD"
        self.tree.links.new(socket, compat.input_socket(node, "Vector"))
        return compat.output_socket(node, "Vector")

    def normal_to_world(self, socket):
        """Object-space normal *socket* in world space: M^-T n = cof(M) n / det(M), from the
        object's axes M e1, M e2, M e3 (Vector Transform of vectors: Eevee 4.2's Vector
        Transform of a normal is not the inverse transpose under non-uniform scale)."""
        if not hasattr(self, "_cofactors"):
            axes = []
            for axis in ((1.0, 0.0, 0.0), (0.0, 1.0, 0.0), (0.0, 0.0, 1.0)):
                node = self.node("ShaderNodeVectorTransform", x=-1300.0)
                node.vector_type = "VECTOR"
                node.convert_from, node.convert_to = "OBJECT", "WORLD"
                compat.input_socket(node, "Vector").default_value = axis
                axes.append(compat.output_socket(node, "Vector"))
            columns = [self.math("CROSS_PRODUCT", axes[(i + 1) % 3], axes[(i + 2) % 3])
                       for i in range(3)]  # cof(M) = [M e2 x M e3, M e3 x M e1, M e1 x M e2]
            det = self.node("ShaderNodeVectorMath", x=-1000.0)
            det.operation = "DOT_PRODUCT"
            self.tree.links.new(axes[0], compat.input_socket(det, "Vector"))
            self.tree.links.new(columns[0], compat.input_socket(det, "Vector_001"))
            inverse = self.node("ShaderNodeMath", x=-900.0)
            inverse.operation = "DIVIDE"
            compat.input_socket(inverse, "Value").default_value = 1.0
            self.tree.links.new(det.outputs["Value"], compat.input_socket(inverse, "Value_001"))
            self._cofactors = (columns, compat.output_socket(inverse, "Value"))
        columns, inverse_det = self._cofactors
        split = self.node("ShaderNodeSeparateXYZ", x=-1100.0)
        self.tree.links.new(socket, compat.input_socket(split, "Vector"))
        total = None
        for k in range(3):
            term = self.math("SCALE", columns[k], (0.0, 0.0, 0.0))
            self.tree.links.new(compat.output_socket(split, "XYZ"[k]), term.node.inputs["Scale"])
            total = term if total is None else self.math("ADD", total, term)
        out = self.math("SCALE", total, (0.0, 0.0, 0.0))
        self.tree.links.new(inverse_det, out.node.inputs["Scale"])
        return out

    def math(self, operation, a, b, name=None):
        node = self.node("ShaderNodeVectorMath", name, x=-1000.0)
        node.operation = operation
        for key, value in (("Vector", a), ("Vector_001", b)):
            socket = compat.input_socket(node, key)
            if isinstance(value, bpy.types.NodeSocket):
                self.tree.links.new(value, socket)
            else:
                socket.default_value = value
        return node.outputs["Vector"]


def build_shading_group(tree, mode, lights, world, light_model, world_keys, scene=None) -> None:
    """(Re)write *tree*: the model for *lights* at the vertices of the pixel's triangle
    (VERTEX, mixed by the barycentric basis) or at its face's centre (FACE)."""
    if tree.animation_data is not None:
        tree.animation_data_clear()
    tree.nodes.clear()
    tree.interface.clear()
    tree.interface.new_socket("Color", in_out="OUTPUT", socket_type="NodeSocketColor")
    if mode == VERTEX:  # the model at the triangle's k-th vertex (for AOVs and tests)
        for name in VERTEX_OUTPUTS:
            tree.interface.new_socket(name, in_out="OUTPUT", socket_type="NodeSocketColor")
    for name, socket_type, default in CONTROL_INPUTS:
        item = tree.interface.new_socket(name, in_out="INPUT", socket_type=socket_type)
        item.default_value = default
    world_copies.clear_listed(tree, loop=False)
    tree.description = (f"Phong {'Per Vertex' if mode == VERTEX else 'Per Face'} shading: the "
                        f"lighting model at the {'vertices of each triangle' if mode == VERTEX else 'centre of each face'}")
    b = _Builder(tree)
    group_in = b.node("NodeGroupInput", x=-1500.0)
    group_out = tree.nodes.new("NodeGroupOutput")
    sockets = {name: group_in.outputs[name] for name, _t, _d in CONTROL_INPUTS}
    # the viewer: the eye of the pixel's ray (below: at infinity for an orthographic camera)
    geometry = b.node("ShaderNodeNewGeometry", x=-1300.0)
    camera = b.node("ShaderNodeCameraData", x=-1300.0)
    toward = b.math("SCALE", geometry.outputs["Incoming"], (0.0, 0.0, 0.0))
    tree.links.new(camera.outputs["View Distance"], toward.node.inputs["Scale"])
    eye = b.math("ADD", geometry.outputs["Position"], toward, "eye")
    orthographic = _orthographic(b, scene)
    # the points where the model is evaluated
    if mode == VERTEX:
        points = [(VERTEX_POSITIONS[k], VERTEX_NORMALS[k]) for k in range(3)]
    else:
        points = [(FACE_CENTRE, FACE_NORMAL)]
    for k, (p_name, n_name) in enumerate(points):
        sockets[f"P{k}"] = b.to_world(b.attribute(p_name), "POINT")
        # the camera seen from point k: the eye, or for an orthographic camera P_k + incoming
        # (so that v = normalize(camera - P_k) is the camera's one direction)
        parallel = b.math("ADD", sockets[f"P{k}"], geometry.outputs["Incoming"])
        toward_parallel = b.math("SUBTRACT", parallel, eye)
        share = b.math("SCALE", toward_parallel, (0.0, 0.0, 0.0))
        b.tree.links.new(orthographic, share.node.inputs["Scale"])
        sockets[f"Camera{k}"] = b.math("ADD", eye, share, f"camera {k}")
        sockets[f"N{k}"] = b.normal_to_world(b.attribute(n_name))
    power = {index for index, obj in enumerate(lights)
             if properties.falloff_of(obj.data) == "POWER"}  # i0/d^k (rig.py alike)
    expression = model.model_color([o.data.type for o in lights], light_model, power)
    colors = [model.substitute(expression, {"P": input_(f"P{k}", VECTOR),
                                            "N": input_(f"N{k}", VECTOR),
                                            "Camera": input_(f"Camera{k}", VECTOR)})
              for k in range(len(points))]
    factories = _ambient_sockets(b, world)
    for index, obj in enumerate(lights):
        factories.update(_light_sockets(b, index, obj, world_keys))
    read = set().union(*(model.leaves(c) for c in colors))
    for name in sorted(read - set(sockets)):
        sockets[name] = factories[name]()
    writer = _Writer(tree, sockets)
    if mode == FACE:
        writer.output(colors[0], group_out.inputs["Color"], "color")
    else:
        weights = b.node("ShaderNodeSeparateXYZ", x=-1000.0)
        tree.links.new(b.attribute(WEIGHTS), compat.input_socket(weights, "Vector"))
        total, mixing = None, []
        for k, color in enumerate(colors):
            scaled = tree.nodes.new("ShaderNodeVectorMath")
            scaled.operation = "SCALE"
            scaled.name = scaled.label = f"vertex {k}"
            writer.output(color, compat.input_socket(scaled, "Vector"), "vector")
            writer.output(color, group_out.inputs[VERTEX_OUTPUTS[k]], "color")
            tree.links.new(compat.output_socket(weights, "XYZ"[k]), scaled.inputs["Scale"])
            mixing.append(scaled)
            if total is None:
                total = compat.output_socket(scaled, "Vector")
                continue
            add = tree.nodes.new("ShaderNodeVectorMath")
            add.operation = "ADD"
            tree.links.new(total, compat.input_socket(add, "Vector"))
            tree.links.new(compat.output_socket(scaled, "Vector"),
                           compat.input_socket(add, "Vector_001"))
            total = compat.output_socket(add, "Vector")
            mixing.append(add)
        tree.links.new(total, group_out.inputs["Color"])
        x = (writer.max_depth + 1) * loader.COLUMN_WIDTH
        for row, node in enumerate(mixing):
            node.location = (x + 200.0 * (row // 2), -200.0 * (row % 2))
    x = (writer.max_depth + 1) * loader.COLUMN_WIDTH
    group_out.location = (x + 700.0, 0.0)


def _orthographic(b, scene):
    """1 when *scene*'s camera is orthographic, else 0: a driver (no Python expression) on
    the camera's type (PERSP 0, ORTHO 1, PANO 2); 0 without a scene or camera."""
    value = b.node("ShaderNodeValue", "camera type")
    compat.value_output(value).default_value = 0.0
    if scene is not None:
        drivers.prop(compat.value_output(value), None, "SCENE", scene, "camera.data.type")
    equal = b.node("ShaderNodeMath", "orthographic")
    equal.operation = "COMPARE"
    b.tree.links.new(compat.value_output(value), compat.input_socket(equal, "Value"))
    compat.input_socket(equal, "Value_001").default_value = 1.0
    compat.input_socket(equal, "Value_002").default_value = 0.25
    return compat.output_socket(equal, "Value")


def _ambient_sockets(b, world) -> dict:
    if world is None:
        return {"Ambient Intensity": lambda: b.constant("Ambient Intensity",
                                                        properties.AMBIENT_INTENSITY[1]),
                "Ambient Color": lambda: b.constant_vector("Ambient Color",
                                                           properties.AMBIENT_COLOR[1])}
    properties.ensure_world_props(world)
    return {"Ambient Intensity": lambda: b.value(
                "Ambient Intensity", "WORLD", world, f'["{properties.AMBIENT_INTENSITY[0]}"]'),
            "Ambient Color": lambda: b.vector(
                "Ambient Color", "WORLD", world, f'["{properties.AMBIENT_COLOR[0]}"]')}


def _light_sockets(b, index, obj, world_keys) -> dict:
    """Leaf name -> a function making its socket, for light *index* (*obj*): its transform
    from the World property its lights group reads (View Layer attribute) or by drivers, the
    rest by drivers."""
    light = obj.data
    properties.ensure_light_props(light)
    keys = {attr: f'["{key}"]' for attr, (key, _default) in properties.LIGHT_KEYS.items()}
    prefix = f"light{index}:"

    def transform(kind):
        key = world_copies.world_key(obj, kind)
        name = f"{prefix}{world_copies.TRANSFORM_SOCKETS[kind]}"
        if key in world_keys:
            socket = b.attribute(key, "VIEW_LAYER")
            socket.node.name = socket.node.label = name
            world_copies.list_key(b.tree, key)
            return socket
        node = b.node("ShaderNodeVectorMath", name)
        node.operation = "ADD"
        compat.input_socket(node, "Vector_001").default_value = (0.0, 0.0, 0.0)
        (drivers.world_location if kind == "LOCATION" else drivers.world_minus_z)(
            compat.input_socket(node, "Vector"), obj)
        return compat.output_socket(node, "Vector")

    factories = {prefix + "Position": lambda: transform("LOCATION"),
                 prefix + "Direction": lambda: transform("AXIS"),
                 prefix + "Color": lambda: b.vector(prefix + "Color", "LIGHT", light, "color")}
    # the light groups' inputs that a setting drives (every model's, node_groups/models.py)
    # and the leaves of the Phong Shading / Power Falloff that the composition "phong" reads
    driven = {target: attr for spec in models.MODELS.values()
              for attr, _types, _when, target in spec.settings if target is not None}
    driven.update({"Diffuse": "diffuse", "Specular": "specular", "Power K": "power_k"})
    for target, attr in driven.items():
        name = prefix + target
        factories[name] = lambda n=name, a=attr: b.value(n, "LIGHT", light, keys[a])
    for target in {spec.spot_angle for spec in models.MODELS.values()}:
        factories[prefix + target] = (lambda n=prefix + target:
                                      b.value(n, "LIGHT", light, "spot_size", scale=0.5))
    return factories
