# SPDX-License-Identifier: GPL-3.0-or-later
"""A lights group's drivers of lights, parked while nothing can read what they drive.

On Blender 5.3+ a Phong material's Eevee side is the light loop (``loop.py``), which reads each
light through Eevee's own light attributes; Eevee compiles nothing of the lights group's
per-light part, which Cycles renders.  Yet that part's drivers read the lights' data (colour,
Diffuse and Specular, the falloff's exponent, Cast Shadow ...), so the depsgraph re-evaluates
the group, and then every material that uses it, on any edit of a light's data: dragging a
light's Power cost 1.4-1.8 times what it costs a Principled scene at 1,000 objects, although
its i0 reaches the group through the World (``world_copies``).

So when the World's copies are parked (``world_copies``: a scene that only Eevee or Workbench
renders, nothing else reading them), the lights groups of the scene that have the loop part
are parked too: their drivers whose variables read a light or an object are written down in
the group's custom property ``PARKED_KEY`` (path, type, expression, variables and their
targets, the targets as ID pointers, which make no depsgraph relation) and removed; the
sockets keep the values they had.  A drag then re-evaluates no material.  Whenever something
could read the per-light part (the engine switched to Cycles, a render or bake by such an
engine, a save, a reader of the World's copies), the drivers are made again from what was
written (:func:`make_live`): the same moments as the World's copies, by the same handlers.
Nothing is added to or removed from ``bpy.data`` either way, so it is safe in ``render_pre``.

Nothing here runs before 5.3: there Eevee compiles the per-light part.
"""

from __future__ import annotations

import bpy

#: Custom property of a parked lights group: its drivers of lights, written down.
PARKED_KEY = "phong_parked_drivers"
#: What is written down of a driver variable's target.
_TARGET_ATTRS = ("id_type", "data_path", "transform_type", "transform_space", "rotation_mode",
                 "bone_target")


def _reads_the_lights(fcurve) -> bool:
    """Whether the driver *fcurve* reads a light's data or an object's transform."""
    return any(isinstance(target.id, (bpy.types.Light, bpy.types.Object))
               for variable in fcurve.driver.variables for target in variable.targets)


def light_fcurves(tree) -> list:
    """The drivers of *tree* that read the lights (their data or their objects)."""
    anim = tree.animation_data
    if anim is None:
        return []
    return [fc for fc in anim.drivers if _reads_the_lights(fc)]


def is_parked(tree) -> bool:
    return PARKED_KEY in tree.keys()


def _written(fcurve) -> dict:
    driver = fcurve.driver
    variables = []
    for variable in driver.variables:
        targets = []
        for target in list(variable.targets)[:_TARGET_COUNT.get(variable.type, 1)]:
            values = {attr: getattr(target, attr) for attr in _TARGET_ATTRS
                      if hasattr(target, attr)}
            if target.id is not None:
                values["id"] = target.id
            targets.append(values)
        variables.append({"name": variable.name, "type": variable.type, "targets": targets})
    return {"path": fcurve.data_path, "index": fcurve.array_index, "type": driver.type,
            "expression": driver.expression, "variables": variables}


#: How many targets each variable type uses.
_TARGET_COUNT = {"SINGLE_PROP": 1, "TRANSFORMS": 1, "CONTEXT_PROP": 1, "ROTATION_DIFF": 2,
                 "LOC_DIFF": 2}


def _make(anim, written) -> bool:
    """The driver *written* made again on *anim*; False where its path no longer resolves
    (the group was rebuilt meanwhile)."""
    try:
        fcurve = anim.drivers.new(written["path"], index=int(written["index"]))
    except (RuntimeError, TypeError):
        return False
    for modifier in list(fcurve.modifiers):
        fcurve.modifiers.remove(modifier)
    driver = fcurve.driver
    driver.type = written["type"]
    driver.expression = written["expression"]
    for values in written["variables"]:
        variable = driver.variables.new()
        variable.name = values["name"]
        variable.type = values["type"]
        for target, attrs in zip(variable.targets, values["targets"]):
            if "id_type" in attrs and variable.type == "SINGLE_PROP":
                target.id_type = attrs["id_type"]
            if "id" in attrs:
                target.id = attrs["id"]
            for attr in _TARGET_ATTRS[1:]:
                if attr in attrs:
                    setattr(target, attr, attrs[attr])
    return True


def park(tree) -> int:
    """Write down and remove *tree*'s drivers of lights (their values stay on the group's
    sockets); returns how many."""
    if is_parked(tree):
        return 0
    lent = light_fcurves(tree)
    if not lent:
        return 0
    tree[PARKED_KEY] = [_written(fc) for fc in lent]
    for fcurve in lent:
        tree.animation_data.drivers.remove(fcurve)
    return len(lent)


def make_live(tree) -> int:
    """Make *tree*'s parked drivers again (with the lights' values of now, at the next
    depsgraph update); returns how many."""
    if not is_parked(tree):
        return 0
    written = [w.to_dict() if hasattr(w, "to_dict") else dict(w) for w in tree[PARKED_KEY]]
    del tree[PARKED_KEY]
    anim = tree.animation_data or tree.animation_data_create()
    have = {(fc.data_path, fc.array_index) for fc in anim.drivers}
    made = 0
    for item in written:
        if (item["path"], int(item["index"])) not in have and _make(anim, item):
            made += 1
    return made


__all__ = ["PARKED_KEY", "is_parked", "light_fcurves", "make_live", "park"]
