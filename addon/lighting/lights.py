# SPDX-License-Identifier: GPL-3.0-or-later
"""Which Blender lights drive Phong materials, and which objects each light reaches.

* :func:`scene_lights`: the scene's Point, Sun and Spot lights that render (visible in the
  view layer, not disabled in renders), and the other lights (Area) that cannot drive Phong.
* :func:`light_set`: the lights that reach one object under Blender's Light Linking (a
  light's ``light_linking.receiver_collection``): with no collection the light reaches
  every object; otherwise only the included objects if there are any, minus the excluded
  ones (Blender manual, Light Linking ▸ Include & Exclude).  An object inside a child
  collection of the receiver collection takes the link state of that child collection.
* :func:`signature`: a cheap fingerprint of everything above, so a depsgraph handler can
  tell in microseconds that nothing changed.
"""

from __future__ import annotations

from ...node_groups import models

#: The light types that drive Phong materials (each model has a light group for each:
#: ``node_groups/models.py``).
SUPPORTED = models.EVERY


def light_objects(scene) -> list:
    """Every light object of *scene* (one pass over its objects)."""
    return [o for o in scene.objects if o.type == "LIGHT"]


def scene_lights(scene, view_layer=None, candidates=None):
    """(supported, unsupported) light objects of *scene* that render, sorted by name;
    *candidates*: its light objects when the caller already has them."""
    view_layer = view_layer or scene.view_layers[0]
    supported, unsupported = [], []
    candidates = light_objects(scene) if candidates is None else candidates
    for obj in sorted(candidates, key=lambda o: o.name):
        if obj.hide_render or not visible(obj, view_layer):
            continue
        (supported if obj.data.type in SUPPORTED else unsupported).append(obj)
    return supported, unsupported


def visible(obj, view_layer) -> bool:
    """Whether *obj* is visible in *view_layer*."""
    try:
        return obj.visible_get(view_layer=view_layer)
    except (TypeError, RuntimeError):
        return not obj.hide_get()


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
    (``phong_falloff`` chooses nodes), and linking."""
    supported, unsupported = scene_lights(scene, view_layer, candidates)
    parts = []
    for obj in supported:
        rule = receivers(obj)
        parts.append((obj.name, obj.data.name, obj.data.type, obj.data.get("phong_falloff"),
                      None if rule is None else (tuple(sorted(rule[0])), tuple(sorted(rule[1])))))
    return (tuple(parts), tuple(o.name for o in unsupported),
            scene.world.name if scene.world else None)
