# SPDX-License-Identifier: GPL-3.0-or-later
"""PROTO expansion, and a field's node looked up: a PROTO instance stands for its PROTO's
first body node; what depends on its fields through IS is copied, the rest shared, at most
:data:`MAX_NODES` nodes, nested at most :data:`MAX_PROTO_DEPTH` deep; an EXTERNPROTO's file
is read through ``files``.  Each function is handed the reading context
(:class:`~.context._Reading`).
"""

from __future__ import annotations

import os

from .graph import _CASE, _IS, _MISSING, _N, _Raw, _Use
from .files import parse_file


#: Most nodes that PROTO expansion copies in one file (only the nodes of a PROTO body that
#: depend on the instance's fields through IS are copied; the rest is shared).
MAX_NODES = 50_000
#: Deepest nesting of PROTO instances inside PROTO bodies.
MAX_PROTO_DEPTH = 32


class _Budget(Exception):
    pass


def proto_of(ctx, inst):
    proto = inst.proto
    if proto.extern_urls is None:
        return proto
    if proto.resolved is None:
        proto.resolved = False
        for url in proto.extern_urls:
            file_part, _, name = url.partition("#")
            if file_part:
                path = ctx.resolver(file_part, proto.src.base)
                src = parse_file(ctx, path, proto.src.depth + 1) \
                    if path and os.path.isfile(path) else None
            else:
                src = proto.src
            if src is None:
                continue
            protos = src.scope.protos
            found = protos.get(name) if name else next(iter(protos.values()), None)
            if found is not None and found.extern_urls is None:
                proto.resolved = found
                break
        if not proto.resolved:
            ctx.notes.add("EXTERNPROTOs whose PROTO was not found: instances left out",
                          proto.name)
    return proto.resolved or None


def expand(ctx, inst):
    """The node a PROTO instance stands for: its PROTO's first body node, with the nodes
    that depend on the instance's fields through IS copied (IS fields taking the instance's
    values, else the interface's defaults) and the rest shared between instances, like a
    USE (memoised per instance)."""
    key = id(inst)
    if key in ctx.expanded:
        return ctx.expanded[key][1]
    ctx.expanded[key] = (inst, None)
    proto = proto_of(ctx, inst)
    if proto is None:
        return None
    if any(p is proto for p in inst.chain):
        ctx.notes.add("PROTO instances inside their own PROTO: left out", proto.name)
        return None
    if len(inst.chain) >= MAX_PROTO_DEPTH:
        ctx.notes.add(f"PROTO instances nested deeper than {MAX_PROTO_DEPTH}: left out",
                      proto.name)
        return None
    if not proto.body:
        return None
    values = {name: spec[2] for name, spec in proto.fields.items()}
    lower = {name.lower(): name for name in proto.fields}
    for name, value in inst.fields.items():
        if name not in values:
            if name.lower() in lower:
                ctx.notes.add(_CASE, f"{name} → {lower[name.lower()]}")
                name = lower[name.lower()]
            else:
                ctx.notes.add("PROTO instance fields not in the PROTO's interface: ignored",
                              f"{proto.name}.{name}")
                continue
        values[name] = value
    try:
        root = copy(ctx, proto, values, inst.chain + (proto,))
    except _Budget:
        ctx.notes.add(f"PROTO expansion beyond {MAX_NODES:,} copied nodes: the rest left "
                      "out", proto.name)
        return None
    if root is not None and root.name is None and root is not proto.body[0]:
        root.name = inst.name
    ctx.expanded[key] = (inst, root)
    return root


def _refs(node):
    """The nodes a node's fields hold (a _Use resolved in its scope), and whether a field
    is an IS."""
    found, has_is = [], False
    for value in node.fields.values():
        for item in (value if isinstance(value, list) else (value,)):
            if isinstance(item, _N):
                found.append(item)
            elif isinstance(item, _Use):
                target = item.scope.defs.get(item.name)
                if target is not None:
                    found.append(target)
            elif isinstance(item, _IS):
                has_is = True
    return found, has_is


def _dynamic(proto) -> set:
    """ids of the body nodes from which an IS can be reached (computed once a PROTO,
    iteratively): only these are copied per instance."""
    if proto.dynamic is not None:
        return proto.dynamic
    dynamic, state = set(), {}
    stack = [(proto.body[0], False)]
    while stack:
        node, done = stack.pop()
        if done:
            found, has_is = _refs(node)
            if has_is or any(id(n) in dynamic for n in found):
                dynamic.add(id(node))
            continue
        if id(node) in state:
            continue
        state[id(node)] = True
        stack.append((node, True))
        stack.extend((n, False) for n in _refs(node)[0] if id(n) not in state)
    proto.dynamic = dynamic
    return dynamic


def copy(ctx, proto, values, chain):
    """Copy the body nodes of *proto* that depend on IS (iteratively), sharing within the
    copy what the body shares (DEF/USE); IS fields take *values* (not copied)."""
    root = proto.body[0]
    dynamic = _dynamic(proto)
    if id(root) not in dynamic:
        return root
    memo = {}
    order = []
    stack = [root]
    while stack:
        node = stack.pop()
        if id(node) in memo or id(node) not in dynamic:
            continue
        ctx.copies += 1
        if ctx.copies > MAX_NODES:
            raise _Budget
        new = _N(node.type, node.name, node.proto, node.src, chain)
        memo[id(node)] = new
        order.append((node, new))
        stack.extend(_refs(node)[0])

    def substitute(value):
        if isinstance(value, _IS):
            if value.name in values:
                return values[value.name]
            for key in values:
                if key.lower() == value.name.lower():
                    return values[key]
            ctx.notes.add("IS naming no field of its PROTO: ignored", value.name)
            return _MISSING
        if isinstance(value, _N):
            return memo.get(id(value), value)
        if isinstance(value, _Use):
            found = value.scope.defs.get(value.name)
            return memo.get(id(found), found) if found is not None else value
        return value

    for node, new in order:
        for key, value in node.fields.items():
            if isinstance(value, list) and value and not isinstance(value, _Raw):
                out = []
                for item in value:
                    item = substitute(item)
                    if item is _MISSING or item is None:
                        continue
                    if isinstance(item, list):
                        out.extend(item)
                    else:
                        out.append(item)
                new.fields[key] = out
            else:
                value = substitute(value)
                if value is not _MISSING:
                    new.fields[key] = value
    return memo[id(root)]


def lookup(ctx, value):
    """A field's node: a _Use resolved in its scope, a PROTO instance expanded to the node
    it stands for (its body's first node), None when there is none."""
    for _ in range(MAX_PROTO_DEPTH + 2):
        if isinstance(value, _Use):
            found = value.scope.defs.get(value.name)
            if found is None:
                ctx.notes.add("USE of names never DEF'd: left out", value.name)
                return None
            value = found
        if not isinstance(value, _N):
            return None
        if value.proto is None:
            return value
        value = expand(ctx, value)
    return None
