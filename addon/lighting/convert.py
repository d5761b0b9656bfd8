# SPDX-License-Identifier: GPL-3.0-or-later
"""Apply Phong Material to what renders: which objects take Phong materials, and one report
of what was converted and what was not.

Every object whose data holds materials that render (meshes, curves, text, surfaces, meta
balls, hair curves, point clouds) takes Phong materials; the objects of a collection that
an Empty instances are converted with it (the collection's own objects, once however often
it is instanced).  An object whose data comes from a library file keeps that data untouched:
its slots take the Phong material on the object (a slot's Link set to Object, put back by
Restore), so the library file is never written.  An object that is itself linked from a
library is converted through a library override of it (``override_linked``): an object
linked into the scene's collections gets one in its place; a collection of a library that
an Empty instances gets one of its hierarchy, which the Empty then instances.  Restore drops
those overrides again (``drop_overrides``): the Empty instances the library's collection, the
scene holds the linked object, exactly as before.  What cannot be overridden is named in the
report with what to do, never skipped silently.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import bpy
import numpy as np

from ...core.wording import name_list
from . import lights as lights_mod
from . import properties, recipe, sources
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
#: Custom property of an Empty whose instanced collection, linked from a library, Apply
#: replaced by a library override of it (Restore points the Empty back and drops the
#: override).  Kept on the Empty, which is this file's own: a library override's own custom
#: properties do not survive a reload.
INSTANCE_OVERRIDE_KEY = "phong_instance_override"
#: Custom property of a scene: {n: object}, the library overrides that Apply made of the
#: objects linked into that scene, which Restore drops (linking the library's object back).
OBJECT_OVERRIDES_KEY = "phong_object_overrides"


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
        return (f"linked from the library '{obj.library.filepath}', and Blender made no "
                "library override of it here: make it local (Object ▸ Relations ▸ Make "
                "Local) to convert it")
    return None


def expand(objects) -> tuple:
    """(the objects of *objects* that can take Phong materials, with the objects of the
    collections their Empties instance; [(name, why)] of those that cannot), each once."""
    found, skipped = [], []
    for obj in lights_mod.instanced_objects(objects, with_objects=True):
        why = why_not(obj)
        if why is not None:
            skipped.append((obj.name, why))
        elif obj.type in KINDS:
            found.append(obj)
    return found, skipped


def _rendering_layer(scene):
    """*scene*'s first view layer that renders (its first where none does)."""
    return next((v for v in scene.view_layers if v.use), scene.view_layers[0])


def rendered_objects(scene, view_layer=None) -> list:
    """The objects of *scene* that render in *view_layer* (default its first that renders)."""
    view_layer = view_layer or _rendering_layer(scene)
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


def _switched_slots(obj) -> list:
    """The slots of *obj* that Apply linked to the object: its record, or, for a library
    override whose record a reload dropped (an override keeps no custom property its library's
    object lacks), every slot linked to the object that holds what its library data's slot
    holds (after Restore: the source material), which linked to the data shows the same."""
    switched = obj.get(OBJECT_SLOTS_KEY)
    if switched:
        return list(switched)
    data = obj.data
    if obj.override_library is None or data is None or data.library is None:
        return []
    materials = getattr(data, "materials", ())
    return [index for index, slot in enumerate(obj.material_slots)
            if slot.link == "OBJECT" and index < len(materials)
            and slot.material is not None and slot.material == materials[index]]


def unlink_slots(obj) -> None:
    """Restore's side of ``_link_slots_to_object``: the slots Apply linked to the object
    are linked to the data again (their object material cleared)."""
    switched = _switched_slots(obj)
    slots = obj.material_slots
    for index in switched:
        if index < len(slots) and slots[index].link == "OBJECT":
            slots[index].material = None
            slots[index].link = "DATA"
    if OBJECT_SLOTS_KEY in obj.keys():
        del obj[OBJECT_SLOTS_KEY]


def apply(scene, objects=None, view_layer=None) -> Report:
    """Give Phong materials to *objects* of *scene* (None: every object that renders), and
    to the objects of the collections their Empties instance; returns the :class:`Report`.
    Objects with no material slot get one."""
    report = Report()
    if objects is None:
        objects = rendered_objects(scene, view_layer)
    objects = override_linked(scene, objects, view_layer)
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
    report.notes = (notes(scene, sync.lights, world_new) + ambient_note(sync.ambient_linked)
                    + engine_notes(bpy.data.materials.get(name) for name in done))
    for note in AFTER_APPLY:  # an upward call: scene.describe.hollow_notes (addon/__init__.py)
        report.notes += note(scene, view_layer, targets)
    report.sync = sync
    return report


#: An upward call: callables ``note(scene, view_layer, objects) -> [line]`` whose lines
#: Apply's report adds (``addon/__init__.py``, ``connect``: ``scene.describe.hollow_notes``,
#: the converted objects that render no Phong surface), so that lighting imports none of it.
AFTER_APPLY: list = []


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


def engine_notes(materials, compared: bool = False) -> list:
    """Lines naming what *materials* read that Blender's engines read differently: images
    that are missing (``recipe.missing_images``: Cycles magenta, Eevee black) and Attribute
    nodes without a name (``recipe.unnamed_attributes``: Cycles 0, Eevee the active colour
    attribute); *compared*: worded for a comparison with Eevee, whose picture differs there."""
    materials = list(materials)
    out = []
    missing = recipe.missing_images(materials)
    if missing:
        out.append(f"missing image(s): {name_list(missing, quote=False)}: Cycles shows a "
                   "missing image magenta, Eevee black" + (
                       ", so Eevee's picture differs there" if compared else
                       "; give each node its image (File > External Data > Find Missing "
                       "Files for moved files)"))
    unnamed = recipe.unnamed_attributes(materials)
    if unnamed:
        out.append(f"Attribute node(s) without a name: {name_list(unnamed, quote=False)}: "
                   "Cycles reads 0 there, Eevee the active colour attribute" + (
                       ", so Eevee's picture differs there" if compared else
                       "; give each the attribute's name"))
    return out


def ambient_note(linked) -> list:
    """One line naming the source materials whose ambient colour (what their Principled
    specular layer adds under the World) read an input that a node feeds at the input's own
    value ([(material name, input names)]); none when there are none."""
    if not linked:
        return []
    names = sorted({name for name, _inputs in linked})
    inputs = sorted({i for _name, found in linked for i in found})
    shown = name_list(names, limit=5)
    return [f"Ambient colour of {len(names)} material(s) ({shown}): {', '.join(inputs)} "
            "fed by nodes, read at the input's own value (the Phong ambient does not follow "
            "the texture)"]


def _box_corners(scene) -> np.ndarray:
    """The world corners (N, 3) of the bounding boxes of *scene*'s objects with materials."""
    parts = []
    for obj in scene.objects:
        if obj.type in KINDS:
            matrix = np.array(obj.matrix_world)
            box = np.array([tuple(c) for c in obj.bound_box])
            parts.append(box @ matrix[:3, :3].T + matrix[:3, 3])
    return np.concatenate(parts) if parts else np.zeros((0, 3))


# -- library overrides ---------------------------------------------------------------------

def _has_surfaces(collection) -> bool:
    return any(o.type in KINDS for o in collection.all_objects)


def override_linked(scene, objects, view_layer=None) -> list:
    """*objects* with what is linked from a library made convertible in this file: an object
    linked into the scene replaced by a library override of it (registered in the scene's
    ``OBJECT_OVERRIDES_KEY``), and each Empty of *objects* that instances a library's
    collection made to instance a library override of that collection's hierarchy (one per
    collection, ``INSTANCE_OVERRIDE_KEY`` on the Empty).  The library files are not written.
    What Blender cannot override stays as it is (``why_not`` names it)."""
    view_layer = view_layer or _rendering_layer(scene)
    out, by_collection = [], {}
    for obj in objects:
        collection = lights_mod.instance_of(obj)
        if (obj.library is None and collection is not None and collection.library is not None
                and _has_surfaces(collection)):
            by_collection.setdefault(collection.as_pointer(), (collection, []))[1].append(obj)
        if (obj.library is not None and obj.type in KINDS
                and any(c.library is None for c in obj.users_collection)):
            override = _override_object(scene, obj)
            out.append(override if override is not None else obj)
        else:
            out.append(obj)
    for collection, empties in by_collection.values():
        _override_instanced(scene, view_layer, collection, empties)
    return out


def _override_object(scene, obj):
    """A library override of the linked *obj* in its place in this file's collections (None
    where Blender makes none)."""
    try:
        override = obj.override_create(remap_local_usages=True)
    except (RuntimeError, TypeError):
        override = None
    if override is None:
        return None
    registered = scene.get(OBJECT_OVERRIDES_KEY)
    if registered is None:
        scene[OBJECT_OVERRIDES_KEY] = {}
        registered = scene[OBJECT_OVERRIDES_KEY]
    registered[str(max((int(k) for k in registered.keys()), default=-1) + 1)] = override
    return override


def _override_instanced(scene, view_layer, collection, empties) -> None:
    """The Empties *empties* made to instance a library override of the library's
    *collection* (its whole hierarchy), which no collection of the scene holds."""
    try:
        override = collection.override_hierarchy_create(scene, view_layer, reference=empties[0])
    except (RuntimeError, TypeError):
        override = None
    if override is None:
        return
    for parent in [scene.collection, *scene.collection.children_recursive]:
        if parent.library is None and override.name in parent.children \
                and parent.children[override.name] == override:
            parent.children.unlink(override)
    for empty in empties:
        empty.instance_collection = override
        empty[INSTANCE_OVERRIDE_KEY] = 1


def drop_overrides(scene, objects) -> int:
    """Restore's side of ``override_linked`` for *objects* (Empties and overridden objects
    among them): each Empty instances the library's collection again, each object override
    gives its place back to the library's object; an override nothing uses any more is
    removed.  Returns how many were dropped."""
    dropped = 0
    registered = scene.get(OBJECT_OVERRIDES_KEY) or {}
    made = {value.as_pointer(): key for key, value in registered.items() if value is not None}
    for obj in objects:
        collection = lights_mod.instance_of(obj)
        if obj.get(INSTANCE_OVERRIDE_KEY) and collection is not None \
                and collection.override_library is not None:
            obj.instance_collection = collection.override_library.reference
            del obj[INSTANCE_OVERRIDE_KEY]
            if collection.users == 0:
                _remove_hierarchy(collection)
            dropped += 1
        elif obj.as_pointer() in made and obj.override_library is not None:
            del registered[made.pop(obj.as_pointer())]
            obj.user_remap(obj.override_library.reference)
            bpy.data.objects.remove(obj)
            dropped += 1
    return dropped


def _remove_hierarchy(collection) -> None:
    """Remove the library override *collection*, its child collections and the objects that
    only they hold."""
    collections = [collection, *collection.children_recursive]
    inside = {c.as_pointer() for c in collections}
    for obj in list(collection.all_objects):
        if obj.override_library is not None and all(
                c.as_pointer() in inside for c in obj.users_collection):
            bpy.data.objects.remove(obj)
    for child in collections[::-1]:
        if child.override_library is not None:
            bpy.data.collections.remove(child)


def restore(obj, names=None) -> int:
    """Restore Original Materials on *obj*: the source materials back in its slots, and the
    slots Apply linked to the object linked to the data again; returns how many slots."""
    changed = sources.restore(obj, names)
    unlink_slots(obj)
    return changed


__all__ = ["KINDS", "Report", "ambient_note", "apply", "drop_overrides", "expand", "notes",
           "override_linked", "rendered_objects", "restore", "why_not"]
