# SPDX-License-Identifier: GPL-3.0-or-later
"""The World's copies of the lights' transforms, the whole concept: their keys, which groups
read them, their drivers, and their being live only where something reads them.

A lights group (``rig.py``) or a Per Vertex / Per Face group (``shading/groups.py``) reads
each light's world location and axis from a World custom property (:func:`world_key`,
listed in the group's ``WORLD_KEYS``) through an Attribute node (:func:`read`), and drivers
on the World keep it equal to the light's transform (:func:`write`): moving a light then
updates the World, not the materials; :func:`prune` removes the copies no group reads.  But a
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

The scene's lights groups with the loop part park and come back with the copies: their
drivers of lights are written down and removed (``parked_drivers.py``), so that a Power or
colour dragged in Eevee re-evaluates no material either.

Nothing here runs before 5.3 (``compat.HAS_LIGHT_LOOP``): there Eevee reads the copies.
"""

from __future__ import annotations

import math
import re
import threading
import zlib

import bpy
from bpy.app.handlers import persistent

from ...node_groups import models
from .. import compat
from . import drivers, ownership, parked_drivers, properties
from . import loop as light_loop

#: Render engines that read no View Layer attribute of a Phong material whose lights
#: groups have the loop part.
LOOP_ENGINES = frozenset({"BLENDER_EEVEE", "BLENDER_EEVEE_NEXT", "BLENDER_WORKBENCH"})
_KINDS = ("LOCATION", "AXIS", "UNIT_AXIS")

#: A light's world location (Point, Spot) and axis (Sun, Spot: ``TRANSFORM_SOCKETS``) reach
#: its lights group as World custom properties of 4 floats (``world_key``), written by drivers on the
#: World and read by Attribute nodes of type View Layer: moving a light then updates the
#: World, not the node trees of the materials.  Each such Attribute node is a
#: search loop in Eevee's shader, whose compile time grows steeply with their number (and
#: with the term AOVs on the view layer: ``compat.py``), so a group reads at most
#: ``compat.VIEW_LAYER_LOOKUPS``; the lights beyond (and a scene without a World) keep
#: drivers on the group's sockets.  The group lists its keys in ``WORLD_KEYS``.
WORLD_PREFIX = "phong_light_"
WORLD_KEYS = "phong_world_keys"
#: The keys a group with the loop part reads beyond ``compat.VIEW_LAYER_LOOKUPS`` (Eevee
#: compiles none of them); apart, so that the Per Vertex / Per Face groups, which Eevee
#: compiles, read only those of ``WORLD_KEYS`` (``shading/groups.py``).
LOOP_WORLD_KEYS = "phong_world_keys_loop"
#: The copies' kinds and the sockets they feed: a light's world location ("LOCATION"), its
#: world -Z axis ("AXIS": the Per Vertex / Per Face groups' Direction, normalised there) and
#: its unit world +Z axis ("UNIT_AXIS": a lights group's light groups, where a sun's is ℓ
#: itself and a spot's cos ω = ℓ·(this), with no node to normalise or negate it).
TRANSFORM_SOCKETS = {"LOCATION": "Position", "AXIS": "Direction", "UNIT_AXIS": "Reversed Axis"}
_SUFFIXES = {"LOCATION": "p", "AXIS": "d", "UNIT_AXIS": "u"}


# -- the keys and who reads them ---------------------------------------------------------

def carries_intensity(obj, kind: str) -> bool:
    """Whether *obj*'s copy *kind* carries the light's i0 in its fourth component (read as
    the Attribute node's Alpha): the location of a point, spot or area light, the axis of a
    sun; so dragging its Power updates the World too, not the node trees of the materials."""
    drawn = models.drawn_as(obj.data.type) if obj.type == "LIGHT" else None
    return drawn is not None and kind == ("UNIT_AXIS" if drawn == "SUN" else "LOCATION")


def _intensity_paths():
    return (f'["{properties.LIGHT_KEYS["intensity"][0]}"]', f'["{properties.FROM_POWER_KEY}"]')


def world_key(obj, kind: str) -> str:
    """The World custom property that carries *obj*'s world location (*kind* "LOCATION"),
    world -Z axis ("AXIS") or unit world +Z axis ("UNIT_AXIS"): its name in letters, digits
    and underscores, and a checksum of the exact name (two names that read the same stay
    apart)."""
    safe = re.sub(r"[^A-Za-z0-9]", "_", obj.name)[:40]
    return f"{WORLD_PREFIX}{safe}_{zlib.crc32(obj.name.encode()):08x}_{_SUFFIXES[kind]}"


def prune(worlds=None) -> int:
    """Remove the light-transform properties (and their drivers) of *worlds* (default: all
    local worlds) that no lights group reads any more; returns how many."""
    used = set()
    for tree in bpy.data.node_groups:
        used.update(tree.get(WORLD_KEYS, ()))
        used.update(tree.get(LOOP_WORLD_KEYS, ()))
    removed = 0
    for world in (bpy.data.worlds if worlds is None else worlds):
        if world is None or world.library is not None:
            continue
        for key in [k for k in world.keys() if k.startswith(WORLD_PREFIX) and k not in used]:
            remove(world, key)
            removed += 1
    return removed


def clear_listed(tree, loop: bool = True) -> None:
    """*tree* (a group being rewritten) lists no key yet (*loop*: nor for its loop part, a
    lights group's)."""
    tree[WORLD_KEYS] = []
    if loop:
        tree[LOOP_WORLD_KEYS] = []


def listed(tree, loop: bool = False) -> tuple:
    """The keys the group *tree* reads (*loop*: those its loop part leaves to Cycles)."""
    return tuple(tree.get(LOOP_WORLD_KEYS if loop else WORLD_KEYS, ())) if tree is not None \
        else ()


def list_key(tree, key) -> None:
    """Add *key* to the keys *tree* (a Per Vertex / Per Face group) reads."""
    tree[WORLD_KEYS] = [*tree.get(WORLD_KEYS, ()), key]


def read(tree, world, obj, kind, socket, location, into=WORLD_KEYS, intensity=None) -> None:
    """*socket* of the lights group *tree* fed by an Attribute node (View Layer) of *obj*'s
    copy *kind* on *world* (written, with its drivers); the key is listed in the group's
    property *into* (``WORLD_KEYS`` or ``LOOP_WORLD_KEYS``); *intensity*: a socket fed by
    the copy's fourth component, the light's i0 (``carries_intensity``)."""
    key = world_key(obj, kind)
    write(world, key, obj, kind)
    attribute = tree.nodes.new("ShaderNodeAttribute")
    attribute.attribute_type = "VIEW_LAYER"
    attribute.attribute_name = key
    attribute.name = attribute.label = f"{TRANSFORM_SOCKETS[kind].lower()}:{obj.name}"
    attribute.location = location
    tree.links.new(attribute.outputs["Vector"], socket)
    if intensity is not None:
        tree.links.new(attribute.outputs["Alpha"], intensity)
    tree[into] = [*tree.get(into, ()), key]


# -- the copies' drivers ---------------------------------------------------------------------

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


def write(world, key, obj, kind) -> None:
    """``world[key]`` (4 floats) = the object's world location (*kind* "LOCATION"), world
    -Z axis ("AXIS") or unit world +Z axis ("UNIT_AXIS") in its first three, in the fourth the light's i0 where the copy
    carries it (``carries_intensity``), else 0; the drivers live on the World (its animation
    data), so a moved light, or one whose Power is dragged, updates the World, not the node
    trees that read it (Attribute nodes of type View Layer: docs/contract.md, "Several
    lights")."""
    matrix = obj.matrix_world
    if kind == "LOCATION":
        value = [float(v) for v in matrix.translation]
    elif kind == "AXIS":
        value = [-float(matrix[i][2]) for i in range(3)]
    else:
        axis = [float(matrix[i][2]) for i in range(3)]
        size = max(math.sqrt(sum(v * v for v in axis)), 1e-30)
        value = [v / size for v in axis]
    carries = carries_intensity(obj, kind)
    value.append(properties.intensity(obj.data) if carries else 0.0)
    current = world.get(key)
    if current is not None and len(current) == 4 and not isinstance(current, str):
        for index, v in enumerate(value):  # in place (no ID property freed: handler-safe)
            current[index] = v
    else:
        world[key] = value
    if _drivers_fit(world, key, obj, kind):
        return  # unchanged: nothing freed or re-made (the handler relinks on many edits)
    path = f'["{bpy.utils.escape_identifier(key)}"]'
    anim = world.animation_data
    if anim is not None and not carries:  # a fourth driver of an earlier copy
        for fcurve in [fc for fc in anim.drivers if fc.data_path == path and fc.array_index == 3]:
            anim.drivers.remove(fcurve)
    if carries:
        if any(k not in obj.data.keys() for k in (properties.FROM_POWER_KEY,
                                                   properties.LIGHT_KEYS["intensity"][0])):
            properties.ensure_light_props(obj.data)  # the driver's variables must exist
        drivers.intensity_expression(_fresh_prop(world, key, 3), obj.data, *_intensity_paths(),
                                     properties.power_scale(obj.data))
    for index in range(3):
        driver = _fresh_prop(world, key, index)
        if kind == "UNIT_AXIS":
            drivers.unit_z_axis(driver, obj, index)
            continue
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


def _drivers_fit(world, key, obj, kind) -> bool:
    """Whether ``world[key]``'s three drivers already read *obj* as *kind* wants."""
    anim = world.animation_data
    if anim is None:
        return False
    path = f'["{bpy.utils.escape_identifier(key)}"]'
    found = {fc.array_index: fc for fc in anim.drivers if fc.data_path == path}
    carries = carries_intensity(obj, kind)
    if sorted(found) != ([0, 1, 2, 3] if carries else [0, 1, 2]):
        return False
    if carries:  # the i0's driver: the expression holds the light's power scale
        fourth = found.pop(3).driver
        want = drivers.power_expression(obj.data, properties.power_scale(obj.data))
        if (fourth.type != "SCRIPTED" or fourth.expression != want
                or any(v.targets[0].id != obj.data for v in fourth.variables)):
            return False
    for index, fcurve in found.items():
        driver = fcurve.driver
        if kind == "UNIT_AXIS":
            if (fcurve.modifiers or driver.type != "SCRIPTED"
                    or driver.expression != drivers.unit_axis_expression(index)
                    or [(v.name, v.type, v.targets[0].id, v.targets[0].data_path)
                        for v in driver.variables] != [
                        (name, "SINGLE_PROP", obj, f"matrix_world[2][{row}]")
                        for row, name in enumerate("abc")]):
                return False
            continue
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


def remove(world, key) -> None:
    """Remove ``world[key]`` and its drivers."""
    path = f'["{bpy.utils.escape_identifier(key)}"]'
    anim = world.animation_data
    if anim is not None:
        for fcurve in [fc for fc in anim.drivers if fc.data_path == path]:
            anim.drivers.remove(fcurve)
    if key in world.keys():
        del world[key]


# -- parked and live -------------------------------------------------------------------------


def _copy_fcurves(world) -> list:
    """The World's drivers of light-transform copies."""
    anim = world.animation_data
    if anim is None:
        return []
    prefix = f'["{WORLD_PREFIX}'
    return [fc for fc in anim.drivers if fc.data_path.startswith(prefix)]


def is_live(world) -> bool:
    """Whether *world*'s light-transform copies have their drivers."""
    return bool(_copy_fcurves(world))


def _readers_need_copies() -> bool:
    """Whether a node group that Eevee compiles reads the copies: one with World keys and
    no loop part (a lights group of a scene with term passes or before 5.3, a Per
    Vertex / Per Face group), used by something."""
    return any(tree.users and tree.get(WORLD_KEYS) and not light_loop.has_loop(tree)
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
    keys = {k for k in world.keys() if k.startswith(WORLD_PREFIX)}
    if not keys:
        return 0
    made = 0
    for obj in bpy.data.objects:
        if obj.type != "LIGHT":
            continue
        for kind in _KINDS:
            key = world_key(obj, kind)
            if key in keys:
                write(world, key, obj, kind)  # unchanged ones are kept
                made += 1
    return made


def _live_if_read(world) -> None:
    """*world*'s parked copies, and the parked lights groups of its scenes, live again where
    something can read them now."""
    if world is None or world.library is not None or can_park(world):
        return
    if not is_live(world) and any(k.startswith(WORLD_PREFIX) for k in world.keys()):
        make_live(world)
    for scene in [s for s in bpy.data.scenes if s.world == world]:
        _groups_live(scene)


def _groups_live(scene) -> int:
    """The parked lights groups of *scene* live again (``parked_drivers``)."""
    return sum(parked_drivers.make_live(tree) for tree in ownership.groups_of(scene)
               if parked_drivers.is_parked(tree))




def follow(scene) -> None:
    """Make *scene*'s World's copies (and its parked lights groups) live where something can
    read them (the end of every Apply / Relink, and the relink handler on an engine switch).
    Parking waits for a light drag (:func:`on_drag`): by then the depsgraph has evaluated the
    copies' drivers (a copy made for a light whose transform was never evaluated, as in a file
    written by a script, would keep a wrong value)."""
    if compat.HAS_LIGHT_LOOP:
        world = getattr(scene, "world", None)
        if world is None:  # groups parked before the World went: nothing parks them now
            _groups_live(scene)
        else:
            _live_if_read(world)  # the World's copies and its scenes' groups


def follow_readers() -> None:
    """Every World whose parked copies something can read now (a material just set Per
    Vertex / Per Face, ``shading/modes.py``, whose group, ``shading/groups.py``, reads
    them): live again."""
    if compat.HAS_LIGHT_LOOP:
        for world in bpy.data.worlds:
            _live_if_read(world)  # the copies and the groups of the World's scenes
        for scene in bpy.data.scenes:
            if scene.world is None:
                _groups_live(scene)


def on_drag(scene) -> None:
    """A light drag in *scene* (``sync.on_depsgraph_update``, after the depsgraph evaluated
    the copies' drivers): park them, and the drivers of lights of its lights groups, where
    nothing can read them.  Once parked, this costs a look at the World's drivers and the
    groups' keys."""
    if not compat.HAS_LIGHT_LOOP or scene.render.engine not in LOOP_ENGINES:
        return
    world = scene.world
    if world is None:
        return
    groups = [t for t in ownership.groups_of(scene)
              if light_loop.has_loop(t) and not parked_drivers.is_parked(t)]
    live = world.animation_data is not None and is_live(world)
    if (live or groups) and can_park(world):  # once parked: a look at the groups' keys
        if live:
            park(world)
        for tree in groups:
            parked_drivers.park(tree)


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
    if scene.render.engine not in LOOP_ENGINES:
        _groups_live(scene)
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
    for scene in bpy.data.scenes:  # the lights groups' drivers too
        _groups_live(scene)


HANDLERS = (("render_pre", before_render), ("object_bake_pre", before_render),
            ("save_pre", before_save))
