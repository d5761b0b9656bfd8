# SPDX-License-Identifier: GPL-3.0-or-later
"""``feeds.feeds()``, the one reader of a Phong material that every exporter uses: what
feeds each input of the lights group (a value, a texture, the importers' chains), which
socket feeds it, and the seeds' Ka = Kd (Ambient Object Color fed by Object Color's socket).
The expected values are the colours the test sets and their products by hand."""

from __future__ import annotations

import pytest


def _phong_material(bpy, level=0.0):
    """A Phong material made by Apply Phong Material on a plane, from a material whose
    Principled BSDF (where Blender gives a new material one) has Specular IOR Level *level*
    (0: no specular layer, the seeds' Ka = Kd)."""
    mesh = bpy.data.meshes.new("Plane")
    mesh.from_pydata([(0, 0, 0), (1, 0, 0), (1, 1, 0), (0, 1, 0)], [], [(0, 1, 2, 3)])
    source = bpy.data.materials.new("Paint")
    from phong_nodes.addon import compat  # noqa: PLC0415  (needs bpy)

    tree = compat.new_material_tree(source)
    tree.nodes["Principled BSDF"].inputs["Specular IOR Level"].default_value = level
    tree.nodes["Principled BSDF"].inputs["Base Color"].default_value = (0.05, 0.1, 0.2, 1.0)
    mesh.materials.append(source)
    obj = bpy.data.objects.new("Plane", mesh)
    bpy.context.scene.collection.objects.link(obj)
    obj.select_set(True)
    bpy.context.view_layer.objects.active = obj
    assert bpy.ops.phong.apply_material() == {"FINISHED"}
    return obj.material_slots[0].material


def _rgb(tree, colour):
    node = tree.nodes.new("ShaderNodeRGB")
    node.outputs[0].default_value = (*colour, 1.0)
    return node


def _image_node(bpy, tree, name):
    node = tree.nodes.new("ShaderNodeTexImage")
    node.image = bpy.data.images.new(name, 4, 4)
    return node


def _vector_math(tree, operation):
    node = tree.nodes.new("ShaderNodeVectorMath")
    node.operation = operation
    return node


def _input(node, identifier):
    return next(s for s in node.inputs if s.identifier == identifier)


def test_plain_controls_and_the_seeds_ambient(bpy_clean):
    bpy = bpy_clean
    from phong_nodes.addon.lighting import recipe
    from phong_nodes.addon.lighting import feeds as feed_reader
    material = _phong_material(bpy)
    nodes = material.node_tree.nodes
    nodes["phong_object_color"].outputs[0].default_value = (0.2, 0.4, 0.6, 1.0)
    nodes["phong_exponent"].outputs[0].default_value = 17.0
    feeds = feed_reader.feeds(material)
    assert feeds["Object Color"].value == pytest.approx((0.2, 0.4, 0.6))
    assert feeds["Object Color"].other is None and feeds["Object Color"].chain is None
    assert feeds["Exponent"].value == pytest.approx(17.0)
    # the recipe links Ambient Object Color from the socket that feeds Object Color
    ambient = feeds[recipe.AMBIENT_INPUT]
    assert ambient.value == pytest.approx((0.2, 0.4, 0.6))
    assert ambient.socket == feeds["Object Color"].socket
    assert ambient.socket.node.name == "phong_object_color"
    assert feeds["Opacity"].value == 1.0 and feeds["Opacity"].other is None


def test_the_ambient_layer_of_a_principled_source(bpy_clean):
    """A Principled source with a specular layer: the Ambient Object Color is a plain colour
    (no texture), brighter than the Object Color in every channel (the layer adds what it
    reflects of the World; a dark base gains the most), and it follows the Object Color's
    control: a brighter control, a brighter ambient."""
    bpy = bpy_clean
    from phong_nodes.addon.lighting import recipe
    from phong_nodes.addon.lighting import feeds as feed_reader
    material = _phong_material(bpy, level=0.5)
    feeds = feed_reader.feeds(material)
    ambient, colour = feeds[recipe.AMBIENT_INPUT], feeds["Object Color"]
    assert colour.value == pytest.approx((0.05, 0.1, 0.2))
    assert ambient.other is None and ambient.texture is None
    assert ambient.socket != colour.socket
    assert all(a > k + 0.01 for a, k in zip(ambient.value, colour.value))
    material.node_tree.nodes["phong_object_color"].outputs[0].default_value = (0.5, 0.6, 0.7, 1)
    brighter = feed_reader.feeds(material)[recipe.AMBIENT_INPUT].value
    assert all(b > a + 0.3 for a, b in zip(ambient.value, brighter))


def test_a_texture_on_object_color_and_ambient(bpy_clean):
    """Ambient fed by Object Color's texture is Object Color's feed; fed by a texture of its
    own (no Ambient control in the material) it is its own, not Object Color's."""
    bpy = bpy_clean
    from phong_nodes.addon.lighting import recipe
    from phong_nodes.addon.lighting import feeds as feed_reader
    material = _phong_material(bpy)
    tree = material.node_tree
    lights = tree.nodes[recipe.LIGHTS_NODE]
    tree.nodes["phong_object_color"].outputs[0].default_value = (0.3, 0.5, 0.7, 1.0)
    diffuse = _image_node(bpy, tree, "diffuse")
    tree.links.new(diffuse.outputs["Color"], lights.inputs["Object Color"])
    tree.links.new(diffuse.outputs["Color"], lights.inputs[recipe.AMBIENT_INPUT])
    feeds = feed_reader.feeds(material)
    colour, ambient = feeds["Object Color"], feeds[recipe.AMBIENT_INPUT]
    assert colour.texture.image.name == "diffuse" and colour.other == colour.texture
    assert colour.value == pytest.approx((0.3, 0.5, 0.7)), "the control's colour is stated"
    assert ambient.other is colour.other and ambient.texture is colour.texture
    assert ambient.value == pytest.approx((0.3, 0.5, 0.7))
    assert recipe.AMBIENT_CONTROL not in tree.nodes
    own = _image_node(bpy, tree, "ambient")
    tree.links.new(own.outputs["Color"], lights.inputs[recipe.AMBIENT_INPUT])
    ambient = feed_reader.feeds(material)[recipe.AMBIENT_INPUT]
    assert ambient.texture.image.name == "ambient"
    assert ambient.socket != feeds["Object Color"].socket


def test_the_importers_chains(bpy_clean):
    """An X3D import's chains: colour × (texture × colour attribute) on Object Color, a Scale
    of it on Ambient; a product of two colours; an unknown node."""
    bpy = bpy_clean
    from phong_nodes.addon.lighting import recipe
    from phong_nodes.addon.lighting import feeds as feed_reader
    material = _phong_material(bpy)
    tree = material.node_tree
    lights = tree.nodes[recipe.LIGHTS_NODE]
    texture = _image_node(bpy, tree, "map")
    attribute = tree.nodes.new("ShaderNodeVertexColor")
    attribute.layer_name = "Col"
    inner = _vector_math(tree, "MULTIPLY")
    tree.links.new(texture.outputs["Color"], _input(inner, "Vector"))
    tree.links.new(attribute.outputs["Color"], _input(inner, "Vector_001"))
    outer = _vector_math(tree, "MULTIPLY")
    tree.links.new(_rgb(tree, (0.5, 0.25, 1.0)).outputs[0], _input(outer, "Vector"))
    tree.links.new(inner.outputs["Vector"], _input(outer, "Vector_001"))
    tree.links.new(outer.outputs["Vector"], lights.inputs["Object Color"])
    scale = _vector_math(tree, "SCALE")
    _input(scale, "Scale").default_value = 0.3
    tree.links.new(outer.outputs["Vector"], _input(scale, "Vector"))
    tree.links.new(scale.outputs["Vector"], lights.inputs[recipe.AMBIENT_INPUT])
    product = _vector_math(tree, "MULTIPLY")
    tree.links.new(_rgb(tree, (0.5, 0.5, 0.25)).outputs[0], _input(product, "Vector"))
    tree.links.new(_rgb(tree, (0.4, 1.0, 0.8)).outputs[0], _input(product, "Vector_001"))
    tree.links.new(product.outputs["Vector"], lights.inputs["Specular Color"])
    mix = tree.nodes.new("ShaderNodeMix")
    mix.data_type = "RGBA"
    tree.links.new(next(s for s in mix.outputs if s.type == "RGBA"),
                   lights.inputs["Irradiant Color"])
    feeds = feed_reader.feeds(material)

    chain = feeds["Object Color"].chain
    assert chain.colour == pytest.approx((0.5, 0.25, 1.0))
    assert chain.texture.image.name == "map"
    assert chain.attribute.layer_name == "Col"
    assert chain.scale is None and not chain.unknown
    assert feeds["Object Color"].texture is None, "not the importers' colour × map"
    chain = feeds[recipe.AMBIENT_INPUT].chain
    assert chain.scale == pytest.approx(0.3)
    assert chain.colour == pytest.approx((0.5, 0.25, 1.0))
    assert chain.texture.image.name == "map" and chain.attribute.layer_name == "Col"
    assert feeds[recipe.AMBIENT_INPUT].socket != feeds["Object Color"].socket
    chain = feeds["Specular Color"].chain
    assert chain.colour == pytest.approx((0.2, 0.5, 0.2))
    assert chain.texture is None and chain.attribute is None and not chain.unknown
    assert feeds["Irradiant Color"].chain.unknown
    assert feeds["Exponent"].chain is None


def test_what_the_writer_writes_the_reader_reads_back(bpy_clean):
    """The round trip of the one writer and the one reader: a new Phong material given
    values (binary fractions: float32 keeps them exactly) and a map on Specular Color by
    ``writer.write`` reads back through ``feeds`` as those values, the map as the Specular
    Color's texture, the Ka its own (not Object Color's)."""
    bpy = bpy_clean
    from phong_nodes.addon.lighting import recipe, writer
    from phong_nodes.addon.lighting import feeds as feed_reader
    group = _phong_material(bpy).node_tree.nodes[recipe.LIGHTS_NODE].node_tree
    material = writer.new_material("Written", group)
    colours = {"Object Color": (0.25, 0.5, 0.75), recipe.AMBIENT_INPUT: (0.125, 0.0625, 0.5),
               "Specular Color": (0.5, 0.375, 0.25), "Irradiant Color": (0.0, 0.125, 0.25)}
    image = bpy.data.images.new("specular map", 4, 4)
    writer.write(material, writer.Values(colours, exponent=17.5, blinn=1.0,
                                         specular_strength=0.0, opacity=0.625,
                                         maps={"Specular Color": image}))
    feeds = feed_reader.feeds(material)
    for target, colour in colours.items():
        assert feeds[target].value == colour, target
    assert feeds["Exponent"].value == 17.5 and feeds["Blinn"].value == 1.0
    assert feeds["Specular Strength"].value == 0.0 and feeds["Opacity"].value == 0.625
    assert feeds["Specular Color"].texture.image == image
    assert all(feeds[t].other is None for t in colours if t != "Specular Color")
    assert feeds[recipe.AMBIENT_INPUT].socket != feeds["Object Color"].socket
    assert recipe.blends(material), "an opacity below 1 blends"
    # written again, the values replace the first ones and the map stays on its input
    writer.write(material, writer.Values({"Object Color": (1.0, 0.0, 0.5)}, exponent=3.0,
                                         opacity=1.0), link=False)
    again = feed_reader.feeds(material)
    assert again["Object Color"].value == (1.0, 0.0, 0.5) and again["Exponent"].value == 3.0
    assert again["Specular Color"].texture.image == image and not recipe.blends(material)


def test_the_writer_refuses_a_colour_of_another_input(bpy_clean):
    """A colour handed for an input that no colour control feeds (a typo, a scalar) is
    refused with a message naming it, and the material is left as it was."""
    bpy = bpy_clean
    from phong_nodes.addon.lighting import writer
    material = _phong_material(bpy)
    before = sorted(n.name for n in material.node_tree.nodes)
    for colors in ({"Object Colour": (1.0, 0.0, 0.0)}, {"Exponent": (1.0, 1.0, 1.0)}):
        with pytest.raises(ValueError, match="not a colour input of a Phong material: Ex|Obj"):
            writer.write(material, writer.Values(colors))
    assert sorted(n.name for n in material.node_tree.nodes) == before
