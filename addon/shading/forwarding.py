# SPDX-License-Identifier: GPL-3.0-or-later
"""The getters and setters behind ``material.phong.shading`` (they forward to the material's
custom property ``phong_shading``) and ``material.phong.opacity`` (the Opacity control node).  No ``bpy`` here, directly or indirectly (see
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
        # the upward call: shading.modes.update (addon/__init__.py, connect)
        callback = _on_change() if _on_change is not None else None
        if callback is not None:
            callback(material)
    return set_


_on_opacity = None


def set_opacity_callback(callback) -> None:
    """*callback(material, value)* sets a material's Opacity (``lighting.opacity.set_opacity``;
    None: nothing)."""
    global _on_opacity
    _on_opacity = None if callback is None else weakref.ref(callback)


def opacity_getter(node_name):
    def get(self):
        tree = self.id_data.node_tree
        node = tree.nodes.get(node_name) if tree is not None else None
        # the Value node's output by identifier (compat.value_output, which imports bpy)
        value = next((s for s in node.outputs if s.identifier == "Value"), None) \
            if node is not None else None
        return float(value.default_value) if value is not None else 1.0
    return get


def opacity_setter():
    def set_(self, value):
        # lighting.opacity.set_opacity (addon/__init__.py, connect)
        callback = _on_opacity() if _on_opacity is not None else None
        if callback is not None:
            callback(self.id_data, value)
    return set_
