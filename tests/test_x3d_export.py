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
        mesh.materials.append(be.plain_source(name))   # its own source material
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
    from phong_nodes.addon.lighting import recipe, writer  # noqa: PLC0415
    from phong_nodes.addon.lighting import feeds as feed_reader

    for obj, ka in ((cubes[1], (0.25, 0.25, 0.125)), (cubes[2], (0.3, 0.1, 0.1))):
        material = obj.material_slots[0].material
        tree = material.node_tree
        node = writer.color_control(tree, recipe.AMBIENT_CONTROL, ka)
        tree.links.new(node.outputs[0], tree.nodes[recipe.LIGHTS_NODE].inputs[
            recipe.AMBIENT_INPUT])
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


PIXEL_FILE = """#X3D V3.3 utf8
PROFILE Interchange
Shape {
  appearance Appearance {
    material DEF Label Material { diffuseColor 0.5 0.25 1 }
    texture DEF Checker PixelTexture { image 2 2 2 0xFF80 0x0040 0x80FF 0x40C0 repeatS FALSE repeatT FALSE }
  }
  geometry IndexedFaceSet { coord Coordinate { point [ 0 0 0, 1 0 0, 1 1 0, 0 1 0 ] }
    coordIndex [ 0 1 2 3 -1 ] texCoord TextureCoordinate { point [ 0 0, 1 0, 1 1, 0 1 ] }
    texCoordIndex [ 0 1 2 3 -1 ] }
}
Transform { translation 2 0 0 children Shape {
  appearance Appearance {
    material DEF Paint Material { diffuseColor 0.1 0.2 0.3 }
    texture DEF Stripes PixelTexture { image 3 1 3 0xFF0000 0x00FF00 0x102030 }
  }
  geometry IndexedFaceSet { coord Coordinate { point [ 0 0 0, 1 0 0, 1 1 0, 0 1 0 ] }
    coordIndex [ 0 1 2 3 -1 ] texCoord TextureCoordinate { point [ 0 0, 1 0, 1 1, 0 1 ] }
    texCoordIndex [ 0 1 2 3 -1 ] }
} }
"""


def _pixel_textures(path):
    """{DEF: (width, height, components, [texels], repeatS)} of the PixelTextures in the
    written file *path*, read from its text here (XML attributes, or the classic encodings'
    ``DEF name PixelTexture { image w h c texel ... }``), not by the importer."""
    import gzip
    import re
    import xml.etree.ElementTree as ET
    raw = open(path, "rb").read()
    text = (gzip.decompress(raw) if raw[:2] == b"\x1f\x8b" else raw).decode("utf-8")
    out = {}
    if path.endswith(".x3d"):
        for node in ET.fromstring(text).iter("PixelTexture"):
            numbers = [int(v, 0) for v in node.get("image").replace(",", " ").split()]
            out[node.get("DEF")] = (*numbers[:3], numbers[3:],
                                    node.get("repeatS", "true").lower() == "true")
        return out
    for match in re.finditer(r"DEF\s+(\S+)\s+PixelTexture\s*\{([^}]*)\}", text):
        body = match.group(2)
        image = re.search(r"image\s+([-0-9xXa-fA-F\s,]+)", body).group(1)
        numbers = [int(v, 0) for v in image.replace(",", " ").split()]
        repeat = re.search(r"repeatS\s+(TRUE|FALSE)", body)
        out[match.group(1)] = (*numbers[:3], numbers[3:], repeat is None or
                               repeat.group(1) == "TRUE")
    return out


@pytest.mark.parametrize("suffix", [".x3d", ".x3dv", ".wrl", ".wrz"])
def test_an_inline_image_is_written_as_a_pixel_texture(bpy_clean, tmp_path, suffix):
    """An image without a file (an imported PixelTexture, packed; an image generated in
    Blender) is written as a PixelTexture with its texels, in every encoding: the file's
    texels and components exactly (read from the written text here), the image generated
    in Blender with the components its texels need; import → export → import keeps them."""
    bpy = bpy_clean
    source = tmp_path / "pixels.x3dv"
    source.write_text(PIXEL_FILE)
    assert bpy.ops.phong.import_x3d(filepath=str(source)) == {"FINISHED"}
    from phong_nodes.addon.lighting import recipe, writer
    from phong_nodes.addon.lighting import feeds as feed_reader
    paint = bpy.data.materials["Paint"]
    generated = bpy.data.images.new("Made", 2, 1, alpha=True)
    generated.colorspace_settings.name = "Non-Color"
    generated.pixels[:] = [0.2, 0.2, 0.2, 1.0, 0.6, 0.6, 0.6, 0.5]
    feeds = feed_reader.feeds(paint)
    node = feeds["Object Color"].texture
    assert node is not None and node.image.name == "Stripes"
    out = str(tmp_path / f"out{suffix}")
    assert bpy.ops.phong.export_x3d(filepath=out) == {"FINISHED"}
    written = _pixel_textures(out)
    assert written["Checker"] == (2, 2, 2, [0xFF80, 0x0040, 0x80FF, 0x40C0], False)
    assert written["Stripes"] == (3, 1, 3, [0xFF0000, 0x00FF00, 0x102030], True)
    # an image made in Blender, without a file: grey with alpha, 2 components
    node.image = generated
    assert bpy.ops.phong.export_x3d(filepath=out) == {"FINISHED"}
    written = _pixel_textures(out)
    assert written["Made"] == (2, 1, 2, [0x33FF, 0x9980], True)
    node.image = bpy.data.images["Stripes"]
    assert bpy.ops.phong.export_x3d(filepath=out) == {"FINISHED"}
    be.reset_empty_file()
    assert bpy.ops.phong.import_x3d(filepath=out) == {"FINISHED"}
    again = str(tmp_path / f"again{suffix}")
    assert bpy.ops.phong.export_x3d(filepath=again) == {"FINISHED"}
    assert _pixel_textures(again) == _pixel_textures(out)
    assert set(_pixel_textures(again)) == {"Checker", "Stripes"}


REUSED = """#VRML V2.0 utf8
NavigationInfo { headlight FALSE }
PROTO Pin [ field SFColor col 1 0 0 field SFVec3f at 0 0 0 ] {
  Transform { translation IS at children Shape {
    appearance Appearance { material DEF Mat Material { diffuseColor IS col } }
    geometry Box { } } }
}
Pin { col 0 1 0 at 0 -3 0 }
Pin { col 0 0 1 at 3 -3 0 }
Transform { children [
  DEF Sun DirectionalLight { direction 0 0 -1 intensity 0.7 ambientIntensity 0.4 color 1 0.5 0.25 }
  Shape { appearance Appearance { material DEF PIN-01 Material { diffuseColor 0.8 0.8 0.1 } }
          geometry Box { } } ] }
Transform { translation 3 0 0 children Shape {
  appearance Appearance { material USE PIN-01 } geometry Box { } } }
Transform { translation 6 0 0 rotation 0 1 0 1.5708 children [
  USE Sun
  Shape { appearance Appearance { material DEF PIN-01 Material {
            diffuseColor 0.1 0.2 0.9 shininess 0.5 } } geometry Sphere { } } ] }
Transform { translation 9 0 0 children [
  USE Sun
  Shape { appearance Appearance { material USE PIN-01 } geometry Box { } } ] }
"""


def _written_materials(path):
    """[(exact name, diffuseColor)] of the Materials DEF'd in the written file *path*, read
    from its text here: the DEF names, mapped back through WorldInfo's exact names."""
    import re
    import xml.etree.ElementTree as ET
    text = open(path, encoding="utf-8").read()
    if path.endswith(".x3d"):
        root = ET.fromstring(text)
        found = [(m.get("DEF"), m.get("diffuseColor")) for m in root.iter("Material")
                 if m.get("DEF")]
        info = [v for w in root.iter("WorldInfo") for v in re.findall(r'"([^"]*)"',
                                                                       w.get("info", ""))]
    else:
        found = re.findall(r"DEF\s+(\S+)\s+Material\s*\{[^}]*?diffuseColor\s+([-0-9.e ]+)",
                           text)
        block = re.search(r"WorldInfo\s*\{[^}]*\}", text)
        info = re.findall(r'"([^"]*)"', block.group(0)) if block else []
    exact = dict(line[len(x3d.NAME_PREFIX):].split("=", 1) for line in info
                 if line.startswith(x3d.NAME_PREFIX))
    return sorted((exact.get(name, name), tuple(round(float(v), 6) for v in colour.split()))
                  for name, colour in found)


@pytest.mark.parametrize("suffix", [".x3d", ".x3dv", ".wrl"])
def test_reused_def_names_and_proto_materials_keep_each_material(bpy_clean, tmp_path,
                                                                 suffix):
    """A file that defines PIN-01 twice (each USE'd after it) and instantiates a PROTO with
    its own Material twice: every Material is its own Phong material with its own values,
    under the file's name and Blender's .001 (PIN-01, PIN-01.001, Mat, Mat.001), each on the
    shapes that use it; the export writes each as its own Material whose exact name
    (WorldInfo) is that name (read from the written text here), and import → export →
    import gives the same materials on the same objects.  The DirectionalLight DEF'd in one
    group and USE'd in two others is one light per direction, each reaching its groups."""
    bpy = bpy_clean
    from phong_nodes.addon.lighting import recipe, writer
    from phong_nodes.addon.lighting import feeds as feed_reader
    source = tmp_path / "reused.wrl"
    source.write_text(REUSED)
    assert bpy.ops.phong.import_x3d(filepath=str(source)) == {"FINISHED"}

    def state():
        out = {}
        for m in bpy.data.materials:
            if recipe.is_phong_material(m):
                users = sorted(o.name for o in bpy.data.objects if o.type == "MESH"
                               and o.material_slots[0].material is m)
                out[m.name] = (tuple(round(v, 6) for v in
                                     feed_reader.feeds(m)["Object Color"].value), users)
        lights = []
        for o in bpy.data.objects:
            if o.type == "LIGHT":
                receivers = o.light_linking.receiver_collection
                lights.append(sorted(round(x.matrix_world.translation.x) for x in
                                     receivers.all_objects) if receivers else None)
        return out, sorted(lights)

    first, lights = state()
    # what the file says: the DEF'd Materials in order, with the PROTO
    # instances' colours for the PROTO's; a Material whose shapes differ in their light set
    # has a variant named after its own Phong material (PIN-01.001 [Sun], not PIN-01 [Sun])
    assert {n: v[0] for n, v in first.items()} == {
        "Mat": (0.0, 1.0, 0.0), "Mat.001": (0.0, 0.0, 1.0),
        "PIN-01": (0.8, 0.8, 0.1), "PIN-01 [no light]": (0.8, 0.8, 0.1),
        "PIN-01.001": (0.1, 0.2, 0.9), "PIN-01.001 [Sun]": (0.1, 0.2, 0.9)}
    x = {o.name: round(o.matrix_world.translation.x) for o in bpy.data.objects}
    assert {n: [x[o] for o in v[1]] for n, v in first.items()} == {
        "Mat": [0], "Mat.001": [3], "PIN-01": [0], "PIN-01 [no light]": [3],
        "PIN-01.001": [6], "PIN-01.001 [Sun]": [9]}
    # the Sun of the groups at x = 0 and 9 (one direction), and of the turned one at x = 6
    assert lights == [[0, 9], [6]]
    out = str(tmp_path / f"out{suffix}")
    assert bpy.ops.phong.export_x3d(filepath=out) == {"FINISHED"}
    assert _written_materials(out) == sorted((n, v[0]) for n, v in first.items())
    be.reset_empty_file()
    assert bpy.ops.phong.import_x3d(filepath=out) == {"FINISHED"}
    assert state() == (first, lights)


@pytest.mark.parametrize("suffix", [".x3d", ".x3dv", ".wrl"])
def test_the_worlds_ambient_light_comes_back_to_the_world(bpy_clean, tmp_path, suffix):
    """The World's Phong ambient light (which X3D lacks) is written as the DirectionalLight
    WorldAmbient of intensity 0 whose ambientIntensity and colour are the World's (read from
    the written text here), and read back into the World (intensity and colour as float32),
    not as a light; a file's own lights keep their ambientIntensity as lights and leave the
    World's ambient at 0."""
    import re
    bpy = bpy_clean
    _seeds_scene(bpy)
    out = str(tmp_path / f"out{suffix}")
    assert bpy.ops.phong.export_x3d(filepath=out) == {"FINISHED"}
    text = open(out, encoding="utf-8").read()
    if suffix == ".x3d":
        block = re.search(r'<DirectionalLight[^>]*DEF="WorldAmbient"[^>]*>', text).group(0)
        fields = dict(re.findall(r'(\w+)="([^"]*)"', block))
    else:
        block = re.search(r"DEF WorldAmbient DirectionalLight\s*\{([^}]*)\}", text).group(1)
        fields = dict(re.findall(r"(\w+)\s+([-0-9.e ]+?)\s*(?=\n|$)", block))
    assert float(fields["intensity"]) == 0.0
    assert float(fields["ambientIntensity"]) == pytest.approx(0.1)
    assert [float(v) for v in fields["color"].split()] == [1.0, 0.5, 0.25]
    be.reset_empty_file()
    assert bpy.ops.phong.import_x3d(filepath=out) == {"FINISHED"}
    world = bpy.context.scene.world
    assert world.phong.ambient_intensity == F32(0.1)
    assert tuple(world.phong.ambient_color) == (1.0, 0.5, 0.25)
    assert "WorldAmbient" not in bpy.data.objects
    names = sorted(o.name for o in bpy.data.objects if o.type == "LIGHT")
    assert [n for n in names if n != "Headlight"] == ["Beam", "Bulb", "Local", "Sky"]
    # a file whose lights carry ambientIntensity: lights, and the World's ambient 0
    be.reset_empty_file()
    source = tmp_path / "lamps.wrl"
    source.write_text("#VRML V2.0 utf8\nNavigationInfo { headlight FALSE }\n"
                      "DEF Lamp PointLight { intensity 0 ambientIntensity 0.4 }\n"
                      "DEF Key DirectionalLight { intensity 0.5 ambientIntensity 0.25 }\n"
                      "Shape { geometry Box { } }\n")
    assert bpy.ops.phong.import_x3d(filepath=str(source)) == {"FINISHED"}
    assert bpy.context.scene.world.phong.ambient_intensity == 0.0
    lights = {o.name: o.data for o in bpy.data.objects if o.type == "LIGHT"}
    assert sorted(lights) == ["Key", "Lamp"]
    assert lights["Lamp"].phong.ambient == F32(0.4) and lights["Key"].phong.ambient == F32(0.25)


@pytest.mark.parametrize("suffix", [".x3d", ".x3dv", ".wrl"])
def test_a_missing_texture_keeps_its_reference(bpy_clean, tmp_path, suffix):
    """A file received without its texture: the import leaves the texture out of the picture
    (the diffuse colour, as X3D browsers show a texture they cannot load) and keeps its
    reference; the export writes the ImageTexture again with its url relative to the written
    file (read from the text here), and a shape of the same Material without a texture stays
    without one (its own material, "[no texture]")."""
    import re
    bpy = bpy_clean
    from phong_nodes.addon.lighting import recipe, writer
    from phong_nodes.addon.lighting import feeds as feed_reader
    source = tmp_path / "received" / "part.wrl"
    source.parent.mkdir()
    source.write_text("""#VRML V2.0 utf8
Shape { appearance Appearance { material DEF Label Material { diffuseColor 0.5 0.25 1 }
          texture DEF Print ImageTexture { url "maps/print.png" repeatS FALSE repeatT FALSE } }
        geometry Box { } }
Transform { translation 3 0 0 children Shape { appearance Appearance { material USE Label }
                                                geometry Box { } } }
""")
    assert bpy.ops.phong.import_x3d(filepath=str(source)) == {"FINISHED"}
    names = sorted(m.name for m in bpy.data.materials if recipe.is_phong_material(m))
    assert names == ["Label", "Label [no texture]"]
    label = bpy.data.materials["Label"]
    assert feed_reader.feeds(label)["Object Color"].value == (0.5, 0.25, 1.0)
    assert feed_reader.feeds(label)["Object Color"].other is None   # not in the picture
    out = tmp_path / "elsewhere" / f"out{suffix}"
    out.parent.mkdir()
    assert bpy.ops.phong.export_x3d(filepath=str(out)) == {"FINISHED"}
    text = out.read_text()
    found = re.findall(r'<ImageTexture[^>]*url="&quot;([^&]+)&quot;', text) if \
        suffix == ".x3d" else re.findall(r'ImageTexture\s*\{[^}]*?url\s*\[?\s*"([^"]+)"', text)
    assert found == ["../received/maps/print.png"], text
    be.reset_empty_file()
    assert bpy.ops.phong.import_x3d(filepath=str(out)) == {"FINISHED"}
    assert sorted(m.name for m in bpy.data.materials if recipe.is_phong_material(m)) == \
        names
    again = bpy.data.materials["Label"]
    assert feed_reader.feeds(again)["Object Color"].value == (0.5, 0.25, 1.0)
    assert str(tmp_path / "received" / "maps" / "print.png") in \
        list(again["phong_x3d_missing_texture"]["paths"])
