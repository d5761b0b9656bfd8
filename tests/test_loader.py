# SPDX-License-Identifier: GPL-3.0-or-later
"""Loading the library into a file: reuse, upgrade in place, no duplicates, no downgrade."""

import pytest

import blender_env as be
from phong_nodes.node_groups import library

STAMP_VERSION = "phong_nodes_version"
STAMP_FINGERPRINT = "phong_nodes_fingerprint"


def new_material(name):
    material = be.import_bpy().data.materials.new(name)
    be.compat().new_material_tree(material)
    return material


def material_with_diffuse(bpy):
    """A user's material: an RGB node linked into Object Color, Intensity typed in."""
    material = new_material("User")
    tree = material.node_tree
    group = tree.nodes.new("ShaderNodeGroup")
    group.node_tree = bpy.data.node_groups["Phong Diffuse"]
    rgb = tree.nodes.new("ShaderNodeRGB")
    rgb.outputs[0].default_value = (0.2, 0.4, 0.6, 1.0)
    tree.links.new(rgb.outputs[0], group.inputs["Object Color"])
    group.inputs["Intensity"].default_value = 0.5
    tree.links.new(group.outputs["Color"], tree.nodes["Material Output"].inputs["Surface"])
    return material, group


def test_older_group_is_upgraded_in_place_keeping_user_links(bpy_clean):
    bpy = bpy_clean
    be.load_groups()
    material, node = material_with_diffuse(bpy)
    old = bpy.data.node_groups["Phong Diffuse"]
    # Make it look like an older library: lower stamp, broken insides, an extra socket.
    old[STAMP_VERSION] = 0
    old.nodes.clear()
    old.interface.new_socket("Obsolete", in_out="INPUT", socket_type="NodeSocketFloat")
    count = len(bpy.data.node_groups)

    be.load_groups()

    assert len(bpy.data.node_groups) == count, "no new group"
    tree = bpy.data.node_groups["Phong Diffuse"]
    assert tree == old, "the same datablock, upgraded in place"
    assert tree[STAMP_VERSION] == library.LIBRARY_VERSION
    assert tree[STAMP_FINGERPRINT] == library.GROUPS["Phong Diffuse"].fingerprint
    assert [s.name for s in be.interface_sockets(tree, "INPUT")] == [
        "Light Vector", "Intensity", "Light Color", "Object Color", "Normal"]
    assert len(tree.nodes) > 2, "nodes rebuilt"
    links = material.node_tree.links
    assert any(l.to_node == node and l.to_socket.name == "Object Color" for l in links)
    assert any(l.from_node == node and l.from_socket.name == "Color" for l in links)
    assert node.inputs["Intensity"].default_value == pytest.approx(0.5)


def test_changed_definition_with_same_version_is_rebuilt(bpy_clean):
    bpy = bpy_clean
    be.load_groups()
    tree = bpy.data.node_groups["Phong Ambient"]
    tree[STAMP_FINGERPRINT] = "something older"
    tree.nodes.clear()
    be.load_groups()
    assert tree[STAMP_FINGERPRINT] == library.GROUPS["Phong Ambient"].fingerprint
    assert len(tree.nodes) > 2


def test_newer_group_is_never_downgraded(bpy_clean):
    bpy = bpy_clean
    be.load_groups()
    tree = bpy.data.node_groups["Phong Specular"]
    tree[STAMP_VERSION] = library.LIBRARY_VERSION + 1
    marker = tree.nodes.new("NodeFrame")
    marker.name = "made by a newer Phong Nodes"
    be.load_groups()
    assert tree.nodes.get("made by a newer Phong Nodes") is not None
    assert tree[STAMP_VERSION] == library.LIBRARY_VERSION + 1


def test_accidental_copies_are_merged_into_the_original(bpy_clean):
    bpy = bpy_clean
    be.load_groups()
    original = bpy.data.node_groups["Phong Diffuse"]
    copy = original.copy()  # what appending a material from another file produces
    assert copy.name == "Phong Diffuse.001"
    material = new_material("Appended")
    node = material.node_tree.nodes.new("ShaderNodeGroup")
    node.node_tree = copy
    be.load_groups()
    assert "Phong Diffuse.001" not in bpy.data.node_groups
    assert node.node_tree == bpy.data.node_groups["Phong Diffuse"]


def test_a_users_own_group_with_our_name_is_kept(bpy_clean):
    bpy = bpy_clean
    mine = bpy.data.node_groups.new("Phong Irradiant", "ShaderNodeTree")
    mine.nodes.new("NodeFrame").name = "mine"
    be.load_groups()
    assert mine.name == "Phong Irradiant (user)"
    assert mine.nodes.get("mine") is not None
    assert bpy.data.node_groups["Phong Irradiant"] != mine


def test_shift_a_menu_lists_every_group_once(extension):
    from phong_nodes.addon.ui import menus  # noqa: PLC0415

    listed = [name for _title, names in menus.SECTIONS for name in names]
    assert sorted(listed) == sorted(library.GROUPS)
    bpy = be.import_bpy()
    assert hasattr(bpy.types, "NODE_MT_phong_add")


def test_adding_a_group_node_reuses_the_group(bpy_clean):
    bpy = bpy_clean
    from phong_nodes.addon.ui import operators  # noqa: PLC0415

    tree = new_material("M").node_tree
    first = operators.add_group_node(tree, "Phong Blinn Specular", (10, 20))
    second = operators.add_group_node(tree, "Phong Blinn Specular", (30, 40))
    assert first.node_tree == second.node_tree == bpy.data.node_groups["Phong Blinn Specular"]
    assert [g.name for g in bpy.data.node_groups] == ["Phong Blinn Specular"]
    assert tree.nodes.active == second and second.select and not first.select
    with pytest.raises(ValueError, match="Unknown Phong group 'Phong Bogus'; expected one of"):
        operators.add_group_node(tree, "Phong Bogus", (0, 0))


def test_appending_a_phong_material_reuses_the_groups_present(bpy_clean, tmp_path):
    bpy = bpy_clean
    be.load_groups()
    material = new_material("Appended Phong")
    node = material.node_tree.nodes.new("ShaderNodeGroup")
    node.node_tree = bpy.data.node_groups["Phong Shading"]
    material.use_fake_user = True
    path = str(tmp_path / "other.blend")
    bpy.ops.wm.save_as_mainfile(filepath=path)

    be.reset_empty_file()
    be.load_groups()
    before = sorted(g.name for g in bpy.data.node_groups)
    result = bpy.ops.wm.append(filepath=f"{path}/Material/Appended Phong",
                               directory=f"{path}/Material/", filename="Appended Phong")
    assert result == {"FINISHED"}
    bpy.context.view_layer.update()  # what the UI does after any change
    assert sorted(g.name for g in bpy.data.node_groups) == before, "no Phong Shading.001"
    appended = bpy.data.materials["Appended Phong"]
    groups = [n.node_tree for n in appended.node_tree.nodes if n.bl_idname == "ShaderNodeGroup"]
    assert groups == [bpy.data.node_groups["Phong Shading"]]


def test_every_operation_node_has_the_declared_sockets(bpy_clean):
    """The operation table (node_groups/expr.py) against this Blender's nodes: each operation's
    node takes the operation, has the declared inputs, and its output carries the result kind."""
    from phong_nodes.node_groups import expr

    socket_types = {expr.FLOAT: "VALUE", expr.VECTOR: "VECTOR", expr.COLOR: "RGBA",
                    expr.SHADER: "SHADER"}
    tree = bpy_clean.data.node_groups.new("Operations", "ShaderNodeTree")
    for op in expr.OPERATIONS:
        node = tree.nodes.new(op.node)
        if op.operation is not None:
            node.operation = op.operation
            assert node.operation == op.operation
        for key, kind in zip(op.inputs, op.operands):
            assert node.inputs[key].type == socket_types[kind], (op.name, key)
        for name, _value in op.settings:
            assert name in node.inputs, (op.name, name)
        assert node.outputs[op.output].type == socket_types[op.kind], (op.name, op.output)
