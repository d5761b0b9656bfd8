# SPDX-License-Identifier: GPL-3.0-or-later
"""Drivers from lights and the world to node inputs, without any Python expression.

Every driver is either an AVERAGE driver with one variable (a TRANSFORMS channel or a
SINGLE_PROP custom property / colour channel / world-matrix entry) or a SCRIPTED driver of a
simple expression (``v * k``, a light's i0, its colour, a unit axis) that Blender evaluates
itself (``driver.is_simple_expression`` is True), so Phong materials follow their lights with
"Auto Run Python Scripts" off and without the extension.
"""

import bpy

def _fresh(socket, index):
    """A new driver F-curve on socket.default_value[index] (or the scalar), emptied."""
    args = ("default_value",) if index is None else ("default_value", index)
    try:
        socket.driver_remove(*args)
    except TypeError:
        pass
    fcurve = socket.driver_add(*args)
    for modifier in list(fcurve.modifiers):
        fcurve.modifiers.remove(modifier)
    driver = fcurve.driver
    for var in list(driver.variables):
        driver.variables.remove(var)
    return fcurve, driver


def prop(socket, index, id_type, id_block, data_path, scale=None):
    """default_value[index] = id_block.<data_path> (times *scale*)."""
    _fcurve, driver = _fresh(socket, index)
    var = driver.variables.new()
    var.name = "v"
    var.type = "SINGLE_PROP"
    var.targets[0].id_type = id_type
    var.targets[0].id = id_block
    var.targets[0].data_path = data_path
    if scale is None:
        driver.type = "AVERAGE"
    else:
        driver.type = "SCRIPTED"
        driver.expression = f"v * {float(scale)!r}"
    return driver


def world_location(socket, obj):
    """Vector socket = the object's world-space location (parents and constraints included)."""
    drivers = []
    for index, channel in enumerate(("LOC_X", "LOC_Y", "LOC_Z")):
        _fcurve, driver = _fresh(socket, index)
        driver.type = "AVERAGE"
        var = driver.variables.new()
        var.name = "loc"
        var.type = "TRANSFORMS"
        target = var.targets[0]
        target.id = obj
        target.transform_type = channel
        target.transform_space = "WORLD_SPACE"
        drivers.append(driver)
    return drivers


def world_minus_z(socket, obj):
    """Vector socket = the object's world -Z axis: minus the third column of its world matrix
    (parents, constraints, animation and mirrored rigs with negative scale included; the
    light groups normalise it).  ``matrix_world[2][i]`` is column 2, row i."""
    return [prop(socket, i, "OBJECT", obj, f"matrix_world[2][{i}]", scale=-1.0)
            for i in range(3)]


def unit_axis_expression(index: int) -> str:
    """Component *index* of the unit +Z axis of an object's world matrix, of the variables
    a, b, c (``matrix_world[2][0..2]``: column 2) as ``unit_z_axis`` names them: a simple
    expression (Blender evaluates it without Python), 0 for a zero axis."""
    return f"{'abc'[index]} / max(sqrt(a * a + b * b + c * c), 1e-30)"


def unit_z_axis(driver, obj, index: int) -> None:
    """Make *driver* (emptied) component *index* of *obj*'s unit world +Z axis: the third
    column of its world matrix, normalised (parents, constraints, animation, scale and
    mirrored rigs included): a sun's unit vector toward the light, a spot's axis reversed."""
    driver.type = "SCRIPTED"
    for row, name in enumerate("abc"):
        _variable(driver, name, "OBJECT", obj, f"matrix_world[2][{row}]")
    driver.expression = unit_axis_expression(index)


def world_unit_z(socket, obj):
    """Vector socket = *obj*'s unit world +Z axis (``unit_z_axis``)."""
    drivers = []
    for index in range(3):
        _fcurve, driver = _fresh(socket, index)
        unit_z_axis(driver, obj, index)
        drivers.append(driver)
    return drivers


def _variable(driver, name, id_type, id_block, data_path) -> None:
    var = driver.variables.new()
    var.name = name
    var.type = "SINGLE_PROP"
    var.targets[0].id_type = id_type
    var.targets[0].id = id_block
    var.targets[0].data_path = data_path


def intensity_expression(driver, light, intensity_path, from_power_path, scale) -> str:
    """Make *driver* (emptied) the light's i0: its own (*intensity_path*) where the int
    property *from_power_path* is 0, else its Power × 2^Exposure × *scale* (one simple
    expression, so dragging the Power slider or flipping the switch is live without Python);
    returns the expression."""
    driver.type = "SCRIPTED"
    _variable(driver, "i", "LIGHT", light, intensity_path)
    _variable(driver, "m", "LIGHT", light, from_power_path)
    _variable(driver, "e", "LIGHT", light, "energy")
    if hasattr(light, "exposure"):
        _variable(driver, "x", "LIGHT", light, "exposure")
    driver.expression = power_expression(light, scale)
    return driver.expression


def power_expression(light, scale) -> str:
    """The expression of ``intensity_expression`` for *light* and *scale*."""
    power = f"e * {float(scale)!r}"
    if hasattr(light, "exposure"):
        power = f"e * pow(2.0, x) * {float(scale)!r}"
    return f"i + m * ({power} - i)"


def light_intensity(socket, light, intensity_path, from_power_path, scale, index=None):
    """default_value (or [*index*]) = the light's i0 (``intensity_expression``)."""
    _fcurve, driver = _fresh(socket, index)
    intensity_expression(driver, light, intensity_path, from_power_path, scale)
    return driver


def light_color_channel(socket, index, light, channel):
    """default_value[index] (or the scalar: *index* None) = channel *channel* of the colour
    *light* emits: its Color, times its Temperature's colour where Use Temperature is on
    (live, without Python)."""
    if not hasattr(light, "temperature_color"):
        return prop(socket, index, "LIGHT", light, f"color[{channel}]")
    _fcurve, driver = _fresh(socket, index)
    driver.type = "SCRIPTED"
    _variable(driver, "c", "LIGHT", light, f"color[{channel}]")
    _variable(driver, "t", "LIGHT", light, f"temperature_color[{channel}]")
    _variable(driver, "u", "LIGHT", light, "use_temperature")
    driver.expression = "c * (u * t + 1.0 - u)"
    return driver


def light_color(socket, light):
    """Colour socket (RGB; alpha left at 1) = the colour *light* emits
    (``light_color_channel``)."""
    socket.default_value[3] = 1.0
    return [light_color_channel(socket, i, light, i) for i in range(3)]


def color(socket, id_type, id_block, data_path):
    """Colour socket (RGB; alpha left at 1) = id_block.<data_path>[0..2]."""
    socket.default_value[3] = 1.0
    return [prop(socket, i, id_type, id_block, f"{data_path}[{i}]") for i in range(3)]


def remove_node_drivers(tree, node_names) -> int:
    """Remove the drivers of *tree* that drive inputs of the named nodes; returns how many."""
    anim = tree.animation_data
    if anim is None:
        return 0
    prefixes = tuple(f'nodes["{bpy.utils.escape_identifier(n)}"]' for n in node_names)
    doomed = [fc for fc in anim.drivers if fc.data_path.startswith(prefixes)]
    for fcurve in doomed:
        anim.drivers.remove(fcurve)
    return len(doomed)
