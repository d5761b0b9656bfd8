# SPDX-License-Identifier: GPL-3.0-or-later
"""Copy the nodes upstream of a socket from one node tree into another: a material's texture
chain into a copy of the Phong template (``sources.from_source``).

Why not copy the whole source material and add the Phong nodes to it: each of those nodes
needs its name (the recipe's identity), and naming a node walks every ID of the file
(``BKE_animdata_fix_paths_rename_all``: 6 ms a name at 30,000 IDs), so Apply on N textured
materials grew as N × the file.  A copy of the template keeps its names; the chain's nodes
need none.

The copy is of what the Python API exposes: each node's writable properties (ID pointers
such as an Image or a node group included), its nested settings (Image User, texture and
colour mapping, a Color Ramp's stops, a curve mapping's points), its inputs' values and the
links among the copied nodes.  A node with anything else (a property that cannot be written
back, a nested setting of a kind not listed) is not copied: :func:`copy_upstream` returns
None, removes what it made, and the caller takes the slower way that keeps everything.
"""

from __future__ import annotations

from .. import compat

#: Node properties that are not settings (or are set otherwise); the ``bl_*`` ones too.
_SKIP = {"rna_type", "name", "location", "location_absolute", "dimensions", "inputs", "outputs",
         "internal_links", "parent", "select", "type", "is_active_output", "color_tag",
         "warning_propagation"}
#: Nested settings (read-only pointers to a struct) copied property by property.
_NESTED = {"ImageUser", "TexMapping", "ColorMapping", "ColorRamp", "CurveMapping"}


class _Unsupported(Exception):
    """A node the copy cannot reproduce."""


def upstream(node) -> list:
    """*node* and every node feeding it, each once, feeders first."""
    order, seen = [], set()

    def visit(current):
        if current.name in seen:
            return
        seen.add(current.name)
        for socket in current.inputs:
            for link in socket.links:
                visit(link.from_node)
        order.append(current)

    visit(node)
    return order


def copy_upstream(src_tree, node, dst_tree, offset=(0.0, 0.0)) -> dict | None:
    """Copy *node* of *src_tree* and the nodes feeding it into *dst_tree*, their links
    among them kept, moved by *offset*; {source node name: new node}, or None (nothing left
    in *dst_tree*) when a node cannot be copied faithfully."""
    nodes = upstream(node)
    made: dict = {}
    try:
        for source in nodes:
            copy = dst_tree.nodes.new(source.bl_idname)
            made[source.name] = copy
            _copy_struct(source, copy, top=True)
            _copy_inputs(source, copy)
        _place(dst_tree, {made[n.name].name: (n.location.x + offset[0], n.location.y + offset[1])
                          for n in nodes})
        for source in nodes:  # every feeder is in *nodes* (``upstream``)
            for socket in source.inputs:
                for link in socket.links:
                    dst_tree.links.new(
                        compat.output_socket(made[link.from_node.name],
                                             link.from_socket.identifier),
                        compat.input_socket(made[source.name], socket.identifier))
    except (_Unsupported, AttributeError, TypeError, ValueError, RuntimeError, KeyError):
        for copy in made.values():
            dst_tree.nodes.remove(copy)
        return None
    return made


def _place(tree, where: dict) -> None:
    """Move the nodes named in *where* ({name: (x, y)}) in one assignment: setting a node's
    location one by one runs Blender's update of the tree each time."""
    flat = [0.0] * (2 * len(tree.nodes))
    tree.nodes.foreach_get("location", flat)
    for index, node in enumerate(tree.nodes):
        if node.name in where:
            flat[2 * index:2 * index + 2] = where[node.name]
    tree.nodes.foreach_set("location", flat)


def _copy_struct(source, copy, top=False) -> None:
    for prop in source.bl_rna.properties:
        key = prop.identifier
        if key in _SKIP or key.startswith("bl_"):
            continue
        if prop.type == "POINTER":
            value = getattr(source, key)
            if not prop.is_readonly:
                if getattr(copy, key) != value:
                    setattr(copy, key, value)
                continue
            if value is None:
                continue
            kind = value.bl_rna.identifier
            if kind not in _NESTED:
                raise _Unsupported(f"{source.bl_rna.identifier}.{key}: {kind}")
            _copy_nested(kind, value, getattr(copy, key))
        elif prop.type == "COLLECTION":  # a node's own list (nested ones: _copy_nested)
            if top and len(getattr(source, key)):
                raise _Unsupported(f"{source.bl_rna.identifier}.{key}")
        elif not prop.is_readonly:
            value = getattr(source, key)
            if getattr(prop, "is_array", False) or getattr(prop, "array_length", 0):
                value = tuple(value)
                if tuple(getattr(copy, key)) != value:
                    setattr(copy, key, value)
            elif getattr(copy, key) != value:
                setattr(copy, key, value)


def _copy_nested(kind, source, copy) -> None:
    if kind == "ColorRamp":
        for key in ("color_mode", "interpolation", "hue_interpolation"):
            setattr(copy, key, getattr(source, key))
        elements, wanted = copy.elements, list(source.elements)
        while len(elements) > 1:  # a ramp keeps at least one stop
            elements.remove(elements[-1])
        first = elements[0]
        first.position, first.color = wanted[0].position, tuple(wanted[0].color)
        for theirs in wanted[1:]:
            elements.new(theirs.position).color = tuple(theirs.color)
        if [(e.position, tuple(e.color)) for e in elements] != \
                [(e.position, tuple(e.color)) for e in wanted]:
            raise _Unsupported("ColorRamp stops")
        return
    if kind == "CurveMapping":
        _copy_struct(source, copy)
        for mine, theirs in zip(copy.curves, source.curves):
            points = mine.points
            while len(points) > len(theirs.points):
                points.remove(points[-1])
            while len(points) < len(theirs.points):
                points.new(0.5, 0.5)
            for point, other in zip(points, theirs.points):
                point.location = tuple(other.location)
                point.handle_type = other.handle_type
        copy.update()
        return
    _copy_struct(source, copy)


def _copy_inputs(source, copy) -> None:
    """The inputs' values and hiding, each only where it differs from the new node's: every
    assignment runs Blender's update of the tree, which costs more as the file grows."""
    for socket in source.inputs:
        target = compat.input_socket(copy, socket.identifier)
        if hasattr(socket, "default_value") and not socket.is_linked:
            value = socket.default_value
            if hasattr(value, "__len__") and not isinstance(value, str):
                value = tuple(value)
                if tuple(target.default_value) != value:
                    target.default_value = value
            elif target.default_value != value:
                target.default_value = value
        if target.hide != socket.hide:
            target.hide = socket.hide


__all__ = ["copy_upstream", "upstream"]
