# SPDX-License-Identifier: GPL-3.0-or-later
"""Helpers for the Blender-side tests: install the extension like a user, set up
pixel-exact scenes, render to multilayer EXR and read the passes back.

Everything that differs between Blender versions lives here (engine ids, EXR settings).
``bpy`` is imported lazily: :func:`import_bpy` must run after ``BLENDER_USER_RESOURCES``
has been pointed at a throw-away folder (conftest.py does that).
"""

from __future__ import annotations

import importlib
import importlib.util
import os
import subprocess
import sys
import zipfile

import numpy as np

REPO_ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
EXT_ID = "phong_nodes"
EXT_REPO = "user_default"
EXT_MODULE = f"bl_ext.{EXT_REPO}.{EXT_ID}"


def source_module(relpath: str):
    """A pure-python module of the source tree (e.g. ``addon/scenes.py``) loaded by path, so
    it is tested without importing the ``addon`` package (which needs bpy)."""
    name = "phong_source_" + relpath.replace("/", "_").removesuffix(".py")
    if name not in sys.modules:
        spec = importlib.util.spec_from_file_location(name, os.path.join(REPO_ROOT, relpath))
        module = importlib.util.module_from_spec(spec)
        spec.loader.exec_module(module)
        sys.modules[name] = module
    return sys.modules[name]


def import_bpy():
    import bpy  # noqa: PLC0415  (lazy on purpose)

    return bpy


# ---------------------------------------------------------------- install like a user

def ext_tool() -> str:
    bpy = import_bpy()
    return os.path.join(bpy.utils.resource_path("LOCAL"),
                        "scripts/addons_core/bl_pkg/cli/blender_ext.py")


def run_ext_tool(*args: str) -> subprocess.CompletedProcess:
    return subprocess.run([sys.executable, ext_tool(), *args],
                          capture_output=True, text=True, check=False)


def build_zip(source_dir: str, output_dir: str) -> str:
    """Build the extension zip with Blender's own tool; returns the zip path."""
    res = run_ext_tool("build", "--source-dir", source_dir, "--output-dir", output_dir)
    if res.returncode != 0:
        raise RuntimeError(f"blender_ext build failed ({res.returncode}):\n{res.stdout}\n{res.stderr}")
    zips = [f for f in os.listdir(output_dir) if f.endswith(".zip")]
    if len(zips) != 1:
        raise RuntimeError(f"expected one zip in {output_dir}, found {zips}\n{res.stdout}")
    return os.path.join(output_dir, zips[0])


def validate_zip(zip_path: str) -> subprocess.CompletedProcess:
    return run_ext_tool("validate", zip_path)


def zip_names(zip_path: str) -> list[str]:
    with zipfile.ZipFile(zip_path) as zf:
        return zf.namelist()


def install_zip(zip_path: str) -> None:
    bpy = import_bpy()
    res = bpy.ops.extensions.package_install_files(
        filepath=zip_path, repo=EXT_REPO, enable_on_install=True)
    if res != {"FINISHED"}:
        raise RuntimeError(f"package_install_files returned {res}")


def addon_enabled() -> bool:
    bpy = import_bpy()
    return EXT_MODULE in bpy.context.preferences.addons


def ensure_enabled() -> None:
    if not addon_enabled():
        import addon_utils  # noqa: PLC0415

        addon_utils.enable(EXT_MODULE, default_set=True)


def reset_empty_file() -> None:
    """Empty file, preferences kept (read_factory_settings would disable the add-on)."""
    bpy = import_bpy()
    bpy.ops.wm.read_homefile(use_empty=True)
    ensure_enabled()


def load_groups() -> None:
    bpy = import_bpy()
    res = bpy.ops.phong.load_node_groups()
    if res != {"FINISHED"}:
        raise RuntimeError(f"phong.load_node_groups returned {res}")


# ---------------------------------------------------------------- version differences

def compat():
    """The installed extension's compatibility module: the one place for version differences."""
    return importlib.import_module(EXT_MODULE + ".addon.compat")


def engine_id(kind: str) -> str:
    """'cycles' or 'eevee' -> the engine enum of this Blender."""
    if kind == "cycles":
        return "CYCLES"
    if kind == "eevee":
        return compat().eevee_engine()
    raise ValueError(kind)


def set_output_multilayer_exr(scene) -> None:
    """32-bit float multilayer EXR output."""
    compat().set_multilayer_exr(scene.render.image_settings)


def configure_engine(scene, kind: str) -> None:
    """The add-on's exact-check settings (one sample at pixel centres)."""
    importlib.import_module(EXT_MODULE + ".addon.render").exact(scene, kind)


# ---------------------------------------------------------------- scene set-up

def new_scene(name: str, width: int, height: int, kind: str = "cycles"):
    bpy = import_bpy()
    scene = bpy.data.scenes.new(name)
    importlib.import_module(EXT_MODULE + ".addon.render").plain_picture(scene, width, height)
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


def add_uv_sphere(scene, name, location, radius, material, segments=48, rings=24):
    """Smooth-shaded UV sphere (the add-on's mesh helper, no operator context needed)."""
    bpy = import_bpy()
    mesh = importlib.import_module(EXT_MODULE + ".addon.meshes").uv_sphere(
        name, radius, segments, rings)
    mesh.materials.append(material)
    mesh.update()
    obj = bpy.data.objects.new(name, mesh)
    obj.location = location
    scene.collection.objects.link(obj)
    return obj


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


def _bake():
    return importlib.import_module(EXT_MODULE + ".addon.bake")


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
    """Render *scene* into the file *path* (the add-on's bake does the same)."""
    _bake().render_exr(scene, path)


def read_multilayer_exr(path: str) -> dict[str, np.ndarray]:
    """{pass name: float32 array (H, W, C)} with row 0 = top of the image (the add-on's reader:
    one EXR part per pass, channels ``<layer>.<pass>.<chan>``)."""
    return _bake().read_exr(path)


# ---------------------------------------------------------------- the SPEC contract
# (group -> [(input socket, kind)], [(output socket, kind)]); kind V = 3 components, S = scalar,
# SH = shader.  Copied from shared/SPEC.md, independently of node_groups/.

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
}


def interface_sockets(tree, in_out: str):
    """Interface socket items of a node group, in order ('INPUT' or 'OUTPUT')."""
    return [item for item in tree.interface.items_tree
            if getattr(item, "item_type", "SOCKET") == "SOCKET" and item.in_out == in_out]
