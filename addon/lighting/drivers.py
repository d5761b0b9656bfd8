# SPDX-License-Identifier: GPL-3.0-or-later
"""Drivers from lights and the world to node inputs, without any Python expression.

Every driver is either an AVERAGE driver with one variable (a TRANSFORMS channel or a
SINGLE_PROP custom property / colour channel / world-matrix entry) or a SCRIPTED driver
``v * k`` that Blender evaluates itself (``driver.is_simple_expression`` is True), so Phong
materials follow their lights with "Auto Run Python Scripts" off and without the extension.
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


def _fresh_prop(id_block, key, index):
    """A new driver F-curve on ``id_block["key"][index]``, emptied."""
    path = f'["{bpy.utils.escape_identifier(key)}"]'
    try:
        id_block.driver_remove(path, index)
    except TypeError:
        pass
    fcurve = id_block.driver_add(path, index)
    for modifier in list(fcurve.modifiers):
        fcurve.modifiers.remove(modifier)
    driver = fcurve.driver
    for var in list(driver.variables):
        driver.variables.remove(var)
    return driver


def world_vector(world, key, obj, kind) -> None:
    """``world[key]`` (4 floats) = the object's world location (*kind* "LOCATION") or world
    -Z axis (*kind* "AXIS") in its first three, 0 in the fourth; the drivers live on the
    World (its animation data), so a moved light updates the World, not the node trees that
    read it (Attribute nodes of type View Layer: docs/contract.md, "Several lights")."""
    matrix = obj.matrix_world
    if kind == "LOCATION":
        value = [float(v) for v in matrix.translation]
    else:
        value = [-float(matrix[i][2]) for i in range(3)]
    current = world.get(key)
    if current is not None and len(current) == 4 and not isinstance(current, str):
        for index, v in enumerate(value):  # in place (no ID property freed: handler-safe)
            current[index] = v
    else:
        world[key] = [*value, 0.0]
    if _world_drivers_fit(world, key, obj, kind):
        return  # unchanged: nothing freed or re-made (the handler relinks on many edits)
    for index in range(3):
        driver = _fresh_prop(world, key, index)
        var = driver.variables.new()
        var.name = "v"
        if kind == "LOCATION":
            driver.type = "AVERAGE"
            var.type = "TRANSFORMS"
            target = var.targets[0]
            target.id = obj
            target.transform_type = ("LOC_X", "LOC_Y", "LOC_Z")[index]
            target.transform_space = "WORLD_SPACE"
        else:
            driver.type = "SCRIPTED"
            driver.expression = "v * -1.0"
            var.type = "SINGLE_PROP"
            var.targets[0].id_type = "OBJECT"
            var.targets[0].id = obj
            var.targets[0].data_path = f"matrix_world[2][{index}]"


def _world_drivers_fit(world, key, obj, kind) -> bool:
    """Whether ``world[key]``'s three drivers already read *obj* as *kind* wants."""
    anim = world.animation_data
    if anim is None:
        return False
    path = f'["{bpy.utils.escape_identifier(key)}"]'
    found = {fc.array_index: fc for fc in anim.drivers if fc.data_path == path}
    if sorted(found) != [0, 1, 2]:
        return False
    for index, fcurve in found.items():
        driver = fcurve.driver
        if len(driver.variables) != 1 or fcurve.modifiers:
            return False
        var = driver.variables[0]
        target = var.targets[0]
        if target.id != obj:
            return False
        if kind == "LOCATION":
            ok = (driver.type == "AVERAGE" and var.type == "TRANSFORMS"
                  and target.transform_type == ("LOC_X", "LOC_Y", "LOC_Z")[index]
                  and target.transform_space == "WORLD_SPACE")
        else:
            ok = (driver.type == "SCRIPTED" and driver.expression == "v * -1.0"
                  and var.type == "SINGLE_PROP" and var.name == "v"
                  and target.data_path == f"matrix_world[2][{index}]")
        if not ok:
            return False
    return True


def remove_world_vector(world, key) -> None:
    """Remove ``world[key]`` and its drivers."""
    path = f'["{bpy.utils.escape_identifier(key)}"]'
    anim = world.animation_data
    if anim is not None:
        for fcurve in [fc for fc in anim.drivers if fc.data_path == path]:
            anim.drivers.remove(fcurve)
    if key in world.keys():
        del world[key]


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
