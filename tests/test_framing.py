# SPDX-License-Identifier: GPL-3.0-or-later
"""A camera moved to see what a scene holds (addon/scene/framing.py, ``phong compare`` on a
file without camera or Viewpoint), checked with Blender's own projection of the box's
corners into the picture (``bpy_extras.object_utils.world_to_camera_view``)."""

import pytest

#: A box 0.3 × 0.1 × 0.2 away from the origin, turned about two axes.
SIZE = (0.3, 0.1, 0.2)
WHERE = (5.0, 3.0, -2.0)
TURN = (0.4, 0.0, 0.9)


def _box(bpy, scene):
    sx, sy, sz = (s / 2 for s in SIZE)
    corners = [(x, y, z) for x in (-sx, sx) for y in (-sy, sy) for z in (-sz, sz)]
    faces = [(0, 1, 3, 2), (4, 6, 7, 5), (0, 4, 5, 1), (2, 3, 7, 6), (0, 2, 6, 4), (1, 5, 7, 3)]
    mesh = bpy.data.meshes.new("Box")
    mesh.from_pydata(corners, [], faces)
    obj = bpy.data.objects.new("Box", mesh)
    obj.location, obj.rotation_euler = WHERE, TURN
    scene.collection.objects.link(obj)
    return obj


@pytest.mark.parametrize("kind, size", [("PERSP", (64, 48)), ("PERSP", (40, 90)),
                                        ("ORTHO", (64, 48)), ("ORTHO", (40, 90))],
                         ids=["persp-wide", "persp-tall", "ortho-wide", "ortho-tall"])
def test_the_box_fills_the_picture_and_the_camera_keeps_its_direction(bpy_clean, kind, size):
    bpy = bpy_clean
    from bpy_extras.object_utils import world_to_camera_view  # noqa: PLC0415
    from mathutils import Vector  # noqa: PLC0415

    from phong_nodes.addon.scene import framing  # noqa: PLC0415
    scene = bpy.context.scene
    scene.render.resolution_x, scene.render.resolution_y = size
    box = _box(bpy, scene)
    data = bpy.data.cameras.new("Camera")
    data.type = kind
    camera = bpy.data.objects.new("Camera", data)
    scene.collection.objects.link(camera)
    camera.rotation_euler = (1.1, 0.2, -0.7)   # any direction; far from the box
    camera.location = (-30.0, 40.0, 12.0)
    scene.camera = camera
    bpy.context.view_layer.update()
    turned = camera.matrix_world.to_3x3().normalized()

    assert framing.frame(scene, camera, [box])
    now = camera.matrix_world.to_3x3().normalized()
    assert [list(row) for row in now] == [pytest.approx(list(row), abs=1e-6) for row in turned]
    points = [box.matrix_world @ Vector(c) for c in box.bound_box]
    seen = [world_to_camera_view(scene, camera, p) for p in points]
    margin = (1.0 - framing.FILL) / 2.0   # each side of the centred box
    for x, y, depth in seen:
        assert margin - 1e-5 <= x <= 1.0 - margin + 1e-5
        assert margin - 1e-5 <= y <= 1.0 - margin + 1e-5
        assert data.clip_start < depth < data.clip_end
    # the box touches the margin on one side at least: framed, not just in view
    edge = min(min(x, 1.0 - x, y, 1.0 - y) for x, y, _ in seen)
    assert edge == pytest.approx(margin, abs=1e-5)
    # its centre on the camera's axis
    centre = sum(points, Vector()) / len(points)
    x, y, _ = world_to_camera_view(scene, camera, centre)
    assert (x, y) == pytest.approx((0.5, 0.5), abs=1e-5)   # float32 matrices


def test_nothing_to_frame_moves_nothing(bpy_clean):
    bpy = bpy_clean
    from phong_nodes.addon.scene import framing  # noqa: PLC0415
    scene = bpy.context.scene
    camera = bpy.data.objects.new("Camera", bpy.data.cameras.new("Camera"))
    scene.collection.objects.link(camera)
    camera.location = (1.0, 2.0, 3.0)
    assert not framing.frame(scene, camera, [])
    assert tuple(camera.location) == (1.0, 2.0, 3.0)


def test_a_camera_added_to_a_scene_no_window_shows_frames_it(bpy_clean):
    """A scene of a multi-scene file that no window shows has no depsgraph of its own: the
    new camera's world matrix still turns to the three-quarter view and frames the box."""
    bpy = bpy_clean
    from bpy_extras.object_utils import world_to_camera_view  # noqa: PLC0415
    from mathutils import Vector  # noqa: PLC0415

    from phong_nodes.addon.scene import framing  # noqa: PLC0415
    other = bpy.data.scenes.new("Other")
    assert bpy.context.scene != other and other.view_layers[0].depsgraph is None
    box = _box(bpy, other)
    camera = framing.add_camera(other, [box])
    assert other.camera == camera
    forward = camera.matrix_world.to_3x3() @ Vector((0.0, 0.0, -1.0))
    assert list(forward.normalized()) == pytest.approx(
        list(Vector((-1.0, 1.0, -1.0)).normalized()), abs=1e-6)
    for corner in box.bound_box:
        x, y, _ = world_to_camera_view(other, camera, box.matrix_world @ Vector(corner))
        assert 0.0 < x < 1.0 and 0.0 < y < 1.0
