# SPDX-License-Identifier: GPL-3.0-or-later
"""Put the library's groups into the current .blend file.

Groups are found by name and tree type, stamped with the library version and a
fingerprint of their definition, and

* reused when the stamp matches,
* upgraded **in place** when older (the interface is updated socket by socket,
  so group nodes in materials keep their links and values),
* never downgraded when newer,
* de-duplicated: accidental copies (``Phong Diffuse.001`` after an append) are
  remapped to the canonical group and removed, by a depsgraph handler after each update
  in which the number of node groups changed (the newest version wins, so nothing is
  downgraded).

The inner nodes are written from the group's expressions by :class:`NodeWriter`: one node per
distinct sub-expression, as the operation table of ``node_groups/expr.py`` says, laid out in
columns by depth.
"""

from __future__ import annotations

import contextlib

import bpy

from bpy.app.handlers import persistent

from ..node_groups.expr import COLOR, Expr
from . import compat
from ..node_groups.library import (
    GROUPS, LIBRARY_VERSION, RIG_GROUPS, VARIANTS, GroupDef, definition,
)

STAMP_GROUP = "phong_nodes_group"
STAMP_VERSION = "phong_nodes_version"
STAMP_FINGERPRINT = "phong_nodes_fingerprint"
TREE_TYPE = "ShaderNodeTree"

CREATED, UPGRADED, CURRENT, NEWER = "created", "upgraded", "up to date", "newer kept"


def load_all() -> dict:
    """Ensure every group is in ``bpy.data``; returns {status: [group names]}."""
    summary: dict = {}
    for name in GROUPS:
        _tree, status = ensure_group(name)
        summary.setdefault(status, []).append(name)
    return summary


def ensure_group(name: str):
    """The group called *name*, created or upgraded as needed; returns (tree, status)."""
    spec = definition(name, compat.NODE_FEATURES)
    tree = _canonical(name)
    if tree is None:
        tree = bpy.data.node_groups.new(name, TREE_TYPE)
        status = CREATED
    else:
        version = int(tree.get(STAMP_VERSION, 0))
        if version > LIBRARY_VERSION:
            return tree, NEWER
        if version == LIBRARY_VERSION and tree.get(STAMP_FINGERPRINT) == spec.fingerprint:
            return tree, CURRENT
        status = UPGRADED
    _write(tree, spec)
    return tree, status


def refresh_variants() -> list:
    """``ensure_group`` for each group of the file that has variants (``library.VARIANTS``):
    one written for another release or by an earlier version (e.g. the seeds' light group without
    5.3's Switch) is rewritten in place, links kept; returns the names rewritten."""
    names = []
    for name in VARIANTS:
        tree = bpy.data.node_groups.get(name)
        if tree is None or tree.library is not None or _stamped(tree) != name:
            continue  # not in the file: nothing to refresh (ensure_group would add it)
        if ensure_group(name)[1] == UPGRADED:
            names.append(name)
    return names


def write_group(tree, name: str) -> None:
    """Write the library's group *name* into *tree* (any file's data, e.g. temporary data)."""
    _write(tree, definition(name, compat.NODE_FEATURES))


def merge_copies() -> int:
    """Merge stamped copies (``Phong Shading.001`` after an append) into their group.

    Returns how many copies were merged."""
    copies = {}
    for tree in bpy.data.node_groups:
        name = _stamped(tree)
        if (name in GROUPS or name in RIG_GROUPS) and tree.name != name and tree.library is None:
            copies[name] = copies.get(name, 0) + 1
    for name in copies:
        _canonical(name)
    return sum(copies.values())


def _stamped(tree) -> str | None:
    return tree.get(STAMP_GROUP) if tree.bl_idname == TREE_TYPE else None


def _canonical(name: str):
    """The one group that stands for *name*; copies are merged into it."""
    candidates = [t for t in bpy.data.node_groups if _stamped(t) == name and t.library is None]
    plain = bpy.data.node_groups.get(name)
    if plain is not None and plain.library is None and plain not in candidates:
        if plain.bl_idname == TREE_TYPE and not plain.get(STAMP_GROUP):
            # A group of the user's that happens to bear our name: keep it, renamed.
            plain.name = f"{name} (user)"
        elif plain.bl_idname != TREE_TYPE:
            plain.name = f"{name} ({plain.bl_idname})"
    if not candidates:
        return None
    candidates.sort(key=lambda t: (int(t.get(STAMP_VERSION, 0)), t.name == name), reverse=True)
    keep = candidates[0]
    for other in candidates[1:]:
        with keeping_links(other, keep):
            other.user_remap(keep)
        bpy.data.node_groups.remove(other)
    if keep.name != name:
        keep.name = name
    return keep


def _write(tree, definition: GroupDef) -> None:
    """(Re)write the interface and the nodes of *tree* from *definition*."""
    _sync_interface(tree, definition)
    tree.nodes.clear()
    group_input = tree.nodes.new("NodeGroupInput")
    group_output = tree.nodes.new("NodeGroupOutput")
    writer = NodeWriter(tree, group_input)
    for spec in definition.outputs:
        writer.output(definition.expressions[spec.name], group_output.inputs[spec.name], spec.kind)
    writer.place_ends(group_output)
    tree.description = definition.description
    tree[STAMP_GROUP] = definition.name
    tree[STAMP_VERSION] = LIBRARY_VERSION
    tree[STAMP_FINGERPRINT] = definition.fingerprint


# -- expressions as nodes ----------------------------------------------------------

COLUMN_WIDTH, ROW_HEIGHT = 220.0, 180.0


def _socket_value(kind: str, value):
    """A constant as the default value of a socket of *kind* (a colour socket is RGBA)."""
    return (*value, 1.0) if kind == COLOR else value


class NodeWriter:
    """Writes expressions into *tree*: one node per distinct sub-expression (its operation's
    node, from ``expr.OPERATIONS``), constants folded into socket values.

    Layout: a node's column is its depth, the longest chain of nodes from the group inputs
    (which, with the Geometry node, stand in column 0 at the left); within a column, nodes stand
    in the order they are finished (arguments before their users)."""

    def __init__(self, tree, group_input):
        self.tree = tree
        self.group_input = group_input
        self.geometry_node = None
        self.sockets: dict = {}  # expression key -> output socket
        self.depth: dict = {}    # expression key -> column
        self.columns: dict = {}  # column -> how many nodes stand in it
        self.max_depth = 0

    def output(self, expression: Expr, target, kind: str) -> None:
        """Connect *expression* to *target* (a Group Output socket of *kind*)."""
        source = self.socket(expression)
        if source is None:
            target.default_value = _socket_value(kind, expression.value)
        else:
            self.tree.links.new(source, target)
        self.max_depth = max(self.max_depth, self.depth.get(expression.key, 0))

    def socket(self, expression: Expr):
        """The output socket computing *expression* (None for a constant)."""
        if expression.op == "const":
            return None
        key = expression.key
        if key not in self.sockets:
            self.sockets[key] = (self._leaf(expression) if expression.is_leaf
                                 else self._operation(expression))
        return self.sockets[key]

    def _leaf(self, expression: Expr):
        self.depth[expression.key] = 0
        if expression.op == "input":
            return self.group_input.outputs[expression.value]
        if self.geometry_node is None:
            self.geometry_node = self.tree.nodes.new("ShaderNodeNewGeometry")
        return self.geometry_node.outputs[expression.value]

    def _operation(self, expression: Expr):
        op = expression.op
        node = self.tree.nodes.new(op.node)
        for name, value in op.properties:  # e.g. a Switch's type, before its sockets
            setattr(node, name, value)
        if op.operation is not None:
            node.operation = op.operation
        if op.clamp:
            node.use_clamp = True
        for name, value in op.settings:
            compat.input_socket(node, name).default_value = value
        depth = 0
        for arg, kind, target_key in zip(expression.args, op.operands, op.inputs):
            target = compat.input_socket(node, target_key)
            source = self.socket(arg)
            if source is None:
                target.default_value = _socket_value(kind, arg.value)
            else:
                self.tree.links.new(source, target)
                depth = max(depth, self.depth[arg.key])
        self.depth[expression.key] = depth + 1
        row = self.columns.get(depth + 1, 0)
        self.columns[depth + 1] = row + 1
        node.location = ((depth + 1) * COLUMN_WIDTH, -row * ROW_HEIGHT)
        return compat.output_socket(node, op.output)

    def place_ends(self, group_output) -> None:
        """The group input and the Geometry node left of column 1, the output right of the last."""
        self.group_input.location = (-300.0, 0.0)
        if self.geometry_node is not None:
            self.geometry_node.location = (-300.0, 400.0)
        group_output.location = ((self.max_depth + 1) * COLUMN_WIDTH + 80.0, 0.0)


def _socket_ids(tree) -> dict:
    """{(in_out, name): identifier} of *tree*'s interface sockets."""
    return {(i.in_out, i.name): i.identifier for i in tree.interface.items_tree
            if i.item_type == "SOCKET"}


@contextlib.contextmanager
def keeping_links(tree, fresh=None):
    """Around a change of *tree*'s interface (or ``tree.user_remap(fresh)``): the group nodes
    using it get their links and input values back on the sockets of the same name.

    Blender keeps a group node's links by socket identifier, and identifiers are not stable
    across a rebuilt interface (a new group numbers its sockets from 0; a cleared one goes on
    counting): a file of 5.2 whose lights group gained 5.3's Eevee Shader output had every
    material control on the wrong input.  Used by every rewrite of a lights or
    shading group (``lighting.rig.rewrite``) and by the merge of a library group's copies.
    The users are looked up only where an identifier can move: a group in use changed in
    place, or a remap to *fresh* where a socket of the same name has another identifier."""
    before = _socket_ids(tree)
    if fresh is not None:
        after = _socket_ids(fresh)
        moved = any(after.get(key, ident) != ident for key, ident in before.items())
    else:
        moved = tree.users > 0
    saved = _group_node_links(tree) if moved else []
    yield
    if fresh is None and _socket_ids(tree) == before:
        return
    for node, inputs, outputs, values in saved:
        _put_back(node, inputs, outputs, values)


def _group_node_links(tree) -> list:
    """[(group node, {input name: sources}, {output name: targets}, {input name: value})]
    of every group node using *tree*."""
    saved = []
    for user in bpy.data.user_map(subset={tree}).get(tree, ()):
        owner_tree = user if isinstance(user, bpy.types.NodeTree) else getattr(
            user, "node_tree", None)
        if owner_tree is None:
            continue
        for node in owner_tree.nodes:
            if node.bl_idname != "ShaderNodeGroup" or node.node_tree != tree:
                continue
            saved.append((node, *_node_links(node)))
    return saved


def _node_links(node) -> tuple:
    """({input name: sources}, {output name: targets}, {input name: value}) of *node*."""
    inputs = {s.name: [l.from_socket for l in s.links] for s in node.inputs}
    outputs = {s.name: [l.to_socket for l in s.links] for s in node.outputs}
    values = {s.name: (tuple(s.default_value) if hasattr(s.default_value, "__len__")
                       else s.default_value)
              for s in node.inputs if hasattr(s, "default_value")}
    return inputs, outputs, values


def set_group(node, group) -> None:
    """``node.node_tree = group`` for the group node *node*, its links and input values kept
    on the sockets of the same name: Blender keeps them by identifier, and two groups of the
    same interface need not number their sockets alike (``keeping_links``: a lights group
    upgraded from an older layout against one written afresh)."""
    old = node.node_tree
    if old is group:
        return
    moved = old is not None and any(_socket_ids(group).get(key, ident) != ident
                                    for key, ident in _socket_ids(old).items())
    saved = _node_links(node) if moved else None
    node.node_tree = group
    if saved is not None:
        _put_back(node, *saved)


def _put_back(node, inputs, outputs, values) -> None:
    """*node*'s links and input values as ``_group_node_links`` saved them, by socket name."""
    links = node.id_data.links
    for socket in node.inputs:
        want = inputs.get(socket.name, [])
        if [l.from_socket.as_pointer() for l in socket.links] != [s.as_pointer() for s in want]:
            for link in list(socket.links):
                links.remove(link)
            for source in want:
                links.new(source, socket)
        if not want and socket.name in values and hasattr(socket, "default_value"):
            try:
                socket.default_value = values[socket.name]
            except (TypeError, ValueError):  # another socket type under that name
                pass
    for socket in node.outputs:
        want = outputs.get(socket.name, [])
        if sorted(l.to_socket.as_pointer() for l in socket.links) != sorted(
                s.as_pointer() for s in want):
            for link in list(socket.links):
                links.remove(link)
            for target in want:
                links.new(socket, target)


def _sync_interface(tree, definition: GroupDef) -> None:
    """Make the interface match, keeping sockets (and so user links) that still fit."""
    wanted = [("INPUT", s) for s in definition.inputs] + [("OUTPUT", s) for s in definition.outputs]
    existing = {}
    for item in list(tree.interface.items_tree):
        if item.item_type != "SOCKET":
            tree.interface.remove(item)
            continue
        key = (item.in_out, item.name)
        if key in existing or not any(k == item.in_out and s.name == item.name
                                      and s.socket_type == item.socket_type for k, s in wanted):
            tree.interface.remove(item)
        else:
            existing[key] = item
    for position, (in_out, spec) in enumerate(wanted):
        item = existing.get((in_out, spec.name))
        if item is None:
            item = tree.interface.new_socket(spec.name, description=spec.description,
                                             in_out=in_out, socket_type=spec.socket_type)
        _set_socket_values(item, spec)
    # Order: outputs then inputs, each as declared; an item already in place is not moved
    # (each change of an interface walks every node tree of the file: 7 ms a change in a
    # file of 20,000 materials)
    wanted_order = [("OUTPUT", s.name) for s in definition.outputs] + \
                   [("INPUT", s.name) for s in definition.inputs]
    for index, (in_out, name) in enumerate(wanted_order):
        items = [i for i in tree.interface.items_tree if i.item_type == "SOCKET"]
        if index < len(items) and (items[index].in_out, items[index].name) == (in_out, name):
            continue
        tree.interface.move(_find(tree, in_out, name), index)


def _find(tree, in_out, name):
    for item in tree.interface.items_tree:
        if item.item_type == "SOCKET" and item.in_out == in_out and item.name == name:
            return item
    raise KeyError(name)


def _set_socket_values(item, spec) -> None:
    """The interface item *item* as *spec* declares it; only what differs is written (each
    write walks every node tree of the file)."""
    if item.description != spec.description:
        item.description = spec.description
    if spec.subtype and hasattr(item, "subtype") and item.subtype != spec.subtype:
        try:
            item.subtype = spec.subtype
        except TypeError:  # older Blender: subtype not settable on this socket type
            pass
    if spec.min is not None and hasattr(item, "min_value") and item.min_value != spec.min:
        item.min_value = spec.min
    if spec.max is not None and hasattr(item, "max_value") and item.max_value != spec.max:
        item.max_value = spec.max
    if spec.default is not None and not _same_value(item.default_value, spec.default):
        item.default_value = spec.default


def _same_value(current, wanted) -> bool:
    """Whether a socket's *current* value already is *wanted* (to float precision)."""
    if hasattr(current, "__len__"):
        wanted = tuple(wanted) if hasattr(wanted, "__len__") else (wanted,)
        return len(current) == len(wanted) and all(
            abs(float(a) - float(b)) <= 1e-7 * max(1.0, abs(float(b)))
            for a, b in zip(current, wanted))
    try:
        return abs(float(current) - float(wanted)) <= 1e-7 * max(1.0, abs(float(wanted)))
    except (TypeError, ValueError):
        return current == wanted



# -- appended copies ----------------------------------------------------------------

_seen = {"count": -1}


@persistent
def merge_appended_copies(_scene, _depsgraph=None):
    count = len(bpy.data.node_groups)
    if count == _seen["count"]:
        return
    merge_copies()
    _seen["count"] = len(bpy.data.node_groups)


#: The loader's handlers, (event of ``bpy.app.handlers``, function) in the order they run
#: (``addon/__init__.py`` registers them).
HANDLERS = (("depsgraph_update_post", merge_appended_copies),)
