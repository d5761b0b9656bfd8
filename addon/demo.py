# SPDX-License-Identifier: GPL-3.0-or-later
"""The demo: one sphere lit by a Phong point light, rendered by Eevee and Cycles.

Built in a new scene (the user's scenes are never touched).  Used by the
headless command ``tools/phong.py``.
"""

from __future__ import annotations

import os
import tempfile

import bpy

from ..node_groups import loader
from . import compat

SCENE_NAME = "Phong Demo"
OBJECT_COLOR = (1.0, 0.246, 0.091)  # 0xFF8855 of seed 004 slide 50, in linear RGB
LIGHT_LOCATION = (2.0, -3.0, 4.0)


def build_scene(resolution: int = 256) -> bpy.types.Scene:
    """A new scene: UV sphere, point light, camera, Phong material."""
    scene = bpy.data.scenes.new(SCENE_NAME)
    scene.render.resolution_x = scene.render.resolution_y = resolution
    scene.render.resolution_percentage = 100
    scene.view_settings.view_transform = "Standard"
    scene.render.film_transparent = False
    world = bpy.data.worlds.new(SCENE_NAME)
    compat.black_world(world)
    scene.world = world

    mesh = bpy.data.meshes.new("Phong Sphere")
    _uv_sphere(mesh, segments=96, rings=48)
    sphere = bpy.data.objects.new("Phong Sphere", mesh)
    scene.collection.objects.link(sphere)

    light = bpy.data.objects.new("Phong Light", bpy.data.lights.new("Phong Light", "POINT"))
    light.location = LIGHT_LOCATION
    scene.collection.objects.link(light)

    camera = bpy.data.objects.new("Camera", bpy.data.cameras.new("Camera"))
    camera.location = (0.0, -6.0, 0.0)
    camera.rotation_euler = (1.5707963267948966, 0.0, 0.0)
    camera.data.lens = 50
    scene.collection.objects.link(camera)
    scene.camera = camera

    mesh.materials.append(_material(light))
    return scene


def _uv_sphere(mesh, segments: int, rings: int) -> None:
    """A smooth unit UV sphere built from data (no operator, so it runs anywhere)."""
    import math

    verts = [(0.0, 0.0, 1.0)]
    for ring in range(1, rings):
        theta = math.pi * ring / rings
        for seg in range(segments):
            phi = 2 * math.pi * seg / segments
            verts.append((math.sin(theta) * math.cos(phi), math.sin(theta) * math.sin(phi),
                          math.cos(theta)))
    verts.append((0.0, 0.0, -1.0))
    bottom = len(verts) - 1
    faces = []
    for seg in range(segments):
        nxt = (seg + 1) % segments
        faces.append((0, 1 + seg, 1 + nxt))
        last = 1 + (rings - 2) * segments
        faces.append((bottom, last + nxt, last + seg))
    for ring in range(rings - 2):
        a, b = 1 + ring * segments, 1 + (ring + 1) * segments
        for seg in range(segments):
            nxt = (seg + 1) % segments
            faces.append((a + seg, b + seg, b + nxt, a + nxt))
    mesh.from_pydata(verts, [], faces)
    mesh.shade_smooth()


def _material(light) -> bpy.types.Material:
    material = bpy.data.materials.new("Phong Demo")
    tree = compat.new_material_tree(material)
    tree.nodes.clear()
    point = tree.nodes.new("ShaderNodeGroup")
    point.node_tree, _ = loader.ensure_group("Phong Point Light")
    point.inputs["Position"].default_value = light.location
    point.inputs["Intensity"].default_value = 20.0
    point.location = (-300, 0)
    shading = tree.nodes.new("ShaderNodeGroup")
    shading.node_tree, _ = loader.ensure_group("Phong Shading")
    shading.inputs["Object Color"].default_value = (*OBJECT_COLOR, 1.0)
    shading.inputs["Exponent"].default_value = 30.0
    shading.inputs["Ambient Intensity"].default_value = 0.15
    tree.links.new(point.outputs["Light Vector"], shading.inputs["Light Vector"])
    tree.links.new(point.outputs["Intensity"], shading.inputs["Light Intensity"])
    output = tree.nodes.new("ShaderNodeOutputMaterial")
    output.location = (300, 0)
    tree.links.new(shading.outputs["Shader"], output.inputs["Surface"])
    return material


def render(scene, engine: str, path: str, samples: int = 16) -> None:
    """Render *scene* with *engine* ('CYCLES' or 'EEVEE') to a PNG, written atomically."""
    if engine == "CYCLES":
        scene.render.engine = "CYCLES"
        scene.cycles.device = "CPU"
        scene.cycles.samples = samples
        scene.cycles.use_denoising = False
    else:
        scene.render.engine = compat.eevee_engine()
        scene.eevee.taa_render_samples = samples
    compat.set_png(scene.render.image_settings)
    folder = os.path.dirname(os.path.abspath(path))
    os.makedirs(folder, exist_ok=True)
    fd, tmp = tempfile.mkstemp(suffix=".png", dir=folder, prefix=".partial-")
    os.close(fd)
    try:
        scene.render.filepath = tmp
        with bpy.context.temp_override(scene=scene):
            bpy.ops.render.render(write_still=True, scene=scene.name)
        os.replace(tmp, path)
    finally:
        if os.path.exists(tmp):
            os.remove(tmp)
