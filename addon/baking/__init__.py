# SPDX-License-Identifier: GPL-3.0-or-later
"""Baking the Phong look into images and colour attributes (``lighting``), showing the bake
with an unlit material and putting the Phong material back (``show``), and glTF export of the
bake through Blender's own exporter (``gltf``)."""
