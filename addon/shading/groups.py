# SPDX-License-Identifier: GPL-3.0-or-later
"""The shader groups of Per Vertex and Per Face shading, **Phong Per Vertex ⟨lights group⟩** /
**Phong Per Face ⟨lights group⟩**, one per lights group and mode (docs/shading_modes.md;
the setting's life is ``modes.py``).

A group reads the attributes of the Geometry Nodes group (``geometry.py``), taken to world
space by the shaded object's transform (so instances are lit where they stand), evaluates
the model (``node_groups/shading_modes.py``: the library's own group expressions, composed as
the lights group composes them) at each of the triangle's vertices (or at the face centre)
and mixes the three colours by the interpolated basis (Gouraud) or shows the one colour
(flat).  The viewer is the eye of the pixel's ray (position + incoming × view distance), so
the camera, and the viewport's view, are followed at render time.  The lights reach it as
they reach the lights group: world transforms from the World's copies (View Layer
attributes, where the lights group reads them: ``lighting/world_copies.py``) or drivers,
their settings, the world's ambient by drivers without Python expressions.
"""

from __future__ import annotations

import bpy

from ...node_groups import models
from ...node_groups import shading_modes as model
from ...node_groups.expr import VECTOR, input_
from .. import compat, loader
from ..lighting import drivers, properties, recipe, rig, world_copies
from ..lighting.lights import SUPPORTED
from .geometry import FACE_CENTRE, FACE_NORMAL, VERTEX_NORMALS, VERTEX_POSITIONS, WEIGHTS

PIXEL, VERTEX, FACE = model.MODES
#: Outputs of a Per Vertex shading group besides Color: the model at the triangle's k-th
#: vertex (constant over the triangle).
VERTEX_OUTPUTS = ("Vertex 0", "Vertex 1", "Vertex 2")
#: Custom properties of a shading group: its lights group (an ID pointer), its mode and the
#: fingerprint of what it was built for.
GROUP_LIGHTS_KEY = "phong_shading_lights"
GROUP_MODE_KEY = "phong_shading_mode"
GROUP_SIGNATURE_KEY = "phong_shading_signature"
GROUP_VERSION = 3  # bump when the layout of the shading groups changes
#: The material's inputs of the shading group (those of the lights group that the model reads).
CONTROL_INPUTS = tuple(i for i in rig.INPUTS if i[0] in model.CONTROLS)


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


def _lights_group(material):
    """The lights group *material* uses, or None."""
    node = material.node_tree.nodes.get(recipe.LIGHTS_NODE)
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
    expression = model.model_color([models.drawn_as(o.data.type) for o in lights], light_model,
                                   power)
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
                                                        properties.NO_WORLD_AMBIENT),
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

    def color():
        node = b.node("ShaderNodeCombineXYZ", prefix + "Color")
        for index, axis in enumerate("XYZ"):
            drivers.light_color_channel(compat.input_socket(node, axis), None, light, index)
        return compat.output_socket(node, "Vector")

    def intensity(name):  # its own i0 or its Power's (rig.py alike)
        node = b.node("ShaderNodeValue", name)
        drivers.light_intensity(compat.value_output(node), light, keys["intensity"],
                                f'["{properties.FROM_POWER_KEY}"]', properties.power_scale(light))
        return compat.value_output(node)

    factories = {prefix + "Position": lambda: transform("LOCATION"),
                 prefix + "Direction": lambda: transform("AXIS"),
                 prefix + "Color": color}
    # the light groups' inputs that a setting drives (every model's, node_groups/models.py)
    # and the leaves of the Phong Shading / Power Falloff that the composition "phong" reads;
    # an Area light's spot settings are the models' constants (models.drawn_as)
    driven = {target: attr for spec in models.MODELS.values()
              for attr, _types, _when, target in spec.settings if target is not None}
    driven.update({"Diffuse": "diffuse", "Specular": "specular", "Power K": "power_k"})
    fixed = properties.settings_of(light) if light.type == "AREA" else {}
    area = {attr for spec in models.MODELS.values() for attr, _value in spec.area}
    for target, attr in driven.items():
        name = prefix + target
        if attr == "intensity":
            factories[name] = lambda n=name: intensity(n)
        elif attr in area and light.type == "AREA":
            factories[name] = lambda n=name, a=attr: b.constant(n, fixed[a])
        else:
            factories[name] = lambda n=name, a=attr: b.value(n, "LIGHT", light, keys[a])
    for target in {spec.spot_angle for spec in models.MODELS.values()}:
        if light.type == "AREA":
            factories[prefix + target] = (lambda n=prefix + target:
                                          b.constant(n, models.AREA_HALF_ANGLE))
        else:
            factories[prefix + target] = (lambda n=prefix + target:
                                          b.value(n, "LIGHT", light, "spot_size", scale=0.5))
    return factories
