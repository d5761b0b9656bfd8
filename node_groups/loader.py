# SPDX-License-Identifier: GPL-3.0-or-later
"""Put the library's groups into the current .blend file.

Groups are found by name and tree type, stamped with the library version and a
fingerprint of their definition, and

* reused when the stamp matches,
* upgraded **in place** when older (the interface is updated socket by socket,
  so group nodes in materials keep their links and values),
* never downgraded when newer,
* de-duplicated: accidental copies (``Phong Diffuse.001`` after an append) are
  remapped to the canonical group and removed.
"""

from __future__ import annotations

import bpy

from . import expr
from .library import GROUPS, LIBRARY_VERSION, GroupDef

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
    definition = GROUPS[name]
    tree = _canonical(name)
    if tree is None:
        tree = bpy.data.node_groups.new(name, TREE_TYPE)
        status = CREATED
    else:
        version = int(tree.get(STAMP_VERSION, 0))
        if version > LIBRARY_VERSION:
            return tree, NEWER
        if version == LIBRARY_VERSION and tree.get(STAMP_FINGERPRINT) == definition.fingerprint:
            return tree, CURRENT
        status = UPGRADED
    _write(tree, definition)
    return tree, status


def merge_copies() -> int:
    """Merge stamped copies (``Phong Shading.001`` after an append) into their group.

    Returns how many copies were merged."""
    copies = {}
    for tree in bpy.data.node_groups:
        name = _stamped(tree)
        if name in GROUPS and tree.name != name and tree.library is None:
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
    expr.build(tree, definition.expressions, group_input, group_output)
    tree.description = definition.description
    tree[STAMP_GROUP] = definition.name
    tree[STAMP_VERSION] = LIBRARY_VERSION
    tree[STAMP_FINGERPRINT] = definition.fingerprint


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
            item = tree.interface.new_socket(spec.name, in_out=in_out, socket_type=spec.socket_type)
        item.description = spec.description
        _set_socket_values(item, spec)
    # Order: inputs then outputs, each as declared.
    for index, spec in enumerate(definition.outputs):
        tree.interface.move(_find(tree, "OUTPUT", spec.name), index)
    n_out = len(definition.outputs)
    for index, spec in enumerate(definition.inputs):
        tree.interface.move(_find(tree, "INPUT", spec.name), n_out + index)


def _find(tree, in_out, name):
    for item in tree.interface.items_tree:
        if item.item_type == "SOCKET" and item.in_out == in_out and item.name == name:
            return item
    raise KeyError(name)


def _set_socket_values(item, spec) -> None:
    if spec.subtype and hasattr(item, "subtype"):
        try:
            item.subtype = spec.subtype
        except TypeError:  # older Blender: subtype not settable on this socket type
            pass
    if spec.min is not None and hasattr(item, "min_value"):
        item.min_value = spec.min
    if spec.max is not None and hasattr(item, "max_value"):
        item.max_value = spec.max
    if spec.default is not None:
        item.default_value = spec.default
    if spec.name in ("Normal", "View Vector"):
        item.hide_value = False

