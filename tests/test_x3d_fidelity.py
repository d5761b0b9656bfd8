# SPDX-License-Identifier: GPL-3.0-or-later
"""What VRML97 / X3D files say that the importer and exporter keep (issue 42): lights under a
scaled Transform attenuate by the distance in their own coordinate system (rendered by Cycles
against the standard's equation computed here by hand), the file's material names survive an
export for any reader, a texture's alpha is the material's opacity, ``solid`` is the
material's Backface Culling, each both ways."""

from __future__ import annotations

import math
import os
import re

import numpy as np
import pytest

import blender_env as be
from test_x3d_import import DATA, png, write

# -- lights under a scaled Transform ----------------------------------------------------------

#: A floor 8 × 6 in the file's XZ plane seen from above by an orthographic view; a point
#: light under a Transform of scale 2.5 and a spot light under one of scale 0.4.
SCALED_LIGHTS = """#X3D V3.3 utf8
PROFILE Immersive
NavigationInfo { headlight FALSE }
OrthoViewpoint { position 0 10 0 orientation 1 0 0 -1.5707963 fieldOfView -4 -3 4 3 }
DEF Floor Shape {
  appearance Appearance { material DEF Ground Material { diffuseColor 0.8 0.7 0.6
    ambientIntensity 0.2 specularColor 0.3 0.3 0.3 shininess 0.2 } }
  geometry IndexedFaceSet { coord Coordinate { point [ -4 0 -3, 4 0 -3, 4 0 3, -4 0 3 ] }
    coordIndex [ 0 3 2 1 -1 ] }
}
Transform { translation -2 0 0.5 scale 2.5 2.5 2.5 children [
  DEF Bulb PointLight { location 0.1 0.6 0 intensity 0.9 ambientIntensity 0.1
                        color 1 0.9 0.8 attenuation 0.5 0.8 0.6 radius 1.2 }
] }
Transform { translation 2 0 -0.5 scale 0.4 0.4 0.4 children [
  DEF Cone SpotLight { location 0 5 0 direction 0.2 -1 0 beamWidth 0.4 cutOffAngle 0.8
                       intensity 0.8 ambientIntensity 0.15 color 0.8 0.9 1
                       attenuation 0.2 0.3 0.05 radius 8 }
] }
"""
#: The lights as the file states them: (translation, scale, location, direction or None,
#: intensity, ambientIntensity, colour, attenuation, radius, beamWidth, cutOffAngle).
LIGHTS = (
    ((-2.0, 0.0, 0.5), 2.5, (0.1, 0.6, 0.0), None, 0.9, 0.1, (1.0, 0.9, 0.8),
     (0.5, 0.8, 0.6), 1.2, None, None),
    ((2.0, 0.0, -0.5), 0.4, (0.0, 5.0, 0.0), (0.2, -1.0, 0.0), 0.8, 0.15, (0.8, 0.9, 1.0),
     (0.2, 0.3, 0.05), 8.0, 0.4, 0.8),
)
GROUND = {"diffuse": np.array([0.8, 0.7, 0.6]), "ambient": 0.2,
          "specular": np.array([0.3, 0.3, 0.3]), "shininess": 0.2}


def standard_equation(points):
    """X3D §17.2.2.4 for the floor (file coordinates, N = V = +Y, the view orthographic), each
    light's distance dL measured in the light's own coordinate system (the Transform's
    inverse applied to the point), as the standard says."""
    n = np.array([0.0, 1.0, 0.0])
    v = n
    total = np.zeros((len(points), 3))
    od, os_ = GROUND["diffuse"], GROUND["specular"]
    oa = GROUND["ambient"] * od
    for (move, scale, location, direction, intensity, ambient, colour, (a0, a1, a2), radius,
         beam, cut) in LIGHTS:
        local = (points - np.array(move)) / scale                 # the light's coordinates
        to_light = np.array(location) - local
        d = np.linalg.norm(to_light, axis=1)
        lv = to_light / d[:, None]                                # a direction: scale-free
        att = 1.0 / np.maximum(a0 + a1 * d + a2 * d * d, 1.0)
        inside = d <= radius
        spot = np.ones(len(points))
        if direction is not None:
            u = np.array(direction) / np.linalg.norm(direction)
            omega = np.arccos(np.clip(-(lv @ u), -1.0, 1.0))
            spot = np.clip((cut - omega) / (cut - beam), 0.0, 1.0)
        h = lv + v
        h /= np.linalg.norm(h, axis=1)[:, None]
        diffuse = np.maximum(lv @ n, 0.0)[:, None] * od
        highlight = np.maximum(h @ n, 0.0)[:, None] ** (128.0 * GROUND["shininess"]) * os_
        term = ambient * oa + intensity * (diffuse + highlight)
        total += (inside * att * spot)[:, None] * np.array(colour) * term
    return np.minimum(total, 1.0)


def _near_a_radius(points):
    """Pixels within 1e-3 of a light's radius (the hard edge may fall on either side)."""
    near = np.zeros(len(points), bool)
    for move, scale, location, *_rest in LIGHTS:
        radius = _rest[5]
        d = np.linalg.norm((points - np.array(move)) / scale - np.array(location), axis=1)
        near |= np.abs(d - radius) < 1e-3
    return near


def _render_floor(bpy, tmp_path, path, size=(80, 60)):
    """Import *path* into a new Cycles scene, probe the floor's positions, render: (file
    coordinates of the floor's pixels, their colours)."""
    from phong_scene import _add_probe_aovs, render  # noqa: PLC0415

    scene = be.new_scene("scaled lights", *size, "cycles")
    bpy.context.window.scene = scene
    assert bpy.ops.phong.import_x3d(filepath=str(path)) == {"FINISHED"}
    for name, kind in (("P", "COLOR"), ("N", "COLOR"), ("I", "COLOR"), ("id", "VALUE")):
        be.add_aov(scene, name, kind)
    floor = bpy.data.objects["Floor"]
    _add_probe_aovs(bpy, floor.active_material, 1)
    passes, _seconds = render(bpy, scene, str(tmp_path / "floor.exr"))
    hit = np.rint(passes["id"][..., 0]).astype(int) == 1
    blender = passes["P"][..., :3].astype(np.float64)[hit]
    points = np.stack([blender[:, 0], blender[:, 2], -blender[:, 1]], axis=1)  # Z up → Y up
    return scene, points, passes["Combined"][..., :3].astype(np.float64)[hit]


def _check_against_the_standard(points, got, label):
    keep = ~_near_a_radius(points)
    want = standard_equation(points[keep])
    error = np.abs(got[keep] - want).max(axis=1)
    be.report(f"[x3d scaled lights {label}] {keep.sum()} pixels, max |Δ| {error.max():.2e}, "
              f"{(error <= 1e-4).mean():.2%} within 1e-4")
    assert keep.sum() > 4000
    assert error.max() <= 1e-4, error.max()
    # the scene is one where a light's distance in the world would differ
    lit = want.max(axis=1) > 0.05
    assert lit.mean() > 0.5


@pytest.mark.cycles
def test_lights_under_a_scaled_transform_attenuate_in_their_own_coordinates(bpy_clean,
                                                                            tmp_path):
    """Cycles within 1e-4 of the standard's equation with dL measured in each light's
    coordinate system (scale 2.5 and 0.4); the values: a1 / s, a2 / s², radius × s."""
    bpy = bpy_clean
    path = write(tmp_path, "scaled_lights.x3dv", SCALED_LIGHTS)
    _scene, points, got = _render_floor(bpy, tmp_path, path)
    _check_against_the_standard(points, got, "import")
    for name, (_move, s, *_r, (a0, a1, a2), radius, _b, _c) in zip(("Bulb", "Cone"), LIGHTS):
        light = bpy.data.lights[name]
        assert light["phong_constant"] == pytest.approx(a0, rel=1e-6)
        assert light["phong_linear"] == pytest.approx(a1 / s, rel=1e-6)
        assert light["phong_quadratic"] == pytest.approx(a2 / (s * s), rel=1e-6)
        assert light["phong_radius"] == pytest.approx(radius * s, rel=1e-6)


@pytest.mark.cycles
def test_scaled_lights_survive_export_and_import(bpy_clean, tmp_path):
    """import → export (lights written in the world) → import: the same values and the same
    rendered pixels of the standard's equation."""
    bpy = bpy_clean
    from phong_nodes.addon.interchange import x3d_export  # noqa: PLC0415

    path = write(tmp_path, "scaled_lights.x3dv", SCALED_LIGHTS)
    scene, _points, _got = _render_floor(bpy, tmp_path, path)
    first = {n: {k: float(bpy.data.lights[n][k]) for k in
                 ("phong_constant", "phong_linear", "phong_quadratic", "phong_radius")}
             for n in ("Bulb", "Cone")}
    out = str(tmp_path / "again.x3d")
    x3d_export.export(bpy.context, out)
    bpy.data.scenes.remove(scene)
    for block in list(bpy.data.objects) + list(bpy.data.lights):
        if block.name in bpy.data.objects:
            bpy.data.objects.remove(block)
    for light in list(bpy.data.lights):
        bpy.data.lights.remove(light)
    _scene, points, got = _render_floor(bpy, tmp_path, out)
    _check_against_the_standard(points, got, "round trip")
    for name, values in first.items():
        light = bpy.data.lights[name]
        for key, value in values.items():
            assert float(light[key]) == pytest.approx(value, rel=1e-6), (name, key)


def test_a_light_under_a_non_uniform_scale_takes_the_cube_root_with_a_warning(bpy_clean,
                                                                                tmp_path):
    """Scale 1 2 4 has no single distance: s = (1 · 2 · 4)^(1/3) = 2, said in the report."""
    bpy = bpy_clean
    from phong_nodes.addon.interchange import x3d_import  # noqa: PLC0415

    path = write(tmp_path, "stretched.x3dv", """#X3D V3.3 utf8
PROFILE Immersive
Transform { scale 1 2 4 children [ DEF Lamp PointLight { attenuation 0.5 0.6 0.8 radius 3 } ] }
Shape { geometry Box { } }
""")
    warnings = x3d_import.import_file(bpy.context, path).warnings
    assert any("non-uniform scale" in w and "Lamp" in w for w in warnings), warnings
    lamp = bpy.data.lights["Lamp"]
    assert lamp["phong_constant"] == pytest.approx(0.5)
    assert lamp["phong_linear"] == pytest.approx(0.6 / 2)
    assert lamp["phong_quadratic"] == pytest.approx(0.8 / 4)
    assert lamp["phong_radius"] == pytest.approx(3 * 2)


# -- the file's material names for every reader ------------------------------------------------

KICAD = os.path.join(DATA, "kicad_R_0805_2012Metric_excerpt.wrl")
DEF_MATERIAL = re.compile(r"DEF\s+([^\s{}\[\],\"'#]+)\s+Material\b")
DEF_MATERIAL_XML = re.compile(r"<Material\b[^>]*\bDEF=['\"]([^'\"]+)['\"]")


def _material_defs(path):
    """The DEF names of the Materials of a written file, by a plain regular expression (as
    any other reader sees them: no WorldInfo)."""
    text = open(path, encoding="utf-8").read()
    return set(DEF_MATERIAL.findall(text)) | set(DEF_MATERIAL_XML.findall(text))


@pytest.mark.parametrize("ending", [".wrl", ".x3dv", ".x3d"])
def test_a_round_trip_of_a_kicad_file_keeps_every_material_name(bpy_clean, tmp_path, ending):
    """KiCad names its materials on purpose (PIN-01, RES-SMD-01 ...); its shapes have no DEF,
    so the importer names their objects after their materials.  Exported, the materials keep
    exactly those names as their DEF, the objects yield; re-imported, the same materials."""
    bpy = bpy_clean
    from phong_nodes.addon.interchange import x3d_export  # noqa: PLC0415

    want = _material_defs(KICAD)
    assert want == {"PIN-01", "PLASTIC-WHITE-01", "RES-SMD-01"}
    assert bpy.ops.phong.import_x3d(filepath=KICAD) == {"FINISHED"}
    objects = {o.name for o in bpy.data.objects if o.type == "MESH"}
    assert objects & want, "objects named after their materials: the collision this is about"
    out = str(tmp_path / ("again" + ending))
    x3d_export.export(bpy.context, out)
    assert _material_defs(out) == want
    text = open(out, encoding="utf-8").read()
    groups = set(re.findall(r"DEF\s+(\S+)\s+Transform\b", text)) | \
        set(re.findall(r"<Transform\b[^>]*\bDEF=['\"]([^'\"]+)['\"]", text))
    assert groups and not groups & want, "the objects yield their names"
    before = {m.name for m in bpy.data.materials}
    assert bpy.ops.phong.import_x3d(filepath=out) == {"FINISHED"}
    again = {m.name for m in bpy.data.materials} - before
    assert {name.rsplit(".", 1)[0] for name in again} == want   # Blender's .001 on clashes


def test_material_defs_come_before_colliding_groups():
    """core.x3d alone: a Transform and a Shape named as a material get another DEF; the
    material keeps its own, in all three encodings."""
    from phong_nodes.core import x3d  # noqa: PLC0415

    paint = x3d.Material(name="Paint")
    mesh = x3d.Mesh(name="Paint", kind="IndexedFaceSet",
                    positions=np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0]], float),
                    face_sizes=np.array([3]), corners=np.array([0, 1, 2]))
    shape = x3d.Shape(name="Paint", geometry=mesh, appearance=x3d.Appearance(material=paint))
    doc = x3d.Document(path="t.x3d", encoding="x3d-xml")
    doc.root.children.append(x3d.Transform(name="Paint", kind="Transform",
                                           matrix=np.diag([2.0, 2.0, 2.0, 1.0]),
                                           children=[shape]))
    for dump in (x3d.dumps_vrml, x3d.dumps_x3dv, x3d.dumps_x3d):
        text = dump(doc)
        names = set(DEF_MATERIAL.findall(text)) | set(DEF_MATERIAL_XML.findall(text))
        assert names == {"Paint"}, (dump.__name__, names)
        back = x3d.loads(text)
        assert back.instances[0].shape.material.name == "Paint"


# -- a texture's alpha --------------------------------------------------------------------------

#: A textured quad (its material transparency 0.25) in front of a green quad, seen from the
#: front by an orthographic view of exactly the quad; the texture's four bands of 16 texels.
ALPHA_SCENE = """#X3D V3.3 utf8
PROFILE Immersive
NavigationInfo { headlight FALSE }
OrthoViewpoint { position 0 0 5 fieldOfView -2 -0.5 2 0.5 }
DirectionalLight { direction 0 0 -1 intensity 0.8 ambientIntensity 0 }
DEF Label Shape {
  appearance Appearance { texture ImageTexture { url "label.png" }
    material DEF Ink Material { diffuseColor 1 1 1 ambientIntensity 0 transparency 0.25 } }
  geometry IndexedFaceSet { coord Coordinate { point [ -2 -0.5 1, 2 -0.5 1, 2 0.5 1, -2 0.5 1 ] }
    coordIndex [ 0 1 2 3 -1 ] texCoord TextureCoordinate { point [ 0 0, 1 0, 1 1, 0 1 ] } }
}
DEF Behind Shape {
  appearance Appearance { material DEF Back Material { diffuseColor 0 0 0 ambientIntensity 0
                                                       emissiveColor 0.2 0.5 0.3 } }
  geometry IndexedFaceSet { coord Coordinate { point [ -3 -1 0, 3 -1 0, 3 1 0, -3 1 0 ] }
    coordIndex [ 0 1 2 3 -1 ] }
}
"""
#: Per band: the texel's RGB and alpha (bytes).
BANDS = (((200, 100, 50), 0), ((200, 100, 50), 255), ((50, 150, 250), 128),
         ((50, 150, 250), 255))
BACK = np.array([0.2, 0.5, 0.3])


def _alpha_png(path):
    texels = np.zeros((16, 64, 4), dtype=np.int64)
    for band, (rgb, alpha) in enumerate(BANDS):
        texels[:, 16 * band:16 * band + 16, :3] = rgb
        texels[:, 16 * band:16 * band + 16, 3] = alpha
    return png(path, texels)


def _render_bands(bpy, path, tmp_path, label):
    from phong_scene import render  # noqa: PLC0415

    scene = be.new_scene(label, 64, 16, "cycles")
    bpy.context.window.scene = scene
    assert bpy.ops.phong.import_x3d(filepath=str(path)) == {"FINISHED"}
    passes, _seconds = render(bpy, scene, str(tmp_path / f"{label}.exr"))
    return scene, passes["Combined"][..., :3].astype(np.float64)


def _check_bands(picture):
    """By hand: a = A × (1 − transparency); the pixel a · 0.8 · RGB + (1 − a) · behind."""
    for band, (rgb, alpha) in enumerate(BANDS):
        a = alpha / 255.0 * (1.0 - 0.25)
        want = a * 0.8 * np.array(rgb) / 255.0 + (1.0 - a) * BACK
        got = picture[4:12, 16 * band + 4:16 * band + 12].reshape(-1, 3)
        assert np.abs(got - want).max() <= 1e-5, (band, got[0], want)


@pytest.mark.cycles
def test_a_textures_alpha_is_the_materials_opacity_both_ways(bpy_clean, tmp_path):
    """An RGBA PNG: where its alpha is 0 the quad behind shows, where it is 1 the material's
    own 1 − transparency blends, between the product; exported, the texture and transparency
    are written back and a re-import renders the same pixels."""
    bpy = bpy_clean
    from phong_nodes.addon.interchange import x3d_export  # noqa: PLC0415
    from phong_nodes.addon.lighting import recipe  # noqa: PLC0415

    _alpha_png(tmp_path / "label.png")
    path = write(tmp_path, "label.x3dv", ALPHA_SCENE)
    scene, picture = _render_bands(bpy, path, tmp_path, "alpha")
    ink = bpy.data.materials["Ink"]
    assert recipe.blends(ink) and recipe.opacity(ink) == pytest.approx(0.75)
    assert not recipe.blends(bpy.data.materials["Back"])
    _check_bands(picture)
    out = tmp_path / "out"
    out.mkdir()
    warnings = x3d_export.export(bpy.context, str(out / "label.x3dv"))
    assert not [w for w in warnings if "opacity map" in w], warnings
    text = (out / "label.x3dv").read_text()
    assert "label.png" in text and re.search(r"transparency 0\.25\b", text)
    bpy.data.scenes.remove(scene)
    for obj in list(bpy.data.objects):
        bpy.data.objects.remove(obj)
    _scene, again = _render_bands(bpy, out / "label.x3dv", tmp_path, "again")
    _check_bands(again)


@pytest.mark.cycles
def test_the_comparison_leaves_out_what_a_textures_alpha_blends(bpy_clean, tmp_path):
    """``phong compare`` of a file with a texture's alpha: the reference (the nearest
    surface's colour) cannot know what shows through, so the label's pixels are left out
    as for an Opacity below 1, and the rest agrees."""
    bpy = bpy_clean
    from phong_nodes.addon.comparison import engine  # noqa: PLC0415

    _alpha_png(tmp_path / "label.png")
    path = write(tmp_path, "label.x3dv", ALPHA_SCENE.replace("transparency 0.25", ""))
    scene = be.new_scene("compare alpha", 64, 32, "cycles")
    bpy.context.window.scene = scene
    assert bpy.ops.phong.import_x3d(filepath=path) == {"FINISHED"}
    metrics = engine.run(scene, str(tmp_path / "compare"), engines=("cycles",))
    assert metrics["ok"], metrics["verdict"]
    assert metrics["pixels"]["compared"] > 0


@pytest.mark.cycles
def test_an_opaque_rgba_texture_leaves_the_material_opaque(bpy_clean, tmp_path):
    bpy = bpy_clean
    from phong_nodes.addon.lighting import recipe  # noqa: PLC0415

    png(tmp_path / "label.png", np.tile([10, 20, 30, 255], (4, 4, 1)))
    path = write(tmp_path, "label.x3dv", ALPHA_SCENE.replace("transparency 0.25", ""))
    assert bpy.ops.phong.import_x3d(filepath=path) == {"FINISHED"}
    assert not recipe.blends(bpy.data.materials["Ink"])


# -- solid ----------------------------------------------------------------------------------------

SOLID = """#X3D V3.3 utf8
PROFILE Immersive
NavigationInfo { headlight FALSE }
OrthoViewpoint { position 0 0 5 fieldOfView -3 -1 3 1 }
DirectionalLight { direction 0 0 1 intensity 1 ambientIntensity 0.5 }
# the viewer sees the backs of both quads of Paint (counter-clockwise seen from behind)
DEF Front Shape { appearance Appearance { material DEF Paint Material { diffuseColor 1 0 0
                                                                         emissiveColor 0 0 0.5 } }
  geometry IndexedFaceSet { coord Coordinate { point [ -2 -1 0, -2 1 0, 0 1 0, 0 -1 0 ] }
    coordIndex [ 0 1 2 3 -1 ] } }
DEF Open Shape { appearance Appearance { material USE Paint }
  geometry IndexedFaceSet { solid FALSE
    coord Coordinate { point [ 0 -1 0, 0 1 0, 2 1 0, 2 -1 0 ] } coordIndex [ 0 1 2 3 -1 ] } }
DEF Ball Shape { appearance Appearance { material DEF Chalk Material { } }
  geometry Sphere { radius 0.1 } }
DEF Disc Shape { appearance Appearance { material DEF Soap Material { } }
  geometry Cylinder { radius 0.1 height 0.1 solid FALSE } }
"""


def test_solid_is_the_materials_backface_culling_with_a_variant_where_shapes_differ(
        bpy_clean, tmp_path):
    """X3D's default solid TRUE (IndexedFaceSet and primitives) culls back faces, solid FALSE
    draws both; one material whose shapes differ becomes two variants.  VRML97's default is
    TRUE too."""
    bpy = bpy_clean
    path = write(tmp_path, "solid.x3dv", SOLID)
    assert bpy.ops.phong.import_x3d(filepath=path) == {"FINISHED"}
    material = {o.name: o.active_material for o in bpy.data.objects if o.type == "MESH"}
    assert material["Front"].name == "Paint" and material["Front"].use_backface_culling
    assert material["Open"].name == "Paint [two-sided]"
    assert not material["Open"].use_backface_culling
    assert material["Ball"].use_backface_culling and not material["Disc"].use_backface_culling
    vrml = write(tmp_path, "solid.wrl", """#VRML V2.0 utf8
Shape { appearance Appearance { material DEF Wood Material { } }
  geometry IndexedFaceSet { coord Coordinate { point [ 0 0 0, 1 0 0, 0 1 0 ] }
    coordIndex [ 0 1 2 -1 ] } }
Shape { appearance Appearance { material DEF Glass Material { } }
  geometry IndexedFaceSet { solid FALSE coord Coordinate { point [ 0 0 0, 1 0 0, 0 1 0 ] }
    coordIndex [ 0 1 2 -1 ] } }
""")
    assert bpy.ops.phong.import_x3d(filepath=vrml) == {"FINISHED"}
    assert bpy.data.materials["Wood"].use_backface_culling
    assert not bpy.data.materials["Glass"].use_backface_culling


@pytest.mark.parametrize("ending", [".x3dv", ".wrl", ".x3d"])
def test_solid_is_written_from_backface_culling_and_read_back(bpy_clean, tmp_path, ending):
    bpy = bpy_clean
    from phong_nodes.addon.interchange import x3d_export  # noqa: PLC0415
    from phong_nodes.core import x3d  # noqa: PLC0415

    path = write(tmp_path, "solid.x3dv", SOLID)
    assert bpy.ops.phong.import_x3d(filepath=path) == {"FINISHED"}
    culling = {m.name: m.use_backface_culling for m in bpy.data.materials}
    out = str(tmp_path / ("again" + ending))
    x3d_export.export(bpy.context, out)
    doc = x3d.load(out)   # the file as written: solid per shape, by its material's name
    written = {inst.shape.material.name: inst.shape.geometry.solid for inst in doc.instances}
    assert written == {name: culling[name] for name in written}
    assert set(written) == {"Paint", "Paint [two-sided]", "Chalk", "Soap"}
    text = open(out, encoding="utf-8").read()
    assert len(re.findall(r"solid(?:=['\"]false['\"]| FALSE)", text)) == 2   # Open and Disc
    for obj in list(bpy.data.objects):
        bpy.data.objects.remove(obj)
    before = set(bpy.data.materials)
    assert bpy.ops.phong.import_x3d(filepath=out) == {"FINISHED"}
    again = {m.name.rsplit(".", 1)[0]: m.use_backface_culling
             for m in set(bpy.data.materials) - before}
    assert again == culling


@pytest.mark.slow
@pytest.mark.cycles
@pytest.mark.eevee
def test_solid_culls_in_eevee_and_cycles_draws_both_sides(bpy_clean, tmp_path):
    """The viewer sees the back of Front (solid) and of Open (solid FALSE): Eevee leaves out
    Front's back; Cycles does not honour Backface Culling and draws it (documented in
    docs/x3d.md; this notices a release that changes it)."""
    bpy = bpy_clean
    from phong_scene import render  # noqa: PLC0415

    path = write(tmp_path, "solid.x3dv", SOLID.replace("DEF Ball", "#").replace(
        "geometry Sphere { radius 0.1 } }", "").replace("DEF Disc", "#").replace(
        "geometry Cylinder { radius 0.1 height 0.1 solid FALSE } }", ""))
    seen = {}
    for engine in ("cycles", "eevee"):
        scene = be.new_scene(engine, 24, 8, engine)
        bpy.context.window.scene = scene
        assert bpy.ops.phong.import_x3d(filepath=path) == {"FINISHED"}
        passes, _seconds = render(bpy, scene, str(tmp_path / f"{engine}.exr"))
        seen[engine] = passes["Combined"][..., :3].astype(np.float64)
    # by hand: the light (direction +z) shines on the faces' fronts, away from the viewer:
    # what the viewer sees of a drawn quad is Ke + Ia·ambientIntensity·Od = (0.1, 0, 0.5)
    want = np.array([0.5 * 0.2 * 1.0, 0.0, 0.5])
    for engine, picture in seen.items():   # Front: x −2..0 (pixels 4..11), Open: 0..2
        front, open_ = picture[2:6, 6:10].reshape(-1, 3), picture[2:6, 14:18].reshape(-1, 3)
        assert np.abs(open_ - want).max() < 2 / 255, (engine, open_[0])
        if engine == "eevee":
            assert np.abs(front).max() < 1e-3, "the back of a solid face is not drawn"
        else:
            assert np.abs(front - want).max() < 1e-5, "Cycles draws both sides"


@pytest.mark.slow
@pytest.mark.cycles
@pytest.mark.eevee
def test_the_comparison_judges_both_sides_and_puts_culling_back(bpy_clean, tmp_path):
    """Choreonoid's fog file: the viewer inside a solid Sphere (radius 90) sees only its
    back.  The comparison judges the lighting equation on both sides (Cycles draws them and
    the reference knows no culling), so Eevee draws them too while it renders; the
    material's Backface Culling is put back afterwards."""
    bpy = bpy_clean
    from phong_nodes.addon.comparison import engine  # noqa: PLC0415

    scene = be.new_scene("inside", 48, 36, "cycles")
    bpy.context.window.scene = scene
    path = os.path.join(DATA, "choreonoid_fog.wrl")
    assert bpy.ops.phong.import_x3d(filepath=path) == {"FINISHED"}
    (material,) = [m for m in bpy.data.materials if m.users]
    assert material.use_backface_culling, "the Sphere is solid"
    metrics = engine.run(scene, str(tmp_path / "compare"), engines=("cycles", "eevee"))
    assert metrics["ok"], metrics["verdict"]
    assert metrics["pixels"]["compared"] == 48 * 36
    assert material.use_backface_culling, "put back"
