# SPDX-License-Identifier: GPL-3.0-or-later
"""Bake Phong Lighting: the Phong look of objects into an image per object (through its UV
map) or into a colour attribute per vertex (Gouraud shading), with Cycles' own bake.

A Phong material ends in an Emission shader of the model's colour (``lighting/recipe.py``),
so Cycles' Emit bake gives the model's colour exactly.  For the bake only, each Phong
material of an object is replaced by a copy in which

* the Emission shows the chosen output of the material's lights group: the Phong Color, a
  single term (Irradiant, Ambient, Diffuse, Specular), or, with ``view="NONE"``,
  min(Irradiant + Ambient + Diffuse, 1) (the colour without the viewer-dependent specular);
* with ``view="CAMERA"`` the View Vector is the direction from the shading point to the scene
  camera (a perspective camera: normalize(camera - P), from the point in the camera's own
  space, Texture Coordinate ▸ Object: bpy 4.2 gives a Geometry ▸ Position outside the
  lights group the first baked object's transform; an orthographic one: its +Z axis), so
  the specular is the one the camera sees.  (Left at zero the View Vector would be the bake's
  own incoming direction, which is not the camera's.)  A View Vector the material links
  itself is kept.

Everything the material shows is baked: textures on Object Color, the light set of the
object (Light Linking) through its lights group, both lighting models.  The copies are
removed and the slots given back afterwards, also after an error.  Each object is baked in
a temporary scene that holds only it (Cycles' bake syncs the whole scene once per object it
bakes), so neither the user's scenes nor their render settings change.

Where the bake goes:

* ``target="IMAGE"``: the image ``Phong Bake <object>`` (8-bit sRGB PNG or 32-bit float
  linear EXR), baked in float and written by ``Image.save_render`` (Standard view
  transform: the sRGB encoding for PNG; EXR as baked), saved into a folder (``//`` = beside
  the .blend) or packed into the .blend; a new bake replaces the object's image (its
  users remapped), so there is never a pile of images;
* ``target="VERTEX"``: the float colour attribute ``Phong Bake`` on the points of the mesh:
  the model evaluated at each vertex, interpolated across the faces by whatever shows it
  (Gouraud shading).

Baking one kind removes the object's bake of the other kind.
"""

from __future__ import annotations

import os
import shutil
import tempfile
import time
from dataclasses import dataclass

import bpy

from ...core import outputs
from ...core.wording import name_list
from .. import compat
from ..scene import describe, render
from ..scene.render import Overrides
from ..lighting import recipe
from ..shading import modes as shading_modes

TARGETS = ("IMAGE", "VERTEX")
TERMS = ("COLOR", "IRRADIANT", "AMBIENT", "DIFFUSE", "SPECULAR")
VIEWS = ("CAMERA", "NONE")
FORMATS = ("PNG", "EXR")
#: The colour attribute of a vertex bake.
ATTRIBUTE = "Phong Bake"
#: Object custom properties: its baked image (an ID pointer), and what was baked.
IMAGE_KEY = "phong_bake_image"
INFO_KEY = "phong_bake"
#: Object custom property while the bake is shown: {slot index: its Phong material}.
SLOTS_KEY = "phong_bake_slots"
#: Marks the temporary bake copies of Phong materials (removed after the bake).
TEMP_KEY = "phong_bake_temp"
IMAGE_NODE = "phong_bake_image"
#: Objects baked per call of Cycles' bake.
CHUNK = 1


class BakeError(ValueError):
    """Objects that cannot be baked with these settings; the message says why (one line)."""


@dataclass
class Settings:
    target: str = "IMAGE"          # "IMAGE" or "VERTEX"
    term: str = "COLOR"            # "COLOR", "IRRADIANT", "AMBIENT", "DIFFUSE", "SPECULAR"
    view: str = "CAMERA"           # "CAMERA" (specular as the scene camera sees it) or "NONE"
    resolution: int = 512          # image size (square), IMAGE only
    file_format: str = "PNG"       # "PNG" (8-bit sRGB) or "EXR" (32-bit float linear)
    directory: str = "//"          # where images are saved ("//": beside the .blend)
    pack: bool = False             # pack the images into the .blend instead of saving them
    smart_uv: bool = False         # give objects without a UV map a Smart UV Project
    margin: int = 16               # pixels the bake extends beyond the UV islands
    refuse_package: bool = True    # refuse a folder inside the extension's own folder (the
                                   # headless command, run from the source tree, does not)


def image_name(obj) -> str:
    return f"Phong Bake {obj.name}"


def file_names(objects, file_format: str) -> dict:
    """{object name: file name} of the bakes of *objects* (``outputs.safe_names``: no two
    objects write one file)."""
    ext = "exr" if file_format == "EXR" else "png"
    names = outputs.safe_names((obj.name for obj in objects), "object")
    return {name: f"{stem}_phong_bake.{ext}" for name, stem in names.items()}


# -- which objects and materials -----------------------------------------------------

def phong_material(obj, index: int):
    """The Phong material of slot *index* of *obj*: the slot's own, or, while the bake is
    shown, the one the slot held before (``show.py``); None when there is none."""
    slot = obj.material_slots[index]
    if recipe.is_phong_material(slot.material):
        return slot.material
    kept = obj.get(SLOTS_KEY)
    material = kept.get(str(index)) if kept is not None else None
    return material if recipe.is_phong_material(material) else None


def has_phong(obj) -> bool:
    return obj.type == "MESH" and any(phong_material(obj, i) is not None
                                      for i in range(len(obj.material_slots)))


def _names(objects, limit=5) -> str:
    return name_list((o.name for o in objects), limit)


def check(scene, objects, settings: Settings) -> tuple:
    """(objects to bake, warnings), or BakeError saying why nothing can be baked as asked.
    Objects that are not meshes with a Phong material are left out with a warning."""
    if settings.target not in TARGETS:
        raise BakeError(f"target {settings.target!r}: expected one of {', '.join(TARGETS)}")
    if settings.term not in TERMS:
        raise BakeError(f"term {settings.term!r}: expected one of {', '.join(TERMS)}")
    if settings.view not in VIEWS:
        raise BakeError(f"view {settings.view!r}: expected one of {', '.join(VIEWS)}")
    if settings.file_format not in FORMATS:
        raise BakeError(f"file format {settings.file_format!r}: expected PNG or EXR")
    if settings.term == "SPECULAR" and settings.view == "NONE":
        raise BakeError("the Specular term needs a viewer: bake it with view CAMERA")
    if settings.target == "IMAGE" and not 1 <= settings.resolution <= 16384:
        raise BakeError(f"resolution {settings.resolution}: expected 1 to 16384 pixels")
    warnings = []
    chosen, skipped = [], []  # one pass: no membership test against a list
    for obj in objects:
        if has_phong(obj):
            chosen.append(obj)
        elif obj.type in ("MESH", "CURVE", "SURFACE", "FONT", "META"):
            skipped.append(obj)
    if skipped:
        warnings.append(f"left out (no mesh with a Phong material): {_names(skipped)}")
    if not chosen:
        raise BakeError("no selected mesh has a Phong material (Apply Phong Material first)")
    if settings.view == "CAMERA" and scene.camera is None:
        raise BakeError(f"scene {scene.name!r} has no camera: the specular is baked as the "
                        "scene camera sees it (or bake with view NONE, without specular)")
    if settings.target == "VERTEX":
        by_mesh = {}
        for obj in chosen:
            by_mesh.setdefault(obj.data.name, []).append(obj)
        shared = next((objs for objs in by_mesh.values() if len(objs) > 1), None)
        if shared is not None:
            raise BakeError(f"objects {_names(shared)} share the mesh {shared[0].data.name!r}: "
                            "vertex colours belong to the mesh; make them single user "
                            "(Object ▸ Relations) or bake to images")
    if settings.target == "IMAGE":
        no_uv = [o for o in chosen if not o.data.uv_layers]
        if no_uv and not settings.smart_uv:
            raise BakeError(f"no UV map on {_names(no_uv)}: add one, or bake with Smart UV "
                            "Project on, or bake to vertex colours")
        if not settings.pack:
            folder = image_folder(settings.directory)
            if folder is None:
                raise BakeError(f"folder {settings.directory!r} is relative to the .blend, "
                                "which is not saved yet: save it, give a folder, or pack the "
                                "images")
            problem = outputs.output_problem(folder, settings.refuse_package)
            if problem is not None:
                raise BakeError(problem)
    linked = [o for o in chosen if o.library is not None or o.data.library is not None]
    if linked:
        raise BakeError(f"{_names(linked)} come from a linked library: their mesh cannot take "
                        "a bake (make them local first)")
    return chosen, warnings


def image_folder(directory: str):
    """The absolute folder of *directory* ("//..." relative to the .blend), or None when it
    is relative to a .blend that is not saved."""
    if directory.startswith("//") and not bpy.data.filepath:
        return None
    return os.path.abspath(bpy.path.abspath(directory or "//"))


# -- the bake material ---------------------------------------------------------------

def camera_matrix(scene, camera):
    """*camera*'s world matrix as *scene* evaluates it.  The object's own ``matrix_world`` is
    what the last evaluation flushed into it: bpy 4.x leaves it stale (the identity, measured)
    after a script places the camera (location, Track To) until a depsgraph of the active
    scene is evaluated, while Cycles' bake reads the evaluated camera."""
    if bpy.context.scene == scene and bpy.context.view_layer is not None:
        depsgraph = bpy.context.evaluated_depsgraph_get()
    else:  # a scene no window shows may have no depsgraph yet
        depsgraph = describe.evaluated(scene, scene.view_layers[0])
    return camera.evaluated_get(depsgraph).matrix_world.copy()


def _view_vector(tree, lights_node, camera, matrix=None) -> None:
    """The View Vector from the shading point to *camera* (world matrix *matrix*, default its
    ``matrix_world``), unless the material links one."""
    socket = lights_node.inputs["View Vector"]
    if socket.is_linked:
        return
    matrix = camera.matrix_world if matrix is None else matrix
    if camera.data.type == "ORTHO":
        axis = matrix.to_3x3().col[2].normalized()  # the camera looks along -Z
        socket.default_value = tuple(axis)
        return
    # The point in the camera's own space (Texture Coordinate ▸ Object of the camera), the
    # way to the camera there (-P), turned into the world by the camera's 3×3 matrix
    coords = tree.nodes.new("ShaderNodeTexCoord")
    coords.object = camera
    rows = matrix.to_3x3()
    combine = tree.nodes.new("ShaderNodeCombineXYZ")
    for axis in range(3):
        dot = tree.nodes.new("ShaderNodeVectorMath")
        dot.operation = "DOT_PRODUCT"
        compat.input_socket(dot, "Vector_001").default_value = tuple(-c for c in rows[axis])
        tree.links.new(coords.outputs["Object"], compat.input_socket(dot, "Vector"))
        tree.links.new(dot.outputs["Value"], compat.input_socket(combine, "XYZ"[axis]))
    unit = tree.nodes.new("ShaderNodeVectorMath")
    unit.operation = "NORMALIZE"
    tree.links.new(combine.outputs["Vector"], compat.input_socket(unit, "Vector"))
    tree.links.new(unit.outputs["Vector"], socket)


def _emitted(tree, lights_node, settings: Settings):
    """The output socket the bake shows."""
    outputs = lights_node.outputs
    if settings.term != "COLOR":
        return outputs[settings.term.title()]
    if settings.view == "CAMERA":
        return outputs["Color"]
    total = outputs["Irradiant"]
    for term in ("Ambient", "Diffuse"):
        add = tree.nodes.new("ShaderNodeVectorMath")
        add.operation = "ADD"
        tree.links.new(total, compat.input_socket(add, "Vector"))
        tree.links.new(outputs[term], compat.input_socket(add, "Vector_001"))
        total = add.outputs["Vector"]
    clamp = tree.nodes.new("ShaderNodeVectorMath")
    clamp.operation = "MINIMUM"
    compat.input_socket(clamp, "Vector_001").default_value = (1.0, 1.0, 1.0)
    tree.links.new(total, compat.input_socket(clamp, "Vector"))
    return clamp.outputs["Vector"]


def bake_material(material, settings: Settings, camera, image=None, matrix=None):
    """A temporary copy of the Phong *material* that emits what *settings* bake (and holds
    the active image node of *image*), seen from *camera* (world matrix *matrix*:
    ``camera_matrix``); ``None`` *material*: one that emits black."""
    if material is None:
        copy = bpy.data.materials.new("Phong Bake (black)")
        tree = compat.new_material_tree(copy)
        tree.nodes.clear()
        output = tree.nodes.new("ShaderNodeOutputMaterial")
        emission = tree.nodes.new("ShaderNodeEmission")
        emission.inputs["Color"].default_value = (0.0, 0.0, 0.0, 1.0)
        tree.links.new(compat.output_socket(emission, "Emission"), output.inputs["Surface"])
    else:
        copy = material.copy()
        copy.name = f"{material.name} (Phong bake)"
        tree = copy.node_tree
        lights_node = tree.nodes[recipe.LIGHTS_NODE]
        if settings.view == "CAMERA":
            _view_vector(tree, lights_node, camera, matrix)
        emission = tree.nodes.new("ShaderNodeEmission")
        emission.inputs["Strength"].default_value = 1.0
        tree.links.new(_emitted(tree, lights_node, settings), emission.inputs["Color"])
        output = tree.nodes[recipe.OUTPUT]
        tree.links.new(compat.output_socket(emission, "Emission"), output.inputs["Surface"])
    copy[TEMP_KEY] = 1
    if image is not None:
        node = tree.nodes.new("ShaderNodeTexImage")
        node.name = IMAGE_NODE
        node.image = image
        for other in tree.nodes:
            other.select = False
        node.select = True
        tree.nodes.active = node
    return copy


# -- images and attributes -----------------------------------------------------------

def _image(obj, settings: Settings):
    """A new float (scene-linear) image for the object's bake; it takes the place of its old
    one (users remapped, the old one removed), so every bake of an object is one image."""
    size = settings.resolution
    old = obj.get(IMAGE_KEY)
    old = old if isinstance(old, bpy.types.Image) else None
    image = bpy.data.images.new(image_name(obj), size, size, alpha=False, float_buffer=True)
    if old is not None:
        old.user_remap(image)
        bpy.data.images.remove(old)
    image.name = image_name(obj)
    obj[IMAGE_KEY] = image
    return image


def remove_image(obj) -> None:
    image = obj.get(IMAGE_KEY)
    if isinstance(image, bpy.types.Image):
        bpy.data.images.remove(image)
    if IMAGE_KEY in obj.keys():
        del obj[IMAGE_KEY]


def remove_attribute(mesh) -> None:
    attribute = mesh.color_attributes.get(ATTRIBUTE)
    if attribute is not None:
        mesh.color_attributes.remove(attribute)


def _attribute(mesh):
    """A fresh float point-domain colour attribute ``Phong Bake``, the active one (the
    bake writes into the active colour attribute)."""
    remove_attribute(mesh)
    attribute = mesh.color_attributes.new(ATTRIBUTE, "FLOAT_COLOR", "POINT")
    mesh.color_attributes.active_color = attribute
    return attribute


def _file_settings(scene, file_format: str, o: Overrides) -> None:
    """The (temporary) scene's output settings that ``Image.save_render`` writes with: 8-bit RGB PNG
    through the Standard view transform (sRGB), or 32-bit float EXR (linear, as baked)."""
    settings = scene.render.image_settings
    if hasattr(settings, "media_type"):  # 5.0+
        o.set(settings, "media_type", "IMAGE")
    if file_format == "EXR":
        o.set(settings, "file_format", "OPEN_EXR")
        o.set(settings, "color_depth", "32")
        o.set(settings, "exr_codec", "ZIP")
    else:
        o.set(settings, "file_format", "PNG")
        o.set(settings, "color_depth", "8")
    o.set(settings, "color_mode", "RGB")
    if hasattr(settings, "color_management"):
        o.set(settings, "color_management", "FOLLOW_SCENE")
    o.set(scene.display_settings, "display_device", "sRGB")
    for attr, value in (("view_transform", "Standard"), ("look", "None"), ("exposure", 0.0),
                        ("gamma", 1.0), ("use_curve_mapping", False)):
        o.set(scene.view_settings, attr, value)
    o.set(scene.render, "dither_intensity", 0.0)


def _save(scene, image, settings: Settings, scratch: str, name: str) -> str | None:
    """Write the baked *image* as the file *name* (``outputs.write_file``: never
    half-written) and make *image* that file, or pack it; returns the file, or None when
    packed."""
    ext = "exr" if settings.file_format == "EXR" else "png"
    folder = scratch if settings.pack else image_folder(settings.directory)
    os.makedirs(folder, exist_ok=True)
    path = os.path.join(folder, name)
    rendered = os.path.join(scratch, f"render.{ext}")
    if hasattr(image, "use_half_precision"):
        image.use_half_precision = False  # bpy 4.2 writes half floats otherwise
    image.save_render(rendered, scene=scene)
    if not settings.pack:
        with open(rendered, "rb") as stream:
            outputs.write_file(path, stream.read())
        os.remove(rendered)
    else:
        os.replace(rendered, path)
    space = image.colorspace_settings.name  # the float bake's: scene linear
    image.filepath_raw = path
    image.source = "FILE"
    image.reload()
    # the file's pixels: sRGB bytes (PNG) or linear floats (EXR) as baked
    image.colorspace_settings.name = "sRGB" if ext == "png" else space
    if settings.pack:
        image.pack()
        image.filepath_raw = f"//{os.path.basename(path)}"
        os.remove(path)
        return None
    if bpy.data.filepath:
        image.filepath_raw = bpy.path.relpath(path)
    return path


# -- the bake --------------------------------------------------------------------------

def _smart_uv(obj) -> None:
    """A UV map by Smart UV Project (every face of the object, in Edit Mode, then back)."""
    mesh = obj.data
    mesh.uv_layers.new(name="UVMap")
    mesh.polygons.foreach_set("select", [True] * len(mesh.polygons))
    layer = bpy.context.view_layer
    active = layer.objects.active
    layer.objects.active = obj
    bpy.ops.object.mode_set(mode="EDIT")
    try:
        bpy.ops.uv.smart_project(island_margin=0.02)
    finally:
        bpy.ops.object.mode_set(mode="OBJECT")
        layer.objects.active = active


def _prepare(obj, settings: Settings):
    """The object's target made ready (a new image, or a fresh colour attribute); returns
    (image or None, the name of the colour attribute that was active)."""
    mesh = obj.data
    if settings.target == "IMAGE":
        if not mesh.uv_layers:
            _smart_uv(obj)
        remove_attribute(mesh)
        return _image(obj, settings), None
    remove_image(obj)
    # the name, read before _attribute replaces the layers: the active attribute may be the
    # old bake, and reading it after its removal reads freed memory (bpy 5.2 crashed so)
    previous = mesh.color_attributes.active_color
    previous_name = previous.name if previous is not None else None
    _attribute(mesh)
    return None, previous_name


def _stage(scene=None):
    """The temporary scene the objects are baked in: Cycles' bake syncs the whole scene for
    every object it bakes, so each is baked in a scene of its own objects alone (the lights
    groups' drivers still read the lights, wherever they are).  It shares *scene*'s World:
    the lights groups read the lights' transforms from World properties through View Layer
    attributes (docs/contract.md), which look in the rendered scene's World."""
    stage = bpy.data.scenes.new("Phong Bake (temporary)")
    if scene is not None:
        stage.world = scene.world
    render.exact(stage, "cycles")
    stage.render.bake.margin_type = "EXTEND"
    return stage


def _bake_chunk(scene, stage, chunk, settings: Settings, camera, scratch, temps,
                matrix, names) -> list:
    """Bake the objects of *chunk* in one call of Cycles' bake, in the scene *stage*, their
    slots holding bake copies of their materials meanwhile (added to *temps*, for the
    caller to remove in one go); returns what was made, per object."""
    prepared = [_prepare(obj, settings) for obj in chunk]
    given = []
    try:
        for obj, (image, _previous) in zip(chunk, prepared):
            if not obj.material_slots:
                raise BakeError(f"{obj.name!r} has no material slot")
            for index, slot in enumerate(obj.material_slots):
                temp = bake_material(phong_material(obj, index), settings, camera, image,
                                     matrix)
                temps.append(temp)
                given.append((slot, slot.material))
                slot.material = temp
            if stage is not scene:
                stage.collection.objects.link(obj)
        target = "IMAGE_TEXTURES" if settings.target == "IMAGE" else "VERTEX_COLORS"
        layer = stage.view_layers[0]
        for obj in chunk:
            obj.select_set(True, view_layer=layer)
        with shading_modes.modifiers_off(chunk), bpy.context.temp_override(
                scene=stage, view_layer=layer, active_object=chunk[0], object=chunk[0],
                selected_objects=list(chunk), selected_editable_objects=list(chunk)):
            layer.update()  # the lights groups' drivers evaluated before Cycles reads them
            try:
                bpy.ops.object.bake(type="EMIT", target=target, save_mode="INTERNAL",
                                    use_clear=True, margin=settings.margin,
                                    use_selected_to_active=False)
            except RuntimeError as error:
                reason = str(error).strip().splitlines()
                raise BakeError(f"{_names(chunk)}: Blender's bake failed: "
                                f"{reason[-1] if reason else 'no reason given'}") from None
    finally:
        for slot, material in reversed(given):
            slot.material = material
        if stage is not scene:
            for obj in chunk:
                stage.collection.objects.unlink(obj)
    results = []
    for obj, (image, previous) in zip(chunk, prepared):
        colors = obj.data.color_attributes
        if previous is not None and previous != ATTRIBUTE and colors.get(previous) is not None:
            colors.active_color = colors.get(previous)
        path = (_save(stage, image, settings, scratch, names[obj.name]) if image is not None
                else None)
        obj[INFO_KEY] = {"target": settings.target, "term": settings.term, "view": settings.view}
        results.append({"object": obj.name, "target": settings.target, "image": image,
                        "path": path, "attribute": ATTRIBUTE if image is None else None})
    return results


def chunks(objects, size: int) -> list:
    return [objects[i:i + size] for i in range(0, len(objects), size)]


def bake(scene, objects, settings: Settings, progress=None) -> tuple:
    """Bake each of *objects* as *settings* say; returns (results, warnings).

    The objects are baked CHUNK at a time, in a temporary scene that holds only them
    (Cycles' bake syncs the whole scene once per object it bakes); the user's scenes and
    render settings are not touched.  *progress(done, total, object name)* is called for
    each object as its chunk is done.  BakeError (nothing baked)
    when the objects cannot be baked as asked; a chunk whose bake fails stops the bake there
    with a BakeError naming its objects (the chunks before it keep their bakes)."""
    objects, warnings = check(scene, objects, settings)
    camera = scene.camera
    matrix = camera_matrix(scene, camera) if camera is not None else None
    results = []
    mode_object = bpy.context.object
    if mode_object is not None and mode_object.mode != "OBJECT":
        raise BakeError(f"{mode_object.name!r} is in {mode_object.mode.title()} Mode: bake from "
                        "Object Mode")
    scratch = tempfile.mkdtemp(prefix="phong-bake-")
    temps = []  # the stage and the bake materials, removed in one go
    try:
        stage = _stage(scene)
        temps.append(stage)
        _file_settings(stage, settings.file_format, Overrides())  # the stage goes later
        names = file_names(objects, settings.file_format)
        for chunk in chunks(objects, CHUNK):
            t0 = time.perf_counter()
            done = _bake_chunk(scene, stage, chunk, settings, camera, scratch, temps, matrix,
                               names)
            seconds = (time.perf_counter() - t0) / len(chunk)
            for result in done:
                result["seconds"] = seconds
                results.append(result)
                if progress is not None:
                    progress(len(results), len(objects), result["object"])
    finally:
        bpy.data.batch_remove(temps)  # one pass: one by one is O(file) each
        shutil.rmtree(scratch, ignore_errors=True)
    return results, warnings
