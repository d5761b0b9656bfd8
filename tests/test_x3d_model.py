# SPDX-License-Identifier: GPL-3.0-or-later
"""The X3D / VRML97 lighting model (docs/x3d.md): its lights-group parts against the
independent numpy reference, and a scene in the model rendered by Cycles and Eevee and compared
pixel by pixel with the standard's lighting equation (reference.py's X3D functions): per-light
ambient, the clamped attenuation, the radius, the linear spot ramp, Blinn highlights without
the N·L condition."""

from __future__ import annotations

import math

import numpy as np
import pytest

import blender_env as be
from phong_nodes.node_groups import library
from phong_nodes.node_groups import reference as ref


def _unit(rng, n):
    v = rng.normal(size=(n, 3))
    return v / np.linalg.norm(v, axis=1, keepdims=True)


def test_x3d_light_terms_equal_the_reference():
    rng = np.random.default_rng(7)
    n = 4000
    inputs = {"Light Vector": _unit(rng, n), "Intensity": rng.uniform(0.0, 2.0, n),
              "Ambient": rng.uniform(0.0, 1.0, n), "Light Color": rng.uniform(0.0, 1.0, (n, 3)),
              "Exponent": np.where(rng.random(n) < 0.2, 0.0, rng.uniform(0.0, 128.0, n)),
              "Normal": _unit(rng, n), "View Vector": _unit(rng, n)}
    got = library.definition("X3D Light Terms").evaluate(inputs)
    want = ref.x3d_light_terms(inputs["Light Vector"], inputs["Intensity"], inputs["Ambient"],
                               inputs["Light Color"], inputs["Exponent"], inputs["Normal"],
                               inputs["View Vector"])
    for name in ("Diffuse Light", "Specular Light", "Ambient Light"):
        assert np.abs(got[name] - want[name]).max() < 1e-9, name
    # the standards' specular has no N·L condition: light from behind still gives a highlight
    behind = (np.sum(inputs["Light Vector"] * inputs["Normal"], axis=1) < 0) \
        & (want["Specular Light"].max(axis=1) > 1e-3)
    assert behind.any()


def test_the_spot_ramp_and_the_clamp_by_hand():
    """Values worked out by hand from the standard's formulas."""
    # a spot straight above a point, 45° ... 60°: the point at 50° is 1/3 down the ramp
    p = np.array([[math.tan(math.radians(50.0)), 0.0, 0.0]])
    out = ref.x3d_spot_light((0.0, 0.0, 1.0), (0.0, 0.0, -1.0), math.radians(45.0),
                             math.radians(60.0), 2.0, 0.5, 1.0, 0.0, 0.0, 100.0, p)
    assert out["Spot Angle"][0] == pytest.approx(math.radians(50.0))
    assert out["Intensity"][0] == pytest.approx(2.0 * (50.0 - 60.0) / (45.0 - 60.0))
    assert out["Ambient"][0] == pytest.approx(0.5 * 2.0 / 3.0)
    # attenuation 1/max(0.2 + 0.1·d, 1): 1 close by (clamped), 1/1.2 at d = 10
    near = ref.x3d_point_light((0.0, 0.0, 1.0), 1.0, 0.0, 0.2, 0.1, 0.0, 100.0,
                               np.array([[0.0, 0.0, 0.0], [0.0, 0.0, -9.0]]))
    assert near["Intensity"] == pytest.approx([1.0, 1.0 / 1.2])
    # the radius: nothing beyond it
    far = ref.x3d_point_light((0.0, 0.0, 0.0), 1.0, 1.0, 1.0, 0.0, 0.0, 3.0,
                              np.array([[2.9, 0.0, 0.0], [3.1, 0.0, 0.0]]))
    assert list(far["Intensity"]) == [1.0, 0.0] and list(far["Ambient"]) == [1.0, 0.0]


def _x3d_scene(bpy):
    """A plane and a sphere in the X3D model under a Point (clamped attenuation, a radius
    that cuts the plane), a Spot (a ramp from 15° to 35°, its own ambient) and a Sun (ambient
    only on the lit side's colour): each rule of the standard shows in the picture."""
    scene = be.new_scene("X3D model", 96, 72, "cycles")
    bpy.context.window.scene = scene
    scene.world.phong.ambient_intensity = 0.0   # X3D has no global ambient light
    be.add_persp_camera(scene, (0.0, -6.0, 4.5), (0.0, 0.0, 0.0))
    floor = be.add_quad(scene, "Floor", -4, -3, 4, 3)
    old = be.plain_source("Ball")
    ball = be.add_uv_sphere(scene, "Ball", (0.5, 0.5, 0.8), 0.8, old, segments=32, rings=16)

    def light(name, kind, location, rotation=(0.0, 0.0, 0.0)):
        obj = bpy.data.objects.new(name, bpy.data.lights.new(name, kind))
        scene.collection.objects.link(obj)
        obj.location, obj.rotation_euler = location, rotation
        return obj

    point = light("Point", "POINT", (-2.0, -0.5, 1.5))
    point.data.color = (1.0, 0.8, 0.6)
    spot = light("Spot", "SPOT", (1.5, -1.0, 3.0), (0.3, 0.2, 0.0))
    spot.data.color = (0.7, 0.9, 1.0)
    spot.data.spot_size = math.radians(70.0)           # cutOffAngle 35°
    sun = light("Sun", "SUN", (0.0, 0.0, 5.0), (0.7, -0.4, 0.3))
    sun.data.color = (0.5, 0.5, 0.6)
    be.apply_phong(scene, (floor, ball), active=ball)
    scene.phong.model = "x3d"
    settings = {point: {"intensity": 0.5, "ambient": 0.1, "constant": 0.4, "linear": 0.1,
                        "quadratic": 0.3, "radius": 3.5},
                spot: {"intensity": 0.6, "ambient": 0.25, "constant": 1.0, "linear": 0.0,
                       "quadratic": 0.05, "radius": 100.0, "beam_width": math.radians(15.0)},
                sun: {"intensity": 0.25, "ambient": 0.3}}
    for obj, values in settings.items():
        for attr, value in values.items():
            setattr(obj.data.phong, attr, value)
    for obj in (floor, ball):
        nodes = obj.active_material.node_tree.nodes
        nodes["phong_exponent"].outputs[0].default_value = 128.0 * 0.2
        nodes["phong_specular_color"].outputs[0].default_value = (0.6, 0.6, 0.5, 1.0)
    ball.active_material.node_tree.nodes["phong_object_color"].outputs[0].default_value = (
        0.8, 0.3, 0.2, 1.0)
    assert bpy.ops.phong.relink_lights() == {"FINISHED"}
    return scene, point, spot, sun


def _compared(scene, folder, label):
    """(metrics, Cycles' max |Δ|, {light name: light}) of the comparison of *scene* with the
    reference (``engine.run``), reported, its verdict asserted."""
    from phong_nodes.addon.comparison import engine  # noqa: PLC0415
    metrics = engine.run(scene, str(folder))
    cycles = metrics["pairs"]["cycles-reference"]["max_abs"]
    eevee = metrics["pairs"]["eevee-reference"]["share_over_1_255"]
    be.report(f"[{label}] Cycles max |Δ| {cycles:.2e}, Eevee {1 - eevee:.3%} within 1/255, "
              f"{metrics['pixels']['compared']} pixels")
    assert metrics["ok"], metrics["verdict"]
    return metrics, cycles, {light["name"]: light for light in metrics["parameters"]["lights"]}


@pytest.mark.slow
@pytest.mark.cycles
@pytest.mark.eevee
def test_a_scene_in_the_x3d_model_matches_the_standards_equation(bpy_clean, tmp_path):
    bpy = bpy_clean
    from phong_nodes.addon.lighting import recipe  # noqa: PLC0415
    scene, point, spot, _sun = _x3d_scene(bpy)
    groups = {m.node_tree.nodes[recipe.LIGHTS_NODE].node_tree.name
              for m in recipe.phong_materials()}
    assert groups == {"X3D Lights X3D model"}
    metrics, cycles, lights = _compared(scene, tmp_path / "x3d", "x3d model")
    assert cycles <= 1e-4 and max(t["max_abs"] for t in metrics["terms"].values()) <= 1e-4
    assert metrics["pixels"]["compared"] > 1500
    assert lights["Spot"]["beam_width"] == pytest.approx(math.radians(15.0))
    assert lights["Point"]["radius"] == pytest.approx(3.5)
    # the picture is not saturated: most of it is below the clamp at 1
    import OpenImageIO as oiio  # noqa: PLC0415
    picture = oiio.ImageBuf(str(tmp_path / "x3d" / "reference.png")).get_pixels(oiio.FLOAT)
    lit = picture[..., :3].max(axis=-1) > 0.02
    assert lit.mean() > 0.5 and (picture[..., :3].max(axis=-1)[lit] < 0.999).mean() > 0.9


# -- the X3D model in scene files (scenes/x3d_lights.toml) ------------------------------

@pytest.mark.slow
@pytest.mark.cycles
@pytest.mark.eevee
def test_the_x3d_scene_file_matches_the_standards_equation(bpy_clean, tmp_path):
    """The shipped X3D scene file, built as `phong demo` builds it: Cycles and Eevee against
    reference.py's X3D equation, and the file's fields on Blender's lights."""
    import os  # noqa: PLC0415

    from phong_nodes.addon.demos import builder  # noqa: PLC0415
    from phong_nodes.core import scenes  # noqa: PLC0415
    data = scenes.load(os.path.join(scenes.SCENES_DIR, "x3d_lights.toml"))
    scene = builder.build(data, 80)
    assert scene.phong.model == "x3d"
    metrics, cycles, lights = _compared(scene, tmp_path / "x3d_lights", "x3d scene file")
    assert cycles <= 1e-4 and metrics["pixels"]["compared"] > 3000
    assert lights["bulb"]["radius"] == pytest.approx(3.0)
    assert lights["bulb"]["quadratic"] == pytest.approx(0.4)
    assert lights["bulb"]["ambient"] == pytest.approx(0.15)
    assert lights["spot"]["beam_width"] == pytest.approx(math.radians(12.0), abs=1e-6)
    assert lights["spot"]["half_angle"] == pytest.approx(30.0, abs=1e-4)
    assert lights["sun"]["ambient"] == pytest.approx(0.2)


@pytest.mark.cycles
def test_an_x3d_scene_files_ambient_light_sees_ambient_intensity_times_the_colour(bpy_clean,
                                                                                   tmp_path):
    """Ka = ambientIntensity × diffuseColor, a checker texture's colours included: lit by the
    World's ambient light alone (white, 1), a tile shows 0.5 × its colour, the textured tile
    0.5 × each of its checker's two colours."""
    from phong_nodes.addon.demos import builder  # noqa: PLC0415
    from phong_nodes.core import scenes  # noqa: PLC0415
    checker = {"type": "checker", "color2": [0.2, 0.6, 1.0], "scale": 2.0}
    tile = {"shape": "plane", "size": 0.9}
    data = scenes.parse({
        "title": "ambient", "model": "x3d", "aspect": 2.0,
        "camera": {"type": "orthographic", "location": [0, 0, 5], "ortho_scale": 4.0},
        "ambient": {"intensity": 1.0, "color": [1.0, 1.0, 1.0]},
        "objects": [
            {"name": "plain", "location": [-1, 0, 0], **tile,
             "material": {"color": [0.8, 0.4, 0.2], "ambient_intensity": 0.5}},
            {"name": "textured", "location": [1, 0, 0], **tile,
             "material": {"color": [0.8, 0.4, 0.2], "ambient_intensity": 0.5,
                          "texture": checker}}]}, "ambient.toml")
    data["name"] = "ambient"
    scene = builder.build(data, 32)
    be.configure_engine(scene, "cycles")
    be.set_output_multilayer_exr(scene)
    be.render_exr(scene, str(tmp_path / "ambient.exr"))
    rgb = be.read_multilayer_exr(str(tmp_path / "ambient.exr"))["Combined"][..., :3]
    left, right = rgb[8:24, 4:28].reshape(-1, 3), rgb[8:24, 36:60].reshape(-1, 3)
    assert np.abs(left - [0.4, 0.2, 0.1]).max() < 1e-4
    colours = {tuple(round(float(v), 3) for v in p) for p in right}
    assert colours == {(0.4, 0.2, 0.1), (0.1, 0.3, 0.5)}, colours
