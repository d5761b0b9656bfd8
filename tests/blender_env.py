# SPDX-License-Identifier: GPL-3.0-or-later
"""Helpers shared by the tests (imported as ``blender_env``; conftest.py holds only fixtures):
the extension enabled in Blender, pixel-exact scenes, renders to multilayer EXR read back,
and the contract's table of sockets.

``bpy`` is imported lazily: :func:`import_bpy` must run after :func:`user_resources` has
pointed ``BLENDER_USER_RESOURCES`` at a throw-away folder (conftest.py does that).
"""

from __future__ import annotations

import contextlib
import os
import subprocess
import sys
import tempfile
import zipfile

import numpy as np

import phong_nodes

REPO_ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
EXT_ID = "phong_nodes"
#: The module Blender enables: the source tree, under the package name the tests import.
EXT_MODULE = "phong_nodes"
if os.path.realpath(os.path.dirname(phong_nodes.__file__)) != os.path.realpath(REPO_ROOT):
    raise RuntimeError(f"phong_nodes is imported from {os.path.dirname(phong_nodes.__file__)}, "
                       f"not from this checkout {REPO_ROOT}: run `bash tools/phong.sh setup`")

SUMMARY: list = []  # lines for the terminal summary (renders, errors per group)
_USER_RES: list = []


def report(line: str) -> None:
    """Record a line for the end-of-run summary (and print it for -s)."""
    SUMMARY.append(line)
    print(line)


def user_resources(create: bool = True) -> str | None:
    """The throw-away BLENDER_USER_RESOURCES folder of this test session."""
    if not _USER_RES and create:
        if "bpy" in sys.modules:
            raise RuntimeError("bpy was imported before BLENDER_USER_RESOURCES was set")
        _USER_RES.append(tempfile.mkdtemp(prefix="phong_user_res_"))
        os.environ["BLENDER_USER_RESOURCES"] = _USER_RES[0]
    return _USER_RES[0] if _USER_RES else None


def supported_releases() -> list:
    """(bpy, python, flags) of each line of requirements/releases.txt (the one list of
    supported Blender releases), in its order, newest first."""
    rows = []
    path = os.path.join(REPO_ROOT, "requirements", "releases.txt")
    for line in open(path, encoding="utf-8"):
        words = line.split("#")[0].split()
        if words:
            rows.append((words[0], words[1], set(words[2:])))
    return rows


def bpy_release() -> str:
    """The release of the installed bpy wheel, e.g. "5.2.3" (what PHONG_BPY takes)."""
    from importlib.metadata import version  # noqa: PLC0415

    return version("bpy")


def import_bpy():
    import bpy  # noqa: PLC0415  (lazy on purpose)

    return bpy


# ---------------------------------------------------------------- the extension

def ext_tool() -> str:
    bpy = import_bpy()
    return os.path.join(bpy.utils.resource_path("LOCAL"),
                        "scripts/addons_core/bl_pkg/cli/blender_ext.py")


def run_ext_tool(*args: str) -> subprocess.CompletedProcess:
    return subprocess.run([sys.executable, ext_tool(), *args],
                          capture_output=True, text=True, check=False)


def zip_names(zip_path: str) -> list[str]:
    with zipfile.ZipFile(zip_path) as zf:
        return zf.namelist()


def _raise(error):
    raise error


def enable() -> None:
    """Enable the extension (the source tree as ``phong_nodes``); errors are raised."""
    import_bpy()
    import addon_utils  # noqa: PLC0415  (a module of bpy's scripts)

    if not addon_enabled():
        addon_utils.enable(EXT_MODULE, default_set=True, handle_error=_raise)


def disable() -> None:
    """Disable the extension if it is enabled (its classes unregistered: bpy 4.2 crashes at
    interpreter exit while an operator class is still registered)."""
    if "bpy" in sys.modules and addon_enabled():
        import addon_utils  # noqa: PLC0415

        addon_utils.disable(EXT_MODULE, default_set=True, handle_error=_raise)


def addon_enabled() -> bool:
    bpy = import_bpy()
    return EXT_MODULE in bpy.context.preferences.addons


def reset_empty_file() -> None:
    """Empty file, preferences kept (read_factory_settings would disable the extension)."""
    bpy = import_bpy()
    bpy.ops.wm.read_homefile(use_empty=True)
    enable()


def load_groups() -> None:
    bpy = import_bpy()
    res = bpy.ops.phong.load_node_groups()
    if res != {"FINISHED"}:
        raise RuntimeError(f"phong.load_node_groups returned {res}")


# ---------------------------------------------------------------- version differences

def compat():
    """The extension's compatibility module: the one place for version differences."""
    from phong_nodes.addon import compat as module  # noqa: PLC0415  (needs bpy)

    return module


def _render():
    from phong_nodes.addon.scene import render  # noqa: PLC0415  (needs bpy)

    return render


def set_output_multilayer_exr(scene) -> None:
    """32-bit float multilayer EXR output."""
    compat().set_multilayer_exr(scene.render.image_settings)


def configure_engine(scene, kind: str) -> None:
    """The add-on's exact-check settings (one sample at pixel centres)."""
    _render().exact(scene, kind)


# ---------------------------------------------------------------- scene set-up

def new_scene(name: str, width: int, height: int, kind: str = "cycles"):
    bpy = import_bpy()
    scene = bpy.data.scenes.new(name)
    _render().plain_picture(scene, width, height)
    world = bpy.data.worlds.new(name + " world")
    compat().black_world(world)
    scene.world = world
    set_output_multilayer_exr(scene)
    configure_engine(scene, kind)
    return scene


def add_ortho_camera(scene, center_xy, width, height):
    """Orthographic camera looking down -Z that sees exactly the rectangle width x height."""
    bpy = import_bpy()
    cam = bpy.data.cameras.new(scene.name + " cam")
    cam.type = "ORTHO"
    cam.ortho_scale = max(width, height)
    cam.sensor_fit = "AUTO"
    cam.clip_start, cam.clip_end = 0.1, 100.0
    obj = bpy.data.objects.new(scene.name + " cam", cam)
    obj.location = (center_xy[0], center_xy[1], 10.0)
    obj.rotation_euler = (0.0, 0.0, 0.0)
    scene.collection.objects.link(obj)
    scene.camera = obj
    return obj


def add_persp_camera(scene, location, look_at, lens=50.0):
    bpy = import_bpy()
    from mathutils import Vector  # noqa: PLC0415

    cam = bpy.data.cameras.new(scene.name + " pcam")
    cam.type = "PERSP"
    cam.lens = lens
    cam.clip_start, cam.clip_end = 0.1, 100.0
    obj = bpy.data.objects.new(scene.name + " pcam", cam)
    obj.location = location
    direction = Vector(look_at) - Vector(location)
    obj.rotation_euler = direction.to_track_quat("-Z", "Y").to_euler()
    scene.collection.objects.link(obj)
    scene.camera = obj
    return obj


def add_quad(scene, name, x0, y0, x1, y1, z=0.0):
    """One quad [x0, x1] x [y0, y1] at height z, normal +Z, no material, linked to *scene*."""
    bpy = import_bpy()
    mesh = bpy.data.meshes.new(name)
    mesh.from_pydata([(x0, y0, z), (x1, y0, z), (x1, y1, z), (x0, y1, z)], [], [(0, 1, 2, 3)])
    obj = bpy.data.objects.new(name, mesh)
    scene.collection.objects.link(obj)
    return obj


def add_uv_plane(scene, name, x0, y0, size, material):
    """Unit-UV square plane [x0, x0+size] x [y0, y0+size] at z = 0, normal +Z."""
    bpy = import_bpy()
    mesh = bpy.data.meshes.new(name)
    verts = [(x0, y0, 0.0), (x0 + size, y0, 0.0), (x0 + size, y0 + size, 0.0), (x0, y0 + size, 0.0)]
    mesh.from_pydata(verts, [], [(0, 1, 2, 3)])
    uv = mesh.uv_layers.new(name="UVMap")
    for loop in mesh.loops:
        vx, vy, _ = verts[loop.vertex_index]
        uv.data[loop.index].uv = ((vx - x0) / size, (vy - y0) / size)
    mesh.materials.append(material)
    mesh.update()
    obj = bpy.data.objects.new(name, mesh)
    scene.collection.objects.link(obj)
    return obj


def plain_source(name):
    """A new material with no specular layer (its Principled BSDF, where it has one, at
    Specular IOR Level 0): a source to which Apply gives Ka = Kd, for tests that set a Phong
    material's values by hand and expect its Ambient Object Color to be its Object Color (a
    Principled layer's own ambient colour: tests/test_principled_ambient.py)."""
    bpy = import_bpy()
    material = bpy.data.materials.new(name)
    tree = compat().new_material_tree(material)
    node = tree.nodes.get("Principled BSDF") if tree is not None else None
    if node is not None:
        node.inputs["Specular IOR Level"].default_value = 0.0
    return material


def add_uv_sphere(scene, name, location, radius, material, segments=48, rings=24):
    """Smooth-shaded UV sphere (the add-on's mesh helper, no operator context needed)."""
    bpy = import_bpy()
    from phong_nodes.addon.scene import meshes  # noqa: PLC0415  (needs bpy)

    mesh = meshes.uv_sphere(name, radius, segments, rings)
    mesh.materials.append(material)
    mesh.update()
    obj = bpy.data.objects.new(name, mesh)
    obj.location = location
    scene.collection.objects.link(obj)
    return obj


def apply_phong(scene, objects, active=None) -> None:
    """Object ▸ Apply Phong Material as a user gives it: *objects* (of *scene*) selected and
    nothing else, *active* (default: the first of them) the active object; asserts that the
    operator finished."""
    bpy = import_bpy()
    objects = list(objects)
    for obj in scene.objects:
        obj.select_set(obj in objects)
    bpy.context.view_layer.objects.active = objects[0] if active is None else active
    assert bpy.ops.phong.apply_material() == {"FINISHED"}


@contextlib.contextmanager
def inlined_cycles_tree(material):
    """The node tree of *material*'s Cycles output once Blender has inlined its groups
    (``Material.inline_shader_nodes``, Blender 5+), of a copy whose EEVEE outputs are removed
    and whose Cycles output is the active one for every engine; the copy is removed after."""
    bpy = import_bpy()
    copy = material.copy()
    try:
        for node in [n for n in copy.node_tree.nodes if n.bl_idname == "ShaderNodeOutputMaterial"]:
            if node.target == "EEVEE":
                copy.node_tree.nodes.remove(node)
            else:
                node.target, node.is_active_output = "ALL", True
        inlined = copy.inline_shader_nodes()  # held: its tree lives as long as it does
        yield inlined.node_tree
    finally:
        bpy.data.materials.remove(copy)


def float_image(name: str, data: np.ndarray):
    """Float32 Non-Color image from an (H, W, 3|4) array (row 0 = bottom, Blender order)."""
    bpy = import_bpy()
    h, w, c = data.shape
    rgba = np.ones((h, w, 4), dtype=np.float32)
    rgba[..., :c] = data
    img = bpy.data.images.new(name, width=w, height=h, alpha=True, float_buffer=True)
    img.colorspace_settings.name = "Non-Color"
    img.alpha_mode = "NONE" if hasattr(img, "alpha_mode") else img.alpha_mode
    img.pixels.foreach_set(rgba.ravel())
    img.update()
    img.pack()
    return img


def add_aov(scene, name: str, kind: str = "COLOR"):
    layer = scene.view_layers[0]
    aov = layer.aovs.add()
    aov.name = name
    aov.type = kind
    return aov


def switch_to_eevee(scene, eevee_mats, aov: str = "eout") -> None:
    """Swap in the Eevee materials (one output in the single AOV *aov* each: Eevee's compile
    time grows fast with the number of AOVs) and Eevee's exact-check settings."""
    layer = scene.view_layers[0]
    while len(layer.aovs):
        layer.aovs.remove(layer.aovs[0])
    add_aov(scene, aov)
    for obj, mat in eevee_mats:
        obj.data.materials[0] = mat
    configure_engine(scene, "eevee")


def render_exr(scene, path: str) -> None:
    """Render *scene* into the file *path* (the add-on's comparison does the same)."""
    from phong_nodes.addon.scene.render import render_exr as render  # noqa: PLC0415  (needs bpy)

    render(scene, path)


def read_multilayer_exr(path: str) -> dict[str, np.ndarray]:
    """{pass name: float32 array (H, W, C)} with row 0 = top of the image (the add-on's reader:
    one EXR part per pass, channels ``<layer>.<pass>.<chan>``)."""
    from phong_nodes.core import compare  # noqa: PLC0415

    return compare.read_exr(path)


# ---------------------------------------------------------------- the SPEC contract
# (group -> [(input socket, kind)], [(output socket, kind)]); kind V = 3 components, S = scalar,
# SH = shader.  Copied from docs/contract.md, independently of node_groups/.

V, S, SH = "V", "S", "SH"

SPEC_GROUPS = {
    "Phong Directional Light": (
        [("Direction", V), ("Intensity", S)],
        [("Light Vector", V), ("Intensity", S)]),
    "Phong Point Light": (
        [("Position", V), ("Intensity", S), ("Quadratic", S), ("Linear", S), ("Constant", S)],
        [("Light Vector", V), ("Intensity", S), ("Distance", S)]),
    "Phong Spot Light": (
        [("Position", V), ("Direction", V), ("Half Angle", S), ("Edge Exponent", S),
         ("Intensity", S), ("Quadratic", S), ("Linear", S), ("Constant", S)],
        [("Light Vector", V), ("Intensity", S), ("Distance", S), ("Cos Angle", S), ("In Cone", S)]),
    "Phong Power Falloff": (
        [("Distance", S), ("Intensity", S), ("Exponent", S)],
        [("Intensity", S)]),
    "Phong Irradiant": ([("Color", V)], [("Color", V)]),
    "Phong Ambient": (
        [("Intensity", S), ("Light Color", V), ("Object Color", V)],
        [("Color", V)]),
    "Phong Diffuse": (
        [("Light Vector", V), ("Intensity", S), ("Light Color", V), ("Object Color", V), ("Normal", V)],
        [("Color", V)]),
    "Phong Specular": (
        [("Light Vector", V), ("Intensity", S), ("Light Color", V), ("Specular Color", V),
         ("Exponent", S), ("Normal", V), ("View Vector", V)],
        [("Color", V)]),
    "Phong Blinn Specular": (
        [("Light Vector", V), ("Intensity", S), ("Light Color", V), ("Specular Color", V),
         ("Exponent", S), ("Normal", V), ("View Vector", V)],
        [("Color", V)]),
    "Phong Color Add": ([("A", V), ("B", V)], [("Color", V)]),
    "Phong Color Multiply": ([("A", V), ("B", V), ("Factor", S)], [("Color", V)]),
    "Phong Shading": (
        [("Light Vector", V), ("Light Intensity", S), ("Light Color", V), ("Object Color", V),
         ("Irradiant Color", V), ("Ambient Intensity", S), ("Ambient Color", V),
         ("Diffuse Strength", S), ("Specular Strength", S), ("Specular Color", V),
         ("Exponent", S), ("Blinn", S), ("Normal", V), ("View Vector", V)],
        [("Irradiant", V), ("Ambient", V), ("Diffuse", V), ("Specular", V), ("Color", V),
         ("Shader", SH)]),
    # three.js r181 (docs/threejs.md)
    "three.js Point Light": (
        [("Position", V), ("Intensity", S), ("Distance", S), ("Decay", S)],
        [("Light Vector", V), ("Intensity", S), ("Distance", S)]),
    "three.js Spot Light": (
        [("Position", V), ("Direction", V), ("Angle", S), ("Penumbra", S), ("Intensity", S),
         ("Distance", S), ("Decay", S)],
        [("Light Vector", V), ("Intensity", S), ("Distance", S), ("Cos Angle", S)]),
    "three.js Ambient": (
        [("Intensity", S), ("Light Color", V), ("Diffuse Color", V)],
        [("Color", V)]),
    "three.js Phong": (
        [("Light Vector", V), ("Intensity", S), ("Light Color", V), ("Diffuse Color", V),
         ("Specular Color", V), ("Shininess", S), ("Specular Strength", S), ("Normal", V),
         ("View Vector", V)],
        [("Diffuse", V), ("Specular", V), ("Color", V)]),
    # X3D / VRML97 (docs/x3d.md)
    "X3D Directional Light": (
        [("Direction", V), ("Intensity", S), ("Ambient Intensity", S)],
        [("Light Vector", V), ("Intensity", S), ("Ambient", S)]),
    "X3D Point Light": (
        [("Position", V), ("Intensity", S), ("Ambient Intensity", S), ("Constant", S),
         ("Linear", S), ("Quadratic", S), ("Radius", S)],
        [("Light Vector", V), ("Intensity", S), ("Ambient", S), ("Distance", S)]),
    "X3D Spot Light": (
        [("Position", V), ("Direction", V), ("Beam Width", S), ("Cut Off Angle", S),
         ("Intensity", S), ("Ambient Intensity", S), ("Constant", S), ("Linear", S),
         ("Quadratic", S), ("Radius", S)],
        [("Light Vector", V), ("Intensity", S), ("Ambient", S), ("Distance", S),
         ("Spot Angle", S)]),
}


def interface_sockets(tree, in_out: str):
    """Interface socket items of a node group, in order ('INPUT' or 'OUTPUT')."""
    return [item for item in tree.interface.items_tree
            if getattr(item, "item_type", "SOCKET") == "SOCKET" and item.in_out == in_out]


# ---------------------------------------------------------------- optional test tools

def skip_unless_ci(reason: str):
    """Skip with *reason* on a developer's machine; under CI (``CI`` set), where the project's
    own files install every tool a test needs, fail instead."""
    import pytest  # noqa: PLC0415

    if os.environ.get("CI"):
        pytest.fail(f"CI runs this test: {reason}")
    pytest.skip(reason, allow_module_level=True)


def need_module(name: str):
    """The module *name* (a pinned test tool: requirements/), else skip_unless_ci."""
    import importlib  # noqa: PLC0415

    try:
        return importlib.import_module(name)
    except ImportError as error:
        skip_unless_ci(f"{name} is missing ({error}): bash tools/phong.sh setup installs it")
