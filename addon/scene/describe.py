# SPDX-License-Identifier: GPL-3.0-or-later
"""A scene as Blender evaluates it, as plain data for the reference (``core/compare.py``).

The reference does not read the lights groups: it reads what they stand for, so a lights
group that has fallen out of step with the scene shows as a mismatch.  Per light: the
world matrix (position, -Z axis) of the evaluated object (parents, constraints, drivers and
animation at the current frame), the light's colour and Phong settings, the spot's cone;
per object with a Phong material: the lights that reach it under Light Linking; the
World's Phong ambient light.  Where the scene's lights groups cast shadow rays
(``lighting/shadows.py``) and a light casts shadows: "triangles", the evaluated triangles of
every object the shadow rays can meet, in world space, read once (numpy, (T, 3, 3)), for the
reference's visibility (``node_groups/reference.py``).
"""

from __future__ import annotations

import contextlib
import json
import math

import bpy
import numpy as np

from ...core import compare, outputs
from ...core.wording import name_list
from ..lighting import lights as lights_mod
from .. import compat
from ..lighting import properties, recipe, rig, shadows
from . import render

#: Custom property on a scene built from a scene file (``demos/builder.py``): the file's dict
#: (JSON); the comparison takes its title, source and description from it.
SCENE_KEY = "phong_demo"
#: The scene files' (and the reference's) light type -> Blender light type.
SCENE_FILE_LIGHTS = {"point": "POINT", "directional": "SUN", "spot": "SPOT"}
#: Blender light type -> the scene files' (and the reference's) light type.
LIGHT_TYPES = {kind: name for name, kind in SCENE_FILE_LIGHTS.items()}


def scene_file(scene) -> dict | None:
    """The scene file's dict a scene was built from, or None."""
    text = scene.get(SCENE_KEY)
    try:
        return json.loads(text) if isinstance(text, str) else None
    except ValueError:
        return None


def view_layer_of(scene, name: str | None = None):
    """The view layer *name* of *scene*, else the first one that renders."""
    if name is not None:
        return scene.view_layers[name]
    return next((layer for layer in scene.view_layers if layer.use), scene.view_layers[0])


def evaluated(scene, view_layer=None):
    """The depsgraph of *view_layer* (default: the first that renders) of *scene*, evaluated
    now.  Blender keeps one only for the scenes a window shows (or rendered): a scene of a
    multi-scene file that no window shows has ``view_layer.depsgraph`` None, so one is made
    for it as the context's scene (headless or not; the window's scene stays).  It is the
    active one: the world matrices of the objects follow."""
    layer = view_layer or view_layer_of(scene)
    depsgraph = layer.depsgraph
    if depsgraph is None:
        with bpy.context.temp_override(scene=scene, view_layer=layer):
            depsgraph = bpy.context.evaluated_depsgraph_get()
    depsgraph.update()
    return depsgraph


def phong_objects(scene, view_layer, instanced: bool = False) -> list:
    """The objects of *view_layer* that render with a Phong material in some slot; with
    *instanced*, then those that render only through a collection instance
    (``instanced_phong_objects``: what the comparison compares)."""
    view_layer = lights_mod.synced(scene, view_layer)  # a scene just made has no objects yet
    collections = lights_mod.render_collections(view_layer)  # once, not per object
    direct = [obj for obj in view_layer.objects
              if not obj.hide_render and hasattr(obj.data, "materials")
              and lights_mod.visible(obj, view_layer, collections)
              and any(recipe.is_phong_material(slot.material) for slot in obj.material_slots)]
    return direct + instanced_phong_objects(scene, view_layer) if instanced else direct


def instanced_phong_objects(scene, view_layer) -> list:
    """The objects that render in *view_layer* only through a collection instance (an
    object's Instancing ▸ Collection, at any depth) with a Phong material of *scene*'s own
    lights groups in some slot: what Apply converts of an instanced collection (a library's
    through its override).  Their instances share the object's pass index, so the comparison
    numbers them as the object.  A Phong material of another scene's lights group is lit by
    that scene's lights, which this scene's reference does not hold: left out."""
    view_layer = lights_mod.synced(scene, view_layer)
    collections = lights_mod.render_collections(view_layer)
    direct = {obj.as_pointer() for obj in view_layer.objects}
    here = scene.as_pointer()
    instancers = [obj for obj in view_layer.objects if lights_mod.instance_of(obj) is not None
                  and lights_mod.visible(obj, view_layer, collections)]
    found = [obj for obj in lights_mod.instanced_objects(instancers, rendering=True)
             if obj.as_pointer() not in direct and hasattr(obj.data, "materials")
             and any(recipe.lights_scene(slot.material) == here
                     for slot in obj.material_slots)]
    return sorted(found, key=lambda o: o.name_full)


def rendering_phong(scene, view_layer, objects, render: bool = True) -> list:
    """Those of *objects* (Phong objects of *scene*) whose rendered geometry may carry a
    Phong material: the object's own evaluated geometry with faces (a mesh; any other kind
    counts), or an instance it makes (Geometry Nodes, particles) or is made into, whose slots
    hold one; an object the depsgraph does not evaluate counts too.  Geometry Nodes that turn
    a mesh into points or instances without its materials leave an object that Apply
    converted rendering no Phong surface at all.  The geometry is the render's
    (``render_geometry``: an object hidden in the viewport renders); without *render* the
    viewport's, as it is (no evaluation at render levels: a quick look that may miss one)."""
    wanted = {obj.as_pointer(): obj for obj in objects}
    seen, found = set(), set()
    with render_geometry(scene) if render else contextlib.nullcontext():
        depsgraph = evaluated(scene, view_layer)
        for inst in depsgraph.object_instances:
            obj = inst.object
            sources = {obj.original.as_pointer()}
            if inst.is_instance and inst.parent is not None:
                sources.add(inst.parent.original.as_pointer())
            sources &= wanted.keys()
            if not sources:
                continue
            seen |= sources
            if sources <= found or (obj.type == "MESH" and not _has_faces(obj.data)):
                continue
            if any(slot.material is not None
                   and recipe.is_phong_material(slot.material.original)
                   for slot in obj.material_slots):
                found |= sources
                if len(found) == len(wanted):  # the usual case: not every instance walked
                    break
    if render:
        evaluated(scene, view_layer)  # back to the viewport's geometry
    return [obj for obj in objects
            if obj.as_pointer() in found or obj.as_pointer() not in seen]


def _has_faces(mesh) -> bool:
    """Whether the evaluated *mesh* has faces; the mesh of an object in Edit Mode (a file
    saved so: glTF-Blender-IO's 11_loose_geometry.blend) is a wrapper that lists none to
    Python, yet renders its faces: it counts."""
    return bool(len(mesh.polygons)) or bool(getattr(mesh, "is_editmode", False))


def hollow_notes(scene, view_layer, objects) -> list:
    """Apply's note on those of *objects* (just converted) that render no Phong surface
    (``rendering_phong`` on the viewport's geometry), or none.  Only an object with a Geometry
    Nodes modifier is looked at (nothing else drops its materials), so a scene without one
    costs no evaluation here (3,000 objects: 2.2 s, bpy 5.3.0)."""
    candidates = [obj for obj in objects
                  if any(modifier.type == "NODES" for modifier in obj.modifiers)]
    if not candidates:
        return []
    rendering = {obj.as_pointer() for obj in rendering_phong(scene, view_layer, candidates,
                                                             render=False)}
    hollow = [obj.name for obj in candidates if obj.as_pointer() not in rendering]
    if not hollow:
        return []
    names = name_list(hollow)
    return [f"{names}: {'renders' if len(hollow) == 1 else 'render'} no Phong surface: "
            "the Geometry Nodes output carries none of the object's materials (points, "
            "instances); a Set Material node gives it the Phong material"]


def folder_name(scene) -> str:
    """The report folder of *scene*: its scene file's name, else its own name made safe
    (``outputs.clean_name``; a run keeps its scenes' folders apart with ``outputs.distinct``)."""
    data = scene_file(scene)
    if data and isinstance(data.get("name"), str):
        return data["name"]
    return outputs.clean_name(scene.name, "scene")


def describe(scene, view_layer, objects) -> dict:
    """The plain-data scene of the reference: name, title, lights, ambient, and *objects*
    (in order: object number k is objects[k - 1]) with the lights that reach each."""
    depsgraph = evaluated(scene, view_layer)
    lights, _unsupported = lights_mod.scene_lights(scene, view_layer)
    rules = [lights_mod.receivers(obj) for obj in lights]
    data = scene_file(scene) or {}
    width, height = scene.render.resolution_x, scene.render.resolution_y
    rays = shadows.casts_rays(scene)
    described = [_light(obj.evaluated_get(depsgraph)) for obj in lights]
    for light, obj in zip(described, lights):
        light["shadows"] = bool(rays and obj.data.use_shadow)
    out = {
        "name": folder_name(scene),
        "title": data.get("title") or f"Scene {scene.name!r}",
        "source": data.get("source", ""),
        "description": data.get("description", ""),
        "aspect": width / height,
        "model": rig.model_of(scene),
        "ambient": _ambient(scene.world),
        "lights": described,
        "objects": [{
            "name": obj.name,
            "lights": [k for k, rule in enumerate(rules) if lights_mod.reaches(rule, obj)],
            "materials": sorted({slot.material.name for slot in obj.material_slots
                                 if recipe.is_phong_material(slot.material)}),
            # Opacity below 1 or an opacity map (a texture's alpha): the picture blends what
            # is behind, which the reference (from the nearest surface's probes) cannot
            # know: its pixels are left out
            "transparent": any(recipe.blends(slot.material)
                               for slot in obj.material_slots
                               if recipe.is_phong_material(slot.material)),
        } for obj in objects],
        "light_names": [obj.name for obj in lights],
    }
    if any(light["shadows"] for light in described):
        with render_geometry(scene):
            depsgraph.update()
            out["triangles"] = triangles(view_layer, depsgraph)
        depsgraph.update()
        out["eevee_shadows"] = render.eevee_shadows(scene)  # else Eevee is compared without
    return out


def warped_notes(scene, view_layer, objects) -> list:
    """The note of a comparison with Eevee when *objects* (Phong objects of *scene*) have flat
    polygons that are not planar (``compare.warped_polygons``, on their evaluated meshes; a
    mesh with custom normals shades by those: left out): Eevee shades such a polygon with
    one normal, Cycles and the reference each of its triangles with its own, so Eevee's
    pixels there may miss the reference, Principled's as much as Phong's."""
    depsgraph = evaluated(scene, view_layer)
    counted, named, total = {}, [], 0
    for obj in objects:
        evaluated_obj = obj.evaluated_get(depsgraph) if obj.type == "MESH" else None
        mesh = evaluated_obj.data if evaluated_obj is not None else None
        if mesh is None or not _has_faces(mesh):
            continue
        key = mesh.as_pointer()
        if key not in counted:
            counted[key] = 0 if mesh.has_custom_normals else _warped_of(evaluated_obj, mesh)
        if counted[key]:
            named.append(obj.name)
            total += counted[key]
    if not named:
        return []
    return [f"{name_list(named)}: {total} flat polygon(s) not planar: Eevee shades a flat "
            "polygon with one normal, Cycles and the reference each of its triangles with its "
            "own, so Eevee's pixels there may miss the reference (as Principled's do); a "
            "Triangulate modifier makes the engines alike"]


def _warped_of(obj, mesh) -> int:
    """``_warped`` of the evaluated *obj* whose mesh is *mesh*; in Edit Mode (a mesh that
    lists no faces to Python) of a copy of what it renders."""
    if len(mesh.polygons):
        return _warped(mesh)
    try:
        copy = obj.to_mesh()
    except RuntimeError:
        return 0
    try:
        return _warped(copy) if copy is not None else 0
    finally:
        obj.to_mesh_clear()


def _warped(mesh) -> int:
    """``compare.warped_polygons`` of *mesh* (evaluated)."""
    polygons, triangles_ = mesh.polygons, mesh.loop_triangles
    smooth = np.zeros(len(polygons), bool)
    polygons.foreach_get("use_smooth", smooth)
    if smooth.all():
        return 0
    normals = np.zeros(len(polygons) * 3, np.float32)
    polygons.foreach_get("normal", normals)
    owner = np.zeros(len(triangles_), np.int32)
    triangles_.foreach_get("polygon_index", owner)
    tri_normals = np.zeros(len(triangles_) * 3, np.float32)
    triangles_.foreach_get("normal", tri_normals)
    return compare.warped_polygons(normals.reshape(-1, 3), ~smooth, tri_normals.reshape(-1, 3),
                                   owner)


@contextlib.contextmanager
def render_geometry(scene):
    """The scene's geometry as a render evaluates it, for a while: each modifier shown as it
    is in renders, a Subdivision Surface or Multiresolution at its render levels, an object
    disabled in the viewport but not in renders enabled (the depsgraph that Python reads is
    the viewport's); everything put back on leaving."""
    undo = render.Overrides()
    try:
        for obj in scene.objects:
            if obj.library is not None:
                continue
            if obj.hide_viewport and not obj.hide_render:
                undo.set(obj, "hide_viewport", False)
            for modifier in obj.modifiers:
                undo.set(modifier, "show_viewport", modifier.show_render)
                if hasattr(modifier, "render_levels") and hasattr(modifier, "levels"):
                    undo.set(modifier, "levels", modifier.render_levels)
        yield
    finally:
        undo.restore()


def triangles(view_layer, depsgraph) -> np.ndarray:
    """The world-space triangles (T, 3, 3) of every object of *view_layer* that Cycles' shadow
    rays can meet (``compat.blocks_raycast``), as evaluated (modifiers, animation), instances
    (collection instances, particles, geometry nodes) included."""
    kinds = ("MESH", "CURVE", "SURFACE", "META", "FONT", "CURVES")
    local = {}  # an object's triangles in its own space, once however often it is instanced
    parts = []
    collections = lights_mod.render_collections(view_layer)  # once, not per instance
    for inst in depsgraph.object_instances:
        obj = inst.object
        original = obj.original
        if obj.type not in kinds or not compat.blocks_raycast(original):
            continue
        if not inst.is_instance and (original.hide_render
                                     or not lights_mod.visible(original, view_layer,
                                                               collections)):
            continue
        key = obj.name_full if not inst.is_instance else (obj.name_full, "instance")
        if key not in local:
            local[key] = _local_triangles(obj)
        corners = local[key]
        if len(corners):
            matrix = np.array(inst.matrix_world, np.float64)
            parts.append(corners @ matrix[:3, :3].T + matrix[:3, 3])
    return np.concatenate(parts) if parts else np.zeros((0, 3, 3))


def _local_triangles(obj) -> np.ndarray:
    """The triangles (T, 3, 3) of the evaluated object *obj* in its own space."""
    try:
        mesh = obj.to_mesh()
    except RuntimeError:
        return np.zeros((0, 3, 3))
    if mesh is None:
        return np.zeros((0, 3, 3))
    try:
        mesh.calc_loop_triangles()
        count = len(mesh.loop_triangles)
        if not count:
            return np.zeros((0, 3, 3))
        corners = np.empty(count * 3, np.int64)
        mesh.loop_triangles.foreach_get("vertices", corners)
        co = np.empty(len(mesh.vertices) * 3, np.float64)
        mesh.vertices.foreach_get("co", co)
        return co.reshape(-1, 3)[corners].reshape(-1, 3, 3)
    finally:
        obj.to_mesh_clear()


def _ambient(world) -> dict:
    key, default = properties.AMBIENT_INTENSITY
    color_key, default_color = properties.AMBIENT_COLOR
    if world is None:  # no World: no world light (Blender's own render)
        return {"intensity": properties.NO_WORLD_AMBIENT, "color": list(default_color)}
    return {"intensity": float(world.get(key, default)),
            "color": [float(c) for c in world.get(color_key, default_color)][:3]}


def _light(obj) -> dict:
    """One evaluated light object as the reference's light (``properties.light_values``: an
    Area light is the spot that draws it)."""
    light = obj.data
    read = properties.light_values(light)
    kind = read["type"]
    matrix = obj.matrix_world
    out = {"name": obj.name, "type": LIGHT_TYPES[kind], "color": list(read["color"])}
    out.update({attr: read["settings"][attr] for attr in properties.read_settings(light.type)})
    if kind in ("POINT", "SPOT"):
        out["position"] = [float(c) for c in matrix.translation]
        out["falloff"] = read["falloff"].lower()  # "quadratic" or "power"
    if kind in ("SUN", "SPOT"):
        out["direction"] = [-float(matrix[i][2]) for i in range(3)]  # the world -Z axis
    if kind == "SPOT":
        out["half_angle"] = math.degrees(read["spot_size"] / 2.0)
    return out
