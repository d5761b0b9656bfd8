# SPDX-License-Identifier: GPL-3.0-or-later
"""The getters and setters behind ``light.phong``, ``world.phong`` and ``scene.phong``: each
forwards to an ID custom property (see ``properties``).

This module must never hold ``bpy``, directly or through another module or function: Blender
4.2 keeps the Python callbacks of a registered PropertyGroup's properties alive for ever
(unregistering the class does not free them), and when their globals lead to the ``bpy``
module, that module is never freed at interpreter exit, so Blender's own clean-up runs from a
C destructor after Python has gone and crashes: a user's script that enabled the extension and
ended normally exited with signal 11 (139).  Globals free of ``bpy`` break that chain; the
callback handed down for the model switch is held by a weak reference for the same reason.
"""

import weakref


def float_getter(key, default):
    def get(self):
        value = self.id_data.get(key, default)
        try:
            return float(value)
        except (TypeError, ValueError):
            return default
    return get


def float_setter(key, also=None):
    """Set the custom property *key*; *also*: (key, value) written with it (a Phong
    Intensity set becomes the light's own i0: ``properties.FROM_POWER_KEY`` 0)."""
    def set_(self, value):
        self.id_data[key] = float(value)
        if also is not None:
            self.id_data[also[0]] = also[1]
        self.id_data.update_tag()  # drivers read the evaluated copy: tag it
    return set_


def flag(id_block, key, absent_key) -> bool:
    """The int custom property *key* of *id_block* as a bool; unset: True unless *absent_key*
    is set (``properties.from_power``: a light follows its Power unless it has an i0)."""
    value = id_block.get(key)
    if value is None:
        return absent_key not in id_block.keys()
    try:
        return bool(int(value))
    except (TypeError, ValueError):
        return True


def bool_getter(key, absent_key):
    """The getter of ``flag``."""
    def get(self):
        return flag(self.id_data, key, absent_key)
    return get


def int_setter(key):
    def set_(self, value):
        self.id_data[key] = int(bool(value))
        self.id_data.update_tag()
    return set_


def color_getter(key, default):
    def get(self):
        value = self.id_data.get(key, default)
        try:
            return tuple(float(c) for c in value[:3])
        except (TypeError, ValueError):
            return default
    return get


def color_setter(key):
    def set_(self, value):
        self.id_data[key] = [float(c) for c in value[:3]]
        self.id_data.update_tag()
    return set_


#: An upward call: a weak reference to the function called with the scene after its model
#: changed, ``lighting.sync.relink_scene`` (set by ``addon/__init__.py``, ``connect``).
_on_model_change = None


def set_model_callback(callback) -> None:
    """*callback(scene)* runs after a scene's Lighting Model changed (None: nothing runs)."""
    global _on_model_change
    _on_model_change = None if callback is None else weakref.ref(callback)


def enum_getter(key, names):
    """The index in *names* of the custom property *key* (its first name when unset)."""
    def get(self):
        value = self.id_data.get(key, names[0])
        return names.index(value) if value in names else 0
    return get


def string_setter(key, names):
    """Set the custom property *key* to the name of the enum item (the depsgraph handler
    relinks the scene when the name changes the lights groups)."""
    def set_(self, value):
        if self.id_data.get(key) == names[value]:
            return
        self.id_data[key] = names[value]
        self.id_data.update_tag()
    return set_


def model_setter(key, names):
    """Set the model name; a change runs the callback of ``set_model_callback``."""
    def set_(self, value):
        scene = self.id_data
        new = names[value]
        if scene.get(key, names[0]) == new:
            return
        scene[key] = new
        # the upward call: lighting.sync.relink_scene (addon/__init__.py, connect)
        callback = _on_model_change() if _on_model_change is not None else None
        if callback is not None:
            callback(scene)
    return set_
