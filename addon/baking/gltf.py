# SPDX-License-Identifier: GPL-3.0-or-later
"""glTF with Baked Phong Lighting: the objects' bakes shown by their unlit display materials
(``show.py``: a Background shader of the baked image or colour attribute) and written by
Blender's own glTF exporter, which turns that pattern into KHR_materials_unlit with the baked
texture as baseColorTexture or the colour attribute as COLOR_0.  Every glTF viewer shows
unlit colours as they are, so the file shows the Phong look exactly (up to 8 bits)."""

from __future__ import annotations

import os

import bpy

from . import lighting, show

#: Options of Blender's glTF exporter, by name; those a Blender release lacks are left out
#: (4.2 to 5.2 differ: export_vertex_color replaced export_colors).
OPTIONS = {
    "use_selection": True, "export_cameras": True, "export_lights": False,
    "export_materials": "EXPORT", "export_apply": True, "export_yup": True,
    "export_vertex_color": "MATERIAL", "export_all_vertex_colors": False,
    "export_active_vertex_color_when_no_material": False, "export_colors": True,
    "export_image_format": "AUTO", "export_extras": False,
}


def exporter_options(filepath: str) -> dict:
    known = {p.identifier for p in bpy.ops.export_scene.gltf.get_rna_type().properties}
    options = {key: value for key, value in OPTIONS.items() if key in known}
    options["export_format"] = "GLB" if filepath.lower().endswith(".glb") else "GLTF_SEPARATE"
    return options


def _has_bake(obj) -> bool:
    """Whether *obj* has a bake (image or colour attribute) that can be reused."""
    info = obj.get(lighting.INFO_KEY)
    if info is None:
        return False
    if info.get("target") == "IMAGE":
        return isinstance(obj.get(lighting.IMAGE_KEY), bpy.types.Image)
    return obj.data.color_attributes.get(lighting.ATTRIBUTE) is not None


def export(filepath: str, scene, objects, settings, rebake=True, progress=None) -> dict:
    """Bake *objects* (or, with *rebake* off, reuse the bake each has, of either kind, and
    bake the others as *settings* say), show the bakes,
    write the glTF file through Blender's exporter (the camera included), and put back the
    Phong materials of the objects that were not showing their bakes.  Returns
    {"path", "baked": [names], "warnings"}."""
    objects, warnings = lighting.check(scene, objects, settings)
    todo = [o for o in objects if rebake or not _has_bake(o)]
    if todo:
        _results, more = show.bake_objects(scene, todo, settings, progress)
        warnings += more
    shown_before = {o.name for o in objects if show.is_shown(o)}
    selection = {o.name: o.select_get() for o in scene.objects}
    active = bpy.context.view_layer.objects.active
    folder = os.path.dirname(os.path.abspath(filepath))
    os.makedirs(folder, exist_ok=True)
    try:
        for obj in objects:
            show.show(obj)
        for obj in scene.objects:
            obj.select_set(obj in objects or obj == scene.camera)
        result = bpy.ops.export_scene.gltf(filepath=os.path.abspath(filepath),
                                           **exporter_options(filepath))
        if result != {"FINISHED"}:
            raise lighting.BakeError(f"Blender's glTF exporter did not finish {filepath}")
    finally:
        for obj in objects:
            if obj.name not in shown_before:
                show.restore(obj)
        for name, selected in selection.items():
            if name in scene.objects:
                scene.objects[name].select_set(selected)
        bpy.context.view_layer.objects.active = active
    return {"path": os.path.abspath(filepath), "baked": [o.name for o in todo],
            "warnings": warnings}
