# SPDX-License-Identifier: GPL-3.0-or-later
"""FBX with Phong materials (issue 45): ``core/fbx/write.py`` (the Phong parts of a binary FBX
rewritten, every other node's bytes kept) and File ▸ Export ▸ FBX (.fbx) with Phong Materials.

The exported files are read here by peers, independently of the exporter: Blender's own
``io_scene_fbx.parse_fbx`` (the properties written on each object), ufbx (the shading model
and values an FBX SDK reader finds), Blender's own importer (the object colour as Base Color,
no metallic, the opacity) and the project's importer (import ∘ export gives every control
again, to float32).  Expected values are the controls the test sets, through the mapping
written out here from the issue."""

from __future__ import annotations

import glob
import math
import os

import numpy as np
import pytest

import blender_env as be

DATA = os.path.join(os.path.dirname(os.path.abspath(__file__)), "data", "fbx")
ufbx = be.need_module("ufbx")


# -- the rewriter, without Blender -----------------------------------------------------------

BINARY_7 = [p for p in sorted(glob.glob(os.path.join(DATA, "*binary.fbx")))
            if "6100" not in os.path.basename(p)]


@pytest.mark.parametrize("path", BINARY_7, ids=os.path.basename)
def test_walk_reencodes_every_header_to_the_same_bytes(path):
    """Every node header re-encoded at its place (``force``) and the footer's padding
    recomputed: the same bytes, for binary FBX 7.x of Maya and Blender alike."""
    from phong_nodes.core import fbx
    data = open(path, "rb").read()
    out, missing = fbx.rewrite(data, force=True)
    assert out == data and missing == []


def test_rewritten_material_and_ambient_are_what_ufbx_reads(tmp_path):
    """Blender 2.93's file (tests/data/fbx) with its material rewritten as a Lambert and
    its ambient set, without Blender: ufbx (through core.fbx's child process) reads the
    values written, the model, the opacity and the user property; every node but the
    rewritten ones keeps its bytes (the file grows by the new properties only)."""
    from phong_nodes.core import fbx
    path = os.path.join(DATA, "blender_293_embedded_textures_7400_binary.fbx")
    data = open(path, "rb").read()
    material = fbx.Material(kind="LAMBERT", colors={
        "Object Color": (0.1, 0.2, 0.3), "Ambient Object Color": (0.4, 0.5, 0.6),
        "Specular Color": (0.0, 0.0, 0.0), "Irradiant Color": (0.01, 0.02, 0.03)},
        exponent=7.0, opacity=0.75, user={"Exponent": 7.0})
    out, missing = fbx.rewrite(data, {"Material.001": material, "Nowhere": material},
                               ambient=(0.2, 0.3, 0.4))
    assert missing == ["material Nowhere"]
    target = tmp_path / "rewritten.fbx"
    target.write_bytes(out)
    scene = fbx.read(str(target))
    m = scene.material("Material.001")
    assert (m.kind, m.shading) == ("LAMBERT", "Lambert")
    assert m.colors["Object Color"] == (0.1, 0.2, 0.3)
    assert m.colors["Ambient Object Color"] == (0.4, 0.5, 0.6)
    assert m.colors["Irradiant Color"] == (0.01, 0.02, 0.03)
    assert m.opacity == 0.75 and m.user == {"Exponent": 7.0} and m.exponent == 7.0
    assert all(m.sources[k] == "object" for k in ("DiffuseFactor", "AmbientFactor",
                                                  "EmissiveFactor", "TransparencyFactor"))
    assert scene.ambient == (0.2, 0.3, 0.4)
    # the embedded textures (Video Content) keep their bytes
    pngs, at = [], data.find(b"\x89PNG")
    while at >= 0:
        end = data.index(b"IEND", at) + 8
        pngs.append(data[at:end])
        at = data.find(b"\x89PNG", end)
    assert len(pngs) >= 4 and all(png in out for png in pngs)
    assert len(out) > len(data)


def test_not_a_binary_fbx_7_is_one_error():
    from phong_nodes.core import fbx
    for data in (b"", b"; FBX 7.4.0 project file", open(os.path.join(
            DATA, "maya_cube_6100_binary.fbx"), "rb").read(),
                 open(BINARY_7[0], "rb").read()[:200]):
        with pytest.raises(fbx.FbxWriteError):
            fbx.rewrite(data, force=True)


# -- the hand scene ---------------------------------------------------------------------------

#: material -> (Object Color, Specular Color, Exponent, Blinn, Irradiant Color, Opacity)
MATERIALS = {
    "Glossy": ((0.8, 0.3, 0.1), (0.5, 0.6, 0.7), 42.0, 0.0, (0.0, 0.0, 0.0), 1.0),
    "Blinny": ((0.2, 0.5, 0.3), (1.0, 1.0, 1.0), 12.5, 1.0, (0.05, 0.0, 0.1), 1.0),
    "Matte": ((0.6, 0.6, 0.2), (0.0, 0.0, 0.0), 20.0, 0.0, (0.0, 0.0, 0.0), 1.0),
    "Glass": ((0.1, 0.2, 0.9), (0.3, 0.3, 0.3), 80.0, 0.25, (0.0, 0.0, 0.0), 0.4),
}
AMBIENT_KA = {"Glossy": (0.25, 0.125, 0.5)}   # an own Ambient Object Color
#: light -> (type, colour, intensity, settings)
LIGHTS = {
    "Quad": ("POINT", (1.0, 0.9, 0.8), 3.0, {"quadratic": 1.0, "linear": 0.0, "constant": 0.0}),
    "Lin": ("POINT", (0.5, 1.0, 0.5), 2.0, {"quadratic": 0.0, "linear": 1.0, "constant": 0.0}),
    "Flat": ("POINT", (1.0, 1.0, 1.0), 0.5, {"quadratic": 0.0, "linear": 0.0, "constant": 1.0}),
    "Half": ("POINT", (1.0, 1.0, 1.0), 1.0, {"quadratic": 0.5, "linear": 0.0, "constant": 0.0}),
    "Mixed": ("POINT", (1.0, 0.5, 0.25), 4.0,
              {"quadratic": 0.125, "linear": 0.25, "constant": 0.5}),
    "Cubic": ("POINT", (1.0, 1.0, 1.0), 1.5, {"falloff": "POWER", "power_k": 3.0}),
    "Soft": ("POINT", (1.0, 1.0, 1.0), 1.5, {"falloff": "POWER", "power_k": 1.5}),
    "Cone": ("SPOT", (1.0, 1.0, 0.5), 6.0, {"edge_exponent": 8.0, "quadratic": 1.0,
                                           "linear": 0.0, "constant": 0.0}),
    "Hard": ("SPOT", (0.5, 0.5, 1.0), 2.0, {"edge_exponent": 0.0, "diffuse": 0.5}),
    "Sky": ("SUN", (1.0, 1.0, 0.9), 0.75, {"specular": 0.25}),
}
WORLD = (0.5, (0.2, 0.4, 0.6))   # Phong ambient intensity, colour


def _hand_scene(bpy):
    """Four planes with the Phong materials of MATERIALS (through Apply Phong Material), one
    with a Principled material beside them, the lights of LIGHTS, the World's ambient."""
    from phong_nodes.addon.lighting import recipe, writer  # noqa: PLC0415
    from phong_nodes.addon.lighting import feeds as feed_reader
    from phong_nodes.addon.lighting import opacity as opacity_nodes

    scene = bpy.context.scene
    world = bpy.data.worlds.new("World")
    scene.world = world
    world.phong.ambient_intensity, world.phong.ambient_color = WORLD
    planes = {}
    for index, name in enumerate([*MATERIALS, "Plastic"]):
        mesh = bpy.data.meshes.new(name)
        mesh.from_pydata([(0, 0, 0), (1, 0, 0), (1, 1, 0), (0, 1, 0)], [], [(0, 1, 2, 3)])
        mesh.materials.append(be.plain_source(name) if name in MATERIALS
                              else bpy.data.materials.new(name))
        obj = bpy.data.objects.new(name, mesh)
        obj.location = (2.0 * index, 0.0, 0.0)
        scene.collection.objects.link(obj)
        planes[name] = obj
    plastic = planes["Plastic"].material_slots[0].material
    plastic.diffuse_color = (0.9, 0.1, 0.1, 1.0)
    for index, (name, (kind, colour, intensity, settings)) in enumerate(LIGHTS.items()):
        light = bpy.data.lights.new(name, kind)
        light.color = colour
        obj = bpy.data.objects.new(name, light)
        obj.location = (index, -3.0, 4.0)
        scene.collection.objects.link(obj)
        light.phong.intensity = intensity
        if kind == "SPOT":
            light.spot_size = math.radians(50.0)
        from phong_nodes.addon.lighting import properties  # noqa: PLC0415
        properties.write_light(light, settings)
    bpy.data.lights["Cone"].use_shadow = False
    be.apply_phong(scene, [o for o in scene.objects if o.name in MATERIALS],
                   active=planes["Glossy"])
    made = {}
    for name, (kd, ks, exponent, blinn, ke, opacity) in MATERIALS.items():
        material = planes[name].material_slots[0].material
        nodes = material.node_tree.nodes
        nodes["phong_object_color"].outputs[0].default_value = (*kd, 1.0)
        nodes["phong_specular_color"].outputs[0].default_value = (*ks, 1.0)
        nodes["phong_exponent"].outputs[0].default_value = exponent
        nodes["phong_blinn"].outputs[0].default_value = blinn
        nodes["phong_irradiant_color"].outputs[0].default_value = (*ke, 1.0)
        opacity_nodes.set_opacity(material, opacity)
        if name in AMBIENT_KA:
            node = writer.color_control(material.node_tree, recipe.AMBIENT_CONTROL,
                                           AMBIENT_KA[name])
            material.node_tree.links.new(node.outputs[0], nodes[recipe.LIGHTS_NODE].inputs[
                recipe.AMBIENT_INPUT])
        made[name] = material
    return planes, made


UFBX_SCRIPT = r"""
import gc, json, sys
gc.disable()   # ufbx 0.0.5's objects crash the collector (core/fbx/read.py)
import ufbx
scene = ufbx.load_file(sys.argv[1], ignore_geometry=True)
out = {}
for i in range(len(scene.materials)):
    m = scene.materials[i]
    v = m.fbx.diffuse_color.value_vec4
    out[m.name] = [ufbx.ShaderType(m.shader_type).name, [v.x, v.y, v.z]]
print(json.dumps(out))
sys.stdout.flush()
import os
os._exit(0)
"""


def _ufbx_materials(path):
    """{material: (ufbx shader type name, DiffuseColor)} as ufbx reads the file (in a child
    process: ufbx 0.0.5's Python objects crash the garbage collector)."""
    import json
    import subprocess
    import sys
    done = subprocess.run([sys.executable, "-c", UFBX_SCRIPT, path], capture_output=True,
                          text=True, timeout=120, check=True)
    return json.loads(done.stdout.strip().splitlines()[-1])


def _f32(values):
    return np.asarray(values, np.float32).astype(np.float64)


def _export(bpy, tmp_path, name="scene.fbx", **options):
    path = str(tmp_path / name)
    assert bpy.ops.phong.export_fbx(filepath=path, **options) == {"FINISHED"}
    return path


#: Blender's FBX options that leave the lights out: Blender 5.0.1's own importer fails on
#: any light (its blen_read_light sets ``lamp.cycles.cast_shadow``, gone in 5.0), so the
#: files its importer reads here are written without them.
NO_LIGHTS = {"object_types": {"MESH", "EMPTY", "CAMERA", "ARMATURE", "OTHER"}}


def _parsed(path):
    """{class: {name: (Properties70 {P name: (type, flags, values)}, {child: props})}} of the
    file's objects, read by Blender's own parse_fbx, and its GlobalSettings properties."""
    from io_scene_fbx import parse_fbx
    root, _version = parse_fbx.parse(path)
    out = {}

    def props(element):
        block = next((e for e in element.elems if e.id == b"Properties70"), None)
        return {} if block is None else {
            p.props[0].decode(): (p.props[1].decode(), p.props[3].decode(), tuple(p.props[4:]))
            for p in block.elems}

    for section in root.elems:
        if section.id == b"Objects":
            for obj in section.elems:
                name = obj.props[1].split(b"\x00\x01")[0].decode()
                children = {e.id.decode(): e.props for e in obj.elems if e.elems == []}
                out.setdefault(obj.id.decode(), {})[name] = (props(obj), children)
        if section.id == b"GlobalSettings":
            out["GlobalSettings"] = props(section)
    return out


def _expected_material(name):
    """The FBX properties a Phong material of MATERIALS must have, from the issue's mapping:
    Lambert where the specular is black; every factor 1, ReflectionFactor 0; the opacity
    triple; colours are the controls (float32)."""
    kd, ks, exponent, _blinn, ke, opacity = MATERIALS[name]
    lambert = ks == (0.0, 0.0, 0.0)
    o = float(np.float32(opacity))
    return lambert, {
        "DiffuseColor": _f32(kd), "AmbientColor": _f32(AMBIENT_KA.get(name, kd)),
        "SpecularColor": _f32(ks), "EmissiveColor": _f32(ke),
        "ShininessExponent": _f32([exponent]), "Shininess": _f32([exponent]),
        "DiffuseFactor": [1.0], "AmbientFactor": [1.0], "SpecularFactor": [1.0],
        "EmissiveFactor": [1.0], "ReflectionFactor": [0.0],
        "Opacity": [o], "TransparencyFactor": [1.0 - o], "TransparentColor": [1.0, 1.0, 1.0]}


@pytest.mark.slow
def test_export_writes_every_phong_value_on_the_object(bpy_clean, tmp_path):
    """Blender's parse_fbx reads the file: each Phong material is an FBX Phong material
    (Lambert for black specular) with every value on the object itself; each light its type,
    colour, Intensity = 100 × Phong intensity, DecayType, cone and CastShadows; GlobalSettings
    AmbientColor = ambient intensity × colour."""
    bpy = bpy_clean
    _planes, made = _hand_scene(bpy)
    parsed = _parsed(_export(bpy, tmp_path))
    for name, material in made.items():
        props, children = parsed["Material"][material.name]
        lambert, want = _expected_material(name)
        model = "Lambert" if lambert else "Phong"
        assert children["ShadingModel"] == [model.encode()], name
        assert props["ShadingModel"][2] == (model.encode(),)
        for key, value in want.items():
            np.testing.assert_allclose(props[key][2], value, rtol=0, atol=1e-12,
                                       err_msg=f"{name} {key}")
        blinn = MATERIALS[name][3]
        if blinn:
            assert props["PhongNodes|Blinn"] == ("double", "U", (pytest.approx(blinn),))
        else:
            assert "PhongNodes|Blinn" not in props
    decay = {"Quad": 2, "Lin": 1, "Flat": 0, "Half": 2, "Mixed": 2, "Cubic": 3, "Soft": 2,
             "Cone": 2, "Hard": 2}
    scale = {"Half": 0.5, "Mixed": 0.125}   # i0/(c r^k) = (i0/c)/r^k: Intensity 100 i0/c
    for name, (kind, colour, intensity, settings) in LIGHTS.items():
        props, _children = parsed["NodeAttribute"][name]
        assert props["LightType"][2] == ({"POINT": 0, "SUN": 1, "SPOT": 2}[kind],)
        np.testing.assert_allclose(props["Color"][2], _f32(colour), atol=1e-12)
        assert props["Intensity"][2][0] == pytest.approx(100 * intensity / scale.get(name, 1))
        if kind != "SUN":
            assert props["DecayType"][2] == (decay[name],), name
        assert props["CastShadows"][2] == (0 if name == "Cone" else 1,)
        if kind == "SPOT":
            outer = props["OuterAngle"][2][0]
            inner = props["InnerAngle"][2][0]
            assert outer == pytest.approx(50.0, abs=1e-5)
            e = settings["edge_exponent"]
            if e == 0:
                assert inner == pytest.approx(outer)   # a hard edge: no fade
            else:   # the edge factor (cos ω)^e is ½ halfway between the half-angles
                assert math.cos(math.radians((inner + outer) / 4)) ** e == pytest.approx(0.5)
    ambient = parsed["GlobalSettings"]["AmbientColor"][2]
    np.testing.assert_allclose(ambient, WORLD[0] * _f32(WORLD[1]), atol=1e-7)


@pytest.mark.slow
def test_peers_read_the_export(bpy_clean, tmp_path):
    """ufbx (an FBX SDK-style reader) finds FBX_PHONG / FBX_LAMBERT materials with the
    values; Blender's own importer shows the object colour as Base Color, no metallic
    (ReflectionFactor 0 written: its template FbxSurfacePhong says 1), and the opacity."""
    bpy = bpy_clean
    _planes, made = _hand_scene(bpy)
    path = _export(bpy, tmp_path)
    names = {name: material.name for name, material in made.items()}
    from phong_nodes.addon.interchange import fbx_export
    meshes = str(tmp_path / "meshes.fbx")
    fbx_export.export(bpy.context, meshes, **NO_LIGHTS)
    read = _ufbx_materials(path)
    for name, material in names.items():
        lambert, want = _expected_material(name)
        kind, diffuse = read[material]
        assert kind == ("FBX_LAMBERT" if lambert else "FBX_PHONG"), name
        np.testing.assert_allclose(diffuse, want["DiffuseColor"], atol=1e-12)
    be.reset_empty_file()
    assert bpy.ops.import_scene.fbx(filepath=meshes) == {"FINISHED"}
    for name, material in names.items():
        principled = next(n for n in bpy.data.materials[material].node_tree.nodes
                          if n.bl_idname == "ShaderNodeBsdfPrincipled")
        kd, _ks, _e, _b, _ke, opacity = MATERIALS[name]
        np.testing.assert_allclose(tuple(principled.inputs["Base Color"].default_value)[:3],
                                   kd, atol=1e-6)
        assert principled.inputs["Metallic"].default_value == 0.0, name
        assert principled.inputs["Alpha"].default_value == pytest.approx(opacity, abs=1e-6)


def _controls(material):
    from phong_nodes.addon.lighting import recipe, writer
    from phong_nodes.addon.lighting import feeds as feed_reader
    from phong_nodes.addon.lighting import opacity as opacity_nodes
    return {k: f.value for k, f in feed_reader.feeds(material).items()}


@pytest.mark.slow
def test_import_of_the_export_gives_every_control_again(bpy_clean, tmp_path):
    """File ▸ Import ▸ FBX (Phong) of the export: every control of every Phong material,
    every Phong setting of every light, the World's ambient, as they were (float32)."""
    bpy = bpy_clean
    from phong_nodes.addon.lighting import properties
    _planes, made = _hand_scene(bpy)
    before = {m.name: _controls(m) for m in made.values()}
    lights = {name: {attr: float(bpy.data.lights[name].get(key, default))
                     for attr, (key, default) in properties.LIGHT_KEYS.items()}
              for name in LIGHTS}
    falloffs = {name: properties.falloff_of(bpy.data.lights[name]) for name in LIGHTS
                if LIGHTS[name][0] != "SUN"}
    path = _export(bpy, tmp_path)
    be.reset_empty_file()
    assert bpy.ops.phong.import_fbx(filepath=path) == {"FINISHED"}
    for name, want in before.items():
        got = _controls(bpy.data.materials[name])
        for key, value in want.items():
            np.testing.assert_allclose(_f32(got[key]), _f32(value), rtol=0, atol=0,
                                       err_msg=f"{name} {key}")
    for name, want in lights.items():
        light = bpy.data.lights[name]
        got = {attr: float(light.get(key, default))
               for attr, (key, default) in properties.LIGHT_KEYS.items()}
        for attr, value in want.items():
            assert np.float32(got[attr]) == pytest.approx(np.float32(value), rel=1e-6), \
                (name, attr)
        if name in falloffs:
            assert properties.falloff_of(light) == falloffs[name], name
        assert light.type == LIGHTS[name][0]
        np.testing.assert_allclose(tuple(light.color), LIGHTS[name][1], atol=1e-7)
    world = bpy.context.scene.world
    assert world.phong.ambient_intensity == pytest.approx(WORLD[0])
    np.testing.assert_allclose(tuple(world.phong.ambient_color), WORLD[1], atol=1e-7)


def test_a_principled_material_is_written_as_blender_writes_it(bpy_clean, tmp_path):
    bpy = bpy_clean
    _hand_scene(bpy)
    ours = _parsed(_export(bpy, tmp_path))
    theirs_path = str(tmp_path / "blender.fbx")
    assert bpy.ops.export_scene.fbx(filepath=theirs_path) == {"FINISHED"}
    theirs = _parsed(theirs_path)
    assert ours["Material"]["Plastic"] == theirs["Material"]["Plastic"]
    assert ours["Geometry"] == theirs["Geometry"]


def test_selection_only_and_a_failed_rewrite_leaves_the_file(bpy_clean, tmp_path,
                                                             monkeypatch):
    """Selected Objects Only writes the selection; a failure after Blender's exporter ran
    leaves the file that was there as it was, and no temporary file."""
    bpy = bpy_clean
    _planes, made = _hand_scene(bpy)
    for obj in bpy.context.scene.objects:
        obj.select_set(obj.name == "Glossy")
    parsed = _parsed(_export(bpy, tmp_path, use_selection=True))
    assert set(parsed["Material"]) == {made["Glossy"].name}
    path = tmp_path / "scene.fbx"
    before = path.read_bytes()
    from phong_nodes.core import fbx

    def broken(*_args, **_kwargs):
        raise fbx.FbxWriteError("broken on purpose")

    monkeypatch.setattr(fbx, "rewrite", broken)
    with pytest.raises(RuntimeError, match="cannot be rewritten .broken on purpose"):
        bpy.ops.phong.export_fbx(filepath=str(path))
    assert path.read_bytes() == before
    assert sorted(os.listdir(tmp_path)) == ["scene.fbx"]


def _scene_controls(bpy):
    from phong_nodes.addon.lighting import properties, recipe, writer
    from phong_nodes.addon.lighting import feeds as feed_reader
    from phong_nodes.addon.lighting import opacity as opacity_nodes
    mats = {m.name: _controls(m) for m in bpy.data.materials if recipe.is_phong_material(m)}
    lights = {l.name: ({attr: float(l.get(key, default))
                        for attr, (key, default) in properties.LIGHT_KEYS.items()},
                       properties.falloff_of(l), l.type, tuple(l.color))
              for l in bpy.data.lights}
    world = bpy.context.scene.world
    return mats, lights, (world.phong.ambient_intensity, tuple(world.phong.ambient_color))


@pytest.mark.parametrize("name", ["maya_phong_properties_7700_ascii.fbx",
                                  pytest.param("maya_material_chart_7700_binary.fbx",
                                               marks=pytest.mark.slow),
                                  pytest.param("motionbuilder_lights_7700_ascii.fbx",
                                               marks=pytest.mark.slow),
                                  pytest.param("handmade_phong_lights_7400_ascii.fbx",
                                               marks=pytest.mark.slow)])
def test_real_files_imported_then_exported_import_the_same(bpy_clean, tmp_path, name):
    """Files of other programs (tests/data/fbx) imported, exported, imported again: the same
    Phong materials, lights and ambient (float32)."""
    bpy = bpy_clean
    assert bpy.ops.phong.import_fbx(filepath=os.path.join(DATA, name)) == {"FINISHED"}
    first = _scene_controls(bpy)
    assert first[0] or first[1], "Phong materials or lights"
    path = _export(bpy, tmp_path)
    be.reset_empty_file()
    assert bpy.ops.phong.import_fbx(filepath=path) == {"FINISHED"}
    again = _scene_controls(bpy)
    assert set(again[0]) == set(first[0])
    for material, controls in first[0].items():
        for key, value in controls.items():
            np.testing.assert_allclose(_f32(again[0][material][key]), _f32(value), rtol=1e-6,
                                       atol=0, err_msg=f"{material} {key}")
    assert set(again[1]) == set(first[1])
    for light, (settings, falloff, kind, colour) in first[1].items():
        got = again[1][light]
        assert (got[1], got[2]) == (falloff, kind), light
        np.testing.assert_allclose(got[3], colour, atol=1e-7)
        for attr, value in settings.items():
            assert np.float32(got[0][attr]) == pytest.approx(np.float32(value), rel=1e-6), \
                (light, attr)
    assert again[2][0] == pytest.approx(first[2][0])
    np.testing.assert_allclose(again[2][1], first[2][1], atol=1e-7)
    # Blender's own importer: the object colour as Base Color, never metallic
    from phong_nodes.addon.interchange import fbx_export
    meshes = str(tmp_path / "meshes.fbx")
    fbx_export.export(bpy.context, meshes, **NO_LIGHTS)
    be.reset_empty_file()
    assert bpy.ops.import_scene.fbx(filepath=meshes) == {"FINISHED"}
    for material, controls in first[0].items():
        principled = next(n for n in bpy.data.materials[material].node_tree.nodes
                          if n.bl_idname == "ShaderNodeBsdfPrincipled")
        assert principled.inputs["Metallic"].default_value == 0.0, material
        np.testing.assert_allclose(tuple(principled.inputs["Base Color"].default_value)[:3],
                                   controls["Object Color"], atol=1e-6, err_msg=material)


@pytest.mark.parametrize("model", ["threejs", "x3d"])
def test_spot_inner_angle_follows_the_scenes_model(bpy_clean, tmp_path, model):
    """The soft edge as each model states it: three.js, InnerAngle = (1 − penumbra) ×
    OuterAngle; X3D, InnerAngle = the beam width (a full angle, in degrees); and the import
    of the export gives the model's setting again."""
    bpy = bpy_clean
    from phong_nodes.addon.lighting import rig
    scene = bpy.context.scene
    scene[rig.MODEL_KEY] = model
    light = bpy.data.lights.new("Spot", "SPOT")
    light.spot_size = math.radians(60.0)
    scene.collection.objects.link(bpy.data.objects.new("Spot", light))
    setting, value = ("penumbra", 0.25) if model == "threejs" else ("beam_width", 0.3)
    light.phong.intensity = 2.0
    setattr(light.phong, setting, value)
    props, _children = _parsed(_export(bpy, tmp_path))["NodeAttribute"]["Spot"]
    outer, inner = props["OuterAngle"][2][0], props["InnerAngle"][2][0]
    assert outer == pytest.approx(60.0, abs=1e-5)
    want = (1 - 0.25) * 60.0 if model == "threejs" else 2 * math.degrees(np.float32(0.3))
    assert inner == pytest.approx(want, abs=1e-4)
    be.reset_empty_file()
    assert bpy.ops.phong.import_fbx(filepath=str(tmp_path / "scene.fbx")) == {"FINISHED"}
    assert getattr(bpy.data.lights["Spot"].phong, setting) == pytest.approx(value, rel=1e-6)


# -- three.js's FBXLoader in Chromium (a peer reader) -----------------------------------------

FBXLOADER_MODULES = (("build/three.module.js", "three/three.module.js"),
                     ("build/three.core.js", "three/three.core.js"),
                     ("examples/jsm/loaders/FBXLoader.js", "three/addons/loaders/FBXLoader.js"),
                     ("examples/jsm/libs/fflate.module.js", "three/addons/libs/fflate.module.js"),
                     ("examples/jsm/curves/NURBSCurve.js", "three/addons/curves/NURBSCurve.js"),
                     ("examples/jsm/curves/NURBSUtils.js", "three/addons/curves/NURBSUtils.js"))

FBXLOADER_PAGE = """<!DOCTYPE html>
<html lang="en"><head><meta charset="utf-8"><title>phong: loading</title>
<script type="importmap">
{"imports": {"three": "./three/three.module.js", "three/addons/": "./three/addons/"}}
</script></head><body>
<pre id="phong-errors"></pre>
<pre id="phong-pixels" data-width="1" data-height="1">AAAAAA==</pre>
<script type="text/plain" id="fbx">@FBX@</script>
<script type="module">
import * as THREE from "three";
import { FBXLoader } from "three/addons/loaders/FBXLoader.js";
try {
  const text = atob(document.getElementById("fbx").textContent.trim());
  const bytes = new Uint8Array(text.length);
  for (let i = 0; i < text.length; i++) { bytes[i] = text.charCodeAt(i); }
  const group = new FBXLoader().parse(bytes.buffer, "./");
  const srgb = (c) => { const t = new THREE.Color(); c.getRGB(t, THREE.SRGBColorSpace);
                        return [t.r, t.g, t.b]; };
  const out = {materials: {}, lights: {}};
  group.traverse((o) => {
    if (o.isMesh) {
      for (const m of [].concat(o.material)) {
        out.materials[m.name] = {type: m.type, color: srgb(m.color), opacity: m.opacity,
          transparent: m.transparent, emissive: srgb(m.emissive),
          specular: m.specular ? srgb(m.specular) : null,
          shininess: m.shininess === undefined ? null : m.shininess};
      }
    }
    if (o.isLight) {
      out.lights[o.name] = {type: o.type, color: srgb(o.color), intensity: o.intensity};
    }
  });
  document.title = "phong: done " + JSON.stringify(out);
} catch (error) {
  document.getElementById("phong-errors").textContent = String(error && error.stack || error);
  document.title = "phong: error";
}
</script></body></html>
"""


def _fbxloader(path, folder):
    """What three.js's FBXLoader reads of the FBX file *path* (in headless Chromium): {"materials":
    {name: {type, color, specular, shininess, opacity, ...}}, "lights": {name: {...}}}, the
    colours back in the file's numbers (FBXLoader reads them as sRGB)."""
    import base64
    import json
    from phong_nodes.core import browser, threejs
    if browser.find_browser() is None:
        be.skip_unless_ci("Chromium is missing: the FBXLoader peer needs it")
    try:
        package = os.path.dirname(os.path.dirname(threejs.three_module()))
    except Exception as error:  # noqa: BLE001 - three.js not installed
        be.skip_unless_ci(f"three.js is missing ({error})")
    for source, target in FBXLOADER_MODULES:
        os.makedirs(os.path.dirname(os.path.join(folder, target)), exist_ok=True)
        with open(os.path.join(package, source), "rb") as stream, \
                open(os.path.join(folder, target), "wb") as out:
            out.write(stream.read())
    page = os.path.join(folder, "fbx.html")
    with open(path, "rb") as stream, open(page, "w", encoding="utf-8") as out:
        out.write(FBXLOADER_PAGE.replace("@FBX@", base64.b64encode(stream.read()).decode()))
    result = browser.render_page(page, timeout=120)
    assert result.title.startswith("phong: done "), (result.title, result.errors)
    return json.loads(result.title[len("phong: done "):])


def test_threejs_fbxloader_reads_the_export(bpy_clean, tmp_path):
    """three.js's FBXLoader (a reader of its own, in Chromium): MeshPhongMaterial for Phong,
    MeshLambertMaterial for Lambert, the colours, shininess = Exponent, the opacity, and each
    light's Intensity / 100 = the Phong intensity where the falloff is a unit one."""
    bpy = bpy_clean
    _planes, made = _hand_scene(bpy)
    names = {name: material.name for name, material in made.items()}
    read = _fbxloader(_export(bpy, tmp_path), str(tmp_path / "page"))
    for name, material in names.items():
        kd, ks, exponent, _blinn, ke, opacity = MATERIALS[name]
        got = read["materials"][material]
        lambert = ks == (0.0, 0.0, 0.0)
        assert got["type"] == ("MeshLambertMaterial" if lambert else "MeshPhongMaterial")
        np.testing.assert_allclose(got["color"], kd, atol=1e-5)
        np.testing.assert_allclose(got["emissive"], ke, atol=1e-5)
        assert got["opacity"] == pytest.approx(opacity, abs=1e-6)
        assert got["transparent"] == (opacity < 1.0)
        if not lambert:
            np.testing.assert_allclose(got["specular"], ks, atol=1e-5)
            assert got["shininess"] == pytest.approx(exponent)
    for name in ("Quad", "Lin", "Flat", "Cone", "Sky"):
        got = read["lights"][name]
        assert got["intensity"] == pytest.approx(LIGHTS[name][2]), name
        np.testing.assert_allclose(got["color"], LIGHTS[name][1], atol=1e-5)


def test_an_unknown_option_is_one_clear_error(bpy_clean, tmp_path):
    bpy = bpy_clean
    from phong_nodes.addon.interchange import fbx_export
    _hand_scene(bpy)
    with pytest.raises(ValueError, match="Blender's FBX exporter failed"):
        fbx_export.export(bpy.context, str(tmp_path / "x.fbx"), no_such_option=True)
    assert os.listdir(tmp_path) == []


def _textured_scene(bpy, folder):
    """A plane whose Phong material takes Object Color = a colour × an image (the importers'
    chain: a Vector Math Multiply of the control and an Image Texture) and Irradiant Color =
    another image alone; the images are PNG files in *folder*."""
    from phong_nodes.addon import compat
    from phong_nodes.addon.lighting import recipe, writer
    from phong_nodes.addon.lighting import feeds as feed_reader
    from phong_nodes.addon.lighting import opacity as opacity_nodes
    images = {}
    for key, rgb in (("diffuse", (0.2, 0.8, 0.4)), ("glow", (0.5, 0.1, 0.9))):
        image = bpy.data.images.new(key, 2, 2)
        image.pixels[:] = [*rgb, 1.0] * 4
        image.filepath_raw = os.path.join(folder, f"{key}.png")
        image.file_format = "PNG"
        image.save()
        images[key] = image
    mesh = bpy.data.meshes.new("Tile")
    mesh.from_pydata([(0, 0, 0), (1, 0, 0), (1, 1, 0), (0, 1, 0)], [], [(0, 1, 2, 3)])
    mesh.uv_layers.new(name="UVMap")
    mesh.materials.append(bpy.data.materials.new("Tile"))
    obj = bpy.data.objects.new("Tile", mesh)
    bpy.context.scene.collection.objects.link(obj)
    obj.select_set(True)
    bpy.context.view_layer.objects.active = obj
    assert bpy.ops.phong.apply_material() == {"FINISHED"}
    material = obj.material_slots[0].material
    tree = material.node_tree
    lights = tree.nodes[recipe.LIGHTS_NODE]
    control = tree.nodes["phong_object_color"]
    control.outputs[0].default_value = (0.5, 0.25, 1.0, 1.0)
    texture = tree.nodes.new("ShaderNodeTexImage")
    texture.image = images["diffuse"]
    multiply = tree.nodes.new("ShaderNodeVectorMath")
    multiply.operation = "MULTIPLY"
    tree.links.new(compat.value_output(control), compat.input_socket(multiply, "Vector"))
    tree.links.new(texture.outputs["Color"], compat.input_socket(multiply, "Vector_001"))
    tree.links.new(compat.output_socket(multiply, "Vector"), lights.inputs["Object Color"])
    glow = tree.nodes.new("ShaderNodeTexImage")
    glow.image = images["glow"]
    tree.links.new(glow.outputs["Color"], lights.inputs["Irradiant Color"])
    return material


def test_image_textures_are_written_and_read_back(bpy_clean, tmp_path):
    """An image texture on a colour is an FBX Texture and Video connected to its property
    (Blender's parse_fbx reads the connections and the file names), with the colour the
    control's (times the map) or white (the map alone); the importer reads colour × map back
    from the same file, and Blender's importer shows the diffuse map as its Base Color."""
    bpy = bpy_clean
    material = _textured_scene(bpy, str(tmp_path))
    name = material.name
    path = _export(bpy, tmp_path)
    from io_scene_fbx import parse_fbx
    root, _version = parse_fbx.parse(path)
    objects = next(e for e in root.elems if e.id == b"Objects")
    ids = {e.props[0]: e for e in objects.elems}
    connections = [c.props for c in next(e for e in root.elems if e.id == b"Connections").elems]
    mat_id = next(i for i, e in ids.items() if e.id == b"Material"
                  and e.props[1].split(b"\x00\x01")[0].decode() == name)
    on = {}
    for kind, child, parent, *prop in connections:
        if kind == b"OP" and parent == mat_id:
            texture = ids[child]
            assert texture.id == b"Texture"
            file = next(e for e in texture.elems if e.id == b"RelativeFilename").props[0]
            videos = [ids[c] for k, c, p, *_ in connections if k == b"OO" and p == child]
            assert [v.id for v in videos] == [b"Video"]
            on[prop[0].decode()] = file.decode()
    # (the Ambient Object Color stays linked to the control itself: no map on AmbientColor)
    assert on == {"DiffuseColor": "diffuse.png", "EmissiveColor": "glow.png"}
    props = _parsed(path)["Material"][name][0]
    np.testing.assert_allclose(props["DiffuseColor"][2], (0.5, 0.25, 1.0), atol=0)
    np.testing.assert_allclose(props["EmissiveColor"][2], (1.0, 1.0, 1.0), atol=0)
    be.reset_empty_file()
    assert bpy.ops.phong.import_fbx(filepath=path) == {"FINISHED"}
    from phong_nodes.addon.lighting import recipe, writer
    from phong_nodes.addon.lighting import feeds as feed_reader
    from phong_nodes.addon.lighting import opacity as opacity_nodes
    feeds = feed_reader.feeds(bpy.data.materials[name])
    assert feeds["Object Color"].value == pytest.approx((0.5, 0.25, 1.0))
    assert bpy.path.basename(feeds["Object Color"].texture.image.filepath) == "diffuse.png"
    assert feeds["Irradiant Color"].value == pytest.approx((1.0, 1.0, 1.0))
    assert bpy.path.basename(feeds["Irradiant Color"].texture.image.filepath) == "glow.png"
    be.reset_empty_file()
    assert bpy.ops.import_scene.fbx(filepath=path) == {"FINISHED"}
    principled = next(n for n in bpy.data.materials[name].node_tree.nodes
                      if n.bl_idname == "ShaderNodeBsdfPrincipled")
    base = principled.inputs["Base Color"].links[0].from_node
    assert bpy.path.basename(base.image.filepath) == "diffuse.png"


UFBX_TEXTURES = r"""
import gc, json, sys
gc.disable()   # ufbx 0.0.5's objects crash the collector (core/fbx/read.py)
import ufbx
scene = ufbx.load_file(sys.argv[1], ignore_geometry=True)
hold, out = [], {}
textures = [scene.textures[i] for i in range(len(scene.textures))]
for i in range(len(scene.materials)):
    m = scene.materials[i]
    links = [m.textures[j] for j in range(len(m.textures))]
    hold += links
    maps = {}
    for link in links:
        t = textures[link.texture.typed_id]
        maps[link.material_prop] = [t.relative_filename, t.filename]
    props = {}
    for name in ("TransparencyFactor", "TransparentColor", "ShininessExponent", "Opacity",
                 "DiffuseColor", "AmbientColor"):
        p = m.props.find_prop(name)
        if p is not None:
            props[name] = [p.value_vec4.x, p.value_vec4.y, p.value_vec4.z]
    out[m.name] = {"maps": maps, "props": props}
print(json.dumps(out))
sys.stdout.flush()
import os
os._exit(0)
"""


def _ufbx_textures(path):
    """{material: {"maps": {property: [relative, file name]}, "props": {...}}} as ufbx reads
    the file (in a child process, as :func:`_ufbx_materials`)."""
    import json
    import subprocess
    import sys
    done = subprocess.run([sys.executable, "-c", UFBX_TEXTURES, path], capture_output=True,
                          text=True, timeout=120, check=True)
    return json.loads(done.stdout.strip().splitlines()[-1])


def _tile(bpy, name):
    from phong_nodes.addon.lighting import recipe, writer
    from phong_nodes.addon.lighting import feeds as feed_reader
    from phong_nodes.addon.lighting import opacity as opacity_nodes
    mesh = bpy.data.meshes.new(name)
    mesh.from_pydata([(0, 0, 0), (1, 0, 0), (1, 1, 0), (0, 1, 0)], [], [(0, 1, 2, 3)])
    mesh.uv_layers.new(name="UVMap")
    mesh.materials.append(bpy.data.materials.new(name + " source"))
    obj = bpy.data.objects.new(name, mesh)
    bpy.context.scene.collection.objects.link(obj)
    for other in bpy.context.view_layer.objects:
        other.select_set(False)
    obj.select_set(True)
    bpy.context.view_layer.objects.active = obj
    assert bpy.ops.phong.apply_material() == {"FINISHED"}
    material = obj.material_slots[0].material
    opacity_nodes.set_opacity(material, 1.0)
    material.name = name
    return material


def _png(bpy, folder, name, rgba, keep=True):
    image = bpy.data.images.new(name, 2, 2, alpha=True)
    image.pixels[:] = list(rgba) * 4
    image.filepath_raw = os.path.join(folder, f"{name}.png")
    image.file_format = "PNG"
    image.save()
    if not keep:
        os.remove(image.filepath_raw)
    return image


def test_every_map_is_written_and_read_back(bpy_clean, tmp_path):
    """The exponent map (Exponent × mean(texel)) is a texture on ShininessExponent with the
    Exponent; an opacity map of a texel's alpha × k (X3D's texture alpha × Opacity) a texture
    on TransparencyFactor as Blender's exporter writes its alpha, k kept; an opacity map of
    the FBX SDK's rule 1 − TF × mean(t) (COLLADA's RGB_ZERO) a texture on TransparencyFactor
    with that factor; a colour map whose file is missing keeps its path, also through the
    project's import and a second export; a packed image is written beside the FBX file.
    ufbx reads each texture on its property with its file; the project's importer gives
    every map back (the same chain's values); Blender's own importer reads the alpha texture
    and the exponent one (as roughness)."""
    bpy = bpy_clean
    from phong_nodes.addon import compat
    from phong_nodes.addon.interchange import fbx_export, native
    from phong_nodes.addon.lighting import recipe, writer
    from phong_nodes.addon.lighting import feeds as feed_reader
    from phong_nodes.addon.lighting import opacity as opacity_nodes
    folder = str(tmp_path / "textures")
    os.makedirs(folder)
    shiny = _tile(bpy, "Shiny")
    tree = shiny.node_tree
    compat.value_output(tree.nodes["phong_exponent"]).default_value = 64.0
    compat.value_output(tree.nodes["phong_specular_color"]).default_value = (0.5, 0.5, 0.5, 1)
    rough = _png(bpy, folder, "rough", (0.25, 0.5, 0.75, 1.0))
    rough.colorspace_settings.name = native.NON_COLOR
    native.exponent_map(shiny, rough)
    lost = _png(bpy, folder, "lost", (0.9, 0.1, 0.1, 1.0), keep=False)   # file not there
    node = native.image_node(tree, "lost", lost, (-1400.0, 0.0))
    tree.links.new(node.outputs["Color"], tree.nodes[recipe.LIGHTS_NODE].inputs[
        "Object Color"])
    # X3D's texture alpha × Opacity, the image packed (an imported PixelTexture)
    leaf = _tile(bpy, "Leaf")
    opacity_nodes.set_opacity(leaf, 0.75)
    label = _png(bpy, folder, "label", (1.0, 1.0, 1.0, 0.5))
    label.pack()
    os.remove(label.filepath_raw)
    tree = leaf.node_tree
    alpha = native.image_node(tree, "alpha", label, (-1400.0, 600.0))
    native.opacity_map(leaf, native.math(
        tree, native.MAP_NODE + "alpha x o", "MULTIPLY", alpha.outputs["Alpha"],
        compat.value_output(tree.nodes[recipe.OPACITY]), (-900.0, 600.0)))
    # COLLADA's RGB_ZERO: 1 − t × mean(texel), a data map
    veil = _tile(bpy, "Veil")
    mask = _png(bpy, folder, "mask", (0.2, 0.4, 0.6, 1.0))
    mask.colorspace_settings.name = native.NON_COLOR
    tree = veil.node_tree
    texel = native.image_node(tree, "mask", mask, (-1400.0, 600.0))
    mean = native.mean_rgb(tree, "mask mean", texel.outputs["Color"], (-1100.0, 600.0))
    scaled = native.math(tree, native.MAP_NODE + "x t", "MULTIPLY", mean, 0.8, (-900.0, 600.0))
    native.opacity_map(veil, native.math(tree, native.MAP_NODE + "1 -", "SUBTRACT", 1.0,
                                         scaled, (-700.0, 600.0)))
    out = tmp_path / "out"
    out.mkdir()
    path = str(out / "maps.fbx")
    warnings = fbx_export.export(bpy.context, path, **NO_LIGHTS)
    assert any("label" in w and "beside" in w for w in warnings), warnings
    assert (out / "label.png").is_file() and not (out / "lost.png").exists()
    read = _ufbx_textures(path)
    rel = os.path.relpath(folder, str(out))
    assert read["Shiny"]["maps"] == {
        "DiffuseColor": [os.path.join(rel, "lost.png"), os.path.join(folder, "lost.png")],
        "ShininessExponent": [os.path.join(rel, "rough.png"), os.path.join(folder, "rough.png")]}
    assert read["Shiny"]["props"]["ShininessExponent"][0] == 64.0
    assert read["Leaf"]["maps"] == {"TransparencyFactor": ["label.png", str(out / "label.png")]}
    assert read["Veil"]["maps"] == {"TransparencyFactor": [os.path.join(rel, "mask.png"),
                                                           os.path.join(folder, "mask.png")]}
    assert read["Veil"]["props"]["TransparencyFactor"][0] == pytest.approx(0.8, abs=1e-7)
    assert read["Veil"]["props"]["TransparentColor"] == [1.0, 1.0, 1.0]
    # the project's importer
    be.reset_empty_file()
    assert bpy.ops.phong.import_fbx(filepath=path) == {"FINISHED"}
    shiny, leaf, veil = (bpy.data.materials[n] for n in ("Shiny", "Leaf", "Veil"))
    feeds = feed_reader.feeds(shiny)
    assert feeds["Exponent"].value == 64.0
    form = fbx_export._walk(feeds["Exponent"].socket)
    assert form[0] == "prod" and form[1] == 64.0 and \
        form[2][0][1].image.filepath.endswith("rough.png")
    feeds = feed_reader.feeds(leaf)
    assert feeds["Opacity"].value == pytest.approx(0.75)
    form = fbx_export._walk(compat.output_socket(feeds["Opacity"].other, "Value"))
    assert form[:2] == ("prod", pytest.approx(0.75)) and form[2][0][0] == "alpha"
    assert bpy.path.basename(form[2][0][1].image.filepath) == "label.png"
    feeds = feed_reader.feeds(veil)
    form = fbx_export._walk(compat.output_socket(feeds["Opacity"].other, "Value"))
    assert form[:2] == ("one_minus", pytest.approx(0.8)) and form[2][0][0] == "mean"
    assert bpy.path.basename(form[2][0][1].image.filepath) == "mask.png"
    # the missing colour map: left out of the picture, its reference kept for the export
    assert feed_reader.feeds(shiny)["Object Color"].texture is None
    assert not [i.name for i in bpy.data.images if i.filepath.endswith("lost.png")]
    again = tmp_path / "again"
    again.mkdir()
    fbx_export.export(bpy.context, str(again / "again.fbx"), **NO_LIGHTS)
    read = _ufbx_textures(str(again / "again.fbx"))
    lost = os.path.join(folder, "lost.png")
    assert read["Shiny"]["maps"]["DiffuseColor"] == [os.path.relpath(lost, str(again)), lost]
    assert "lost.png" not in str(read["Leaf"]) + str(read["Veil"])
    # Blender's path_mode COPY: the image files that are there copied beside the FBX file
    be.reset_empty_file()
    copied = tmp_path / "copied"
    copied.mkdir()
    assert bpy.ops.phong.import_fbx(filepath=path) == {"FINISHED"}
    fbx_export.export(bpy.context, str(copied / "copy.fbx"), path_mode="COPY", **NO_LIGHTS)
    assert sorted(os.listdir(copied)) == ["copy.fbx", "label.png", "mask.png", "rough.png"]
    read = _ufbx_textures(str(copied / "copy.fbx"))
    assert read["Veil"]["maps"]["TransparencyFactor"] == ["mask.png", str(copied / "mask.png")]
    assert read["Shiny"]["maps"]["DiffuseColor"][1] == os.path.join(folder, "lost.png")
    # Blender's own importer: the alpha texture and the exponent's (its roughness)
    be.reset_empty_file()
    assert bpy.ops.import_scene.fbx(filepath=path) == {"FINISHED"}

    def principled(name):
        return next(n for n in bpy.data.materials[name].node_tree.nodes
                    if n.bl_idname == "ShaderNodeBsdfPrincipled")

    alpha = principled("Leaf").inputs["Alpha"].links[0].from_node
    assert bpy.path.basename(alpha.image.filepath) == "label.png"
    rough_node = principled("Shiny").inputs["Roughness"].links[0].from_node
    while rough_node.bl_idname != "ShaderNodeTexImage":
        rough_node = next(i for i in rough_node.inputs if i.is_linked).links[0].from_node
    assert bpy.path.basename(rough_node.image.filepath) == "rough.png"


def test_an_x3d_files_pixel_textures_are_fbx_maps(bpy_clean, tmp_path):
    """An X3D file's PixelTextures (packed images, no file) on its chains (a grey texture ×
    diffuseColor, ambientIntensity × texel × diffuseColor, the texel's alpha × Opacity) are
    FBX maps: each image written beside the FBX file once, on DiffuseColor and AmbientColor
    with the chain's colour (ufbx reads colour and file) and its alpha on TransparencyFactor;
    no warning that a chain was left out.  The project's importer reads the maps back as
    data (Non-Color, as X3D's texels are), each image once; embedded, the same texels."""
    bpy = bpy_clean
    from test_x3d_export import PIXEL_FILE  # noqa: PLC0415
    from phong_nodes.addon.interchange import fbx_export
    source = tmp_path / "pixels.x3dv"
    source.write_text(PIXEL_FILE)
    assert bpy.ops.phong.import_x3d(filepath=str(source)) == {"FINISHED"}
    out = tmp_path / "out"
    out.mkdir()
    path = str(out / "pixels.fbx")
    warnings = fbx_export.export(bpy.context, path, **NO_LIGHTS)
    assert not [w for w in warnings if "fed by nodes" in w or "left out" in w], warnings
    assert sorted(os.listdir(out)) == ["Checker.png", "Stripes.png", "pixels.fbx"]
    read = _ufbx_textures(path)
    checker = ["Checker.png", str(out / "Checker.png")]
    assert read["Label"]["maps"] == {"DiffuseColor": checker, "AmbientColor": checker,
                                     "TransparencyFactor": checker}
    assert read["Label"]["props"]["DiffuseColor"] == [0.5, 0.25, 1.0]
    np.testing.assert_allclose(read["Label"]["props"]["AmbientColor"],
                               _f32([0.1, 0.05, 0.2]), rtol=1e-7)
    stripes = ["Stripes.png", str(out / "Stripes.png")]
    assert read["Paint"]["maps"] == {"DiffuseColor": stripes, "AmbientColor": stripes}
    assert read["Paint"]["props"]["DiffuseColor"] == [1.0, 1.0, 1.0]   # an RGB texture replaces
    # the project's importer: X3D's texels are data (Non-Color), and stay so (NonColor<prop>)
    be.reset_empty_file()
    assert bpy.ops.phong.import_fbx(filepath=path) == {"FINISHED"}
    from phong_nodes.addon.lighting import recipe, writer
    from phong_nodes.addon.lighting import feeds as feed_reader
    from phong_nodes.addon.lighting import opacity as opacity_nodes
    for name, image in (("Label", "Checker.png"), ("Paint", "Stripes.png")):
        feeds = feed_reader.feeds(bpy.data.materials[name])
        for key in ("Object Color", "Ambient Object Color"):
            node = feeds[key].chain.texture if feeds[key].texture is None else \
                feeds[key].texture
            assert node.image.name == image, (name, key)
            assert node.image.colorspace_settings.name == "Non-Color", (name, key)
    assert sorted(i.name for i in bpy.data.images) == ["Checker.png", "Stripes.png"]
    # embedded (Blender's embed_textures with path_mode COPY): no file beside, the bytes in
    # the Video's Content, read back as packed images of the same texels
    be.reset_empty_file()
    assert bpy.ops.phong.import_x3d(filepath=str(source)) == {"FINISHED"}
    texels = {n: list(bpy.data.images[n].pixels) for n in ("Checker", "Stripes")}
    inside = tmp_path / "inside"
    inside.mkdir()
    warnings = fbx_export.export(bpy.context, str(inside / "pixels.fbx"), embed_textures=True,
                                 path_mode="COPY", **NO_LIGHTS)
    assert not [w for w in warnings if "beside" in w], warnings
    assert os.listdir(inside) == ["pixels.fbx"]
    be.reset_empty_file()
    assert bpy.ops.phong.import_fbx(filepath=str(inside / "pixels.fbx")) == {"FINISHED"}
    for name in ("Checker", "Stripes"):
        image = bpy.data.images[name + ".png"]
        assert image.packed_file is not None
        assert list(image.pixels) == pytest.approx(texels[name], abs=0.5 / 255)
