# SPDX-License-Identifier: GPL-3.0-or-later
"""Flattening: the shared scene graph into shape and light instances with world matrices,
stable ids, paths and light scopes (``Document.instances`` and ``Document.lights``).
DEF/USE may multiply a small file into astronomically many instances: flattening counts
them on the shared graph first, places a shared group's instances with one batched matrix
product a use, keeps the first :data:`MAX_INSTANCES` with a warning giving the total, and
visits at most :data:`MAX_VISITS` groups; paths keep the :data:`PATH_LIMIT` innermost
names.
"""

from __future__ import annotations

import math

import numpy as np

from .model import Light, LightInstance, Shape, ShapeInstance, Transform, Viewpoint


#: Most shape and light instances that flattening keeps (DEF/USE can multiply a file).
MAX_INSTANCES = 100_000
#: Most groups that flattening visits (shared groups count once per use unless they can be
#: placed whole); with MAX_INSTANCES this bounds the time DEF/USE can cost.
MAX_VISITS = 1_000_000
#: A flattened instance's ``path`` keeps the names of at most this many innermost groups.
PATH_LIMIT = 32


# -- flattening -----------------------------------------------------------------------------

def _weights(root, count) -> dict:
    """{id(group): how many things *count* finds below it, with DEF/USE multiplicity},
    computed once per shared group (iteratively; capped at 2⁶²)."""
    out, seen = {}, set()
    stack = [(root, False)]
    while stack:
        node, done = stack.pop()
        key = id(node)
        if done:
            total = 0
            for child in node.children:
                total += out.get(id(child), 0) if isinstance(child, Transform) else count(child)
            out[key] = min(total, 1 << 62)
            continue
        if key in seen:         # done, or an ancestor (a cycle, which counts as nothing)
            continue
        seen.add(key)
        stack.append((node, True))
        for child in node.children:
            if isinstance(child, Transform) and id(child) not in seen:
                stack.append((child, False))
    return out


def _local_matrices(root) -> tuple:
    """({id(group): its local matrix as float64, or None for the identity},
    {id(group): how many times groups name it as a child}), once a shared group,
    iteratively."""
    local, refs = {}, {}
    stack = [root]
    while stack:
        node = stack.pop()
        if id(node) in local:
            continue
        m = np.asarray(node.matrix, dtype=np.float64)
        local[id(node)] = None if m.shape == (4, 4) and m.tobytes() == _EYE_BYTES else m
        for child in node.children:
            if isinstance(child, Transform):
                refs[id(child)] = refs.get(id(child), 0) + 1
                if id(child) not in local:
                    stack.append(child)
    return local, refs


_EYE_BYTES = np.eye(4).tobytes()


class _Block:
    """The instances below a shared group, relative to it: shapes, their matrices (k, 4, 4)
    and paths; lights, their matrices (m, 4, 4), scopes ((m, 2) start, stop; -1 for a global
    light) and paths; the bound viewpoint's matrix (or None)."""

    __slots__ = ("shapes", "rel", "paths", "lights", "light_rel", "scopes", "light_paths",
                 "viewpoint")


def _flatten(doc, notes) -> None:
    """Fill ``doc.instances``, ``doc.lights`` and ``doc.viewpoint_matrix`` by walking the
    graph iteratively: groups with nothing to show below them are skipped by their counts
    (computed once per shared group), and a shared group that fits the budget is flattened
    once relative to itself and placed with one batched matrix product a use.  At most
    MAX_INSTANCES shape and light instances, in document order, and MAX_VISITS groups
    visited; paths keep the PATH_LIMIT innermost names."""
    viewpoint = doc.viewpoint

    def counted(child):
        if isinstance(child, Shape):
            return 1 if child.geometry is not None else 0
        if isinstance(child, Light):
            return 1
        return 1 if viewpoint is not None and child is viewpoint else 0

    weights = _weights(doc.root, counted)
    local, refs = _local_matrices(doc.root)
    blocks = {}
    eye = np.eye(4)
    no_matrices = np.zeros((0, 4, 4))
    visits = [0]

    def compose(group, done):
        """_Block of *group* from the blocks of its child groups (in *done* or cached)."""
        counted_children = [c for c in group.children if (weights.get(id(c)) if
                            isinstance(c, Transform) else counted(c))]
        if len(counted_children) == 1 and isinstance(counted_children[0], Transform):
            # a group around one group (common, and DEF/USE chains): its block moved
            child = counted_children[0]
            inner = blocks[id(child)] if id(child) in blocks else done.get(id(child))
            if inner is None:
                return None
            m = local[id(child)]
            out = _Block()
            out.shapes, out.lights = inner.shapes, inner.lights
            prefix = (child.name,) if child.name else ()
            out.paths = inner.paths if not prefix else [(prefix + p)[-PATH_LIMIT:]
                                                        for p in inner.paths]
            out.light_paths = inner.light_paths if not prefix else [
                (prefix + p)[-PATH_LIMIT:] for p in inner.light_paths]
            out.scopes = inner.scopes
            if m is None:
                out.rel, out.light_rel, out.viewpoint = (inner.rel, inner.light_rel,
                                                         inner.viewpoint)
                return out
            out.rel = np.matmul(m, inner.rel)
            out.light_rel = np.matmul(m, inner.light_rel) if inner.lights else no_matrices
            out.viewpoint = None if inner.viewpoint is None else np.dot(m, inner.viewpoint)
            if not (np.isfinite(out.rel).all() and np.isfinite(out.light_rel).all()):
                return None
            return out
        shapes, rels, paths = [], [], []
        lights, light_rels, scopes, light_paths = [], [], [], []
        seen_viewpoint = None
        own_scoped = []
        for child in group.children:
            if isinstance(child, Transform):
                if not weights.get(id(child)):
                    continue
                inner = blocks[id(child)] if id(child) in blocks else done.get(id(child))
                if inner is None:
                    return None
                m = local[id(child)]
                offset = len(shapes)
                prefix = (child.name,) if child.name else ()
                shapes.extend(inner.shapes)
                rels.append(inner.rel if m is None else np.matmul(m, inner.rel))
                paths.extend(inner.paths if not prefix else
                             [(prefix + p)[-PATH_LIMIT:] for p in inner.paths])
                if inner.lights:
                    lights.extend(inner.lights)
                    light_rels.append(inner.light_rel if m is None
                                      else np.matmul(m, inner.light_rel))
                    scopes.append(np.where(inner.scopes >= 0, inner.scopes + offset, -1))
                    light_paths.extend(inner.light_paths if not prefix else
                                       [(prefix + p)[-PATH_LIMIT:] for p in inner.light_paths])
                if seen_viewpoint is None and inner.viewpoint is not None:
                    seen_viewpoint = inner.viewpoint if m is None else np.dot(m, inner.viewpoint)
            elif isinstance(child, Shape):
                if child.geometry is not None:
                    shapes.append(child)
                    rels.append(eye[None])
                    paths.append(())
            elif isinstance(child, Light):
                if not child.is_global:
                    own_scoped.append(sum(len(x) for x in scopes))
                lights.append(child)
                light_rels.append(eye[None])
                scopes.append(np.array([[-1, -1]]))
                light_paths.append(())
            elif isinstance(child, Viewpoint) and child is viewpoint and seen_viewpoint is None:
                seen_viewpoint = eye
        out = _Block()
        out.shapes, out.paths, out.lights, out.light_paths = shapes, paths, lights, light_paths
        out.rel = np.concatenate(rels) if rels else no_matrices
        out.light_rel = np.concatenate(light_rels) if light_rels else no_matrices
        out.scopes = np.concatenate(scopes) if scopes else np.zeros((0, 2), np.int64)
        out.scopes[own_scoped] = (0, len(shapes))
        out.viewpoint = seen_viewpoint
        if not (np.isfinite(out.rel).all() and np.isfinite(out.light_rel).all()):
            return None
        return out

    def block(group):
        """_Block of a shared group, computed iteratively (children first) and cached for
        every shared group met; None when a matrix is not finite."""
        if id(group) in blocks:
            return blocks[id(group)]
        done, busy = {}, set()
        stack = [(group, False)]
        while stack:
            node, finished = stack.pop()
            key = id(node)
            if finished:
                busy.discard(key)
                visits[0] += 1
                result = compose(node, done)
                if refs.get(key, 0) > 1:
                    blocks[key] = result
                else:
                    done[key] = result
                for child in node.children:     # a child used once is needed no more
                    if isinstance(child, Transform) and refs.get(id(child), 0) <= 1:
                        done.pop(id(child), None)
                continue
            if key in blocks or key in done or key in busy:
                continue
            busy.add(key)
            stack.append((node, True))
            stack.extend((c, False) for c in node.children if isinstance(c, Transform)
                         and weights.get(id(c)) and id(c) not in blocks and id(c) not in done)
        return blocks[id(group)] if id(group) in blocks else done.get(id(group))

    instances, lights = [], []
    doc.instances, doc.lights = instances, lights
    doc.viewpoint_matrix = np.eye(4)
    found_viewpoint = False
    truncated = stopped = broken = cycles = 0
    on_stack = {id(doc.root)}
    # a bound on |world entries|: |(A·B)ij| ≤ 4·max|A|·max|B|
    scale = {key: 4.0 * float(np.abs(m).max()) + 1.0 for key, m in local.items() if m is not None}
    root_matrix = local[id(doc.root)]
    start = eye if root_matrix is None else root_matrix
    stack = [[doc.root, start, 0, 0, [], (), float(np.abs(start).max()) + 1.0]]
    budget = MAX_INSTANCES
    with np.errstate(over="ignore", invalid="ignore"):
        while stack:
            frame = stack[-1]
            group, matrix, i = frame[0], frame[1], frame[2]
            children = group.children
            if i >= len(children):
                for light in frame[4]:
                    light.scope = range(frame[3], len(instances))
                on_stack.discard(id(group))
                stack.pop()
                continue
            frame[2] = i + 1
            child = children[i]
            if isinstance(child, Transform):
                weight = weights.get(id(child))
                if not weight:
                    continue
                if id(child) in on_stack:       # a graph built by hand may hold a cycle
                    cycles += 1
                    continue
                visits[0] += 1
                if visits[0] > MAX_VISITS:
                    stopped = 1
                    break
                m = local[id(child)]
                bound = frame[6]
                if m is None:
                    world = matrix
                else:
                    world = np.dot(matrix, m)   # np.dot: a third of ``@``'s overhead on 4×4
                    bound *= scale[id(child)]
                    if bound > 1e300:           # only then can a product overflow
                        if not math.isfinite(world.sum()):
                            broken += 1
                            continue
                        bound = float(np.abs(world).max()) * 4.0 + 1.0
                path = (frame[5] + (child.name,))[-PATH_LIMIT:] if child.name else frame[5]
                if refs.get(id(child), 0) > 1 \
                        and weight <= budget - len(instances) - len(lights):
                    shared = block(child)
                    if shared is not None:
                        mats = np.matmul(world, shared.rel)
                        if np.isfinite(mats).all():
                            base = len(instances)
                            instances.extend(
                                ShapeInstance(base + k, s, mats[k],
                                              (path + p)[-PATH_LIMIT:] if p else path)
                                for k, (s, p) in enumerate(zip(shared.shapes, shared.paths)))
                            if shared.lights:
                                lmats = np.matmul(world, shared.light_rel)
                                ranges = (shared.scopes + base).tolist()
                                lights.extend(
                                    LightInstance(light, lmats[k], None if scope[0] < base
                                                  else range(*scope),
                                                  (path + lpath)[-PATH_LIMIT:])
                                    for k, (light, scope, lpath) in enumerate(
                                        zip(shared.lights, ranges, shared.light_paths)))
                            if shared.viewpoint is not None and not found_viewpoint:
                                doc.viewpoint_matrix = np.dot(world, shared.viewpoint)
                                found_viewpoint = True
                            continue
                stack.append([child, world, 0, len(instances), [], path, bound])
                on_stack.add(id(child))
            elif isinstance(child, Shape):
                if child.geometry is None:
                    continue
                if len(instances) + len(lights) >= budget:
                    truncated = 1
                    break
                instances.append(ShapeInstance(len(instances), child, matrix, frame[5]))
            elif isinstance(child, Light):
                if len(instances) + len(lights) >= budget:
                    truncated = 1
                    break
                light = LightInstance(child, matrix, None, frame[5])
                lights.append(light)
                if not child.is_global:
                    frame[4].append(light)
            elif isinstance(child, Viewpoint):
                if child is viewpoint and not found_viewpoint:
                    doc.viewpoint_matrix = matrix
                    found_viewpoint = True
    if truncated or stopped:
        for frame in stack:
            for light in frame[4]:
                light.scope = range(frame[3], len(instances))
    if truncated:
        total = _weights(doc.root, lambda c: 1 if isinstance(c, (Shape, Light))
                         and (not isinstance(c, Shape) or c.geometry is not None) else 0)
        notes.add(f"the scene holds {total.get(id(doc.root), 0):,} shape and light instances "
                  f"(DEF/USE multiplies them): the first {MAX_INSTANCES:,} are kept")
    if stopped:
        notes.add(f"flattening stopped after {MAX_VISITS:,} groups (DEF/USE nests them "
                  f"deeply): the {len(instances):,} shape instances before are kept")
    if broken:
        notes.add("groups whose world matrix is not finite left out", n=broken)
    if cycles:
        notes.add("groups inside themselves (a cycle in the graph) left out", n=cycles)
