# SPDX-License-Identifier: GPL-3.0-or-later
"""Which scene a lights group belongs to, which light set it stands for and which highlight
it draws: the custom properties every lights group carries, and the look-ups on them.
Apart from ``rig.py`` (which writes the groups) so that the modules ``rig`` imports
(``shadows``) can find a scene's groups without importing it back."""

from __future__ import annotations

import bpy

from ...node_groups import library

#: Custom properties of a lights group: the scene it belongs to (an ID pointer) and its
#: light set.
SCENE_KEY = "phong_lights_scene"
SET_KEY = "phong_lights_set"
#: The highlight its light groups draw (``library.HIGHLIGHTS``): the blend by the material's
#: Blinn, or Phong's or Blinn-Phong's alone; a group without it (written before the variants)
#: blends.
HIGHLIGHT_KEY = "phong_lights_highlight"


def owner(tree):
    """The scene a lights group belongs to (an ID pointer: it follows a renamed scene), or
    None (its scene was deleted)."""
    scene = tree.get(SCENE_KEY)
    return scene if isinstance(scene, bpy.types.Scene) else None


def groups_of(scene) -> list:
    """The lights groups of *scene* (local ones)."""
    return [t for t in bpy.data.node_groups if t.library is None and owner(t) == scene]


def highlight_of(tree) -> str:
    """The highlight a lights group draws (``HIGHLIGHT_KEY``)."""
    return tree.get(HIGHLIGHT_KEY) or library.BLEND


def find(scene, key: str, highlight: str = library.BLEND):
    """The lights group of *scene* for the light set *key* and *highlight*, or None."""
    for tree in groups_of(scene):
        if tree.get(SET_KEY) == key and highlight_of(tree) == highlight:
            return tree
    return None


__all__ = ["HIGHLIGHT_KEY", "SCENE_KEY", "SET_KEY", "find", "groups_of", "highlight_of",
           "owner"]
