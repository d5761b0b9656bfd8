# SPDX-License-Identifier: GPL-3.0-or-later
"""The extension installs like a user would install it, and loads the SPEC node groups."""

import math

import pytest

import blender_env as be



def test_zip_builds_validates_and_has_no_tests(installed):
    assert installed.validate.returncode == 0, installed.validate.stdout + installed.validate.stderr
    assert "blender_manifest.toml" in installed.names
    bad = [n for n in installed.names if n.startswith("tests/") or "/tests/" in n]
    assert not bad, f"the zip ships test files: {bad}"
    assert not [n for n in installed.names if n.endswith(".pyc") or "__pycache__" in n]


def test_installed_and_enabled(installed):
    bpy = be.import_bpy()
    assert be.EXT_MODULE in bpy.context.preferences.addons
    assert hasattr(bpy.ops.phong, "load_node_groups")


def test_enabled_after_reset(bpy_clean):
    bpy = bpy_clean
    bpy.ops.wm.read_homefile(use_empty=True)
    assert be.EXT_MODULE in bpy.context.preferences.addons
    assert len(bpy.data.objects) == 0


def test_load_twice_one_copy_each(bpy_clean):
    bpy = bpy_clean
    be.load_groups()
    be.load_groups()
    names = [g.name for g in bpy.data.node_groups]
    for group in be.SPEC_GROUPS:
        assert names.count(group) == 1, f"{group!r}: {names.count(group)} copies in {names}"
    dup = [n for n in names if any(n.startswith(g + ".") for g in be.SPEC_GROUPS)]
    assert not dup, f"duplicated groups after loading twice: {dup}"
    for group in be.SPEC_GROUPS:
        assert bpy.data.node_groups[group].bl_idname == "ShaderNodeTree"


@pytest.mark.parametrize("group", list(be.SPEC_GROUPS))
def test_sockets_match_spec(bpy_clean, group):
    bpy = bpy_clean
    be.load_groups()
    tree = bpy.data.node_groups[group]
    spec_in, spec_out = be.SPEC_GROUPS[group]
    got_in = [s.name for s in be.interface_sockets(tree, "INPUT")]
    got_out = [s.name for s in be.interface_sockets(tree, "OUTPUT")]
    assert got_in == [n for n, _ in spec_in], f"{group} inputs"
    assert got_out == [n for n, _ in spec_out], f"{group} outputs"
    for item, (name, kind) in zip(be.interface_sockets(tree, "INPUT") + be.interface_sockets(tree, "OUTPUT"),
                                  spec_in + spec_out):
        if kind == be.S:
            assert item.socket_type == "NodeSocketFloat", (group, name, item.socket_type)
        elif kind == be.SH:
            assert item.socket_type == "NodeSocketShader", (group, name, item.socket_type)
        else:
            assert item.socket_type in ("NodeSocketVector", "NodeSocketColor"), (group, name, item.socket_type)


# SPEC defaults: (group, socket) -> value
SPEC_DEFAULTS = {
    ("Phong Directional Light", "Direction"): (0.0, 0.0, -1.0),
    ("Phong Point Light", "Quadratic"): 1.0,
    ("Phong Point Light", "Linear"): 0.0,
    ("Phong Point Light", "Constant"): 0.0,
    ("Phong Point Light", "Intensity"): 1.0,
    ("Phong Spot Light", "Half Angle"): math.radians(30.0),
    ("Phong Spot Light", "Edge Exponent"): 0.0,
    ("Phong Spot Light", "Intensity"): 1.0,
    ("Phong Spot Light", "Quadratic"): 1.0,
    ("Phong Spot Light", "Linear"): 0.0,
    ("Phong Spot Light", "Constant"): 0.0,
    ("Phong Power Falloff", "Intensity"): 1.0,
    ("Phong Power Falloff", "Exponent"): 2.0,
    ("Phong Color Multiply", "Factor"): 1.0,
    ("Phong Irradiant", "Color"): (0.0, 0.0, 0.0),
    ("Phong Shading", "Diffuse Strength"): 1.0,
    ("Phong Shading", "Specular Strength"): 1.0,
    # SPEC: "A Normal / View Vector input left at the zero vector (the unconnected default)"
    ("Phong Diffuse", "Normal"): (0.0, 0.0, 0.0),
    ("Phong Specular", "Normal"): (0.0, 0.0, 0.0),
    ("Phong Specular", "View Vector"): (0.0, 0.0, 0.0),
    ("Phong Blinn Specular", "Normal"): (0.0, 0.0, 0.0),
    ("Phong Blinn Specular", "View Vector"): (0.0, 0.0, 0.0),
    ("Phong Shading", "Normal"): (0.0, 0.0, 0.0),
    ("Phong Shading", "View Vector"): (0.0, 0.0, 0.0),
}


@pytest.mark.parametrize("key", list(SPEC_DEFAULTS), ids=[f"{g}-{s}" for g, s in SPEC_DEFAULTS])
def test_spec_defaults(bpy_clean, key):
    bpy = bpy_clean
    be.load_groups()
    group, socket = key
    tree = bpy.data.node_groups[group]
    item = next(s for s in be.interface_sockets(tree, "INPUT") if s.name == socket)
    want = SPEC_DEFAULTS[key]
    got = item.default_value
    if isinstance(want, tuple):
        got = tuple(got)[:3]
        assert got == pytest.approx(want, abs=1e-6), f"{group}.{socket} default {got} != {want}"
    else:
        assert got == pytest.approx(want, abs=1e-6), f"{group}.{socket} default {got} != {want}"
    if key == ("Phong Spot Light", "Half Angle"):
        assert item.subtype == "ANGLE", f"Half Angle subtype {item.subtype}"
