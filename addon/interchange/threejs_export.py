# SPDX-License-Identifier: GPL-3.0-or-later
"""A scene with Phong materials as a three.js page (``core/threejs.py`` writes it).

What is exported, so that three.js and Blender shade the same geometry under the same
lights (docs/threejs.md, "The exported page"):

* every object of the view layer with a Phong material: Blender's own triangles
  (``loop_triangles`` of the evaluated mesh, modifiers applied) with their corner normals,
  in world space, one three.js mesh per object and material slot;
* the scene camera: its world matrix and Blender's own projection matrix
  (``calc_matrix_camera`` at the page's size: lens, sensor fit, shift, orthographic);
* the lights as Blender evaluates them (``demos/describe.describe``) with their three.js
  settings (intensity, distance, decay, angle = half the spot size, penumbra), and the
  World's Phong ambient light as an AmbientLight; Light Linking as light sets (the page
  renders each set's objects with its lights);
* each Phong material's controls: Object Color (color), Specular Color (specular),
  Exponent (shininess), Irradiant Color (emissive), Specular Strength (0:
  MeshLambertMaterial);
* shadows (the exported page; the comparison's peer page has none): where Blender casts Phong
  shadows (``describe``'s lights' "shadows": Cast Shadow on, a Blender with shadow rays), the
  light's ``castShadow``; each mesh ``receiveShadow``, and ``castShadow`` where the shadow
  rays meet its object (``compat.blocks_raycast``); ``renderer.shadowMap.enabled``.
  three.js's shadow maps approximate the shadow rays (``core/threejs.with_shadows``).

All colours are linear.  What three.js cannot show is reported as warnings: a texture on
Object Color (its control's colour is exported), an own Ambient Object Color, Blinn (the
three.js model has none), a scene in the seeds' model (the page shows three.js's model).
"""

from __future__ import annotations

import numpy as np

from ...core import threejs
from ...node_groups import models
from .. import compat
from ..lighting import feeds as feed_reader
from ..lighting import recipe
from ..scene import describe

#: The control that feeds each three.js material field (by the lights group's input).
FIELDS = {"color": "Object Color", "specular": "Specular Color", "shininess": "Exponent",
          "emissive": "Irradiant Color", "specular_strength": "Specular Strength"}


def _column_major(matrix) -> list:
    return [float(matrix[row][col]) for col in range(4) for row in range(4)]


def _value(feeds, name, warnings, material):
    """The value of input *name* of the lights group (``feeds.feeds``): the value the
    material states; a texture or other nodes feeding it are named in a warning."""
    feed = feeds[name]
    if feed.other is not None:
        warnings.append(f"{material.name}: {name} comes from a {feed.other.bl_idname} node "
                        "(a texture); the page uses its control's value")
    value = feed.value
    return list(value) if isinstance(value, tuple) else float(value)


def material_dict(material, warnings: list) -> dict:
    """The three.js material of a Phong material: its values (``feeds.feeds``) mapped by
    ``threejs.material_of``."""
    feeds = feed_reader.feeds(material)
    values = {key: _value(feeds, name, warnings, material) for key, name in FIELDS.items()}
    values["ambient"] = _value(feeds, recipe.AMBIENT_INPUT, warnings, material)
    values["blinn"] = _value(feeds, "Blinn", warnings, material)
    out, notes = threejs.material_of(material.name, values)
    warnings.extend(f"{material.name}: {note}" for note in notes)
    return out


def _mesh_arrays(obj, depsgraph):
    """(positions (T, 3, 3), corner normals (T, 3, 3), material index (T,)) in world space."""
    evaluated = obj.evaluated_get(depsgraph)
    mesh = evaluated.to_mesh()
    try:
        mesh.calc_loop_triangles()
        count = len(mesh.loop_triangles)
        loops = np.empty(count * 3, np.int32)
        mesh.loop_triangles.foreach_get("loops", loops)
        slots = np.empty(count, np.int32)
        mesh.loop_triangles.foreach_get("material_index", slots)
        co = np.empty(len(mesh.vertices) * 3, np.float64)
        mesh.vertices.foreach_get("co", co)
        vertex_of = np.empty(len(mesh.loops), np.int32)
        mesh.loops.foreach_get("vertex_index", vertex_of)
        normals = np.empty(len(mesh.loops) * 3, np.float64)
        mesh.corner_normals.foreach_get("vector", normals)
    finally:
        evaluated.to_mesh_clear()
    matrix = np.array(evaluated.matrix_world, dtype=np.float64)
    points = co.reshape(-1, 3)[vertex_of[loops]]
    points = points @ matrix[:3, :3].T + matrix[:3, 3]
    normal_matrix = np.linalg.inv(matrix[:3, :3]).T
    corner = normals.reshape(-1, 3)[loops] @ normal_matrix.T
    corner /= np.maximum(np.linalg.norm(corner, axis=1, keepdims=True), 1e-30)
    return points.reshape(-1, 3, 3), corner.reshape(-1, 3, 3), slots


def camera_dict(scene, depsgraph, width: int, height: int, world=None) -> dict:
    """The scene camera for a page: its type, world matrix (column-major; *world(rows)*
    converts it, e.g. to glTF's Y-up world) and Blender's own projection matrix at
    width × height (``calc_matrix_camera``: lens, sensor fit, shift, orthographic)."""
    camera = scene.camera.evaluated_get(depsgraph)
    projection = camera.calc_matrix_camera(depsgraph, x=width, y=height,
                                           scale_x=scene.render.pixel_aspect_x,
                                           scale_y=scene.render.pixel_aspect_y)
    rows = [list(row) for row in camera.matrix_world]
    return {"type": "orthographic" if camera.data.type == "ORTHO" else "perspective",
            "matrix_world": world(rows) if world else _column_major(rows),
            "projection": _column_major(projection)}


def scene_dict(scene, view_layer, width: int, height: int, objects=None,
               described=None, shadows: bool = False) -> tuple:
    """(the page's scene dict (``core/threejs.py``), warnings) of *scene* at width × height.
    *objects*: the Phong objects to export (default: those of the view layer); *described*:
    ``describe.describe`` of them when the caller has it already; *shadows*: the lights that
    cast Phong shadows cast three.js's (shadow maps)."""
    if scene.camera is None:
        raise ValueError(f"scene {scene.name!r} has no camera")
    if objects is None:
        objects = describe.phong_objects(scene, view_layer)
    if not objects:
        raise ValueError(f"scene {scene.name!r} has no object with a Phong material in view "
                         f"layer {view_layer.name!r} (Apply Phong Material first)")
    depsgraph = describe.evaluated(scene, view_layer)  # None for a scene no window shows
    data = described or describe.describe(scene, view_layer, objects)
    warnings = []
    model = models.get(data["model"])   # its mapping to three.js's values
    note = threejs.model_note(model, scene.name)
    if note:
        warnings.append(note)
    mats, index, meshes, casts = [], {}, [], []
    for obj, entry in zip(objects, data["objects"]):
        points, normals, slots = _mesh_arrays(obj, depsgraph)
        for slot_index in np.unique(slots):
            slot = obj.material_slots[int(slot_index)] if obj.material_slots else None
            material = slot.material if slot is not None else None
            if not recipe.is_phong_material(material):
                warnings.append(f"{obj.name}: faces without a Phong material are not exported")
                continue
            if material.name not in index:
                index[material.name] = len(mats)
                mats.append(material_dict(material, warnings))
            picked = slots == slot_index
            meshes.append({
                "name": f"{obj.name} [{material.name}]", "material": index[material.name],
                "lights": entry["lights"],
                "positions": np.round(points[picked].ravel(), 6).tolist(),
                "normals": np.round(normals[picked].ravel(), 6).tolist()})
            casts.append(compat.blocks_raycast(obj))
    page = {
        "format": "phong-nodes-threejs", "version": 1,
        "title": data["title"], "width": int(width), "height": int(height),
        "camera": camera_dict(scene, depsgraph, width, height),
        "ambient": {"color": data["ambient"]["color"], "intensity": data["ambient"]["intensity"]},
        "lights": [threejs.light_of(light, model) for light in data["lights"]],
        "materials": mats,
        "meshes": meshes,
    }
    if shadows:
        page = threejs.with_shadows(page, [light["shadows"] for light in data["lights"]], casts)
        if page.get("shadows"):
            warnings.append("shadows: three.js's shadow maps, near Blender's shadow rays but "
                            "not exact (the map's resolution and bias move the edges)")
    return page, sorted(set(warnings))


def export(context, filepath: str, use_selection=False, width=None, height=None) -> list:
    """Write the three.js page *filepath* (and three.js beside it) of *context*'s scene (its
    selected Phong objects: *use_selection*); returns the warnings.  The size defaults to
    the scene's render size."""
    scene, view_layer = context.scene, context.view_layer
    objects = None
    if use_selection:
        chosen = set(context.selected_objects or ())
        objects = [o for o in describe.phong_objects(scene, view_layer) if o in chosen]
    if width is None or height is None:
        percent = scene.render.resolution_percentage / 100.0
        width = max(1, round(scene.render.resolution_x * percent))
        height = max(1, round(scene.render.resolution_y * percent))
    data, warnings = scene_dict(scene, view_layer, width, height, objects, shadows=True)
    threejs.write_page(filepath, data)
    return warnings
