# SPDX-License-Identifier: GPL-3.0-or-later
"""The World's copies of the lights' transforms: live only where something reads them
(issue 38).

A lights group reads each light's world location and axis from a World custom property
(``rig.world_key``) that drivers on the World keep equal to the light's transform
(``drivers.world_vector``): moving a light then updates the World, not the materials.  But a
World update is not free in Eevee: besides the depsgraph's work, Eevee marks its world
light probe dirty on any update of the World and renders it again (``eevee::World::sync``).
On Blender 5.3+, where a Phong material's Eevee side is the light loop (``loop.py``), Eevee
reads none of those properties: only Cycles does (the material's per-light nodes), and the
Per Vertex / Per Face groups or a lights group without the loop part.

So in a scene that Eevee (or Workbench) renders and whose every reader of the copies is
such a loop group, the copies are **parked**: their drivers are removed, their values kept,
and a light drag updates the light's object only, as in a Principled scene.  They are made
live again (drivers back, values current) whenever something could read them:

* the scene's render engine becomes one that is not Eevee or Workbench (the relink
  handler, on the engine switch), and before any render or bake by such an engine
  (``render_pre``, ``object_bake_pre``), also from a script that renders right after
  switching;
* a reader appears (a term pass on a view layer comes with a relink, which ends with
  :func:`follow`; a Per Vertex / Per Face material calls :func:`follow_readers`);
* the file is saved (``save_pre``): a saved file renders the same in Cycles without the
  extension.

They are parked by a light drag in Eevee (the relink handler tells one): by then the
depsgraph has evaluated their drivers, so a parked value is the light's transform then.

Nothing here runs before 5.3 (``compat.HAS_LIGHT_LOOP``): there Eevee reads the copies.
"""

from __future__ import annotations

import threading

import bpy
from bpy.app.handlers import persistent

from .. import compat
from . import drivers, rig
from . import loop as light_loop

#: Render engines that read no View Layer attribute of a Phong material whose lights
#: groups have the loop part.
LOOP_ENGINES = frozenset({"BLENDER_EEVEE", "BLENDER_EEVEE_NEXT", "BLENDER_WORKBENCH"})
_KINDS = ("LOCATION", "AXIS")


def _copy_fcurves(world) -> list:
    """The World's drivers of light-transform copies."""
    anim = world.animation_data
    if anim is None:
        return []
    prefix = f'["{rig.WORLD_PREFIX}'
    return [fc for fc in anim.drivers if fc.data_path.startswith(prefix)]


def is_live(world) -> bool:
    """Whether *world*'s light-transform copies have their drivers."""
    return bool(_copy_fcurves(world))


def _readers_need_copies() -> bool:
    """Whether a node group that Eevee compiles reads the copies: one with World keys and
    no loop part (a lights group of a scene with term passes, of the X3D model, a Per
    Vertex / Per Face group), used by something."""
    return any(tree.users and tree.get(rig.WORLD_KEYS) and not light_loop.has_loop(tree)
               for tree in bpy.data.node_groups)


def can_park(world) -> bool:
    """Whether nothing that renders *world*'s scenes can read its copies (see above)."""
    if not compat.HAS_LIGHT_LOOP or world is None or world.library is not None:
        return False
    scenes = [s for s in bpy.data.scenes if s.world == world]
    return (bool(scenes) and all(s.render.engine in LOOP_ENGINES for s in scenes)
            and not _readers_need_copies())


def park(world) -> int:
    """Remove the drivers of *world*'s copies (their values stay); returns how many."""
    doomed = _copy_fcurves(world)
    for fcurve in doomed:
        world.animation_data.drivers.remove(fcurve)
    return len(doomed)


def make_live(world) -> int:
    """Drivers again on each copy of *world* whose light still exists, and its value now;
    returns how many copies were made live."""
    if world is None or world.library is not None:
        return 0
    keys = {k for k in world.keys() if k.startswith(rig.WORLD_PREFIX)}
    if not keys:
        return 0
    made = 0
    for obj in bpy.data.objects:
        if obj.type != "LIGHT":
            continue
        for kind in _KINDS:
            key = rig.world_key(obj, kind)
            if key in keys:
                drivers.world_vector(world, key, obj, kind)  # unchanged ones are kept
                made += 1
    return made


def _live_if_read(world) -> None:
    """*world*'s parked copies live again where something can read them now."""
    if (world is not None and world.library is None and not is_live(world)
            and any(k.startswith(rig.WORLD_PREFIX) for k in world.keys())
            and not can_park(world)):
        make_live(world)


def follow(scene) -> None:
    """Make *scene*'s World's copies live where something can read them (the end of every
    Apply / Relink, and the relink handler on an engine switch).  Parking waits for a light
    drag (:func:`on_drag`): by then the depsgraph has evaluated the copies' drivers (a copy
    made for a light whose transform was never evaluated, as in a file written by a script,
    would keep a wrong value)."""
    if compat.HAS_LIGHT_LOOP:
        _live_if_read(getattr(scene, "world", None))


def follow_readers() -> None:
    """Every World whose parked copies something can read now (a material just set Per
    Vertex / Per Face: ``shading/modes.py``): live again."""
    if compat.HAS_LIGHT_LOOP:
        for world in bpy.data.worlds:
            _live_if_read(world)


def on_drag(scene) -> None:
    """A light drag in *scene* (``sync.on_depsgraph_update``, after the depsgraph evaluated
    the copies' drivers): park them where nothing can read them.  Once parked, this costs a
    look at the World's drivers."""
    if not compat.HAS_LIGHT_LOOP or scene.render.engine not in LOOP_ENGINES:
        return
    world = scene.world
    if world is None or world.animation_data is None or not world.animation_data.drivers:
        return
    if is_live(world) and can_park(world):
        park(world)


@persistent
def before_render(scene=None, *_args) -> None:
    """``render_pre`` / ``object_bake_pre``: a render or bake by an engine that reads the
    copies finds them live (the render's own depsgraph evaluates their drivers).  Only in
    Blender's main thread (a script's render or bake): a render job's thread must not edit
    data, and in the interface the engine switch has made them live already."""
    if not compat.HAS_LIGHT_LOOP or threading.current_thread() is not threading.main_thread():
        return
    if not isinstance(scene, bpy.types.Scene):  # a bake names its object
        scene = getattr(bpy.context, "scene", None)
        if scene is None:
            return
    world = getattr(scene, "world", None)
    if world is None or world.library is not None:
        return
    if scene.render.engine not in LOOP_ENGINES and not is_live(world):
        make_live(world)


@persistent
def before_save(*_args) -> None:
    """``save_pre``: every local World's copies live in the file (Cycles renders it right
    without the extension)."""
    if not compat.HAS_LIGHT_LOOP:
        return
    for world in bpy.data.worlds:
        if world.library is None and not is_live(world):
            make_live(world)


HANDLERS = (("render_pre", before_render), ("object_bake_pre", before_render),
            ("save_pre", before_save))
