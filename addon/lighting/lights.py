# SPDX-License-Identifier: GPL-3.0-or-later
"""Which Blender lights drive Phong materials, and which objects each light reaches.

* :func:`scene_lights`: the scene's Point, Sun, Spot and Area lights that render (in F12:
  not disabled in renders, in a collection of the view layer that renders; hidden in the
  viewport or not), and the other lights that cannot drive Phong.
* :func:`light_set`: the lights that reach one object under Blender's Light Linking (a
  light's ``light_linking.receiver_collection``): with no collection the light reaches
  every object; otherwise only the included objects if there are any, minus the excluded
  ones (Blender manual, Light Linking ▸ Include & Exclude).  An object inside a child
  collection of the receiver collection takes the link state of that child collection.
* :func:`instanced_objects`: the objects that collection instances bring into a scene (an
  object's Instancing ▸ Collection, at any depth), the one walk Apply, the relink handler and
  the comparison share.
* :func:`signature`: a cheap fingerprint of everything above, so a depsgraph handler can
  tell in microseconds that nothing changed.
"""

from __future__ import annotations

import bpy

from ...node_groups import models
from . import properties

#: The light types that drive Phong materials (each model has a light group for each, an Area
#: light drawn as a spot: ``node_groups/models.py``).
SUPPORTED = models.RENDERED


def light_objects(scene) -> list:
    """Every light object of *scene* (one pass over its objects)."""
    return [o for o in scene.objects if o.type == "LIGHT"]


def scene_lights(scene, view_layer=None, candidates=None):
    """(supported, unsupported) light objects of *scene* that render (F12: hidden in the
    viewport or not), sorted by name; *candidates*: its light objects when the caller already
    has them."""
    view_layer = view_layer or scene.view_layers[0]
    supported, unsupported = [], []
    candidates = light_objects(scene) if candidates is None else candidates
    collections = render_collections(view_layer)
    for obj in sorted(candidates, key=lambda o: o.name):
        if not visible(obj, view_layer, collections):
            continue
        (supported if obj.data.type in SUPPORTED else unsupported).append(obj)
    return supported, unsupported


def synced(scene, view_layer):
    """*view_layer* of *scene* with its objects and layer collections: Blender fills them
    lazily, and a scene just made (a demo scene, a scene of a file no window shows) has none
    until something evaluates its depsgraph, which this does."""
    if view_layer.layer_collection is None:
        with bpy.context.temp_override(scene=scene, view_layer=view_layer):
            bpy.context.evaluated_depsgraph_get().update()
    return view_layer


def render_collections(view_layer) -> frozenset:
    """The pointers of the collections of *view_layer* whose objects render: neither the
    collection nor one above it excluded from the layer or disabled in renders.  The
    viewport's switches (the eye, the monitor) do not matter: a render shows what they hide."""
    found = set()
    root = view_layer.layer_collection
    if root is None:  # a view layer Blender has not synced yet: the scene's collections
        stack = [view_layer.id_data.collection]
        while stack:
            collection = stack.pop()
            if not collection.hide_render:
                found.add(collection.as_pointer())
                stack.extend(collection.children)
        return frozenset(found)
    stack = [root]
    while stack:
        layer = stack.pop()
        if layer.exclude or layer.collection.hide_render:
            continue
        found.add(layer.collection.as_pointer())
        stack.extend(layer.children)
    return frozenset(found)


def visible(obj, view_layer, collections=None) -> bool:
    """Whether *obj* renders in *view_layer* (what F12 shows): not disabled in renders, and in
    a collection that renders (*collections*: ``render_collections(view_layer)`` when the
    caller already has them)."""
    if obj.hide_render:
        return False
    if collections is None:
        collections = render_collections(view_layer)
    return any(c.as_pointer() in collections for c in obj.users_collection)


def instance_of(obj):
    """The collection *obj* instances (Instancing ▸ Collection), else None."""
    return obj.instance_collection if obj.instance_type == "COLLECTION" else None


def instanced_objects(objects, rendering: bool = False, with_objects: bool = False):
    """The objects the collection instances of *objects* bring: each instanced collection's
    objects, each followed by what it instances in turn, then its child collections', at any
    depth, depth first, each object and collection once.  *with_objects*: *objects*
    themselves too, each before what it instances.  *rendering*: what of it renders, a
    collection or object disabled in renders left out with all it holds and instances (the
    visibility of *objects* themselves is the caller's to judge)."""
    seen = set()
    stack = [(obj, True) for obj in reversed(list(objects))]
    while stack:
        item, root = stack.pop()
        pointer = item.as_pointer()
        if pointer in seen or (rendering and not root and item.hide_render):
            continue
        if isinstance(item, bpy.types.Collection):
            seen.add(pointer)
            stack.extend((child, False) for child in reversed(list(item.children)))
            stack.extend((obj, False) for obj in reversed(list(item.objects)))
            continue
        if not root or with_objects:
            seen.add(pointer)
            yield item
        collection = instance_of(item)
        if collection is not None:
            stack.append((collection, False))


def receivers(light_obj):
    """None when *light_obj* reaches every object, else (included, excluded): sets of object
    pointers from its receiver collection."""
    linking = getattr(light_obj, "light_linking", None)
    collection = getattr(linking, "receiver_collection", None) if linking else None
    if collection is None:
        return None
    included, excluded = set(), set()
    for entry, obj in zip(collection.collection_objects, collection.objects):
        (excluded if entry.light_linking.link_state == "EXCLUDE" else included).add(
            obj.as_pointer())
    for entry, child in zip(collection.collection_children, collection.children):
        target = excluded if entry.light_linking.link_state == "EXCLUDE" else included
        target.update(o.as_pointer() for o in child.all_objects)
    return included, excluded


def reaches(rule, obj) -> bool:
    """Whether a light with receivers *rule* lights *obj*."""
    if rule is None:
        return True
    included, excluded = rule
    pointer = obj.as_pointer()
    if pointer in excluded:
        return False
    return pointer in included if included else True


def light_set(obj, lights, rules) -> tuple:
    """The lights of *lights* (a list, with their *rules*) that reach *obj*."""
    return tuple(light for light, rule in zip(lights, rules) if reaches(rule, obj))


def signature(scene, view_layer=None, candidates=None) -> tuple:
    """Everything the lights groups of *scene* are built from, except values that drivers
    carry (transforms, colours, Phong settings): which lights, their types and falloffs
    (``phong_falloff`` chooses nodes), before 5.3 the constants that choose a three.js or X3D
    light's nodes (``properties.facts_of``), and linking."""
    supported, unsupported = scene_lights(scene, view_layer, candidates)
    model = properties.model_of(scene)
    parts = []
    for obj in supported:
        rule = receivers(obj)
        # power_scale: the constant of the i0 driver (an Area light's Normalize and shape);
        # facts_of: the constants that choose its group before 5.3
        facts = properties.facts_of(obj.data, model)
        parts.append((obj.name, obj.data.name, obj.data.type, properties.falloff_of(obj.data),
                      properties.power_scale(obj.data),
                      None if facts is None else tuple(sorted(facts.items())),
                      None if rule is None else (tuple(sorted(rule[0])), tuple(sorted(rule[1])))))
    return (tuple(parts), tuple(o.name for o in unsupported),
            scene.world.name if scene.world else None)
