# SPDX-License-Identifier: GPL-3.0-or-later
"""The one reader of a Phong material, for every exporter: what feeds each input of its lights
group (a value, a texture, a chain of the importers' nodes), the twin of ``writer.py``."""

from __future__ import annotations

from .. import compat
from . import recipe


class Feed:
    """What feeds one input of a Phong material's lights group: *value* (a float, or 3
    floats for a colour), the value the material states (its control's, an RGB / Value
    node's, else the socket's own); *other*: the node that feeds the input instead when that
    is not a plain value (a texture, a chain), else None; *texture*: the Image Texture node
    (with an image) when *other* is one, or the importers' colour × map (a Vector Math
    Multiply of an RGB node and an Image Texture: *value* is then that RGB node's colour),
    else None; *socket*: the output socket linked to the input (None when unlinked): two
    inputs fed by the same socket show the same thing (the seeds' Ka = Kd); *chain*: the
    :class:`Chain` that *other* heads (None when *other* is)."""

    __slots__ = ("value", "other", "texture", "socket", "chain")

    def __init__(self, value, other=None, texture=None, socket=None, chain=None):
        self.value, self.other, self.texture = value, other, texture
        self.socket, self.chain = socket, chain

    def __repr__(self):
        return f"Feed({self.value!r}, {getattr(self.other, 'name', None)!r})"


class Chain:
    """The product that a chain of nodes feeding an input makes, as the importers build it:
    Vector Math Multiply and Scale nodes over RGB nodes (*colour*: the product of their
    colours, None without one), an Image Texture with an image (*texture*: the node), a Color
    Attribute (*attribute*: the node), a Scale's factor (*scale*); *unknown*: another node is
    in it (or it is deeper than 8 nodes)."""

    __slots__ = ("colour", "texture", "attribute", "scale", "unknown")

    def __init__(self, socket=None):
        self.colour = self.texture = self.attribute = self.scale = None
        self.unknown = False
        if socket is not None:
            self._walk(socket, 0)

    def _walk(self, source, depth) -> None:
        node = source.node
        kind = node.bl_idname
        if depth > 8:
            self.unknown = True
        elif kind == "ShaderNodeRGB":
            value = _plain_value(compat.value_output(node).default_value)
            self.colour = value if self.colour is None else tuple(
                a * b for a, b in zip(self.colour, value))
        elif kind == "ShaderNodeTexImage" and node.image is not None:
            self.texture = node
        elif kind == "ShaderNodeVertexColor":
            self.attribute = node
        elif kind == "ShaderNodeVectorMath" and node.operation in ("MULTIPLY", "SCALE"):
            identifiers = ("Vector", "Vector_001") if node.operation == "MULTIPLY" else \
                ("Vector",)
            if node.operation == "SCALE":
                self.scale = float(compat.input_socket(node, "Scale").default_value)
            for identifier in identifiers:
                socket = compat.input_socket(node, identifier)
                if socket.is_linked:
                    self._walk(socket.links[0].from_socket, depth + 1)
        else:
            self.unknown = True


def _plain_value(value):
    return tuple(float(v) for v in tuple(value)[:3]) if hasattr(value, "__len__") \
        else float(value)


def feeds(material) -> dict:
    """{input of the lights group: :class:`Feed`} of the Phong material *material*, for every
    input a control feeds (Object Color, Ambient Object Color, Specular Color, Exponent,
    Blinn, Irradiant Color, Specular Strength), and "Opacity": the Opacity control, *other*
    the opacity map (``recipe.OPACITY_MAP``) where one feeds the blend.  An Ambient Object
    Color fed by the socket that feeds Object Color (the seeds' model) is Object Color's
    feed; one fed by the ambient layer of a converted Principled material holds the colour
    that layer makes of Object Color's value."""
    tree = material.node_tree
    lights = tree.nodes[recipe.LIGHTS_NODE]
    out = {}
    for target, control in recipe.FEED_CONTROLS.items():
        socket = lights.inputs.get(target)
        if socket is None:
            continue
        node = tree.nodes.get(control)
        stated = _plain_value(compat.value_output(node).default_value) \
            if node is not None and node.bl_idname in compat.VALUE_OUTPUTS else None
        if not socket.is_linked:
            out[target] = Feed(_plain_value(socket.default_value))
            continue
        upstream = socket.links[0].from_node
        if upstream.bl_idname in compat.VALUE_OUTPUTS:
            out[target] = Feed(_plain_value(compat.value_output(upstream).default_value),
                               socket=socket.links[0].from_socket)
            continue
        feed = Feed(stated if stated is not None else _plain_value(socket.default_value),
                    upstream, socket=socket.links[0].from_socket,
                    chain=Chain(socket.links[0].from_socket))
        if upstream.bl_idname == "ShaderNodeTexImage" and upstream.image is not None:
            feed.texture = upstream
        elif upstream.bl_idname == "ShaderNodeVectorMath" and upstream.operation == "MULTIPLY":
            a, b = (compat.input_socket(upstream, k) for k in ("Vector", "Vector_001"))
            if a.is_linked and b.is_linked:
                rgb, image = a.links[0].from_node, b.links[0].from_node
                if rgb.bl_idname == "ShaderNodeRGB" and \
                        image.bl_idname == "ShaderNodeTexImage" and image.image is not None:
                    feed.value = _plain_value(compat.value_output(rgb).default_value)
                    feed.texture = image
        out[target] = feed
    ambient, colour = out.get(recipe.AMBIENT_INPUT), out.get("Object Color")
    if ambient is not None and colour is not None and ambient.other is not None and \
            ambient.socket == colour.socket:   # the seeds' model: what feeds Object Color
        out[recipe.AMBIENT_INPUT] = Feed(colour.value, colour.other, colour.texture, colour.socket,
                                  colour.chain)
    layer = _ambient_layer(lights, colour)
    if layer is not None:
        out[recipe.AMBIENT_INPUT] = layer
    out["Opacity"] = Feed(recipe.opacity(material), tree.nodes.get(recipe.OPACITY_MAP))
    return out


def _ambient_layer(lights, colour):
    """The Feed of an Ambient Object Color that the ambient layer of a converted Principled
    material feeds (``writer.ambient_layer``: Object Color's feed × scale + offset): its
    value Object Color's value × scale + offset; *other* the layer node where a texture or
    chain feeds Object Color (its value is then the control's colour's), else None: a
    plain colour.  None when the input is fed otherwise."""
    socket = lights.inputs.get(recipe.AMBIENT_INPUT)
    if socket is None or not socket.is_linked or colour is None:
        return None
    node = socket.links[0].from_node
    if node.name != recipe.AMBIENT_LAYER or node.bl_idname != "ShaderNodeVectorMath":
        return None
    vector = compat.input_socket(node, "Vector")
    if not vector.is_linked or vector.links[0].from_socket != colour.socket:
        return None
    scale, offset = (tuple(compat.input_socket(node, k).default_value)
                     for k in ("Vector_001", "Vector_002"))
    kd = colour.value if isinstance(colour.value, tuple) else (colour.value,) * 3
    value = tuple(float(k) * float(a) + float(b) for k, a, b in zip(kd, scale, offset))
    if colour.other is None:
        return Feed(value, socket=socket.links[0].from_socket)
    return Feed(value, node, socket=socket.links[0].from_socket,
                chain=Chain(socket.links[0].from_socket))
