# SPDX-License-Identifier: GPL-3.0-or-later
"""Per Vertex and Per Face shading, live, without Python at render time (docs/shading_modes.md).

A Phong material's Shading (``material["phong_shading"]``: PIXEL, VERTEX, FACE) says where
the model is evaluated.  PIXEL is the lights group in the shader (``lighting/rig.py``).
VERTEX and FACE evaluate the same model (``node_groups/shading_modes.py``: the library's own
group expressions, composed as the lights group composes them) in a Geometry Nodes group of
the material, "Phong Per Vertex <material>", that every object using the material runs as
its last modifier:

* P, N: the mesh's positions and normals (of the evaluated mesh: after the user's
  subdivision, mirror, armature) taken to world space by the object's own transform (Self
  Object ▸ Object Info; normals by the inverse transpose);
* the camera: the scene's active camera (Active Camera ▸ Object Info), so a camera switch is
  followed;
* each light of the material's light set: its world position and -Z axis from Object Info,
  its data (Phong settings, colour, spot size) and the world's ambient and the material's
  controls by drivers without Python expressions (``lighting/drivers.py``);
* the colour is stored on the point (VERTEX) or face (FACE) domain as the colour attribute
  the material shows (Attribute ▸ Emission): the renderer interpolates a point attribute
  across each face (Gouraud) and keeps a face attribute constant (flat).

Everything is data of the file: a saved file renders the same without the extension.
"""

from __future__ import annotations

import bpy
from bpy.app.handlers import persistent

from ...node_groups import shading_modes as model
from .. import loader
from ..lighting import drivers, materials, properties, rig

#: Custom property of the material: its shading mode (docs/contract.md).
SHADING_KEY = "phong_shading"
MODES = model.MODES
PIXEL, VERTEX, FACE = MODES
DOMAINS = {VERTEX: "POINT", FACE: "FACE"}
#: Custom properties of the Geometry Nodes group: the material it evaluates (an ID pointer)
#: and the fingerprint of what it was built for.
TREE_MATERIAL_KEY = "phong_shading_material"
TREE_SIGNATURE_KEY = "phong_shading_signature"
MODIFIER_NAME = "Phong Shading"
ATTRIBUTE_NODE = "phong_shading_attribute"
EMISSION_NODE = materials.SHADING_EMISSION  # "phong_shading_emission"
ATTRIBUTE_PREFIX = "phong_lit"

#: Lights-group input -> the control node that holds it when nothing else does.
CONTROL_OF = {"Object Color": "phong_object_color", "Specular Color": "phong_specular_color",
              "Exponent": "phong_exponent", "Blinn": "phong_blinn",
              "Irradiant Color": "phong_irradiant_color",
              "Ambient Object Color": "phong_object_color",
              "Specular Strength": "phong_specular_strength"}


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


def attribute_name(material) -> str:
    """The colour attribute *material* shows in Per Vertex / Per Face mode."""
    return f"{ATTRIBUTE_PREFIX}:{material.name}"


def tree_of(material):
    """The material's Geometry Nodes group, or None."""
    for tree in bpy.data.node_groups:
        if tree.bl_idname == "GeometryNodeTree" and tree.get(TREE_MATERIAL_KEY) == material:
            return tree
    return None


def users(material) -> list:
    """The mesh objects whose material slots hold *material*."""
    return [o for o in bpy.data.objects if o.type == "MESH" and o.library is None
            and any(slot.material == material for slot in o.material_slots)]


# -- putting a mode into effect ----------------------------------------------------------

def update(material, objects=None, tree=False) -> None:
    """Make *material* and its objects show its shading mode; *objects* (its users) and
    *tree* (its Geometry Nodes group or None) when the caller has looked them up."""
    if not materials.is_phong_material(material):
        return
    mode = mode_of(material)
    tree = tree_of(material) if tree is False else tree
    if mode == PIXEL:
        _surface_per_pixel(material)
        if tree is not None:
            _remove_modifiers(tree, [])
            bpy.data.node_groups.remove(tree)
        return
    if tree is None:
        tree = bpy.data.node_groups.new(f"Phong Per Vertex {material.name}", "GeometryNodeTree")
        tree[TREE_MATERIAL_KEY] = material
    lights, world, light_model = _light_set(material)
    attribute = attribute_name(material)
    signature = repr((mode, attribute, light_model,
                      [(o.name, o.data.type, properties.falloff_of(o.data)) for o in lights],
                      world.name if world is not None else None, _control_paths(material)))
    if tree.get(TREE_SIGNATURE_KEY) != signature:
        build(tree, material, lights, world, light_model, mode, attribute)
        tree[TREE_SIGNATURE_KEY] = signature
    objects = users(material) if objects is None else objects
    for obj in objects:
        _ensure_modifier(obj, tree)
    _remove_modifiers(tree, objects)
    _surface_per_mesh(material, attribute)


def refresh(scene=None) -> int:
    """Update every Phong material that is not Per Pixel (or still has a Geometry Nodes
    group); returns how many.  Run after the lights groups changed (``sync``)."""
    trees = {}
    for tree in [t for t in bpy.data.node_groups if TREE_MATERIAL_KEY in t.keys()]:
        material = tree.get(TREE_MATERIAL_KEY)
        if isinstance(material, bpy.types.Material):
            trees[material.as_pointer()] = tree
        else:  # its material was deleted
            _remove_modifiers(tree, [])
            bpy.data.node_groups.remove(tree)
    todo = [m for m in materials.phong_materials()
            if mode_of(m) != PIXEL or m.as_pointer() in trees]
    if not todo:
        return 0
    wanted = {m.as_pointer() for m in todo}
    uses = {pointer: [] for pointer in wanted}
    for obj in bpy.data.objects:
        if obj.type != "MESH" or obj.library is not None:
            continue
        for pointer in {s.material.as_pointer() for s in obj.material_slots
                        if s.material is not None} & wanted:
            uses[pointer].append(obj)
    for material in todo:
        update(material, uses[material.as_pointer()], trees.get(material.as_pointer()))
    return len(todo)


_BUSY: list = []


@persistent
def follow_objects(_scene, depsgraph=None) -> None:
    """After an edit of mesh objects: one that got a Per Vertex / Per Face material (a slot
    assigned by hand) gets its modifier, and a modifier the user added after Phong Shading
    puts Phong Shading last again.  Only the updated objects are looked at."""
    if _BUSY or depsgraph is None or not (depsgraph.id_type_updated("OBJECT")
                                          or depsgraph.id_type_updated("MESH")):
        return
    # Only materials that have their group are followed: not a temporary copy (Bake Phong
    # Lighting swaps in copies of the materials, which keep the custom property)
    followed = {t.get(TREE_MATERIAL_KEY).as_pointer() for t in bpy.data.node_groups
                if t.bl_idname == "GeometryNodeTree"
                and isinstance(t.get(TREE_MATERIAL_KEY), bpy.types.Material)}
    if not followed:
        return  # no Per Vertex / Per Face material in the file: nothing to follow
    objects, meshes = set(), set()
    for change in depsgraph.updates:
        original = getattr(change.id, "original", None)
        if isinstance(original, bpy.types.Object):
            objects.add(original)
        elif isinstance(original, bpy.types.Mesh):  # a slot of the mesh was assigned
            meshes.add(original.as_pointer())
    if meshes:
        objects.update(o for o in bpy.data.objects
                       if o.type == "MESH" and o.data.as_pointer() in meshes)
    todo = {}
    for obj in objects:
        if obj.type != "MESH" or obj.library is not None:
            continue
        for slot in obj.material_slots:
            material = slot.material
            if material is None or material.as_pointer() not in followed:
                continue
            if mode_of(material) == PIXEL:
                continue
            if not materials.is_phong_material(material):
                continue
            modifiers = obj.modifiers
            mine = [m for m in modifiers if m.type == "NODES" and m.node_group is not None
                    and m.node_group.get(TREE_MATERIAL_KEY) == material]
            if not mine or modifiers[-1].type != "NODES" or modifiers[-1].node_group is None \
                    or modifiers[-1].node_group.get(TREE_MATERIAL_KEY) is None:
                todo[material.name] = material
    if not todo:
        return
    _BUSY.append(True)
    try:
        for material in todo.values():
            update(material)
    finally:
        _BUSY.pop()


def register():
    bpy.app.handlers.depsgraph_update_post.append(follow_objects)


def unregister():
    if follow_objects in bpy.app.handlers.depsgraph_update_post:
        bpy.app.handlers.depsgraph_update_post.remove(follow_objects)


def _light_set(material):
    """(light objects, world, model) of the lights group *material* uses."""
    node = material.node_tree.nodes.get(materials.LIGHTS_NODE)
    group = node.node_tree if node is not None else None
    scene = rig.owner(group) if group is not None else None
    if scene is None:
        return [], None, rig.MODELS[0]
    names = list(group.get("phong_lights", []))
    lights = [scene.objects.get(n) for n in names]
    lights = [o for o in lights if o is not None and o.type == "LIGHT"
              and o.data.type in model.LIGHT_GROUPS["seeds"]]
    light_model = group.get(rig.MODEL_KEY, rig.MODELS[0])
    return lights, scene.world, light_model if light_model in model.MODELS else rig.MODELS[0]


def _ensure_modifier(obj, tree) -> None:
    modifier = next((m for m in obj.modifiers if m.type == "NODES" and m.node_group == tree),
                    None)
    if modifier is None:
        modifier = obj.modifiers.new(MODIFIER_NAME, "NODES")
        modifier.node_group = tree
    index = list(obj.modifiers).index(modifier)
    ours = [i for i, m in enumerate(obj.modifiers)
            if m.type == "NODES" and m.node_group is not None
            and m.node_group.get(TREE_MATERIAL_KEY) is not None]
    if any(i > index for i, m in enumerate(obj.modifiers) if i not in ours):
        obj.modifiers.move(index, len(obj.modifiers) - 1)  # last: the lit mesh is the one seen


def _remove_modifiers(tree, keep) -> None:
    keep = set(o.name for o in keep)
    for obj in bpy.data.objects:
        if obj.name in keep or obj.type != "MESH":
            continue
        for modifier in [m for m in obj.modifiers if m.type == "NODES" and m.node_group == tree]:
            obj.modifiers.remove(modifier)


# -- the material's surface -----------------------------------------------------------

def _surface_per_pixel(material) -> None:
    tree = material.node_tree
    for name in (ATTRIBUTE_NODE, EMISSION_NODE):
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


def _surface_per_mesh(material, attribute: str) -> None:
    tree = material.node_tree
    node = materials.named_node(tree, ATTRIBUTE_NODE, "ShaderNodeAttribute", (-20.0, 420.0))
    node.label = "Phong Per Vertex / Per Face colour"
    node.attribute_type = "GEOMETRY"
    if node.attribute_name != attribute:
        node.attribute_name = attribute
    emission = materials.named_node(tree, EMISSION_NODE, "ShaderNodeEmission", (200.0, 420.0))
    emission.inputs["Strength"].default_value = 1.0
    tree.links.new(node.outputs["Color"], emission.inputs["Color"])
    materials.apply_opacity(material)  # the emission into the output (or the opacity mix)
    for aov_name in materials.AOVS:
        aov = tree.nodes.get(f"phong_aov:{aov_name}")
        if aov is None:
            continue
        if aov_name == materials.AOV_NAME:  # Phong Color: the stored colour
            tree.links.new(node.outputs["Color"], aov.inputs["Color"])
        else:  # the per-pixel terms are not computed in this mode (and not compiled by Eevee)
            for link in list(aov.inputs["Color"].links):
                tree.links.remove(link)
            aov.inputs["Color"].default_value = (0.0, 0.0, 0.0, 1.0)


def _control_paths(material) -> dict:
    """Lights-group input -> (data path in the material of the value that feeds it, or
    None, and its constant value)."""
    tree = material.node_tree
    lights = tree.nodes.get(materials.LIGHTS_NODE)
    paths = {}
    for name, control in CONTROL_OF.items():
        source = None
        socket = lights.inputs.get(name) if lights is not None else None
        if socket is not None and socket.is_linked:
            node = socket.links[0].from_node
            if node.bl_idname in ("ShaderNodeRGB", "ShaderNodeValue"):
                source = node
        if source is None:
            source = tree.nodes.get(control)
        if source is not None:
            path = f'node_tree.nodes["{bpy.utils.escape_identifier(source.name)}"].outputs[0].default_value'
            paths[name] = (path, None)
        else:
            value = socket.default_value if socket is not None else 0.0
            paths[name] = (None, tuple(value)[:3] if hasattr(value, "__len__") else float(value))
    return paths


# -- the Geometry Nodes group -------------------------------------------------------------

class _Writer(loader.NodeWriter):
    """The node writer of the shader groups, its leaves mapped to sockets of this tree."""

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
        drivers.prop(node.outputs[0], None, id_type, id_block, path, scale)
        return node.outputs[0]

    def constant(self, name, value):
        node = self.node("ShaderNodeValue", name)
        node.outputs[0].default_value = float(value)
        return node.outputs[0]

    def vector(self, name, id_type, id_block, path):
        """A vector of three driven channels: path[0], path[1], path[2]."""
        node = self.node("ShaderNodeCombineXYZ", name)
        for index, socket in enumerate(node.inputs[:3]):
            drivers.prop(socket, None, id_type, id_block, f"{path}[{index}]")
        return node.outputs[0]

    def constant_vector(self, name, value):
        node = self.node("ShaderNodeCombineXYZ", name)
        for index, socket in enumerate(node.inputs[:3]):
            socket.default_value = float(value[index])
        return node.outputs[0]


def build(tree, material, lights, world, light_model, mode, attribute) -> None:
    """(Re)write *tree*: the model for *lights* evaluated on the mesh, stored as *attribute*."""
    if tree.animation_data is not None:
        tree.animation_data_clear()
    tree.nodes.clear()
    if not any(i.item_type == "SOCKET" and i.in_out == "INPUT" for i in tree.interface.items_tree):
        tree.interface.clear()
        tree.interface.new_socket("Geometry", in_out="INPUT", socket_type="NodeSocketGeometry")
        tree.interface.new_socket("Geometry", in_out="OUTPUT", socket_type="NodeSocketGeometry")
    if hasattr(tree, "is_modifier"):
        tree.is_modifier = True
    tree.description = (f"Phong {'Per Vertex' if mode == VERTEX else 'Per Face'} shading of "
                        f"{material.name}: the lighting model at each "
                        f"{'vertex' if mode == VERTEX else 'face centre'}")
    b = _Builder(tree)
    sockets = {}
    # geometry: world position and normal, camera position
    self_info = b.node("GeometryNodeObjectInfo", "self", x=-1300.0)
    self_info.transform_space = "ORIGINAL"
    tree.links.new(b.node("GeometryNodeSelfObject", x=-1500.0).outputs[0],
                   self_info.inputs["Object"])
    point = b.node("FunctionNodeTransformPoint", "world position", x=-1100.0)
    tree.links.new(b.node("GeometryNodeInputPosition", x=-1300.0).outputs[0], point.inputs[0])
    tree.links.new(self_info.outputs["Transform"], point.inputs[1])
    invert = b.node("FunctionNodeInvertMatrix", x=-1300.0)
    tree.links.new(self_info.outputs["Transform"], invert.inputs[0])
    transpose = b.node("FunctionNodeTransposeMatrix", x=-1200.0)
    tree.links.new(invert.outputs[0], transpose.inputs[0])
    normal = b.node("FunctionNodeTransformDirection", "world normal", x=-1100.0)
    tree.links.new(b.node("GeometryNodeInputNormal", x=-1300.0).outputs[0], normal.inputs[0])
    tree.links.new(transpose.outputs[0], normal.inputs[1])
    camera_info = b.node("GeometryNodeObjectInfo", "camera", x=-1100.0)
    camera_info.transform_space = "ORIGINAL"
    tree.links.new(b.node("GeometryNodeInputActiveCamera", x=-1300.0).outputs[0],
                   camera_info.inputs["Object"])
    sockets.update({"P": point.outputs[0], "N": normal.outputs[0],
                    "Camera": camera_info.outputs["Location"]})
    power = {index for index, obj in enumerate(lights)
             if properties.falloff_of(obj.data) == "POWER"}  # i0/d^k (rig.py alike)
    expression = model.model_color([o.data.type for o in lights], light_model, power)
    factories = {}  # leaf name -> makes its socket (only the leaves the model reads are made)
    # the material's controls
    for name, (path, value) in _control_paths(material).items():
        vector = model.CONTROLS[name] == "vector"
        if path is None:
            factories[name] = (lambda n=name, v=value, vec=vector:
                               b.constant_vector(n, v) if vec else b.constant(n, v))
        elif vector:
            factories[name] = lambda n=name, p=path: b.vector(n, "MATERIAL", material, p)
        else:
            factories[name] = lambda n=name, p=path: b.value(n, "MATERIAL", material, p)
    # the ambient light
    if world is None:
        factories["Ambient Intensity"] = lambda: b.constant("Ambient Intensity",
                                                            properties.AMBIENT_INTENSITY[1])
        factories["Ambient Color"] = lambda: b.constant_vector("Ambient Color",
                                                               properties.AMBIENT_COLOR[1])
    else:
        properties.ensure_world_props(world)
        factories["Ambient Intensity"] = lambda: b.value(
            "Ambient Intensity", "WORLD", world, f'["{properties.AMBIENT_INTENSITY[0]}"]')
        factories["Ambient Color"] = lambda: b.vector(
            "Ambient Color", "WORLD", world, f'["{properties.AMBIENT_COLOR[0]}"]')
    # the lights
    for index, obj in enumerate(lights):
        factories.update(_light_sockets(b, index, obj))
    for name in sorted(model.leaves(expression) - set(sockets)):
        sockets[name] = factories[name]()
    store = tree.nodes.new("GeometryNodeStoreNamedAttribute")
    store.name = "store"
    store.data_type = "FLOAT_COLOR"
    store.domain = DOMAINS[mode]
    store.inputs["Name"].default_value = attribute
    group_in = tree.nodes.new("NodeGroupInput")
    group_out = tree.nodes.new("NodeGroupOutput")
    writer = _Writer(tree, sockets)
    value_socket = next(s for s in store.inputs if s.name == "Value" and s.enabled)
    writer.output(expression, value_socket, "color")
    x = (writer.max_depth + 1) * loader.COLUMN_WIDTH
    store.location = (x, 0.0)
    group_in.location = (x - 200.0, 300.0)
    group_out.location = (x + 250.0, 0.0)
    tree.links.new(group_in.outputs[0], store.inputs["Geometry"])
    tree.links.new(store.outputs["Geometry"], group_out.inputs[0])


def _light_sockets(b, index, obj) -> dict:
    """Leaf name -> a function making its socket, for light *index* (*obj*)."""
    light = obj.data
    properties.ensure_light_props(light)
    keys = {attr: f'["{key}"]' for attr, (key, _default) in properties.LIGHT_KEYS.items()}
    prefix = f"light{index}:"
    made = {}

    def info():
        if "info" not in made:
            node = b.node("GeometryNodeObjectInfo", f"{prefix}{obj.name}")
            node.transform_space = "ORIGINAL"
            node.inputs["Object"].default_value = obj
            made["info"] = node
        return made["info"]

    def direction():
        node = b.node("FunctionNodeTransformDirection", f"{prefix}Direction")
        node.inputs[0].default_value = (0.0, 0.0, -1.0)  # the light's -Z axis
        b.tree.links.new(info().outputs["Transform"], node.inputs[1])
        return node.outputs[0]

    factories = {prefix + "Position": lambda: info().outputs["Location"],
                 prefix + "Direction": direction,
                 prefix + "Color": lambda: b.vector(prefix + "Color", "LIGHT", light, "color")}
    for attr in ("intensity", "quadratic", "linear", "constant", "edge_exponent", "diffuse",
                 "specular", "distance", "decay", "penumbra", "power_k"):
        name = prefix + attr.replace("_", " ").title()
        factories[name] = lambda n=name, a=attr: b.value(n, "LIGHT", light, keys[a])
    for name in ("Half Angle", "Angle"):
        factories[prefix + name] = (lambda n=prefix + name:
                                    b.value(n, "LIGHT", light, "spot_size", scale=0.5))
    return factories
