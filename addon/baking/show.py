# SPDX-License-Identifier: GPL-3.0-or-later
"""Show a bake with an unlit material, and put the Phong material back.

*Show* gives every slot of an object that holds a Phong material the object's display
material ``Phong Bake <object>``: a Background shader (unlit: what Blender's glTF exporter
writes as KHR_materials_unlit) of the baked image (through the UV map) or of the colour
attribute ``Phong Bake``.  The Phong materials are kept on the object (``phong_bake_slots``:
ID pointers, so they stay in the file) and *restore* puts them back and removes the display
material.  Showing again rebuilds the display material in place (one per object)."""

from __future__ import annotations

import bpy

from .. import compat
from . import lighting

DISPLAY_KEY = "phong_bake_display"


def display_name(obj) -> str:
    return f"Phong Bake {obj.name}"


def is_shown(obj) -> bool:
    return obj.get(lighting.SLOTS_KEY) is not None


def _display_material(obj):
    info = obj.get(lighting.INFO_KEY)
    if info is None:
        raise lighting.BakeError(f"{obj.name!r} has no Phong bake: bake it first")
    material = obj.get(DISPLAY_KEY)
    if not isinstance(material, bpy.types.Material):
        material = bpy.data.materials.new(display_name(obj))
        obj[DISPLAY_KEY] = material
    tree = compat.new_material_tree(material)
    tree.nodes.clear()
    output = tree.nodes.new("ShaderNodeOutputMaterial")
    output.location = (300.0, 0.0)
    background = tree.nodes.new("ShaderNodeBackground")
    background.inputs["Strength"].default_value = 1.0
    tree.links.new(compat.output_socket(background, "Background"), output.inputs["Surface"])
    if info["target"] == "IMAGE":
        image = obj.get(lighting.IMAGE_KEY)
        if not isinstance(image, bpy.types.Image):
            raise lighting.BakeError(f"{obj.name!r}: its baked image is gone: bake it again")
        source = tree.nodes.new("ShaderNodeTexImage")
        source.image = image
        source.interpolation = "Linear"
    else:
        if obj.data.color_attributes.get(lighting.ATTRIBUTE) is None:
            raise lighting.BakeError(f"{obj.name!r}: its colour attribute "
                                     f"{lighting.ATTRIBUTE!r} is gone: bake it again")
        source = tree.nodes.new("ShaderNodeVertexColor")
        source.layer_name = lighting.ATTRIBUTE
    source.location = (-300.0, 0.0)
    tree.links.new(source.outputs["Color"], background.inputs["Color"])
    material[DISPLAY_KEY] = 1
    return material


def show(obj) -> int:
    """Switch the Phong slots of *obj* to its display material; returns the slots changed."""
    material = _display_material(obj)
    kept = dict(obj.get(lighting.SLOTS_KEY) or {})
    changed = 0
    for index, slot in enumerate(obj.material_slots):
        phong = lighting.phong_material(obj, index)
        if phong is None:
            continue
        kept[str(index)] = phong
        if slot.material is not material:
            slot.material = material
            changed += 1
    obj[lighting.SLOTS_KEY] = kept
    return changed


def restore(obj) -> int:
    """Put the Phong materials back on *obj* and remove its display material; returns the
    slots changed."""
    kept = obj.get(lighting.SLOTS_KEY)
    changed = 0
    if kept is not None:
        for key, phong in kept.items():
            index = int(key)
            if index < len(obj.material_slots) and isinstance(phong, bpy.types.Material):
                obj.material_slots[index].material = phong
                changed += 1
        del obj[lighting.SLOTS_KEY]
    material = obj.get(DISPLAY_KEY)
    if DISPLAY_KEY in obj.keys():
        del obj[DISPLAY_KEY]
    if isinstance(material, bpy.types.Material) and material.users == 0:
        bpy.data.materials.remove(material)
    return changed


def refresh(obj) -> None:
    """After a new bake: a shown object shows the new one (image or attribute)."""
    if is_shown(obj):
        show(obj)


def bake_objects(scene, objects, settings, progress=None, display=False) -> tuple:
    """Bake Phong Lighting (``lighting.bake``) and keep what shows it current: an object
    already showing its bake shows the new one; *display*: show it on every baked object.
    Returns (results, warnings)."""
    results, warnings = lighting.bake(scene, objects, settings, progress)
    for result in results:
        obj = scene.objects[result["object"]]
        if display:
            show(obj)
        else:
            refresh(obj)
    return results, warnings
