# SPDX-License-Identifier: GPL-3.0-or-later
"""Differences between the supported Blender versions (4.2 LTS to 5.0), in one place."""

import os
import sys

import bpy

VERSION = bpy.app.version


def exit_process(code: int) -> None:
    """Exit a headless ``bpy`` process with *code*.  The bpy 4.x module can crash in its own
    clean-up at interpreter exit, turning success into signal 11 (bpy 4.2.23: after an Eevee
    render, and whenever a property with Python get/set callbacks was registered, as the
    Light and World Phong settings are): once our files are written and closed, leave
    without running it."""
    sys.stdout.flush()
    sys.stderr.flush()
    if VERSION < (5, 0, 0):
        os._exit(code)
    sys.exit(code)


def eevee_engine() -> str:
    """Eevee's engine id: 'BLENDER_EEVEE_NEXT' in 4.2-4.5, 'BLENDER_EEVEE' again from 5.0."""
    items = bpy.types.RenderSettings.bl_rna.properties["engine"].enum_items.keys()
    return "BLENDER_EEVEE_NEXT" if "BLENDER_EEVEE_NEXT" in items else "BLENDER_EEVEE"


def set_multilayer_exr(image_settings, set_=setattr) -> None:
    """32-bit float multilayer EXR: every pass (AOVs included) in its own part.
    *set_(owner, attribute, value)* does the setting."""
    if hasattr(image_settings, "media_type"):  # 5.0+
        set_(image_settings, "media_type", "MULTI_LAYER_IMAGE")
    set_(image_settings, "file_format", "OPEN_EXR_MULTILAYER")
    set_(image_settings, "color_depth", "32")
    set_(image_settings, "exr_codec", "ZIP")


def set_png(image_settings) -> None:
    if hasattr(image_settings, "media_type"):
        image_settings.media_type = "IMAGE"
    image_settings.file_format = "PNG"
    image_settings.color_mode = "RGB"
    image_settings.color_depth = "8"


def uses_nodes(id_block) -> bool:
    """Whether a material or world draws from its node tree (always from 5.0 on, where
    ``use_nodes`` is deprecated)."""
    return VERSION >= (5, 0, 0) or id_block.use_nodes


def new_material_tree(material):
    """The node tree of a material, switched on where Blender still needs ``use_nodes``."""
    if not uses_nodes(material):
        material.use_nodes = True
    return material.node_tree


def black_world(world) -> None:
    """A world that adds no light and shows black (5.0 gives new worlds a grey Background)."""
    world.color = (0.0, 0.0, 0.0)
    if not uses_nodes(world):
        return
    background = world.node_tree.nodes.get("Background") if world.node_tree else None
    if background is not None:
        background.inputs["Color"].default_value = (0.0, 0.0, 0.0, 1.0)
