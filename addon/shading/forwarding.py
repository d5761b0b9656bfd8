# SPDX-License-Identifier: GPL-3.0-or-later
"""The getter and setter behind ``material.phong.shading``: they forward to the material's
custom property ``phong_shading``.  No ``bpy`` here, directly or indirectly (see
``lighting/forwarding.py`` for why: Blender 4.2 keeps these callbacks alive for ever); the
function that puts a new mode into effect is held by a weak reference."""

import weakref

_on_change = None


def set_callback(callback) -> None:
    """*callback(material)* runs after a material's shading mode changed (None: nothing)."""
    global _on_change
    _on_change = None if callback is None else weakref.ref(callback)


def getter(key, names):
    def get(self):
        value = self.id_data.get(key, names[0])
        return names.index(value) if value in names else 0
    return get


def setter(key, names):
    def set_(self, value):
        material = self.id_data
        new = names[value]
        if material.get(key, names[0]) == new and key in material.keys():
            return
        material[key] = new
        callback = _on_change() if _on_change is not None else None
        if callback is not None:
            callback(material)
    return set_
