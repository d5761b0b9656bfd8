# SPDX-License-Identifier: GPL-3.0-or-later
"""The material a Phong material was made from: the Phong version of a user's material, the
source kept and found again, put back (``restore``), and Phong materials of older layouts
brought up to date (``upgrade``, the lights group node remade: ``renew_group_node``).

Materials are converted, not objects: one Phong material per distinct source material
(and light set), so objects that shared a material share its Phong version.  The source
material is kept with a fake user (so it is not purged on save) and named by its Phong
version: ``material["phong_source"]`` its name, ``material["phong_source_key"]`` a token the
source carries too (``source["phong_source_key"]``: the source is found again after a rename;
a library's source, whose token is not saved, by its name and ``material["phong_source_library"]``);
``restore`` puts it back.  Not an ID pointer: the depsgraph follows those, and each Phong
material would bring its source material and node tree into every update (layout 4
and earlier held a pointer, ``upgrade`` turns it into the name and token).
"""

from __future__ import annotations

import os
import uuid

import bpy

from .. import compat
from ...core import specular_albedo
from . import drivers, node_copy, recipe, writer


SOURCE_KEY = "phong_source"
SOURCE_TOKEN = "phong_source_key"
#: The library file (its path as Blender holds it) of a source material linked from a library:
#: the token written on it is not saved (a library's data is saved by its own file), so after
#: a reload the source is found by its name in that library.
SOURCE_LIBRARY_KEY = "phong_source_library"
#: Marks a Phong material made for a slot that had no material.
EMPTY_SOURCE_KEY = "phong_source_empty"
OLD_GENERATED = "phong_gen:"  # prefix of the per-light nodes of layout 1


def source_of(material, names=None):
    """The material a Phong material was made from (None if unknown or made for no material):
    the material named ``material["phong_source"]`` carrying its token, else the one carrying
    the token under another name (renamed since), else an ID pointer of layout 4 and before.
    *names*: a dict name -> material of ``bpy.data.materials`` (callers that ask for many)."""
    source = material.get(SOURCE_KEY)
    if isinstance(source, bpy.types.Material):
        return source
    token = material.get(SOURCE_TOKEN)
    if not isinstance(token, str) or not token:
        return None
    if not isinstance(source, str):
        named = None
    elif names is not None:
        named = names.get(source)
    else:
        named = bpy.data.materials.get(source)
    if named is not None and named.get(SOURCE_TOKEN) == token and named is not material:
        return named
    found = next((m for m in bpy.data.materials if m.get(SOURCE_TOKEN) == token
                  and m is not material and not recipe.is_phong_material(m)), None)
    library = material.get(SOURCE_LIBRARY_KEY)
    if found is None and isinstance(source, str) and isinstance(library, str):
        found = _linked(source, library)
    return found


def _linked(name, library):
    """The material *name* of a library, the one of file *library* where several libraries
    hold one of that name (paths compared absolute: a save may make them relative)."""
    def where(path, owner=None):
        return os.path.normpath(bpy.path.abspath(path, library=owner))

    found = [m for m in bpy.data.materials if m.library is not None and m.name == name]
    if len(found) > 1:
        wanted = where(library)
        found = [m for m in found if where(m.library.filepath, m.library.library) == wanted] \
            or found
    return found[0] if found else None


def keep_source(material, source) -> None:
    """Name *source* as the source of the Phong *material* and keep it (a fake user)."""
    token = source.get(SOURCE_TOKEN)
    if not isinstance(token, str) or not token:
        token = uuid.uuid4().hex
        source[SOURCE_TOKEN] = token
    if not source.use_fake_user and source.library is None:
        source.use_fake_user = True
    material[SOURCE_KEY] = source.name
    material[SOURCE_TOKEN] = token
    if source.library is not None:
        material[SOURCE_LIBRARY_KEY] = source.library.filepath
    elif SOURCE_LIBRARY_KEY in material.keys():
        del material[SOURCE_LIBRARY_KEY]


def _principled(material, rendered=False):
    """The Principled BSDF of *material*: the one its active Material Output shows, else
    (unless *rendered*) its first; *rendered*: the one Cycles renders, else None."""
    tree = material.node_tree if material is not None and compat.uses_nodes(material) else None
    if tree is None:
        return None
    if rendered:
        output = tree.get_output_node("CYCLES")  # Blender's own choice of output
        node = output.inputs["Surface"].links[0].from_node \
            if output is not None and output.inputs["Surface"].is_linked else None
        return node if node is not None and node.bl_idname == "ShaderNodeBsdfPrincipled" \
            else None
    output = next((n for n in tree.nodes if n.bl_idname == "ShaderNodeOutputMaterial"
                   and n.is_active_output), None)
    if output is not None and output.inputs["Surface"].is_linked:
        node = output.inputs["Surface"].links[0].from_node
        if node.bl_idname == "ShaderNodeBsdfPrincipled":
            return node
    return next((n for n in tree.nodes if n.bl_idname == "ShaderNodeBsdfPrincipled"), None)


def base_color(material):
    """The base colour of a material (Principled BSDF's, else its viewport colour), or None."""
    if material is None:
        return None
    node = _principled(material)
    if node is not None:
        return tuple(node.inputs["Base Color"].default_value)
    return tuple(material.diffuse_color)


def _unlinked(node, name, default):
    """The value of *node*'s input *name* where nothing feeds it, else *default*."""
    socket = node.inputs.get(name)
    if socket is None or socket.is_linked:
        return default
    return socket.default_value


def source_controls(material) -> dict:
    """{lights-group input: value} that a source material gives its Phong version besides
    the Object Color: a Principled BSDF's highlight as the Specular Color (white × 2·Specular IOR
    Level, at most 1, × its Specular Tint: 0 gives a diffuse Phong material, Blender's
    default 0.5 white) and its emission as the Irradiant Color (Emission Color × Strength);
    the defaults for any other material."""
    specular = recipe.default("Specular Color")
    irradiant = recipe.default("Irradiant Color")
    node = _principled(material) if material is not None else None
    if node is not None:
        level = min(1.0, 2.0 * float(_unlinked(node, "Specular IOR Level", 0.5)))
        tint = _unlinked(node, "Specular Tint", (1.0, 1.0, 1.0, 1.0))
        tint = tuple(tint)[:3] if hasattr(tint, "__len__") else (1.0, 1.0, 1.0)
        specular = (*(level * float(t) for t in tint), 1.0)
        strength = float(_unlinked(node, "Emission Strength", 0.0))
        color = tuple(_unlinked(node, "Emission Color", (0.0, 0.0, 0.0, 1.0)))[:3]
        irradiant = (*(max(0.0, strength * float(c)) for c in color), 1.0)
    return {"Specular Color": specular, "Irradiant Color": irradiant}


#: The Principled inputs the ambient colour reads (``ambient_terms``).
AMBIENT_INPUTS = ("Roughness", "IOR", "Specular IOR Level", "Specular Tint", "Metallic")


def _value(node, name, default):
    """The default value of *node*'s input *name* (linked or not), else *default*."""
    socket = node.inputs.get(name)
    if socket is None:
        return default
    value = socket.default_value
    return tuple(value)[:3] if hasattr(value, "__len__") else float(value)


def ambient_terms(material):
    """((scale, offset), linked): a Principled source's ambient colour Ka = Kd × scale +
    offset, what a uniform World gives its diffuse base under its specular layer plus that
    layer (and a metal's lobe) (``core/specular_albedo.py``), and the names of the inputs it
    read that something feeds (their own values were used); ((1, 1, 1), (0, 0, 0)) and ()
    for any other material (Ka = Kd), one whose Principled BSDF is not what Cycles renders
    included (Blender's versioning of a material without nodes gives Cycles a Diffuse BSDF
    and Eevee a Principled one)."""
    node = _principled(material, rendered=True) if material is not None else None
    if node is None:
        return ((1.0, 1.0, 1.0), (0.0, 0.0, 0.0)), ()
    linked = tuple(name for name in (*AMBIENT_INPUTS, "Base Color")
                   if node.inputs.get(name) is not None and node.inputs[name].is_linked
                   and (name != "Base Color" or _value(node, "Metallic", 0.0) > 0.0))
    terms = specular_albedo.principled_ambient(
        roughness=_value(node, "Roughness", 0.5), ior=_value(node, "IOR", 1.5),
        level=_value(node, "Specular IOR Level", 0.5),
        tint=_value(node, "Specular Tint", (1.0, 1.0, 1.0)),
        metallic=_value(node, "Metallic", 0.0),
        base=_value(node, "Base Color", (0.8, 0.8, 0.8)),
        multiscatter=getattr(node, "distribution", "MULTI_GGX") != "GGX")
    return terms, linked


def base_color_link(material):
    """The output socket that feeds the Principled Base Color (a texture), or None."""
    node = _principled(material)
    socket = node.inputs.get("Base Color") if node is not None else None
    if socket is not None and socket.is_linked and not socket.links[0].is_muted:
        return socket.links[0].from_socket
    return None


def from_source(source, name, lights_group, template=None, linked=None, ambient=None):
    """The Phong version of *source* (a material, or None for an empty slot).

    Without a texture chain on the source's Base Color: a copy of *template* (the same
    layout: Eevee compiles one shader for all of them) with the source's base colour, or a
    new material when there is no template.  With one: the same copy with the chain copied
    in (``node_copy``) feeding Object Color; where the chain cannot be copied (or there is
    no template), a copy of the source whose other nodes are removed, given the recipe's
    nodes (each named: slower in a large file, see ``_textured_from_template``).  Its
    Ambient Object Color: ``ambient_terms`` of the source (``writer.ambient_layer``); where
    an input it reads is fed by a node, (source name, input names) is appended to *linked*;
    *ambient*: ``ambient_terms(source)`` where the caller has it already.
    """
    texture = base_color_link(source) if source is not None else None
    if texture is not None:
        material = (_textured_from_template(source, texture, template, name)
                    if template is not None else None)
        if material is None:
            material = _strip_to_texture(source.copy(), texture)
            compat.rename(material, name)
            writer.control_nodes(material.node_tree, base_color(source))
            writer.wire(material, lights_group, _socket_in_copy(material, texture))
    elif template is not None:
        material = template.copy()
        compat.rename(material, name)
        value = base_color(source)
        recipe.set_quietly(writer.control_output(material, "Object Color"),
                           recipe.default("Object Color") if value is None
                           else (*value[:3], 1.0))
    else:
        material = writer.new_material(name, lights_group, base_color(source))
    for target, value in source_controls(source).items():
        control = writer.control_output(material, target)
        if tuple(control.default_value) != value:
            recipe.set_quietly(control, value)
    (scale, offset), inputs = ambient if ambient is not None else ambient_terms(source)
    writer.ambient_layer(material, scale, offset)
    if inputs and linked is not None:
        linked.append((source.name, inputs))
    for key in list(material.keys()):
        if key.startswith("phong_") and key != recipe.MATERIAL_TAG:
            del material[key]
    if source is None:
        material[EMPTY_SOURCE_KEY] = 1
    else:
        keep_source(material, source)
    return material


def _textured_from_template(source, texture, template, name):
    """A copy of *template* (the recipe's named nodes kept: naming a node walks the whole
    file) with *source*'s texture chain copied in (``node_copy``) feeding Object Color (and
    the ambient light, or the template's ambient layer, where they see the Object Color
    control); None
    when the chain cannot be copied faithfully."""
    material = template.copy()
    tree = material.node_tree
    made = node_copy.copy_upstream(source.node_tree, texture.node, tree, (-500.0, 0.0))
    if made is None:
        bpy.data.materials.remove(material)
        return None
    compat.rename(material, name)
    feed = compat.output_socket(made[texture.node.name], texture.identifier)
    control = writer.control_output(material, "Object Color")
    value = base_color(source)
    recipe.set_quietly(control, recipe.default("Object Color") if value is None
                       else (*value[:3], 1.0))
    lights = tree.nodes[recipe.LIGHTS_NODE]
    tree.links.new(feed, lights.inputs["Object Color"])
    ambient = lights.inputs[recipe.AMBIENT_INPUT]
    if ambient.is_linked and ambient.links[0].from_socket == control:
        tree.links.new(feed, ambient)
    layer = tree.nodes.get(recipe.AMBIENT_LAYER)  # the template's ambient layer
    vector = compat.input_socket(layer, "Vector") if layer is not None else None
    if vector is not None and vector.is_linked and vector.links[0].from_socket == control:
        tree.links.new(feed, vector)
    return material


def _socket_in_copy(material, socket):
    node = material.node_tree.nodes[socket.node.name]
    return compat.output_socket(node, socket.identifier)


def _strip_to_texture(material, texture_socket):
    """Keep only the nodes upstream of *texture_socket* (by name) in the copy *material*."""
    tree = material.node_tree
    keep = {node.name for node in node_copy.upstream(tree.nodes[texture_socket.node.name])}
    doomed = [n.name for n in tree.nodes if n.name not in keep]
    drivers.remove_node_drivers(tree, doomed)
    for name in doomed:
        tree.nodes.remove(tree.nodes[name])
    return material


def group_links(material, name=recipe.LIGHTS_NODE) -> dict:
    """{input name: the output sockets linked to it} of the group node *name*."""
    node = material.node_tree.nodes.get(name) if material.node_tree is not None else None
    if node is None:
        return {}
    return {s.name: [l.from_socket for l in s.links] for s in node.inputs if s.is_linked}


def renew_group_node(material, links=None, name=recipe.LIGHTS_NODE) -> bool:
    """Make the group node *name* of *material* again, with the same group, links and input
    values (a file written by a newer Blender: ``compat.file_from_newer_release``), and link
    *links* ({input name: output sockets}: ``group_links`` before) to the inputs that have
    none; returns whether there was a node."""
    tree = material.node_tree
    node = tree.nodes.get(name) if tree is not None else None
    if node is None or node.bl_idname != "ShaderNodeGroup":
        return False
    group, location, width, label = node.node_tree, tuple(node.location), node.width, node.label
    sources = {s.name: [l.from_socket for l in s.links] for s in node.inputs if s.is_linked}
    for input_name, sockets in (links or {}).items():
        sources.setdefault(input_name, sockets)
    values = {s.name: (tuple(s.default_value) if hasattr(s.default_value, "__len__")
                       else s.default_value)
              for s in node.inputs if hasattr(s, "default_value")}
    targets = {s.name: [l.to_socket for l in s.links] for s in node.outputs}
    tree.nodes.remove(node)
    node = tree.nodes.new("ShaderNodeGroup")
    node.name, node.label, node.location, node.width = name, label, location, width
    node.node_tree = group
    for socket in node.inputs:
        if socket.name in values and socket.name not in sources:
            socket.default_value = values[socket.name]
        for source in sources.get(socket.name, ()):
            tree.links.new(source, socket)
    for socket in node.outputs:
        for target in targets.get(socket.name, ()):
            tree.links.new(socket, target)
    return True


def upgrade(material) -> bool:
    """Turn a Phong material of layout 1 (every light's nodes in the material) into the
    recipe: the control nodes and their values stay; returns whether it changed."""
    layout = int(material.get(recipe.MATERIAL_TAG, 0))
    if layout >= recipe.LAYOUT:
        return False
    source = material.get(SOURCE_KEY)
    if isinstance(source, bpy.types.Material):  # layout <= 4: an ID pointer
        del material[SOURCE_KEY]
        keep_source(material, source)
    if layout >= 4:
        return True
    tree = material.node_tree
    names = [n.name for n in tree.nodes if n.name.startswith(OLD_GENERATED)]
    if tree.animation_data is not None:
        tree.animation_data_clear()
    for name in names:
        tree.nodes.remove(tree.nodes[name])
    for key in ("phong_lights",):
        if key in material.keys():
            del material[key]
    return True


def restore(obj, names=None) -> int:
    """Put back the source materials in the slots of *obj* that hold a Phong material made
    from one; returns how many slots changed.  *names*: as for ``source_of``."""
    changed = 0
    for slot in obj.material_slots:
        material = slot.material
        if not recipe.is_phong_material(material):
            continue
        source = source_of(material, names)
        if source is not None:
            slot.material = source
            changed += 1
        elif material.get(EMPTY_SOURCE_KEY):
            slot.material = None
            changed += 1
    return changed
