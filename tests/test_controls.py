# SPDX-License-Identifier: GPL-3.0-or-later
"""Two controls the COLLADA and FBX importers set: a Phong material's Opacity
(``opacity.set_opacity``, MTL ``d``) and a light's power falloff i0/d^k
(``light["phong_falloff"] = "POWER"``, ``light["phong_power_k"]``).

Rendered pixels against the numpy reference, worked out here: the blend
opacity × front + (1 − opacity) × back from the reference colour of each surface, and
i0/d^k (times the spot's cone and cos^e edge) from the light's position and the pixel's
point.  Cycles within 1e-4, Eevee within 1/255 on 99.5 % of the pixels."""

from __future__ import annotations

import math
import os

import numpy as np
import pytest

import blender_env as be
from blender_env import report
from phong_nodes.core import mtl
from phong_scene import (_add_probe_aovs, _controls, _light, phong_shading, reference_color,
                         render)

SIZE = 32
CY_TOL = 1e-4
EEVEE_STEP, EEVEE_SHARE = 1.0 / 255.0, 0.995
AMBIENT = 0.1
FRONT_Z = 0.5
OBJ_DATA = os.path.join(os.path.dirname(os.path.abspath(__file__)), "data", "obj")


def _ref():
    from phong_nodes.node_groups import reference  # noqa: PLC0415

    return reference


def _materials():
    from phong_nodes.addon.lighting import recipe, writer  # noqa: PLC0415  (needs bpy)
    from phong_nodes.addon.lighting import opacity as opacity_nodes  # noqa: PLC0415

    return recipe, writer, opacity_nodes


def _properties():
    from phong_nodes.addon.lighting import properties  # noqa: PLC0415  (needs bpy)

    return properties


# -- scenes --------------------------------------------------------------------------

def _scene(bpy, name, kind):
    scene = be.new_scene(name, SIZE, SIZE, kind)
    bpy.context.window.scene = scene
    scene.world.phong.ambient_intensity = AMBIENT
    scene.world.phong.ambient_color = (1.0, 1.0, 1.0)
    for aov, aov_kind in (("P", "COLOR"), ("N", "COLOR"), ("I", "COLOR"), ("id", "VALUE")):
        be.add_aov(scene, aov, aov_kind)
    assert bpy.ops.phong.add_term_passes() == {"FINISHED"}
    be.add_ortho_camera(scene, (0.0, 0.0), 4.0, 4.0)  # looks straight down -Z
    return scene


def _plane(bpy, scene, name, z, x1, color):
    """A plane at height z over x in [-3, x1], y in [-3, 3], its source material *color*."""
    obj = be.add_quad(scene, name, -3.0, -3.0, x1, 3.0, z)
    mesh = obj.data
    source = bpy.data.materials.new(name + " source")
    be.compat().new_material_tree(source)
    source.node_tree.nodes["Principled BSDF"].inputs["Base Color"].default_value = color
    mesh.materials.append(source)
    return obj


def _apply(bpy, scene, objects):
    be.apply_phong(scene, objects)
    for ident, obj in enumerate(objects, start=1):
        _add_probe_aovs(bpy, obj.active_material, ident)


def _opacity_scene(bpy, kind):
    """A back plane (z = 0, everywhere) and a front plane (z = 0.5, left half) under a
    point light; both Phong, separate materials."""
    scene = _scene(bpy, f"Opacity {kind}", kind)
    back = _plane(bpy, scene, "Back", 0.0, 3.0, (0.2, 0.6, 0.3, 1.0))
    front = _plane(bpy, scene, "Front", FRONT_Z, 0.0, (0.9, 0.3, 0.1, 1.0))
    point = _light(bpy, scene, "Point", "POINT", (0.5, 0.3, 2.0))
    point.data.phong.intensity = 2.5
    point.data.color = (1.0, 0.9, 0.8)
    _apply(bpy, scene, [back, front])
    assert back.active_material is not front.active_material
    front.active_material.node_tree.nodes["phong_blinn"].outputs[0].default_value = 1.0
    return scene, back, front, point


def _geometry(passes, mask):
    return tuple(passes[k][..., :3][mask].astype(np.float64) for k in ("P", "N", "I"))


def _blend_reference(scene, back, front, point, opacity, probes):
    """(expected Combined, expected "Phong Color", front mask) from the Cycles probes:
    under the front plane the back plane's point is the same (x, y) at z = 0 (the camera
    looks straight down)."""
    ident = np.rint(probes["id"][..., 0]).astype(int)
    front_px, back_px = ident == 2, ident == 1
    assert front_px.sum() > 200 and back_px.sum() > 200, "both planes are in the picture"
    combined = np.zeros(ident.shape + (3,))
    phong = np.zeros_like(combined)
    P, N, I = _geometry(probes, back_px)
    combined[back_px], _ = reference_color(scene.world, [point],
                                           _controls(back.active_material, ambient=True),
                                           P, N, I)
    phong[back_px] = combined[back_px]
    P, N, I = _geometry(probes, front_px)
    seen, _ = reference_color(scene.world, [point], _controls(front.active_material, ambient=True),
                              P, N, I)
    behind = P.copy()
    behind[:, 2] = 0.0
    under, _ = reference_color(scene.world, [point],
                               _controls(back.active_material, ambient=True),
                               behind, N, I)
    combined[front_px] = opacity * seen + (1.0 - opacity) * under
    phong[front_px] = seen
    assert np.abs(seen - under).max() > 0.2, "front and back differ: the blend shows"
    return combined, phong, front_px, back_px


def _eevee(scene, keep=()):
    """Eevee's exact settings, and no AOV but *keep*: Eevee's shader compile time grows fast
    with the number of AOVs (4.5 under load: 10 minutes for the nine of the Cycles renders)."""
    layer = scene.view_layers[0]
    for aov in [a for a in layer.aovs if a.name not in keep]:
        layer.aovs.remove(aov)
    be.configure_engine(scene, "eevee")


def _eevee_share(got, expected, mask):
    diff = np.abs(got[..., :3] - expected)[mask].max(axis=-1)
    return float((diff <= EEVEE_STEP).mean()), float(diff.max())


# -- opacity --------------------------------------------------------------------------

@pytest.mark.slow
@pytest.mark.parametrize("opacity", [0.5, 0.2])
def test_opacity_blends_the_phong_colour_over_what_is_behind(bpy_clean, blender_tmp, opacity):
    bpy = bpy_clean
    recipe, writer, opacity_nodes = _materials()
    scene, back, front, point = _opacity_scene(bpy, "cycles")
    material = front.active_material
    nodes = material.node_tree.nodes
    assert nodes["phong_opacity"].outputs[0].default_value == 1.0
    assert nodes["phong_opacity"].parent == nodes["phong_controls"]
    opaque_links = sorted((l.from_node.name, l.to_node.name) for l in material.node_tree.links)
    assert opacity_nodes.set_opacity(material, opacity) == pytest.approx(opacity)
    assert material.surface_render_method == "BLENDED"
    passes, cycles_s = render(bpy, scene, str(blender_tmp / f"opacity_{opacity}_cycles.exr"))
    combined, phong, front_px, back_px = _blend_reference(scene, back, front, point, opacity,
                                                          passes)
    hit = front_px | back_px
    err = np.abs(passes["Combined"][..., :3] - combined)[hit].max()
    err_aov = np.abs(passes["Phong Color"][..., :3] - phong)[hit].max()
    # Eevee: the same scene and materials
    _eevee(scene)
    eevee, eevee_s = render(bpy, scene, str(blender_tmp / f"opacity_{opacity}_eevee.exr"))
    share, worst = _eevee_share(eevee["Combined"], combined, hit)
    report(f"[opacity {opacity}] {bpy.app.version_string}: Cycles max|Combined-ref| {err:.2e}, "
           f"max|Phong Color-unblended ref| {err_aov:.2e} ({cycles_s:.2f} s); Eevee "
           f"{share:.2%} within 1/255, max {worst:.2e} ({eevee_s:.2f} s)")
    assert err <= CY_TOL
    assert err_aov <= CY_TOL, "Cycles' AOVs keep the front's unblended Phong values"
    assert share >= EEVEE_SHARE
    # back to opaque: the recipe's nodes and links exactly as before, Eevee's default method
    opacity_nodes.set_opacity(material, 1.0)
    assert "phong_opacity_mix" not in nodes and "phong_opacity_transparent" not in nodes
    assert sorted((l.from_node.name, l.to_node.name) for l in material.node_tree.links) == \
        opaque_links
    assert material.surface_render_method == "DITHERED"


def test_opacity_is_clamped_and_bad_values_are_refused(bpy_clean):
    bpy = bpy_clean
    recipe, writer, opacity_nodes = _materials()
    _scene_, _back, front, _point = _opacity_scene(bpy, "cycles")
    material = front.active_material
    assert opacity_nodes.set_opacity(material, 1.7) == 1.0 and recipe.opacity(material) == 1.0
    assert "phong_opacity_mix" not in material.node_tree.nodes
    assert opacity_nodes.set_opacity(material, -2) == 0.0 and recipe.opacity(material) == 0.0
    assert "phong_opacity_mix" in material.node_tree.nodes
    for bad in (float("nan"), "half", None):
        with pytest.raises(ValueError, match="opacity must be a number"):
            opacity_nodes.set_opacity(material, bad)
    assert recipe.opacity(material) == 0.0, "a refused value changes nothing"


@pytest.mark.slow
def test_an_opaque_material_renders_as_before(bpy_clean, blender_tmp):
    """Opacity 1 (the default, or set back): the same pixels as a material never touched,
    in Eevee (whose shader the Mix/Transparent nodes would change)."""
    bpy = bpy_clean
    recipe, writer, opacity_nodes = _materials()
    scene, _back, front, _point = _opacity_scene(bpy, "eevee")
    _eevee(scene, keep=("Phong Color",))
    before, _s = render(bpy, scene, str(blender_tmp / "opaque_before.exr"))
    opacity_nodes.set_opacity(front.active_material, 0.3)
    opacity_nodes.set_opacity(front.active_material, 1.0)
    after, _s = render(bpy, scene, str(blender_tmp / "opaque_after.exr"))
    assert np.array_equal(before["Combined"], after["Combined"])
    assert np.array_equal(before["Phong Color"], after["Phong Color"])


def test_relink_and_edits_of_the_control_keep_the_nodes_in_step(bpy_clean):
    bpy = bpy_clean
    recipe, writer, opacity_nodes = _materials()
    _scene_, _back, front, _point = _opacity_scene(bpy, "cycles")
    material = front.active_material
    opacity_nodes.set_opacity(material, 0.4)
    writer.wire(material, material.node_tree.nodes["phong_lights"].node_tree)
    surface = material.node_tree.nodes["phong_output"].inputs["Surface"]
    assert surface.links[0].from_node.name == "phong_opacity_mix"
    assert bpy.ops.phong.relink_lights() == {"FINISHED"}
    assert surface.links[0].from_node.name == "phong_opacity_mix"
    # an edit of the control in the node editor (the active object's material) switches the
    # nodes by itself
    bpy.context.view_layer.objects.active = front
    control = material.node_tree.nodes["phong_opacity"].outputs[0]
    control.default_value = 1.0
    bpy.context.view_layer.update()  # what Blender's UI does after each change
    assert surface.links[0].from_node.name == "phong_lights"
    assert material.surface_render_method == "DITHERED"
    control.default_value = 0.25
    bpy.context.view_layer.update()
    assert surface.links[0].from_node.name == "phong_opacity_mix"
    assert material.surface_render_method == "BLENDED"
    # material.phong.opacity (the panel's slider, scripts) switches at once, active or not
    bpy.context.view_layer.objects.active = None
    material.phong.opacity = 1.0
    assert control.default_value == 1.0 and material.phong.opacity == 1.0
    assert surface.links[0].from_node.name == "phong_lights"
    material.phong.opacity = 0.5
    assert surface.links[0].from_node.name == "phong_opacity_mix"
    # a script that writes the node of another object's material: Relink brings it in line
    control.default_value = 1.0
    bpy.context.view_layer.update()
    assert surface.links[0].from_node.name == "phong_opacity_mix", "not the active object's"
    assert bpy.ops.phong.relink_lights() == {"FINISHED"}
    assert surface.links[0].from_node.name == "phong_lights"


# -- MTL d -------------------------------------------------------------------------------

def test_mtl_d_imports_as_opacity_and_exports_as_d(bpy_clean, tmp_path, capfd):
    bpy = bpy_clean
    scene = be.new_scene("MTL d", 16, 16)
    bpy.context.window.scene = scene
    _light(bpy, scene, "Sun", "SUN", (0.0, 0.0, 5.0))
    (tmp_path / "m.obj").write_text(
        "mtllib m.mtl\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 2 0 0\nv 2 1 0\n"
        "usemtl glass\nf 1 2 3 4\nusemtl window\nf 2 5 6 3\nusemtl wall\nf 1 2 6\n")
    (tmp_path / "m.mtl").write_text(
        "newmtl glass\nKd 0.2 0.4 0.6\nd 0.5\nillum 2\n"
        "newmtl window\nKd 0.5 0.5 0.5\nTr 0.25\nillum 1\n"
        "newmtl wall\nKd 0.7 0.7 0.7\nd 1\nillum 1\n")
    capfd.readouterr()
    assert bpy.ops.phong.import_obj(filepath=str(tmp_path / "m.obj")) == {"FINISHED"}
    logged = "".join(capfd.readouterr())
    assert "transparency" not in logged, logged
    recipe, writer, opacity_nodes = _materials()
    got = {name: recipe.opacity(bpy.data.materials[name])
           for name in ("glass", "window", "wall")}
    assert got == {"glass": 0.5, "window": 0.75, "wall": 1.0}
    assert bpy.data.materials["glass"].surface_render_method == "BLENDED"
    assert "phong_opacity_mix" not in bpy.data.materials["wall"].node_tree.nodes
    out = tmp_path / "out.mtl"
    assert bpy.ops.phong.export_mtl(filepath=str(out)) == {"FINISHED"}
    text = out.read_text()
    written = {m.name: m for m in mtl.load(str(out))}
    assert written["glass"].scalars["d"] == 0.5 and "\nd 0.5\n" in text
    assert written["window"].scalars["d"] == 0.75
    assert "d" not in written["wall"].scalars, "an opaque material writes no d"


# -- power falloff -------------------------------------------------------------------------

def _falloff_scene(bpy, kind, light_type):
    scene = _scene(bpy, f"Falloff {light_type} {kind}", kind)
    plane = _plane(bpy, scene, "Plane", 0.0, 3.0, (0.5, 0.45, 0.4, 1.0))
    if light_type == "POINT":
        light = _light(bpy, scene, "Lamp", "POINT", (0.4, -0.3, 1.4))
    else:
        light = _light(bpy, scene, "Lamp", "SPOT", (-0.3, 0.2, 1.6), (0.15, -0.1, 0.0))
        light.data.spot_size = math.radians(90.0)
        light.data.phong.edge_exponent = 2.0
    light.data.phong.intensity = 1.0
    light.data.color = (1.0, 0.95, 0.9)
    light.data.phong.quadratic, light.data.phong.constant = 0.5, 0.3  # not the power's
    _apply(bpy, scene, [plane])
    nodes = plane.active_material.node_tree.nodes  # a highlight that never reaches 1 (k = 0)
    nodes["phong_specular_color"].outputs[0].default_value = (0.2, 0.25, 0.3, 1.0)
    return scene, plane, light


def _power_reference(scene, plane, light, probes, k):
    """i0/max(d^k, 1e-6) (times max(cos ω, 0)^e inside a spot's cone) at each pixel's point,
    then the Phong terms of the reference.  Returns (colour, mask, pixels near the cone edge)."""
    ident = np.rint(probes["id"][..., 0]).astype(int)
    mask = ident == 1
    P, N, I = _geometry(probes, mask)
    mw = np.array(light.matrix_world, dtype=np.float64)
    to_light = mw[:3, 3] - P
    d = np.linalg.norm(to_light, axis=-1)
    ell = to_light / d[:, None]
    intensity = light.data.phong.intensity / np.maximum(d ** k, 1e-6)
    near = np.zeros(len(P), bool)
    if light.data.type == "SPOT":
        axis = -mw[:3, 2] / np.linalg.norm(mw[:3, 2])
        cos_w = -(ell @ axis)
        cos_t = math.cos(light.data.spot_size / 2.0)
        intensity = np.where(cos_w >= cos_t,
                             intensity * np.maximum(cos_w, 0.0) ** light.data.phong.edge_exponent,
                             0.0)
        near = np.abs(cos_w - cos_t) < 1e-5
    controls = _controls(plane.active_material, ambient=True)
    out = phong_shading({
        **controls, "Light Vector": ell, "Light Intensity": intensity,
        "Light Color": np.array(light.data.color, dtype=np.float64),
        "Ambient Intensity": AMBIENT, "Ambient Color": np.ones(3)},
        {"Position": P, "Normal": N, "Incoming": I})
    image = np.zeros(mask.shape + (3,))
    image[mask] = out["Color"]
    edge = np.zeros(mask.shape, bool)
    edge[mask] = near
    return image, mask & ~edge, edge


def _set_power(bpy, light, k):
    _properties().write_light(light.data, {"falloff": "POWER", "power_k": k})
    bpy.context.view_layer.update()  # what Blender's UI does after each change


def _falls_off_as_power(plane) -> bool:
    """Whether the lights group of *plane*'s material draws the light "Lamp" with the Power
    falloff i0/d^k: its light group reads k (the seeds' model: one light group per light)."""
    tree = plane.active_material.node_tree.nodes["phong_lights"].node_tree
    node = tree.nodes["light:Lamp"]
    return "Falloff Exponent" in node.inputs and "Quadratic" not in node.inputs


@pytest.mark.slow
@pytest.mark.parametrize("light_type", ["POINT", "SPOT"])
def test_power_falloff_cycles_and_eevee(bpy_clean, blender_tmp, light_type):
    bpy = bpy_clean
    scene, plane, light = _falloff_scene(bpy, "cycles", light_type)
    assert not _falls_off_as_power(plane)
    _set_power(bpy, light, 2.0)
    assert _falls_off_as_power(plane)
    assert light.data.phong.falloff == "POWER" and light.data["phong_falloff"] == "POWER"
    results, means, references = [], [], {}
    ks = (0.0, 1.0, 2.0, 3.0, 1.7)
    for k in ks:  # Cycles (with the probes) first, then Eevee once without AOVs
        _properties().write_light(light.data, {"power_k": k})
        assert light.data["phong_power_k"] == k and light.data.phong.power_k == pytest.approx(k)
        probes, seconds = render(bpy, scene, str(blender_tmp / f"{light_type}_{k}_cycles.exr"))
        expected, mask, edge = _power_reference(scene, plane, light, probes, k)
        assert edge.sum() <= 3
        assert expected[mask].std() > 0.01 and expected[mask].max() < 1.0, "lit, unclamped"
        err = np.abs(probes["Combined"][..., :3] - expected)[mask].max()
        err_aov = np.abs(probes["Phong Color"][..., :3] - expected)[mask].max()
        results.append(f"k={k:g}: Cycles max {max(err, err_aov):.1e} ({seconds:.2f} s)")
        assert err <= CY_TOL and err_aov <= CY_TOL, (light_type, k, err, err_aov)
        means.append(float(expected[mask].mean()))
        references[k] = expected, mask
    _eevee(scene)
    for k in ks:
        _properties().write_light(light.data, {"power_k": k})
        got, seconds = render(bpy, scene, str(blender_tmp / f"{light_type}_{k}_eevee.exr"))
        share, worst = _eevee_share(got["Combined"], *references[k])
        results.append(f"k={k:g}: Eevee {share:.2%} within 1/255 (max {worst:.1e}, "
                       f"{seconds:.1f} s)")
        assert share >= EEVEE_SHARE, (light_type, k)
    report(f"[power falloff {light_type}] {bpy.app.version_string}: " + "; ".join(results))
    # d < 1 only near a few points: more k is darker on average
    assert means[0] > means[1] > means[2] > means[3]


def test_switching_the_falloff_updates_the_picture(bpy_clean, blender_tmp):
    bpy = bpy_clean
    scene, plane, light = _falloff_scene(bpy, "cycles", "POINT")
    quadratic, _s = render(bpy, scene, str(blender_tmp / "switch_quadratic.exr"))
    light.data.phong.falloff = "POWER"        # the panel's way (k: 2.0 by default)
    light.data.phong.power_k = 3.0
    bpy.context.view_layer.update()
    power, _s = render(bpy, scene, str(blender_tmp / "switch_power.exr"))
    expected, mask, _edge = _power_reference(scene, plane, light, power, 3.0)
    assert np.abs(power["Combined"][..., :3] - expected)[mask].max() <= CY_TOL
    assert np.abs(power["Combined"] - quadratic["Combined"])[mask].max() > 0.05
    light.data.phong.falloff = "QUADRATIC"
    bpy.context.view_layer.update()
    assert not _falls_off_as_power(plane)
    back, _s = render(bpy, scene, str(blender_tmp / "switch_back.exr"))
    assert np.abs(back["Combined"] - quadratic["Combined"]).max() <= 1e-6
    # the quadratic picture is the quadratic formula's (α = 0.5, β = 0, γ = 0.3)
    ref = _ref()
    P, N, I = _geometry(back, mask)
    expected_q, _ = reference_color(scene.world, [light],
                                    _controls(plane.active_material, ambient=True),
                                    P, N, I)
    assert np.abs(back["Combined"][..., :3][mask] - expected_q).max() <= CY_TOL
    assert ref is not None


def test_bad_falloff_is_refused_with_a_clear_message(bpy_clean):
    bpy = bpy_clean
    light = bpy.data.lights.new("L", "POINT")
    with pytest.raises(ValueError, match="falloff must be one of QUADRATIC, POWER"):
        _properties().write_light(light, {"falloff": "CUBIC"})
    assert "phong_falloff" not in light.keys()
    light["phong_falloff"] = "cubic"  # written by someone else: read as the default
    assert light.phong.falloff == "QUADRATIC"
    _properties().write_light(light, {"falloff": "power", "power_k": 1.5})
    assert light["phong_falloff"] == "POWER" and light.phong.power_k == 1.5


# -- save and reopen -----------------------------------------------------------------------

def test_saved_file_reopens_and_renders_the_same(bpy_clean, blender_tmp, tmp_path):
    bpy = bpy_clean
    recipe, writer, opacity_nodes = _materials()
    scene, back, front, point = _opacity_scene(bpy, "cycles")
    opacity_nodes.set_opacity(front.active_material, 0.5)
    _set_power(bpy, point, 1.5)
    before, _s = render(bpy, scene, str(blender_tmp / "saved_before.exr"))
    path, name = str(tmp_path / "controls.blend"), scene.name
    bpy.ops.wm.save_as_mainfile(filepath=path)
    bpy.ops.wm.open_mainfile(filepath=path)
    scene = bpy.data.scenes[name]
    material = bpy.data.objects["Front"].active_material
    assert recipe.opacity(material) == 0.5
    assert bpy.data.lights["Point"]["phong_falloff"] == "POWER"
    after, _s = render(bpy, scene, str(blender_tmp / "saved_after.exr"))
    assert np.abs(after["Combined"] - before["Combined"]).max() <= 1e-6
    # and it is the blend of the power-lit planes
    ident = np.rint(after["id"][..., 0]).astype(int)
    front_px = ident == 2
    P, N, I = _geometry(after, front_px)
    light = bpy.data.objects["Point"]
    mw = np.array(light.matrix_world, dtype=np.float64)

    def colour(material, P):
        to_light = mw[:3, 3] - P
        d = np.linalg.norm(to_light, axis=-1)
        out = phong_shading({
            **_controls(material, ambient=True), "Light Vector": to_light / d[:, None],
            "Light Intensity": light.data.phong.intensity / d ** 1.5,
            "Light Color": np.array(light.data.color, dtype=np.float64),
            "Ambient Intensity": AMBIENT, "Ambient Color": np.ones(3)},
            {"Position": P, "Normal": N, "Incoming": I})
        return out["Color"]

    behind = P.copy()
    behind[:, 2] = 0.0
    expected = 0.5 * colour(material, P) + 0.5 * colour(bpy.data.objects["Back"].active_material,
                                                        behind)
    assert np.abs(after["Combined"][..., :3][front_px] - expected).max() <= CY_TOL


# -- panels ----------------------------------------------------------------------------------

class _Layout:
    """Records what a panel's draw() shows (prop calls: owner, attribute, text)."""

    use_property_split = False

    def __init__(self):
        self.props = []

    def prop(self, owner, attribute, text=None, **_options):
        self.props.append((owner, attribute, text))

    def column(self, **_options):
        return self

    def __getattr__(self, _name):
        return lambda *args, **kwargs: self


def _draw(panel, **context):
    layout = _Layout()
    panel.draw(type("Panel", (), {"layout": layout})(), type("Context", (), context)())
    return layout.props


def test_panels_show_falloff_power_k_and_opacity(bpy_clean):
    bpy = bpy_clean
    from phong_nodes.addon.ui import panels  # noqa: PLC0415  (needs bpy)

    scene, plane, light = _falloff_scene(bpy, "cycles", "SPOT")
    shown = [a for _o, a, _t in _draw(panels.DATA_PT_phong_light, light=light.data, scene=scene)]
    assert "falloff" in shown and "quadratic" in shown and "power_k" not in shown
    light.data.phong.falloff = "POWER"
    shown = [a for _o, a, _t in _draw(panels.DATA_PT_phong_light, light=light.data, scene=scene)]
    assert "power_k" in shown and "quadratic" not in shown
    props = _draw(panels.MATERIAL_PT_phong, material=plane.active_material, scene=scene)
    assert (plane.active_material.phong, "opacity") in [(o, a) for o, a, _t in props]


# -- the comparison's reference ------------------------------------------------------------

def test_the_comparison_reference_knows_the_power_falloff():
    """The seeds' model's reference light (the reference of Compare / the bake:
    ``LightingModel.reference_light``) for a power light: i0/d^k, and the spot's cone and
    edge, against the formula worked out here."""
    from phong_nodes.core import compare  # noqa: PLC0415
    from phong_nodes.node_groups import models  # noqa: PLC0415

    def light_at(light, P):
        ell, intensity, _ambient, edge = models.get("seeds").reference_light(
            light, P, compare.AMBIGUOUS)
        return ell, intensity, edge

    P = np.array([[0.0, 0.0, 0.0], [1.0, 0.5, 0.0], [3.0, 0.0, 0.0], [0.2, -0.1, 1.5]])
    light = {"type": "point", "position": [0.0, 0.0, 2.0], "intensity": 1.5, "quadratic": 7.0,
             "linear": 7.0, "constant": 7.0, "falloff": "power", "power_k": 1.7}
    d = np.linalg.norm(P - [0.0, 0.0, 2.0], axis=-1)
    _ell, intensity, _edge = light_at(light, P)
    np.testing.assert_allclose(intensity, 1.5 / d ** 1.7, rtol=1e-12)
    spot = {**light, "type": "spot", "direction": [0.0, 0.0, -1.0], "half_angle": 40.0,
            "edge_exponent": 3.0, "penumbra": 0.0}
    cos_w = (2.0 - P[:, 2]) / d
    want = np.where(cos_w >= math.cos(math.radians(40.0)), 1.5 / d ** 1.7 * cos_w ** 3, 0.0)
    np.testing.assert_allclose(light_at(spot, P)[1], want, rtol=1e-12)
    assert want[2] == 0.0 and want[0] > 0.0, "one point outside the cone, one inside"
    quadratic = {**light, "falloff": "quadratic"}
    np.testing.assert_allclose(light_at(quadratic, P)[1], 1.5 / (7 * d * d + 7 * d + 7))


def test_describe_gives_the_reference_the_falloff(bpy_clean):
    bpy = bpy_clean
    from phong_nodes.addon.scene import describe  # noqa: PLC0415  (needs bpy)

    scene, plane, light = _falloff_scene(bpy, "cycles", "SPOT")
    layer = scene.view_layers[0]
    data = describe.describe(scene, layer, [plane])
    assert data["lights"][0]["falloff"] == "quadratic"
    _set_power(bpy, light, 2.5)
    data = describe.describe(scene, layer, [plane])
    assert (data["lights"][0]["falloff"], data["lights"][0]["power_k"]) == ("power", 2.5)


@pytest.mark.cycles
def test_compare_phong_scene_checks_power_lights_and_leaves_out_see_through_objects(
        bpy_clean, tmp_path):
    """The comparison (Compare Phong Scene) end to end: a power light matches its reference;
    a half-opaque object's pixels, which blend what is behind, are left out and counted."""
    bpy = bpy_clean
    from phong_nodes.addon.comparison import engine  # noqa: PLC0415

    bpy.ops.phong.build_demo_scene(name="two_lights", resolution=24)
    scene = bpy.data.scenes["two_lights"]
    first = engine.run(scene, str(tmp_path / "quadratic"), engines=("cycles",))
    assert first["ok"], first["verdict"]
    _set_power(bpy, scene.objects["green"], 1.3)
    _materials()[2].set_opacity(scene.objects["both"].active_material, 0.5)
    second = engine.run(scene, str(tmp_path / "power"), engines=("cycles",))
    assert second["ok"], second["verdict"]
    green = next(l for l in second["parameters"]["lights"] if l["name"] == "green")
    assert (green["falloff"], green["power_k"]) == ("power", 1.3)
    report(f"[compare power + opacity] {bpy.app.version_string}: {second['pixels']}")
    assert second["pixels"]["ambiguous"] > first["pixels"]["ambiguous"] + 20
