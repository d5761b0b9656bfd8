# SPDX-License-Identifier: GPL-3.0-or-later
"""The headlight of VRML97 / X3D: a white directional light along the viewer's view direction.

``NavigationInfo { headlight TRUE }`` (the standards' default) lights a scene with a
DirectionalLight of intensity 1, ambientIntensity 0, colour white and direction (0, 0, -1) in
the viewer's space (ISO/IEC 19775-1 §23.4.4, VRML97 §6.29).  In Blender it is a Sun named
"Headlight" whose transform a Copy Transforms constraint takes from the scene camera: a Sun
shines along its local -Z, a camera looks along its local -Z, so the light follows the camera
wherever it moves or turns (animated, parented or constrained too: the lights group reads the
evaluated world matrix, ``world_copies.write``).

The Sun carries ``HEADLIGHT_KEY`` so that the X3D export writes ``headlight TRUE`` instead of a
light; :func:`is_headlight` also recognises a Sun constrained to the scene camera without it.
"""

from __future__ import annotations

import bpy

from . import properties

NAME = "Headlight"
#: Custom property of a headlight object (the value 1).
HEADLIGHT_KEY = "phong_headlight"
CONSTRAINT = "Follow Camera"
#: The standard's headlight: intensity 1, ambientIntensity 0, white.
VALUES = {"intensity": 1.0, "ambient": 0.0}
COLOR = (1.0, 1.0, 1.0)


def camera_target(obj):
    """The object a headlight's constraint follows, or None."""
    for constraint in obj.constraints:
        if constraint.type in ("COPY_TRANSFORMS", "COPY_ROTATION") and not constraint.mute:
            return constraint.target
    return None


def is_headlight(obj, scene=None) -> bool:
    """Whether *obj* is a headlight: a Sun marked by ``HEADLIGHT_KEY``, or a Sun whose Copy
    Transforms / Copy Rotation constraint follows *scene*'s camera."""
    if obj is None or obj.type != "LIGHT" or obj.data.type != "SUN":
        return False
    if obj.get(HEADLIGHT_KEY):
        return True
    camera = scene.camera if scene is not None else None
    return camera is not None and camera_target(obj) is camera


def headlights(scene) -> list:
    """The headlights among *scene*'s objects."""
    return [obj for obj in scene.objects if is_headlight(obj, scene)]


def follow(obj, camera) -> None:
    """Make *obj* take its transform from *camera* (one Copy Transforms constraint)."""
    constraint = obj.constraints.get(CONSTRAINT)
    if constraint is None or constraint.type != "COPY_TRANSFORMS":
        if constraint is not None:
            obj.constraints.remove(constraint)
        constraint = obj.constraints.new("COPY_TRANSFORMS")
        constraint.name = CONSTRAINT
    constraint.target = camera


def add(scene, camera=None, collection=None, name=NAME):
    """A new headlight in *scene* (linked into *collection*, default the scene's own) that
    follows *camera* (default the scene camera; ValueError without one); returns the object."""
    camera = camera if camera is not None else scene.camera
    if camera is None:
        raise ValueError(f"scene {scene.name!r} has no camera for the headlight to follow")
    light = bpy.data.lights.new(name, "SUN")
    light.use_shadow = False  # a browser's headlight casts no shadow (X3D's default)
    light.color = COLOR
    properties.write_light(light, VALUES)
    obj = bpy.data.objects.new(name, light)
    obj[HEADLIGHT_KEY] = 1
    (collection or scene.collection).objects.link(obj)
    follow(obj, camera)
    obj.matrix_world = camera.matrix_world.copy()   # where the constraint puts it (viewport)
    return obj


def ensure(scene, collection=None):
    """The scene's headlight following its camera: an existing one is pointed at the scene
    camera (the camera may have changed), else one is added; returns (object, added)."""
    found = headlights(scene)
    if scene.camera is None:
        raise ValueError(f"scene {scene.name!r} has no camera for the headlight to follow")
    if found:
        for obj in found:
            follow(obj, scene.camera)
        return found[0], False
    return add(scene, collection=collection), True
