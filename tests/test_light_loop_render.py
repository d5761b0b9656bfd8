# SPDX-License-Identifier: GPL-3.0-or-later
"""Eevee's light loop on Blender 5.3+ (issue 38): Phong materials whose EEVEE Material Output
shows their lights group's loop part (addon/lighting/loop.py), rendered by Eevee, against the
independent numpy reference (node_groups/reference.py, through tests/phong_scene.py's
reference_color) and against Cycles (the per-light part), within 1/255 as shown (Eevee's
pixel is irradiant + ambient + Σ lights, unclamped: min(x, 1) is what the screen shows).

Every light type and falloff with 1, 4 and 16 lights; a light added, removed, retyped,
recoloured, its Phong settings and its Light Linking changed while the relink handler is
held (no Relink): Eevee follows, Cycles keeps the lights group it had; the switches that
keep the lights group's Shader in Eevee (term passes, Opacity below 1); a file of 5.3 opened
where there is no loop.  Skipped before 5.3 (the nodes do not exist)."""

from __future__ import annotations

import math
import os
import subprocess

import numpy as np
import pytest

import blender_env as be
from blender_env import report
from phong_scene import TERMS, _add_probe_aovs, _controls, _light, reference_color

STEP = 1.0 / 255.0
SIZE = 40


@pytest.fixture
def loop_bpy(bpy_clean):
    if not be.compat().HAS_LIGHT_LOOP:
        pytest.skip(f"Eevee's light loop needs Blender 5.3+ (bpy {be.bpy_release()} has no "
                    "Light Accumulation node): Phong materials keep the lights group in Eevee")
    return bpy_clean


def _modules():
    from phong_nodes.addon.lighting import loop, properties, recipe, rig, sync  # noqa: PLC0415
    from phong_nodes.addon.lighting import world_copies  # noqa: PLC0415

    return loop, recipe, properties, rig, sync, world_copies


#: Lights cycled by the scenes: (type, falloff or None).  Positions and angles from the index.
KINDS = (("POINT", "QUADRATIC"), ("SUN", None), ("SPOT", "QUADRATIC"), ("POINT", "POWER"),
         ("SPOT", "POWER"))


def _scene(bpy, name, n_lights, intensity=None, blinn=0.35):
    """A plane and a sphere (ids 1 and 2, probe AOVs P / N / I / id, no Phong term pass: the
    loop) under *n_lights* lights cycling KINDS, converted by Apply Phong Material."""
    scene = be.new_scene(name, SIZE, SIZE, "cycles")
    bpy.context.window.scene = scene
    scene.world.phong.ambient_intensity = 0.05
    scene.world.phong.ambient_color = (1.0, 0.95, 0.9)
    for aov, kind in (("P", "COLOR"), ("N", "COLOR"), ("I", "COLOR"), ("id", "VALUE")):
        be.add_aov(scene, aov, kind)
    be.add_ortho_camera(scene, (0.0, 0.0), 4.0, 4.0)
    plane = be.add_quad(scene, "Plane", -3, -3, 3, 3)
    source = bpy.data.materials.new("Sphere source")
    be.compat().new_material_tree(source)
    source.node_tree.nodes["Principled BSDF"].inputs["Base Color"].default_value = (
        0.3, 0.55, 0.8, 1.0)
    sphere = be.add_uv_sphere(scene, "Sphere", (0.3, 0.2, 0.7), 1.0, source, segments=32,
                              rings=16)
    lights = [_add_light(bpy, scene, index, n_lights, intensity) for index in range(n_lights)]
    be.apply_phong(scene, (plane, sphere), active=sphere)
    _add_probe_aovs(bpy, plane.active_material, 1)
    _add_probe_aovs(bpy, sphere.active_material, 2)
    tree = sphere.active_material.node_tree
    tree.nodes["phong_exponent"].outputs[0].default_value = 12.0
    tree.nodes["phong_blinn"].outputs[0].default_value = blinn  # the plane's: 0
    tree.nodes["phong_specular_color"].outputs[0].default_value = (0.9, 0.85, 1.0, 1.0)
    tree.nodes["phong_irradiant_color"].outputs[0].default_value = (0.02, 0.0, 0.03, 1.0)
    bpy.context.view_layer.update()
    return scene, plane, sphere, lights


def _add_light(bpy, scene, index, count, intensity=None):
    kind, falloff = KINDS[index % len(KINDS)]
    angle = 2.0 * math.pi * index / max(count, 1)
    location = (2.2 * math.cos(angle), 2.2 * math.sin(angle), 1.6 + 0.3 * (index % 3))
    rotation = (0.5 * math.sin(angle + 0.3), -0.5 * math.cos(angle), 0.2 * index)
    obj = _light(bpy, scene, f"L{index:02d} {kind.lower()}", kind, location, rotation)
    light = obj.data
    light.color = (1.0, 0.7 + 0.3 * math.cos(index), 0.6 + 0.4 * math.sin(index) ** 2)
    light.phong.intensity = intensity if intensity is not None else 1.4 / max(count, 1) ** 0.5
    if kind != "SUN":
        light.phong.quadratic, light.phong.linear, light.phong.constant = 0.7, 0.15, 0.05
        light.phong.falloff = falloff
        light.phong.power_k = 1.0 + 0.25 * (index % 4)
    if kind == "SUN":
        light.phong.intensity *= 0.4
    if kind == "SPOT":
        light.spot_size = math.radians(70.0 + 5.0 * (index % 5))
        light.phong.edge_exponent = 1.5 * (index % 3)
        light.spot_blend = 0.3  # Blender's own soft edge: the loop ignores it
    light.phong.diffuse = 0.8 + 0.1 * (index % 3)
    light.phong.specular = 0.6 + 0.2 * (index % 2)
    light.diffuse_factor = 1.0 + 0.25 * (index % 2)  # Light Accumulation multiplies by it
    light.energy = 5.0  # a Phong light's reach does not depend on its watts
    return obj


def _render(bpy, scene, engine, path):
    be.configure_engine(scene, engine)
    be.render_exr(scene, path)
    return {k: v[::-1] for k, v in be.read_multilayer_exr(path).items()}


def _expected(scene, objects, geometry):
    """(reference min(sum, 1), unclamped sum, pixels compared) for *objects* {id: (object,
    lights reaching it)} from Cycles' probes."""
    ident = np.rint(geometry["id"][..., 0]).astype(int)
    P, N, I = (geometry[k][..., :3].astype(np.float64) for k in ("P", "N", "I"))
    clamped, unclamped = np.zeros(P.shape), np.zeros(P.shape)
    edge = np.zeros(ident.shape, bool)
    for key, (obj, reach) in objects.items():
        m = ident == key
        terms = {}
        clamped[m], edge[m] = reference_color(scene.world, reach,
                                              _controls(obj.active_material), P[m], N[m],
                                              I[m], terms)
        unclamped[m] = sum(terms[t] for t in TERMS)
    return clamped, unclamped, np.isin(ident, list(objects)) & ~edge


def _check(label, eevee, cycles, clamped, unclamped, mask):
    """Eevee as shown within 1/255 of the reference and of Cycles on every compared pixel;
    Eevee's own value is the unclamped sum (to half-float precision)."""
    shown = np.minimum(eevee["Combined"][..., :3].astype(np.float64), 1.0)
    err_ref = np.abs(shown - clamped).max(axis=-1)[mask]
    err_cycles = np.abs(shown - cycles["Combined"][..., :3]).max(axis=-1)[mask]
    err_sum = (np.abs(eevee["Combined"][..., :3] - unclamped)
               / np.maximum(unclamped, 1.0)).max(axis=-1)[mask]
    over = int((unclamped.max(axis=-1)[mask] > 1.0).sum())
    report(f"[loop {label}] {int(mask.sum())} px ({over} above 1): Eevee-ref max "
           f"{err_ref.max():.2e}, Eevee-Cycles max {err_cycles.max():.2e}, Eevee/sum rel "
           f"{err_sum.max():.2e}")
    assert mask.sum() > 0.5 * mask.size
    assert clamped[mask].std() > 0.02, "lit, not flat"
    assert err_ref.max() <= STEP, label
    assert err_cycles.max() <= STEP, label
    assert err_sum.max() <= 2e-3, f"{label}: Eevee's value is the sum (half floats)"
    return over


def _loop_materials(recipe, loop, objects):
    for obj in objects:
        tree = obj.active_material.node_tree
        lights = tree.nodes[recipe.LIGHTS_NODE]
        assert loop.has_loop(lights.node_tree)
        output = tree.nodes[recipe.OUTPUT_EEVEE]
        assert output.target == "EEVEE" and output.inputs["Surface"].is_linked
        assert tree.nodes[recipe.OUTPUT].target == "CYCLES", "Eevee leaves the lights out"
        assert not any(n.bl_idname == "ShaderNodeOutputAOV" and n.aov_name.startswith("Phong")
                       for n in tree.nodes), "no term AOV: Eevee would compile the lights"


@pytest.mark.eevee
@pytest.mark.cycles
@pytest.mark.parametrize("n_lights", [1, pytest.param(4, marks=pytest.mark.slow),
                                      pytest.param(16, marks=pytest.mark.slow)])
def test_the_loop_matches_the_reference_and_cycles(loop_bpy, blender_tmp, n_lights):
    bpy = loop_bpy
    loop, recipe, _properties, rig, _sync, copies = _modules()
    # the sphere's highlight Blinn's (1), a blend (0.35); the plane's Phong's (0)
    scene, plane, sphere, lights = _scene(bpy, f"Loop {n_lights}", n_lights,
                                          blinn=1.0 if n_lights == 1 else 0.35)
    _loop_materials(recipe, loop, (plane, sphere))
    group = plane.active_material.node_tree.nodes[recipe.LIGHTS_NODE].node_tree
    assert len(copies.listed(group)) + len(copies.listed(group, loop=True)) == sum(
        2 if o.data.type == "SPOT" else 1 for o in lights), "every transform from the World"
    cycles = _render(bpy, scene, "cycles", str(blender_tmp / f"loop_{n_lights}_cycles.exr"))
    eevee = _render(bpy, scene, "eevee", str(blender_tmp / f"loop_{n_lights}_eevee.exr"))
    clamped, unclamped, mask = _expected(scene, {1: (plane, lights), 2: (sphere, lights)},
                                         cycles)
    _check(f"{n_lights} lights", eevee, cycles, clamped, unclamped, mask)


@pytest.mark.eevee
@pytest.mark.cycles
@pytest.mark.slow
def test_above_one_the_loop_shows_the_same_and_stores_the_sum(loop_bpy, blender_tmp):
    """Bright lights: where the model's sum passes 1 the reference (and Cycles) clamp, Eevee's
    loop cannot (no node after Light Accumulation): its value is the sum, shown as 1."""
    bpy = loop_bpy
    scene, plane, sphere, lights = _scene(bpy, "Loop bright", 4, intensity=3.0)
    cycles = _render(bpy, scene, "cycles", str(blender_tmp / "loop_bright_cycles.exr"))
    eevee = _render(bpy, scene, "eevee", str(blender_tmp / "loop_bright_eevee.exr"))
    clamped, unclamped, mask = _expected(scene, {1: (plane, lights), 2: (sphere, lights)},
                                         cycles)
    over = _check("bright", eevee, cycles, clamped, unclamped, mask)
    assert over > 0.2 * mask.sum(), "many pixels above 1"
    raw = eevee["Combined"][..., :3].max(axis=-1)[mask]
    assert raw.max() > 1.5, "Eevee's values above 1 are the sums, not 1"


@pytest.mark.eevee
@pytest.mark.cycles
@pytest.mark.slow
def test_lights_added_removed_retyped_and_set_need_no_relink(loop_bpy, blender_tmp):
    """With the relink handler held (sync.paused: no lights group is rebuilt), a light added,
    one removed, one retyped (point to spot), one recoloured with new Phong settings (its
    packed settings follow by the light handler alone): Eevee shows the new lights, Cycles
    still the lights group's."""
    bpy = loop_bpy
    loop, recipe, _properties, _rig, sync, copies = _modules()
    scene, plane, sphere, lights = _scene(bpy, "Loop edits", 4)
    group = plane.active_material.node_tree.nodes[recipe.LIGHTS_NODE].node_tree
    built = list(group["phong_lights"])
    with sync.paused():
        added = _add_light(bpy, scene, 7, 4)  # a spot with power falloff
        added.data.phong.intensity = 0.9
        gone = lights[1]
        bpy.data.objects.remove(gone)
        retyped = lights[0]
        retyped.data.type = "SPOT"
        retyped.data.spot_size = math.radians(100.0)
        retyped.rotation_euler = (0.3, 0.2, 0.0)
        edited = lights[2].data
        edited.color = (0.4, 1.0, 0.5)
        edited.phong.intensity = 1.7
        edited.phong.edge_exponent = 4.0
        edited.phong.falloff = "POWER"
        edited.phong.power_k = 1.3
        edited.specular_factor = 2.0
        bpy.context.view_layer.update()
        now = [o for o in (lights[0], lights[2], lights[3], added)]
        assert list(group["phong_lights"]) == built, "the handler held: no relink"
        cycles = _render(bpy, scene, "cycles", str(blender_tmp / "loop_edits_cycles.exr"))
        eevee = _render(bpy, scene, "eevee", str(blender_tmp / "loop_edits_eevee.exr"))
    clamped, unclamped, mask = _expected(scene, {1: (plane, now), 2: (sphere, now)}, cycles)
    shown = np.minimum(eevee["Combined"][..., :3], 1.0)
    err = np.abs(shown - clamped).max(axis=-1)[mask]
    stale = np.abs(cycles["Combined"][..., :3] - clamped).max(axis=-1)[mask]
    report(f"[loop edits without relink] Eevee-ref max {err.max():.2e}; Cycles (lights group "
           f"not rebuilt) off by up to {stale.max():.2f}")
    assert err.max() <= STEP
    assert stale.max() > 0.05, "Cycles needs the relink: the edits show"
    sync.relink_scene(scene)  # and the relink brings Cycles in line
    cycles = _render(bpy, scene, "cycles", str(blender_tmp / "loop_edits_cycles2.exr"))
    err = np.abs(cycles["Combined"][..., :3] - clamped).max(axis=-1)[mask]
    assert err.max() <= 1e-4


@pytest.mark.eevee
@pytest.mark.cycles
@pytest.mark.slow
def test_light_linking_in_the_loop(loop_bpy, blender_tmp):
    """A light whose receiver collection excludes the sphere: Eevee's loop honours Light
    Linking itself (Cycles' side has a lights group per light set); changed with the handler
    held, Eevee follows."""
    bpy = loop_bpy
    _loop, _recipe, _properties, _rig, sync, copies = _modules()
    scene, plane, sphere, lights = _scene(bpy, "Loop linking", 4)
    receivers = bpy.data.collections.new("receivers")
    receivers.objects.link(sphere)
    lights[0].light_linking.receiver_collection = receivers
    entry = receivers.collection_objects[0]
    entry.light_linking.link_state = "EXCLUDE"
    bpy.context.view_layer.update()  # the handler relinks: a light set per object (Cycles)
    cycles = _render(bpy, scene, "cycles", str(blender_tmp / "loop_link_cycles.exr"))
    eevee = _render(bpy, scene, "eevee", str(blender_tmp / "loop_link_eevee.exr"))
    objects = {1: (plane, lights), 2: (sphere, lights[1:])}
    clamped, unclamped, mask = _expected(scene, objects, cycles)
    _check("light linking", eevee, cycles, clamped, unclamped, mask)
    with sync.paused():  # light 0 now reaches the sphere only (Include)
        entry.light_linking.link_state = "INCLUDE"
        bpy.context.view_layer.update()
        eevee = _render(bpy, scene, "eevee", str(blender_tmp / "loop_link_eevee2.exr"))
    objects = {1: (plane, lights[1:]), 2: (sphere, lights)}
    clamped, _unclamped, mask = _expected(scene, objects, cycles)
    err = np.abs(np.minimum(eevee["Combined"][..., :3], 1.0) - clamped).max(axis=-1)[mask]
    report(f"[loop linking changed without relink] Eevee-ref max {err.max():.2e}")
    assert err.max() <= STEP


def test_what_keeps_the_lights_group_in_eevee(loop_bpy):
    """The term passes (their AOVs would make Eevee evaluate the per-light part) and Opacity
    below 1 (a blend of more than 1 is another picture) keep the lights group's Shader in
    Eevee; back again, the loop."""
    bpy = loop_bpy
    loop, recipe, _properties, rig, _sync, copies = _modules()
    scene, plane, sphere, _lights = _scene(bpy, "Loop switches", 2)
    material = sphere.active_material
    nodes = material.node_tree.nodes
    from phong_nodes.addon.lighting import opacity, shadows  # noqa: PLC0415

    opacity.set_opacity(material, 0.5)
    assert recipe.OPACITY_MIX in nodes
    if shadows.has_shadows(nodes[recipe.LIGHTS_NODE].node_tree):
        # the group's shadow rays stay out of Eevee: its EEVEE output blends the group's
        # Shader (no Raycast node, not the loop), the CYCLES one its Cycles Shader
        mix = nodes[recipe.OPACITY_MIX_EEVEE]
        assert nodes[recipe.OUTPUT_EEVEE].inputs["Surface"].links[0].from_node == mix
        second = be.compat().input_socket
        assert second(mix, "Shader_001").links[0].from_socket.name == "Shader"
        assert second(nodes[recipe.OPACITY_MIX], "Shader_001").links[0].from_socket.name \
            == shadows.CYCLES_SHADER
    else:
        assert recipe.OUTPUT_EEVEE not in nodes
    opacity.set_opacity(material, 1.0)
    assert recipe.OUTPUT_EEVEE in nodes and recipe.OPACITY_MIX not in nodes
    assert bpy.ops.phong.add_term_passes() == {"FINISHED"}
    for obj in (plane, sphere):
        tree = obj.active_material.node_tree
        assert recipe.OUTPUT_EEVEE not in tree.nodes
        assert not loop.has_loop(tree.nodes[recipe.LIGHTS_NODE].node_tree)
        assert all(f"phong_aov:{name}" in tree.nodes for name in recipe.AOVS)
    layer = scene.view_layers[0]
    for name in rig.PASS_NAMES:
        layer.aovs.remove(layer.aovs[name])
    assert bpy.ops.phong.relink_lights() == {"FINISHED"}
    _loop_materials(recipe, loop, (plane, sphere))


def test_a_file_of_5_3_without_the_loop(loop_bpy, blender_tmp, monkeypatch):
    """Where the loop does not exist (an earlier Blender opening a file of 5.3: the extension's
    load handler, played here with compat.HAS_LIGHT_LOOP off), the groups are rebuilt without
    the loop part and the materials lose their EEVEE Material Output: the lights group's
    Shader again in both engines, the term AOVs back."""
    bpy = loop_bpy
    loop, recipe, _properties, rig, sync, copies = _modules()
    scene, plane, sphere, _lights = _scene(bpy, "Loop old", 3)
    from phong_nodes.addon import compat  # noqa: PLC0415

    monkeypatch.setattr(compat, "HAS_LIGHT_LOOP", False)
    sync.upgrade_on_load()
    for obj in (plane, sphere):
        tree = obj.active_material.node_tree
        group = tree.nodes[recipe.LIGHTS_NODE].node_tree
        assert not group.get(loop.LOOP_KEY)
        assert not any(n.label.startswith(loop.NODE_PREFIX) for n in group.nodes)
        if compat.HAS_RAYCAST:  # 5.2: shadow rays, so Eevee shows the group's Shader apart
            output = tree.nodes[recipe.OUTPUT_EEVEE]
            assert output.inputs["Surface"].links[0].from_socket.name == "Shader"
            assert not any(f"phong_aov:{name}" in tree.nodes for name in recipe.AOVS)
        else:
            assert recipe.OUTPUT_EEVEE not in tree.nodes
            assert all(f"phong_aov:{name}" in tree.nodes for name in recipe.AOVS)
        assert len(group.get(copies.WORLD_KEYS, ())) <= compat.VIEW_LAYER_LOOKUPS


def _previous_release():
    """The newest supported release before 5.3 whose environment is here (tools/phong.sh
    setup), as (release, python), or None."""
    for release, _python, _flags in be.supported_releases():
        if tuple(int(x) for x in release.split(".")[:2]) >= (5, 3):
            continue
        python = os.path.join(be.REPO_ROOT, f".venv-bpy{release}", "bin", "python")
        if os.path.exists(python):
            return release, python
    return None


@pytest.mark.eevee
@pytest.mark.slow
def test_a_file_of_5_3_opens_and_renders_the_same_before_5_3(loop_bpy, blender_tmp):
    """Saved on 5.3 with the loop, opened by the newest earlier release here with the
    extension enabled: the load handler rebuilds the groups without the loop, Eevee there
    renders what Eevee renders here (within 1/255, shown) and no node is undefined."""
    bpy = loop_bpy
    previous = _previous_release()
    if previous is None:
        pytest.skip("no environment of a release before 5.3 here "
                    "(PHONG_BPY=5.2.3 bash tools/phong.sh setup)")
    scene, _plane, _sphere, _lights = _scene(bpy, "Loop file", 4)
    eevee = _render(bpy, scene, "eevee", str(blender_tmp / "loop_file_53.exr"))
    blend = str(blender_tmp / "loop_53.blend")
    bpy.ops.wm.save_as_mainfile(filepath=blend, copy=True)
    out = str(blender_tmp / "loop_file_old.exr")
    code = (
        "import os, sys, tempfile; os.environ.setdefault('BLENDER_USER_RESOURCES', "
        "tempfile.mkdtemp()); import blender_env as be; "
        "import bpy; be.enable(); "
        f"bpy.ops.wm.open_mainfile(filepath={blend!r}); "
        "scene = bpy.data.scenes['Loop file']; bpy.context.window.scene = scene; "
        "bad = [n.name for m in bpy.data.materials if m.node_tree for n in m.node_tree.nodes "
        "if n.bl_idname == 'NodeUndefined'] + [n.name for g in bpy.data.node_groups for n in "
        "g.nodes if n.bl_idname == 'NodeUndefined']; "
        "print('UNDEFINED', len(bad), flush=True); "
        f"be.configure_engine(scene, 'eevee'); be.render_exr(scene, {out!r}); "
        "sys.stdout.flush(); os._exit(0)")
    run = subprocess.run([previous[1], "-c", code], capture_output=True, text=True,
                         cwd=os.path.join(be.REPO_ROOT, "tests"), timeout=600)  # blender_env
    assert run.returncode == 0, run.stdout[-2000:] + run.stderr[-2000:]
    assert "UNDEFINED 0" in run.stdout, run.stdout[-2000:]
    old = {k: v[::-1] for k, v in be.read_multilayer_exr(out).items()}
    ident = np.rint(eevee["id"][..., 0]).astype(int) > 0
    err = np.abs(np.minimum(eevee["Combined"][..., :3], 1.0)
                 - old["Combined"][..., :3]).max(axis=-1)[ident]
    report(f"[loop file opened by bpy {previous[0]}] Eevee there vs Eevee on 5.3 (shown): max "
           f"{err.max():.2e}")
    assert err.max() <= STEP


@pytest.mark.eevee
@pytest.mark.cycles
@pytest.mark.slow
@pytest.mark.parametrize("name", ["threejs_spot_penumbra", "threejs_point_cutoff", "two_lights"])
def test_the_comparison_of_a_demo_scene_on_the_loop(loop_bpy, tmp_path, name):
    """Compare Phong Scene (core/compare.py) on demo scenes whose materials show the loop in
    Eevee (the three.js model's spot with a penumbra, its point light's cut-off distance; the
    seeds' two lights): Eevee as shown within 1/255 of the reference and of Cycles, Cycles'
    term passes (from AOVs in the comparison's copy of the lights group: the materials have
    none) within 1e-4."""
    bpy = loop_bpy
    loop, recipe, _properties, _rig, _sync, copies = _modules()
    from phong_nodes.addon.comparison import engine  # noqa: PLC0415

    bpy.ops.phong.build_demo_scene(name=name, resolution=48)
    scene = bpy.data.scenes[name]
    phong = [slot.material for obj in scene.objects for slot in obj.material_slots
             if recipe.is_phong_material(slot.material)]
    assert phong and all(recipe.OUTPUT_EEVEE in m.node_tree.nodes for m in phong
                         if not recipe.blends(m))
    metrics = engine.run(scene, str(tmp_path / name))
    pairs = metrics["pairs"]
    report(f"[loop comparison {name}] {metrics['verdict']}; eevee-reference max "
           f"{pairs['eevee-reference']['max_abs']:.2e}, eevee-cycles max "
           f"{pairs['eevee-cycles']['max_abs']:.2e}, above 1: {metrics['eevee_above_1']}")
    assert metrics["ok"], metrics["verdict"]
    assert pairs["eevee-reference"]["share_over_1_255"] == 0.0
    assert pairs["eevee-cycles"]["max_abs"] <= STEP
    assert max(t["max_abs"] for t in metrics["terms"].values()) <= 1e-4


def test_the_loop_is_there_exactly_from_5_3(bpy_clean):
    """compat.HAS_LIGHT_LOOP on every release: the nodes exist from 5.3 on; a file just made is
    not from a newer release; the View Layer lookups of a group on the loop are unlimited only
    where the loop is."""
    bpy = bpy_clean
    compat = be.compat()
    has = hasattr(bpy.types, "ShaderNodeLightAccumulation")
    assert compat.HAS_LIGHT_LOOP == has == (bpy.app.version >= (5, 3, 0))
    assert not compat.file_from_newer_release()
    assert compat.view_layer_lookups(False) == compat.VIEW_LAYER_LOOKUPS
    assert compat.view_layer_lookups(True) == (compat.LOOP_VIEW_LAYER_LOOKUPS if has
                                               else compat.VIEW_LAYER_LOOKUPS)


def test_before_5_3_the_material_is_the_one_of_5_2(bpy_clean):
    """Where there is no loop (and on 5.3 with the term passes on) Apply makes the recipe of
    5.2: one Material Output of target ALL showing the lights group, the term AOVs, no loop
    part in the group, the lights' transforms within compat.VIEW_LAYER_LOOKUPS."""
    bpy = bpy_clean
    loop, recipe, _properties, rig, _sync, copies = _modules()
    compat = be.compat()
    scene = be.new_scene("Recipe", 8, 8, "cycles")
    bpy.context.window.scene = scene
    if compat.HAS_LIGHT_LOOP:
        assert bpy.ops.phong.add_term_passes() == {"FINISHED"}
    plane = be.add_quad(scene, "Plane", -1, -1, 1, 1)
    for index in range(6):
        _light(bpy, scene, f"L{index}", ("POINT", "SPOT")[index % 2], (index, 0.0, 2.0))
    plane.select_set(True)
    assert bpy.ops.phong.apply_material() == {"FINISHED"}
    tree = plane.active_material.node_tree
    group = tree.nodes[recipe.LIGHTS_NODE].node_tree
    from phong_nodes.addon.lighting import shadows  # noqa: PLC0415

    # 5.2 casts Phong shadows in Cycles (the lights cast shadows by default): its Raycast
    # nodes stay out of Eevee's output; on 5.3 the term passes take the shadow rays away
    rays = compat.HAS_RAYCAST and not compat.HAS_LIGHT_LOOP
    assert shadows.has_shadows(group) == rays
    outputs = [n for n in tree.nodes if n.bl_idname == "ShaderNodeOutputMaterial"]
    assert sorted(n.target for n in outputs) == (["CYCLES", "EEVEE"] if rays else ["ALL"])
    # the term AOVs where nothing keeps them out (the shadow rays do, as the loop does)
    assert [f"phong_aov:{name}" in tree.nodes for name in recipe.AOVS] == [
        not rays] * len(recipe.AOVS)
    assert not loop.has_loop(group) and not group.get(loop.LOOP_KEY)
    assert not any(n.label.startswith(loop.NODE_PREFIX) for n in group.nodes)
    assert [o.name for o in group.interface.items_tree if o.in_out == "OUTPUT"] == [
        name for name, _type in rig.OUTPUTS]
    assert len(group.get(copies.WORLD_KEYS, ())) <= compat.VIEW_LAYER_LOOKUPS
    assert not group.get(copies.LOOP_WORLD_KEYS)
