# SPDX-License-Identifier: GPL-3.0-or-later
"""Apply Phong Material to what renders: which objects take Phong materials, and one report
of what was converted and what was not.

Every object whose data holds materials that render (meshes, curves, text, surfaces, meta
balls, hair curves, point clouds) takes Phong materials; the objects of a collection that
an Empty instances are converted with it (the collection's own objects, once however often
it is instanced).  An object whose data comes from a library file keeps that data untouched:
its slots take the Phong material on the object (a slot's Link set to Object, put back by
Restore), so the library file is never written.  An object that is itself linked from a
library cannot be changed in this file: it is named in the report with what to do, never
skipped silently.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from . import lights as lights_mod
from . import materials, properties
from . import sync as sync_mod

#: Object types whose data holds materials that render as surfaces.
KINDS = ("MESH", "CURVE", "SURFACE", "FONT", "META", "CURVES", "POINTCLOUD")
#: Why the other types that hold materials take no Phong material.
NOT_SURFACES = {"VOLUME": "a volume (Phong shades surfaces)",
                "GPENCIL": "a Grease Pencil object (its materials are not node materials)",
                "GREASEPENCIL": "a Grease Pencil object (its materials are not node materials)"}
#: Custom property of an object whose slots were switched to Link: Object by Apply (its data
#: is linked from a library): the indices of those slots, which Restore links to the data
#: again.
OBJECT_SLOTS_KEY = "phong_object_slots"


@dataclass
class Report:
    """What one Apply did: *converted* object names, *skipped* (name, why), *materials* (the
    Phong materials given, by name), *lights* (the light objects that drive them), *notes*
    (warnings about the lights and the World)."""

    converted: list = field(default_factory=list)
    skipped: list = field(default_factory=list)
    materials: list = field(default_factory=list)
    lights: list = field(default_factory=list)
    notes: list = field(default_factory=list)
    #: the run's ``sync.Sync`` (its lights, their linking rules, the unsupported lights)
    sync: object = None

    def text(self) -> str:
        """A short summary, a line each."""
        lines = [f"{len(self.converted)} object(s) converted, {len(self.materials)} Phong "
                 f"material(s), {len(self.lights)} light(s)"]
        if self.skipped:
            lines.append(f"not converted ({len(self.skipped)}):")
            lines.extend(f"  {name}: {why}" for name, why in self.skipped)
        lines.extend(self.notes)
        for obj in getattr(self.sync, "unsupported", ()):
            lines.append(f"Light '{obj.name}' ({obj.data.type.title()}) does not drive Phong "
                         "materials")
        return "\n".join(lines)


def why_not(obj) -> str | None:
    """Why *obj* cannot take Phong materials in this file, or None when it can."""
    if obj.type in NOT_SURFACES:
        return NOT_SURFACES[obj.type]
    if obj.type not in KINDS or not hasattr(obj.data, "materials"):
        return None  # no materials to convert (an Empty, a light, an armature ...)
    if obj.library is not None:
        return (f"linked from the library '{obj.library.filepath}': make it local or a "
                "library override (Object ▸ Library Override) to convert it")
    return None


def expand(objects) -> tuple:
    """(the objects of *objects* that can take Phong materials, with the objects of the
    collections their Empties instance; [(name, why)] of those that cannot), each once."""
    found, skipped, seen = [], [], set()
    stack = list(objects)[::-1]
    visited_collections = set()
    while stack:
        obj = stack.pop()
        pointer = obj.as_pointer()
        if pointer in seen:
            continue
        seen.add(pointer)
        collection = obj.instance_collection if obj.instance_type == "COLLECTION" else None
        if collection is not None and collection.as_pointer() not in visited_collections:
            visited_collections.add(collection.as_pointer())
            stack.extend(reversed(list(collection.all_objects)))
        why = why_not(obj)
        if why is not None:
            skipped.append((obj.name, why))
        elif obj.type in KINDS:
            found.append(obj)
    return found, skipped


def rendered_objects(scene, view_layer=None) -> list:
    """The objects of *scene* that render in *view_layer* (default its first that renders)."""
    view_layer = view_layer or next((v for v in scene.view_layers if v.use),
                                    scene.view_layers[0])
    view_layer = lights_mod.synced(scene, view_layer)
    collections = lights_mod.render_collections(view_layer)
    return [obj for obj in view_layer.objects if lights_mod.visible(obj, view_layer, collections)]


def _link_slots_to_object(obj) -> None:
    """Slots of *obj* whose data is a library's: Link set to Object, holding the data's
    material, so that Apply writes the object (remembered for Restore)."""
    if obj.data is None or obj.data.library is None:
        return
    switched = list(obj.get(OBJECT_SLOTS_KEY, []))
    for index, slot in enumerate(obj.material_slots):
        if slot.link == "DATA":
            material = slot.material
            slot.link = "OBJECT"
            slot.material = material
            switched.append(index)
    if switched:
        obj[OBJECT_SLOTS_KEY] = sorted(set(switched))


def unlink_slots(obj) -> None:
    """Restore's side of ``_link_slots_to_object``: the slots Apply linked to the object
    are linked to the data again (their object material cleared)."""
    switched = obj.get(OBJECT_SLOTS_KEY)
    if not switched:
        return
    slots = obj.material_slots
    for index in switched:
        if index < len(slots) and slots[index].link == "OBJECT":
            slots[index].material = None
            slots[index].link = "DATA"
    del obj[OBJECT_SLOTS_KEY]


def apply(scene, objects=None, view_layer=None) -> Report:
    """Give Phong materials to *objects* of *scene* (None: every object that renders), and
    to the objects of the collections their Empties instance; returns the :class:`Report`.
    Objects with no material slot get one."""
    report = Report()
    if objects is None:
        objects = rendered_objects(scene, view_layer)
    targets, report.skipped = expand(objects)
    done = {}
    if not targets:
        return report
    for obj in targets:
        if obj.data.library is not None and not obj.material_slots:
            report.skipped.append((obj.name, "its data, linked from a library, has no "
                                             "material slot"))
    targets = [o for o in targets if o.data.library is None or o.material_slots]
    for obj in targets:
        _link_slots_to_object(obj)
    world = scene.world
    world_new = world is not None and properties.AMBIENT_INTENSITY[0] not in world.keys()
    with sync_mod.session(scene, view_layer) as sync:
        sync.prepare(targets)
        for obj in targets:
            for material in sync.apply(obj):
                done[material.name] = None
            report.converted.append(obj.name)
    report.materials = list(done)
    report.lights = [o.name for o in sync.lights]
    report.notes = notes(scene, sync.lights, world_new)
    report.sync = sync
    return report


def notes(scene, lights, world_new=False) -> list:
    """Warnings about how *scene*'s lights and World become Phong light: an Area light's
    far field where it is coarse (a spread below 180°, a light large for the scene), and
    (*world_new*: the World took its Phong ambient light now) a World whose light Phong's
    uniform ambient light only approximates."""
    out = []
    corners = None  # the scene's box corners, read once for every Area light
    for obj in lights:
        light = obj.data
        if light.type != "AREA":
            continue
        if corners is None:
            corners = _box_corners(scene)
        if light.spread < 3.14159:
            out.append(f"Area light '{obj.name}': its Spread ({light.spread * 57.2958:.0f}°) "
                       "narrows and brightens its beam, which the Phong light (a Lambertian "
                       "emitter's far field, a 180° cone) does not follow")
        size = max(light.size, light.size_y if light.shape in ("RECTANGLE", "ELLIPSE") else 0.0)
        origin = np.array(obj.matrix_world.translation)
        distance = (float(np.sqrt(((corners - origin) ** 2).sum(axis=1)).min())
                    if len(corners) else None)
        if distance is not None and size > 0.1 * distance:
            out.append(f"Area light '{obj.name}': {size:.3g} m across, {distance:.3g} m from "
                       "the nearest object: Phong draws it as a point emitter, exact from "
                       "10 times its size on")
    if world_new and scene.world is not None:
        _intensity, _color, note = properties.world_light(scene.world)
        if note:
            out.append(note)
    return out


def _box_corners(scene) -> np.ndarray:
    """The world corners (N, 3) of the bounding boxes of *scene*'s objects with materials."""
    parts = []
    for obj in scene.objects:
        if obj.type in KINDS:
            matrix = np.array(obj.matrix_world)
            box = np.array([tuple(c) for c in obj.bound_box])
            parts.append(box @ matrix[:3, :3].T + matrix[:3, 3])
    return np.concatenate(parts) if parts else np.zeros((0, 3))


def restore(obj, names=None) -> int:
    """Restore Original Materials on *obj*: the source materials back in its slots, and the
    slots Apply linked to the object linked to the data again; returns how many slots."""
    changed = materials.restore(obj, names)
    if obj.get(OBJECT_SLOTS_KEY):
        unlink_slots(obj)
    return changed


__all__ = ["KINDS", "Report", "apply", "expand", "notes", "rendered_objects", "restore",
           "why_not"]
