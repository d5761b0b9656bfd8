# SPDX-License-Identifier: GPL-3.0-or-later
"""VRML97 / X3D export (issue 36; addon/interchange/x3d_export.py).

Import → export → import keeps names and values (materials' controls and lights' settings bit
for bit as float32, transforms, light sets, the camera's view, the headlight) for the
hand-written files and the real files of tests/data/x3d, in every encoding (.x3d, .x3dv,
.wrl, gzipped); a scene made in Blender in the seeds' model is written with the values X3D
can say (read back here with ``core.x3d`` and checked against values worked out by hand) and
one warning saying it is mapped, plus a warning for each value it cannot say.
"""

from __future__ import annotations

import math
import os

import numpy as np
import pytest

import blender_env as be
from phong_nodes.core import x3d

DATA = os.path.join(os.path.dirname(os.path.abspath(__file__)), "data", "x3d")
F32 = np.float32
CONTROLS = ("phong_object_color", "phong_specular_color", "phong_irradiant_color",
            "phong_exponent", "phong_ambient_color", "phong_opacity")
LIGHT_KEYS = ("phong_intensity", "phong_light_ambient", "phong_constant", "phong_linear",
              "phong_quadratic", "phong_radius", "phong_beam_width")


class _Points:
    """World-space corners, equal to another's when they match as sets within 1e-4 of the
    scene's size (float32 positions written as decimals and turned twice)."""

    def __init__(self, points):
        self.points = np.array(points, dtype=np.float64).reshape(-1, 3)

    def __eq__(self, other):
        a, b = self.points, other.points
        if a.shape != b.shape:
            return False
        if not len(a):
            return True
        tolerance = 1e-4 * (1.0 + float(np.abs(a).max()))
        for part in np.array_split(a, max(1, len(a) // 512)):   # each near one of the other's
            nearest = np.sqrt(((part[:, None, :] - b[None, :, :]) ** 2).sum(-1)).min(axis=1)
            if nearest.max() > tolerance:
                return False
        return True

    def __repr__(self):
        return f"_Points({len(self.points)})"


class _Close:
    """An array equal to another within 1e-5 (float32 transforms written as decimals)."""

    def __init__(self, values):
        self.values = np.asarray(values, dtype=np.float64)

    def __eq__(self, other):
        return self.values.shape == other.values.shape and bool(
            np.allclose(self.values, other.values, rtol=0.0, atol=1e-5))

    def __repr__(self):
        return f"_Close({np.round(self.values, 6).tolist()})"


def _value(node):
    value = node.outputs[0].default_value
    return tuple(F32(value)[:3]) if hasattr(value, "__len__") else F32(value)


def _state(bpy):
    """Names and values: objects (matrix to 1e-5: float32 transforms written as decimals),
    their materials, lights (settings, colour, cone, receivers), the materials' controls
    (exact float32), the camera's view and every mesh's world-space face corners."""
    objects, materials = {}, {}
    scene = bpy.context.scene
    for obj in bpy.data.objects:
        entry = {"type": obj.type, "hide": obj.hide_render}
        matrix = np.array(obj.matrix_world)
        if obj.type == "LIGHT":   # its place and axis (a light's roll means nothing)
            matrix = np.concatenate([matrix[:3, 3], -matrix[:3, 2]])
            if obj.data.type == "SUN":
                matrix[:3] = 0.0   # a directional light has no place in the file
        entry["matrix"] = _Close(matrix)
        if obj.type == "MESH":
            mesh = obj.data
            entry["materials"] = [s.material.name for s in obj.material_slots]
            corners = [tuple(obj.matrix_world @ mesh.vertices[i].co)
                       for p in mesh.polygons for i in p.vertices]
            corners += [tuple(obj.matrix_world @ mesh.vertices[i].co)
                        for e in mesh.edges if e.is_loose for i in e.vertices]
            entry["faces"] = (len(mesh.polygons), sum(e.is_loose for e in mesh.edges))
            entry["corners"] = _Points(corners)
        if obj.type == "LIGHT":
            data = obj.data
            entry["settings"] = {k: float(data[k]) for k in LIGHT_KEYS}
            entry["color"] = tuple(F32(data.color))
            entry["cone"] = F32(getattr(data, "spot_size", 0.0))
            collection = obj.light_linking.receiver_collection
            entry["receivers"] = sorted(o.name for o in collection.objects) if collection \
                else None
        objects[obj.name] = entry
    for material in bpy.data.materials:
        nodes = material.node_tree.nodes
        materials[material.name] = {k: _value(nodes[k]) for k in CONTROLS if k in nodes}
        materials[material.name]["unlit"] = bool(material.get("phong_x3d_unlit"))
        texture = nodes.get("phong_x3d_texture")
        materials[material.name]["texture"] = texture.image.name if texture else None
    camera = scene.camera.data
    render = scene.render
    aspect = render.resolution_x / render.resolution_y
    if camera.type == "ORTHO":   # the width and height it shows
        fit = camera.sensor_fit if camera.sensor_fit != "AUTO" else (
            "HORIZONTAL" if aspect >= 1 else "VERTICAL")
        width = camera.ortho_scale if fit == "HORIZONTAL" else camera.ortho_scale * aspect
        view = ("ORTHO", round(width, 5), round(width / aspect, 5))
    else:
        view = ("PERSP", round(min(camera.angle_x if camera.sensor_fit != "VERTICAL" else
                                   2 * math.atan(math.tan(camera.angle_y / 2) * aspect),
                                   10.0), 5))
    return objects, materials, (scene.camera.name, view)


REAL = sorted(n for n in os.listdir(DATA) if n.endswith((".wrl", ".x3d", ".x3dv")))
#: the largest of them, round-tripped in the slow run (CI's `test --all -m slow`) only
SLOW_REAL = {"hand_rules.x3dv", "hand_scope.wrl", "threejs_camera.wrl",
             "threejs_meshWithTexture.wrl", "x3dom_Drum55Gallon.x3d"}


@pytest.mark.parametrize("name", [pytest.param(n, marks=pytest.mark.slow) if n in SLOW_REAL
                                  else n for n in REAL])
def test_import_export_import_keeps_names_and_values(bpy_clean, tmp_path, name):
    bpy = bpy_clean
    scene = bpy.context.scene
    scene.render.resolution_x, scene.render.resolution_y = 160, 120
    assert bpy.ops.phong.import_x3d(filepath=os.path.join(DATA, name)) == {"FINISHED"}
    first = _state(bpy)
    for ending in (".x3d", ".wrl", ".x3dv", ".x3dz"):
        out = tmp_path / f"out{ending}"
        assert bpy.ops.phong.export_x3d(filepath=str(out)) == {"FINISHED"}
        be.reset_empty_file()
        scene = bpy.context.scene
        scene.render.resolution_x, scene.render.resolution_y = 160, 120
        assert bpy.ops.phong.import_x3d(filepath=str(out)) == {"FINISHED"}
        again = _state(bpy)
        assert again[2] == first[2], (ending, "camera")
        assert again[1] == first[1], (ending, "materials")
        assert sorted(again[0]) == sorted(first[0]), (ending, "object names")
        for key, entry in first[0].items():
            assert again[0][key] == entry, (ending, key)


@pytest.mark.slow
def test_textures_colours_unlit_off_lights_and_shears_survive_a_round_trip(bpy_clean, tmp_path):
    from test_x3d_import import LIGHTS, TEXTURED, png, write  # noqa: PLC0415

    bpy = bpy_clean
    png(tmp_path / "rgb.png", np.tile([51, 102, 153], (4, 4, 1)))
    png(tmp_path / "grey.png", np.full((4, 4), 128))
    shear = ("#VRML V2.0 utf8\nTransform { translation 1 2 3 scale 2 1 1 scaleOrientation "
             "0 0 1 0.5 children DEF Skew Shape { geometry Box { } } }\n")
    for text, name in ((TEXTURED, "textured.x3dv"), (LIGHTS, "lights.x3dv"),
                       (shear, "shear.wrl")):
        be.reset_empty_file()
        assert bpy.ops.phong.import_x3d(filepath=write(tmp_path, name, text)) == {"FINISHED"}
        first = _state(bpy)
        for ending in (".x3d", ".wrl"):
            out = tmp_path / "sub" / f"out{ending}"   # textures found relative to it
            out.parent.mkdir(exist_ok=True)
            assert bpy.ops.phong.export_x3d(filepath=str(out)) == {"FINISHED"}
            if name == "textured.x3dv":
                assert "../rgb.png" in out.read_text()
            be.reset_empty_file()
            assert bpy.ops.phong.import_x3d(filepath=str(out)) == {"FINISHED"}
            again = _state(bpy)
            if name == "textured.x3dv" and ending == ".wrl":   # no OrthoViewpoint in VRML97
                assert again[2][1][0] == "PERSP" and first[2][1][0] == "ORTHO"
                again = (again[0], again[1], first[2])
            assert again == first, (name, ending)


def _seeds_scene(bpy):
    """A scene made in Blender, in the seeds' model: three cubes with Phong materials, four
    lights (one linked to one cube), the World's ambient light, a camera."""
    from mathutils import Vector  # noqa: PLC0415

    scene = bpy.context.scene
    scene.render.resolution_x, scene.render.resolution_y = 200, 100
    world = bpy.data.worlds.new("World")
    scene.world = world
    world.phong.ambient_intensity = 0.1
    world.phong.ambient_color = (1.0, 0.5, 0.25)
    cubes = []
    for index, name in enumerate(("Plain", "Own Ka", "Odd Ka")):
        mesh = bpy.data.meshes.new(name)
        mesh.from_pydata([(0, 0, 0), (1, 0, 0), (1, 1, 0), (0, 1, 0)], [], [(0, 1, 2, 3)])
        mesh.materials.append(bpy.data.materials.new(name))   # its own source material
        obj = bpy.data.objects.new(name, mesh)
        obj.location = (3.0 * index, 2.0, 1.0)
        scene.collection.objects.link(obj)
        cubes.append(obj)

    def light(name, kind, location):
        obj = bpy.data.objects.new(name, bpy.data.lights.new(name, kind))
        obj.location = location
        scene.collection.objects.link(obj)
        return obj

    point = light("Bulb", "POINT", (1.0, 2.0, 3.0))
    spot = light("Beam", "SPOT", (0.0, 0.0, 5.0))
    spot.data.spot_size = math.radians(60.0)
    sun = light("Sky", "SUN", (0.0, 0.0, 9.0))
    local = light("Local", "POINT", (5.0, 0.0, 2.0))
    camera = bpy.data.objects.new("Cam", bpy.data.cameras.new("Cam"))
    camera.location = (0.0, -8.0, 2.0)
    camera.rotation_euler = (Vector((0, 0, 1)) - camera.location).to_track_quat("-Z", "Y") \
        .to_euler()
    camera.data.lens, camera.data.sensor_width, camera.data.sensor_fit = 50.0, 36.0, "AUTO"
    scene.collection.objects.link(camera)
    scene.camera = camera
    be.apply_phong(scene, cubes)
    for obj, (kd, exponent) in zip(cubes, (((0.8, 0.4, 0.2), 200.0), ((0.5, 0.5, 0.25), 64.0),
                                           ((0.2, 0.4, 0.6), 32.0))):
        material = obj.material_slots[0].material
        nodes = material.node_tree.nodes
        nodes["phong_object_color"].outputs[0].default_value = (*kd, 1.0)
        nodes["phong_exponent"].outputs[0].default_value = exponent
        nodes["phong_specular_color"].outputs[0].default_value = (0.5, 0.5, 0.5, 1.0)
    from phong_nodes.addon.lighting import materials  # noqa: PLC0415

    for obj, ka in ((cubes[1], (0.25, 0.25, 0.125)), (cubes[2], (0.3, 0.1, 0.1))):
        material = obj.material_slots[0].material
        tree = material.node_tree
        node = materials.color_control(tree, materials.AMBIENT_CONTROL, ka)
        tree.links.new(node.outputs[0], tree.nodes[materials.LIGHTS_NODE].inputs[
            materials.AMBIENT_INPUT])
    point.data.phong.intensity = 2.0
    point.data.phong.constant, point.data.phong.linear, point.data.phong.quadratic = \
        0.5, 0.25, 0.125
    spot.data.phong.edge_exponent = 2.0
    linked = bpy.data.collections.new("only plain")
    linked.objects.link(cubes[0])
    local.light_linking.receiver_collection = linked
    sun.light_linking.receiver_collection = linked
    bpy.context.view_layer.update()
    assert bpy.ops.phong.relink_lights() == {"FINISHED"}
    assert bpy.ops.phong.add_headlight() == {"FINISHED"}
    return cubes


def _read(path):
    doc = x3d.load(str(path))
    lights = {inst.light.name: inst for inst in doc.lights}
    shapes = {inst.path[-1]: inst for inst in doc.instances}
    return doc, lights, shapes


@pytest.mark.slow
@pytest.mark.parametrize("ending", [".x3d", ".wrl"])
def test_a_blender_scene_in_the_seeds_model_is_written_mapped(bpy_clean, tmp_path, capfd,
                                                               ending):
    bpy = bpy_clean
    _seeds_scene(bpy)
    out = tmp_path / f"scene{ending}"
    capfd.readouterr()
    assert bpy.ops.phong.export_x3d(filepath=str(out)) == {"FINISHED"}
    logged = capfd.readouterr().out
    assert logged.count("is in the seeds lighting model, not X3D / VRML97") == 1
    assert "Exponent 200 above X3D's 128" in logged
    assert "material Phong Odd Ka: Ambient Color (0.3, 0.1, 0.1) is not a multiple" in logged
    assert "the soft edge (Edge Exponent) written as a hard cone" in logged
    doc, lights, shapes = _read(out)
    assert doc.headlight is True and "Headlight" not in lights, "the headlight as itself"
    # materials: Kd, Ks; shininess = exponent / 128 (200: clamped to 1); ambientIntensity:
    # Ka = Kd (the seeds' default) → 1, Ka = ½ Kd → 0.5, not a multiple → the nearest:
    # (0.3, 0.1, 0.1)·(0.2, 0.4, 0.6) / |(0.2, 0.4, 0.6)|² = 0.16 / 0.56
    plain, own, odd = (shapes[n].shape.material for n in ("Plain", "Own Ka", "Odd Ka"))
    assert (plain.diffuse, plain.shininess, plain.ambient_intensity) == ((0.8, 0.4, 0.2), 1, 1)
    assert plain.specular == (0.5, 0.5, 0.5) and plain.name.startswith("Phong Plain")
    assert (own.shininess, own.ambient_intensity) == (0.5, 0.5)
    assert odd.ambient_intensity == pytest.approx(0.16 / 0.56, rel=1e-6)
    # lights in Y up: Blender (x, y, z) → file (x, z, −y)
    bulb = lights["Bulb"]
    assert bulb.world_location() == pytest.approx((1, 3, -2), abs=1e-6)
    assert (bulb.light.intensity, bulb.light.attenuation) == (2.0, (0.5, 0.25, 0.125))
    assert bulb.light.radius == 1e6, "the seeds' model has no radius"
    beam = lights["Beam"]
    assert beam.world_direction() == pytest.approx((0, -1, 0), abs=1e-6)
    assert beam.light.cut_off_angle == pytest.approx(math.radians(30.0), abs=1e-7)
    assert beam.light.beam_width == beam.light.cut_off_angle, "a hard cone"
    ambient = lights["WorldAmbient"]   # the World's ambient light: the same ambient term
    assert (ambient.light.intensity, ambient.light.ambient_intensity, ambient.light.color) == \
        (0.0, pytest.approx(0.1), (1.0, 0.5, 0.25))
    assert ambient.scope is None if ending == ".x3d" else ambient.scope == range(0, 3)
    # Light Linking: the sun and the point light reach only "Plain"
    sky = lights["Sky"]
    assert [doc.instances[i].path[-1] for i in sky.scope] == ["Plain"]
    if ending == ".x3d":
        assert [doc.instances[i].path[-1] for i in lights["Local"].scope] == ["Plain"]
    else:
        assert lights["Local"].scope is None, "VRML97: point lights light everything"
        assert "light-linked point and spot lights written global" in logged
    # the camera: 200 × 100 at lens 50 on a 36 mm sensor (AUTO: the width) sees
    # 2·atan(18/50) across and 2·atan(9/50) up: X3D's fieldOfView is the smaller
    vp = doc.viewpoint
    assert vp.name == "Cam" and vp.field_of_view == pytest.approx(2 * math.atan(9 / 50),
                                                                   rel=1e-6)
    assert vp.position == pytest.approx((0, 2, 8), abs=1e-6)


def test_an_orthographic_camera_and_export_errors(bpy_clean, tmp_path):
    bpy = bpy_clean
    scene = bpy.context.scene
    scene.render.resolution_x, scene.render.resolution_y = 100, 200
    camera = bpy.data.objects.new("Top", bpy.data.cameras.new("Top"))
    camera.data.type, camera.data.ortho_scale = "ORTHO", 8.0   # AUTO: the taller side
    scene.collection.objects.link(camera)
    scene.camera = camera
    assert bpy.ops.phong.export_x3d(filepath=str(tmp_path / "top.x3d")) == {"FINISHED"}
    vp = x3d.load(str(tmp_path / "top.x3d")).viewpoint
    assert vp.kind == "OrthoViewpoint" and vp.ortho_field == (-2, -4, 2, 4)
    with pytest.raises(RuntimeError, match="not an X3D or VRML file name"):
        bpy.ops.phong.export_x3d(filepath=str(tmp_path / "scene.obj"))
    with pytest.raises(RuntimeError, match="not a file in an existing folder"):
        bpy.ops.phong.export_x3d(filepath=str(tmp_path / "nowhere" / "scene.x3d"))
    assert sorted(os.listdir(tmp_path)) == ["top.x3d"]


@pytest.mark.parametrize("name", ["near.x3d", "near.x3dv", "near.wrl"])
def test_a_near_camera_writes_the_avatar_size_browsers_clip_by(bpy_clean, tmp_path, name):
    """X3D browsers clip what is nearer to the viewer than NavigationInfo's avatarSize[0] / 2
    (0.125 by default; X_ITE 15's getNearValue): a camera whose clip start is nearer (a small
    part framed by phong compare, or Blender's default 0.1) gets avatarSize = 2 x clip start;
    one at 0.125 or beyond writes none (the browsers' default)."""
    import re  # noqa: PLC0415

    bpy = bpy_clean
    scene = bpy.context.scene
    camera = bpy.data.objects.new("Close", bpy.data.cameras.new("Close"))
    scene.collection.objects.link(camera)
    scene.camera = camera
    written = {}
    for clip in (0.01, 0.5):
        camera.data.clip_start = clip
        path = tmp_path / f"{clip}_{name}"
        assert bpy.ops.phong.export_x3d(filepath=str(path)) == {"FINISHED"}
        text = path.read_text()
        found = re.search(r"avatarSize\W+([0-9.eE+-]+)", text)
        written[clip] = float(found.group(1)) if found else None
    assert written[0.01] == pytest.approx(0.02, rel=1e-6)
    assert written[0.5] is None


def test_gzipped_export_is_gzip(bpy_clean, tmp_path):
    bpy = bpy_clean
    assert bpy.ops.phong.import_x3d(filepath=os.path.join(DATA, "hand_scope.wrl")) == \
        {"FINISHED"}
    for name in ("a.wrz", "a.x3dz", "a.x3dvz", "a.wrl.gz"):
        assert bpy.ops.phong.export_x3d(filepath=str(tmp_path / name)) == {"FINISHED"}
        assert (tmp_path / name).read_bytes()[:2] == b"\x1f\x8b"
        doc = x3d.load(str(tmp_path / name))
        assert doc.encoding == ("vrml97" if "wr" in name else "x3d-xml" if name == "a.x3dz"
                                else "x3d-classic")
        assert len(doc.instances) == 5 and doc.headlight is False
