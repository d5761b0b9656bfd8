# SPDX-License-Identifier: GPL-3.0-or-later
"""``material.phong``: ``shading`` (Per Pixel, Per Vertex, Per Face; stored as the material's
custom property ``phong_shading``, so a file keeps it without the extension) and ``opacity``
(the Opacity control node, switching the material's transparency as it is set)."""

import bpy
from bpy.props import EnumProperty, FloatProperty, PointerProperty

from ..lighting import recipe
from . import forwarding, modes

SHADING_ITEMS = (
    ("PIXEL", "Per Pixel", "The model evaluated at every pixel (Phong shading)"),
    ("VERTEX", "Per Vertex", "The model evaluated at every vertex and the colour interpolated "
     "across each face (Gouraud shading); live, in the shader"),
    ("FACE", "Per Face", "The model evaluated once per face, at its centre with its normal "
     "(flat shading); live, in the shader"),
)


class PhongMaterialSettings(bpy.types.PropertyGroup):
    """Phong settings of a material (stored as custom properties of the material)"""

    shading: EnumProperty(
        name="Shading", items=SHADING_ITEMS,
        get=forwarding.getter(modes.SHADING_KEY, modes.MODES),
        set=forwarding.setter(modes.SHADING_KEY, modes.MODES),
        description="Where the Phong model is evaluated: at every pixel, at every vertex "
                    "(interpolated across faces) or once per face")
    opacity: FloatProperty(
        name="Opacity", min=0.0, max=1.0, default=1.0, subtype="FACTOR",
        get=forwarding.opacity_getter(recipe.OPACITY), set=forwarding.opacity_setter(),
        description="Opacity × Phong colour + (1 − opacity) × what is behind (the Opacity "
                    "control node; below 1 the material blends)")


def register():
    # what a set value calls (forwarding's callbacks) is set by addon/__init__.py (connect)
    bpy.utils.register_class(PhongMaterialSettings)
    bpy.types.Material.phong = PointerProperty(type=PhongMaterialSettings)


def unregister():
    del bpy.types.Material.phong
    bpy.utils.unregister_class(PhongMaterialSettings)
