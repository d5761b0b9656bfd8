# SPDX-License-Identifier: GPL-3.0-or-later
"""The Geometry Nodes group of Per Vertex and Per Face shading, **Phong Shading Geometry**,
and its modifier (docs/shading_modes.md; the setting's life is ``modes.py``).

The group does not depend on lights or camera: it runs as the last modifier of every mesh
object with a Per Vertex / Per Face material, stores on each face the centre and normal of
the face (Per Face), then triangulates and stores on each triangle the positions and normals
of its three vertices, and on each corner its barycentric basis vector (Per Vertex), all in
object space, for the shading groups (``groups.py``) to read.
"""

from __future__ import annotations

import contextlib

import bpy

from .. import compat

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
_POINT_NORMAL = "phong_vertex_normal"  # temporary, removed by the group


def geometry_tree():
    """The modifier's Geometry Nodes group, or None."""
    for tree in bpy.data.node_groups:
        if tree.bl_idname == "GeometryNodeTree" and GEOMETRY_KEY in tree.keys() \
                and tree.library is None:
            return tree
    return None


def modifiers_of(obj, tree) -> list:
    """The modifiers of *obj* that run the Geometry Nodes group *tree*."""
    return [m for m in obj.modifiers if m.type == "NODES" and m.node_group == tree]


def ensure_modifier(obj, tree) -> None:
    if obj.type != "MESH" or obj.library is not None:
        return
    modifier = next(iter(modifiers_of(obj, tree)), None)
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
            for modifier in modifiers_of(obj, tree):
                if modifier.show_viewport or modifier.show_render:
                    off.append((modifier, modifier.show_viewport, modifier.show_render))
                    modifier.show_viewport = modifier.show_render = False
    try:
        yield
    finally:
        for modifier, viewport, render in off:
            modifier.show_viewport, modifier.show_render = viewport, render


def remove_modifier(obj, tree) -> None:
    for modifier in modifiers_of(obj, tree):
        obj.modifiers.remove(modifier)


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
