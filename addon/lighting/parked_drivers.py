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
are parked too: their drivers whose variables read a light or an object move to a *twin*, a
copy of the group that no material uses (``TWIN_KEY`` points to it), and the group keeps the
values they had.  A drag then re-evaluates the twin, not the materials.  Whenever something
could read the per-light part (the engine switched to Cycles, a render or bake by such an
engine, a save, a reader of the World's copies), the drivers move back and the twin goes
(:func:`make_live`): the same moments as the World's copies, by the same handlers.

Nothing here runs before 5.3: there Eevee compiles the per-light part.
"""

from __future__ import annotations

import bpy

#: Custom property of a parked lights group: its twin (an ID pointer), which holds the
#: drivers it lent.
TWIN_KEY = "phong_parked_drivers"
#: Custom property of a twin (so that a twin whose group is gone is found and removed).
TWIN_MARK = "phong_parked_twin"


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
    return isinstance(tree.get(TWIN_KEY), bpy.types.NodeTree)


def park(tree) -> int:
    """Move *tree*'s drivers of lights to a twin (their values stay on the group's sockets);
    returns how many moved."""
    if is_parked(tree):
        return 0
    lent = light_fcurves(tree)
    if not lent:
        return 0
    twin = tree.copy()  # carries every driver; no material uses it
    for key in list(twin.keys()):
        del twin[key]  # not a lights group of any scene, reading no World key
    twin[TWIN_MARK] = 1
    twin.name = f"{tree.name} (parked drivers)"
    tree[TWIN_KEY] = twin
    for fcurve in lent:
        tree.animation_data.drivers.remove(fcurve)
    return len(lent)


def make_live(tree, drop_twin: bool = True) -> int:
    """Give *tree* its drivers of lights back from its twin and remove the twin (*drop_twin*
    False: leave it to :func:`prune_twins`, for ``render_pre`` and ``save_pre``, where removing
    an ID crashes the render that follows; a twin nothing uses is not saved either); returns
    how many came back."""
    twin = tree.get(TWIN_KEY)
    if twin is None:
        return 0
    del tree[TWIN_KEY]
    if not isinstance(twin, bpy.types.NodeTree):
        return 0
    anim = tree.animation_data or tree.animation_data_create()
    have = {(fc.data_path, fc.array_index) for fc in anim.drivers}
    back = 0
    for fcurve in light_fcurves(twin):
        if (fcurve.data_path, fcurve.array_index) not in have:
            anim.drivers.from_existing(src_driver=fcurve)
            back += 1
    if drop_twin:
        bpy.data.node_groups.remove(twin)
    return back


def prune_twins() -> int:
    """Remove the twins whose group is gone or no longer parked (a relink replaced it);
    returns how many."""
    kept = {tree.get(TWIN_KEY).as_pointer() for tree in bpy.data.node_groups
            if is_parked(tree)}
    doomed = [t for t in bpy.data.node_groups
              if t.get(TWIN_MARK) and t.as_pointer() not in kept]
    for twin in doomed:
        bpy.data.node_groups.remove(twin)
    return len(doomed)


__all__ = ["TWIN_KEY", "TWIN_MARK", "is_parked", "light_fcurves", "make_live", "park",
           "prune_twins"]
