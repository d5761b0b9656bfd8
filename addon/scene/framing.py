# SPDX-License-Identifier: GPL-3.0-or-later
"""A camera moved to see what a scene holds, as a viewer's View All does (``phong compare``
on a file or a scene without a camera or Viewpoint).

The camera keeps its direction (the file's default view): it moves sideways until the
bounding box of the objects is centred in the picture, then along its axis until every
corner of the box is inside the picture with a margin (a perspective camera: the distance
from each corner's offset and the field of view; an orthographic one: ``ortho_scale``).
The fields of view are the render frame's (``Camera.view_frame``: sensor fit, the picture's
aspect).  Its clipping planes then hold the box.
"""

from __future__ import annotations

import bpy
from mathutils import Vector

from . import describe

#: The box fills at most this share of the picture's limiting side.
FILL = 0.9


def visible_meshes(scene) -> list:
    """The scene's mesh objects that render and have vertices."""
    return [obj for obj in scene.objects if obj.type == "MESH" and not obj.hide_render
            and len(obj.data.vertices)]


def box(objects) -> list:
    """The world corners of the bounding boxes of *objects* (their world matrices current)."""
    return [obj.matrix_world @ Vector(corner) for obj in objects for corner in obj.bound_box]


def add_camera(scene, objects):
    """A new camera of *scene*, its scene camera, looking from the front, right and above (a
    three-quarter view, so that no plane of the axes is seen edge-on) and framed on
    *objects*; returns it."""
    camera = bpy.data.objects.new("Camera", bpy.data.cameras.new("Camera"))
    scene.collection.objects.link(camera)
    camera.rotation_euler = (-Vector((1.0, -1.0, 1.0))).to_track_quat("-Z", "Y").to_euler()
    scene.camera = camera
    frame(scene, camera, objects)
    return camera


def frame(scene, camera, objects) -> bool:
    """Move *camera* (an object with camera data, unparented or not) so that *objects* fill
    the picture of *scene*; False (nothing moved) when there is nothing to frame."""
    describe.evaluated(scene)   # world matrices of what was just added (in *scene*'s own layer)
    points = box(objects)
    if not points:
        return False
    low = Vector([min(p[i] for p in points) for i in range(3)])
    high = Vector([max(p[i] for p in points) for i in range(3)])
    centre = (low + high) / 2.0
    radius = max((high - low).length / 2.0, 1e-6)
    rotation = camera.matrix_world.to_3x3().normalized()
    inverse = rotation.transposed()
    # corners around the centre in the camera's axes: x right, y up, z towards the camera
    local = [inverse @ (p - centre) for p in points]
    half_x = max(abs(p.x) for p in local)
    half_y = max(abs(p.y) for p in local)
    near_z, far_z = max(p.z for p in local), min(p.z for p in local)
    data = camera.data
    corners = data.view_frame(scene=scene)   # the picture's corners in camera space
    frame_x = min(abs(c.x) for c in corners)
    frame_y = min(abs(c.y) for c in corners)
    if data.type == "ORTHO":
        # the frame's half sides scale with ortho_scale
        scale = max(half_x / (frame_x * FILL), half_y / (frame_y * FILL), 1e-9)
        data.ortho_scale = max(data.ortho_scale * scale, 1e-6)
        distance = near_z + radius
    else:
        depth = abs(corners[0].z)
        tan_x, tan_y = frame_x / depth, frame_y / depth
        # each corner inside the frustum: |x| <= FILL * tan * (distance - z)
        distance = max(max(abs(p.x) / (FILL * tan_x) + p.z, abs(p.y) / (FILL * tan_y) + p.z)
                       for p in local)
        distance = max(distance, near_z + 0.01 * radius)
    forward = rotation @ Vector((0.0, 0.0, -1.0))
    matrix = camera.matrix_world.copy()
    matrix.translation = centre - forward * distance
    camera.matrix_world = matrix
    near, far = distance - near_z, distance - far_z
    data.clip_start = max(near * 0.5, 1e-6)
    data.clip_end = max(far * 2.0, data.clip_start * 10.0)
    describe.evaluated(scene)   # the camera's world matrix, which headlights follow
    return True
