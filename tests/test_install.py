# SPDX-License-Identifier: GPL-3.0-or-later
"""The extension installs like a user would install it, and loads the contract's node groups."""

import json
import math
import os
import subprocess
import sys

import pytest

import blender_env as be



INSTALL_AS_A_USER = """
import json, os, sys
import bpy
zip_path = sys.argv[1]
result = bpy.ops.extensions.package_install_files(filepath=zip_path, repo="user_default",
                                                  enable_on_install=True)
module = "bl_ext.user_default.phong_nodes"
enabled = module in bpy.context.preferences.addons
bpy.ops.wm.read_homefile(use_empty=True)
loaded = bpy.ops.phong.load_node_groups() if enabled else None
libraries = [lib.path for lib in bpy.context.preferences.filepaths.asset_libraries
             if lib.name == "Phong Nodes"]
print("RESULT " + json.dumps({
    "install": sorted(result), "enabled": enabled, "load": sorted(loaded or ()),
    "asset_libraries": libraries,
    "asset_files": sorted(os.listdir(libraries[0])) if libraries else [],
    "groups": sorted(g.name for g in bpy.data.node_groups),
    "file": sys.modules[module].__file__ if module in sys.modules else None}))
"""

# A user's own headless script: install and enable the zip, use the extension (a light's
# Phong settings, Apply, the model switch, an Eevee and a Cycles render), then simply end.
# Nothing of the project's internals is called: Python ends as it ends for any script.
USER_SCRIPT = """
import sys
import bpy
zip_path, out = sys.argv[1:3]
bpy.ops.extensions.package_install_files(filepath=zip_path, repo="user_default",
                                         enable_on_install=True)
bpy.ops.wm.read_homefile(use_empty=False)
scene = bpy.context.scene
for obj in scene.objects:
    obj.select_set(obj.type == "MESH")
light = next(obj for obj in scene.objects if obj.type == "LIGHT")
light.data.phong.intensity = 2.0
scene.world.phong.ambient_intensity = 0.2
assert bpy.ops.phong.apply_material() == {"FINISHED"}
scene.phong.model = "threejs"
scene.phong.model = "seeds"
scene.render.resolution_x = scene.render.resolution_y = 16
for engine in ("CYCLES", "BLENDER_EEVEE_NEXT" if bpy.app.version < (5, 0, 0) else "BLENDER_EEVEE"):
    scene.render.engine = engine
    scene.render.filepath = f"{out}/{engine}.png"
    bpy.ops.render.render(write_still=True)
print("USER SCRIPT DONE", bpy.app.version_string)
"""


@pytest.fixture(scope="module")
def built(tmp_path_factory):
    """The zip that `bash tools/phong.sh build` makes, built and validated by Blender's tool."""
    out = tmp_path_factory.mktemp("dist")
    env = {**os.environ, "PHONG_VENV": sys.prefix, "PHONG_BPY": be.bpy_release()}
    result = subprocess.run(["bash", os.path.join(be.REPO_ROOT, "tools", "phong.sh"), "build",
                             str(out)], env=env, capture_output=True, text=True, timeout=300)
    assert result.returncode == 0, result.stdout[-3000:] + result.stderr[-3000:]
    zip_path = result.stdout.strip().splitlines()[-1]
    assert os.path.dirname(zip_path) == str(out), result.stdout
    return zip_path, be.run_ext_tool("validate", zip_path), be.zip_names(zip_path)


def test_zip_builds_validates_and_has_no_tests(built):
    zip_path, validate, names = built
    assert validate.returncode == 0, validate.stdout + validate.stderr
    assert "blender_manifest.toml" in names and "__init__.py" in names
    for folder in ("tests/", "tools/", "cli/", "benchmarks/", "docs/", ".ci/"):
        assert not [n for n in names if n.startswith(folder)], f"the zip ships {folder}"
    assert not [n for n in names if n.endswith(".pyc") or "__pycache__" in n]
    for package in ("node_groups", "core", "addon", "addon/lighting", "addon/demos", "addon/ui",
                    "addon/interchange", "addon/scene", "addon/comparison", "addon/baking"):
        assert f"{package}/__init__.py" in names, f"{package} missing from the zip"


NETWORK_MODULES = {"socket", "ssl", "http", "urllib", "ftplib", "smtplib", "requests", "urllib3",
                   "asyncio", "xmlrpc", "websocket", "webbrowser"}


def test_manifest_meets_the_extensions_platform_checklist():
    """What the Extensions Platform asks of a manifest: a short tagline without a full stop,
    tags and licence, every permission with its reason (files, since the extension writes
    reports, exports and its asset library; never network), no maximum version."""
    import tomllib  # noqa: PLC0415

    with open(os.path.join(be.REPO_ROOT, "blender_manifest.toml"), "rb") as handle:
        manifest = tomllib.load(handle)
    assert len(manifest["tagline"]) <= 64 and not manifest["tagline"].endswith(".")
    assert manifest["tags"] and manifest["license"] == ["SPDX:GPL-3.0-or-later"]
    assert manifest["blender_version_min"] == "4.2.0"
    assert "blender_version_max" not in manifest
    assert set(manifest["permissions"]) == {"files"}, manifest["permissions"]
    reason = manifest["permissions"]["files"]
    assert 0 < len(reason) <= 64 and not reason.endswith("."), reason


def test_the_zip_uses_no_network(built):
    """No module of the zip imports a network library (the manifest asks for no network)."""
    import ast  # noqa: PLC0415
    import zipfile  # noqa: PLC0415

    zip_path, _validate, names = built
    found = []
    with zipfile.ZipFile(zip_path) as archive:
        for name in (n for n in names if n.endswith(".py")):
            for node in ast.walk(ast.parse(archive.read(name), name)):
                if isinstance(node, ast.Import):
                    modules = [alias.name for alias in node.names]
                elif isinstance(node, ast.ImportFrom) and not node.level:
                    modules = [node.module or ""]
                else:
                    continue
                found += [(name, m) for m in modules if m.split(".")[0] in NETWORK_MODULES]
    assert not found, found


def test_zip_installs_and_enables_as_a_user_would(built, tmp_path):
    """Install the zip with Blender's own operator into a fresh user folder, in a process of
    its own (in this one the source tree is enabled under the name phong_nodes)."""
    zip_path, _validate, _names = built
    env = {**os.environ, "BLENDER_USER_RESOURCES": str(tmp_path / "user")}
    result = subprocess.run([sys.executable, "-c", INSTALL_AS_A_USER, zip_path], env=env,
                            capture_output=True, text=True, timeout=300)
    lines = [line for line in result.stdout.splitlines() if line.startswith("RESULT ")]
    assert result.returncode == 0 and lines, result.stdout[-2000:] + result.stderr[-2000:]
    got = json.loads(lines[-1].removeprefix("RESULT "))
    assert got["install"] == ["FINISHED"] and got["enabled"], got
    assert got["load"] == ["FINISHED"], got
    assert got["groups"] == sorted(be.SPEC_GROUPS), got["groups"]
    assert got["file"].startswith(str(tmp_path / "user")), got["file"]
    # the asset library lives in the extension's user folder, not in the extension's own
    (library,) = got["asset_libraries"]
    assert library.startswith(str(tmp_path / "user")), library
    assert not library.startswith(os.path.dirname(got["file"]) + os.sep), library
    assert "blender_assets.cats.txt" in got["asset_files"]
    assert [n for n in got["asset_files"] if n.startswith("phong_nodes_") and n.endswith(".blend")]


@pytest.mark.slow
def test_a_users_script_with_the_extension_enabled_exits_0(built, tmp_path):
    """bpy 4.2 crashed (signal 11, exit 139) at interpreter exit after any script that had
    enabled the extension; the script must end with 0 on every supported release."""
    zip_path, _validate, _names = built
    env = {**os.environ, "BLENDER_USER_RESOURCES": str(tmp_path / "user")}
    result = subprocess.run([sys.executable, "-c", USER_SCRIPT, zip_path, str(tmp_path)],
                            env=env, capture_output=True, text=True, timeout=600)
    assert "USER SCRIPT DONE" in result.stdout, result.stdout[-2000:] + result.stderr[-2000:]
    assert result.returncode == 0, (result.returncode, result.stderr[-2000:])
    eevee = "BLENDER_EEVEE_NEXT" if be.import_bpy().app.version < (5, 0, 0) else "BLENDER_EEVEE"
    assert sorted(p.name for p in tmp_path.glob("*.png")) == sorted(["CYCLES.png", f"{eevee}.png"])


def test_enabled_from_the_source_tree(extension):
    bpy = extension
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


def test_ci_package_list_covers_every_library_named():
    """`.ci/run` installs (as root) what `cli/system.py --packages` prints: it must run with a
    bare Python (no bpy) and name the package of every library that it can report."""
    tool = os.path.join(be.REPO_ROOT, "cli", "system.py")
    result = subprocess.run(["python3", "-I", tool, "--packages"], capture_output=True,
                            text=True, timeout=60)
    assert result.returncode == 0, result.stderr
    listed = set(result.stdout.split())
    message = " ".join(f"{lib}: cannot open shared object file" for lib in
                       ("libXi.so.6", "libEGL_mesa.so.0", "libxkbcommon.so.0"))
    named = subprocess.run(["python3", "-c", "import sys, system as c; print(' '.join("
                            "c.PACKAGES[lib] for lib in c.missing_from_message(sys.argv[1])))",
                            message], cwd=os.path.dirname(tool), capture_output=True, text=True)
    assert set(named.stdout.split()) == {"libxi6", "libegl-mesa0", "libxkbcommon0"}, named.stderr
    assert set(named.stdout.split()) <= listed and "libgl1-mesa-dri" in listed
    with open(os.path.join(be.REPO_ROOT, ".ci", "run")) as handle:
        assert "cli/system.py --packages" in handle.read()
