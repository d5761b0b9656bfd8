# SPDX-License-Identifier: GPL-3.0-or-later
"""FBX imported with its Phong and Lambert materials and its lights as exact Phong values.

The scene comes from Blender's own FBX importer where it reads the file (binary FBX 7100 and
later); ASCII files and FBX 6.1 are built from ufbx (meshes with normals, UVs and vertex
colours, the node hierarchy, cameras, lights; axes and units converted as Blender's importer
does: Z up, metres).  Then ``core/fbx`` gives every material and light its values, by the
FBX SDK's rules (see there), and:

    Object Color        DiffuseColor × DiffuseFactor          (× a DiffuseColor texture)
    Ambient (Ka)        AmbientColor × AmbientFactor          (× an AmbientColor texture)
    Specular Color      SpecularColor × SpecularFactor        (Lambert: black)
    Exponent            ShininessExponent, else Shininess     (Blinn shading: Blinn = 1)
    Irradiant Color     EmissiveColor × EmissiveFactor        (× an EmissiveColor texture)
    Opacity             Opacity, else 1 − TransparencyFactor × mean(TransparentColor);
                        a file of Blender's exporter: its TransparencyFactor map's alpha
    light               colour; Phong Intensity = Intensity / 100; DecayType k = 0, 1, 2
                        as γ = 1 / β = 1 / α = 1, k = 3 as the power falloff 1/d³;
                        spot: spot_size = OuterAngle, spot_blend = 1 − Inner/Outer,
                        Phong Edge Exponent from both (core.fbx.spot_edge_exponent)
    World               Phong ambient colour = GlobalSettings AmbientColor, intensity 1

Every material is a Phong material under the file's name (``.001`` where the scene already
holds it), and the import adds nothing else (``native.py``): Blender's importer's
Principled materials are replaced, the materials and images nothing uses are removed.
Materials of other shading models (PBR, Arnold, ShaderFX) are made as Apply Phong Material
makes them from Blender's import (default values on the ufbx path), named in one warning.
Maps on TransparentColor / TransparencyFactor give the opacity, a map on ShininessExponent
the exponent (``native.opacity_map``, ``native.exponent_map``); a map whose file is not
there is left out and its reference kept for the export (``keys.FBX_MISSING_MAPS``).  Any
failure raises :class:`core.fbx.FbxError` and removes what the import had added.
"""

from __future__ import annotations

import math
import os
import re
import tempfile

import bpy
from mathutils import Matrix

from ...core import fbx
from .. import compat
from ..lighting import opacity as opacity_nodes
from ..lighting import properties, recipe, writer
from ..lighting import sources as source_materials
from ..lighting import sync as sync_mod
from . import keys, native
from .native import ensure_fbx_addon

FbxError = fbx.FbxError
#: Custom property on imported objects, lights and materials: the FBX file they came from.
SOURCE_KEY = "phong_fbx_source"
def _base_name(name: str) -> str:
    base, dot, suffix = name.rpartition(".")
    return base if dot and suffix.isdigit() and len(suffix) == 3 else name


def _binary_7100(path) -> bool:
    """Whether the file says it is binary FBX 7100 or later (its header: the magic
    "Kaydara FBX Binary  \\0", two bytes, the version as little-endian uint32)."""
    try:
        with open(path, "rb") as handle:
            head = handle.read(27)
    except OSError:
        return False
    return (head[:21] == b"Kaydara FBX Binary  \x00" and len(head) == 27
            and int.from_bytes(head[23:27], "little") >= 7100)


def _blender_reads(data: fbx.Scene) -> bool:
    return not data.ascii and data.version >= 7100


# -- the ufbx build (ASCII, FBX 6.1, or where Blender's importer fails) ----------------------

def _mesh(item: fbx.MeshData, name, warnings, path):
    import numpy as np
    mesh = bpy.data.meshes.new(name or "Mesh")
    sizes = np.asarray(item.face_sizes, dtype=np.int64)
    mesh.vertices.add(len(item.positions))
    mesh.vertices.foreach_set("co", np.asarray(item.positions, np.float32).ravel())
    mesh.loops.add(len(item.loop_vertex))
    mesh.loops.foreach_set("vertex_index", np.asarray(item.loop_vertex, np.int32))
    mesh.polygons.add(len(sizes))
    mesh.polygons.foreach_set("loop_start", (np.cumsum(sizes) - sizes).astype(np.int32))
    mesh.polygons.foreach_set("loop_total", sizes.astype(np.int32))
    mesh.polygons.foreach_set("material_index", np.asarray(item.face_material, np.int32))
    for index, (uv_name, values) in enumerate(item.uvs):
        layer = mesh.uv_layers.new(name=uv_name)
        if layer is None:  # Blender holds at most 8 UV maps
            warnings.append(f"{path}: mesh {name}: UV sets after the {index}th left out "
                            f"({len(item.uvs)} in the file)")
            break
        layer.data.foreach_set("uv", np.asarray(values, np.float32).ravel())
    for color_name, values in item.colors:
        layer = mesh.color_attributes.new(color_name, "FLOAT_COLOR", "CORNER")
        if layer is not None:
            layer.data.foreach_set("color", np.asarray(values, np.float32).ravel())
    mesh.update(calc_edges=True)
    if mesh.validate(clean_customdata=False):
        warnings.append(f"{path}: mesh {name}: invalid faces or indices removed")
    mesh.update()
    normals = item.normals
    if normals is not None and len(normals) == len(mesh.loops):
        if hasattr(mesh, "use_auto_smooth"):  # Blender < 4.1
            mesh.use_auto_smooth = True
        mesh.polygons.foreach_set("use_smooth", [True] * len(mesh.polygons))
        mesh.normals_split_custom_set(np.asarray(normals, np.float32))
    return mesh


def _build(context, data: fbx.Scene, path, warnings) -> list:
    """The scene of *data* (read with geometry) in Blender, as Blender's FBX importer makes
    it: objects in the active collection, Z up, metres.  Returns the material slots to fill,
    (mesh, index, material name) or (object, index, name) for a slot linked to the object
    (the materials are made afterwards, Phong from birth: :func:`_finish`)."""
    collection = context.collection or context.scene.collection
    meshes, names, made, slots = {}, {}, {}, []
    for node in data.nodes:
        thing = None
        if node.kind == "MESH":
            if node.mesh not in meshes:
                meshes[node.mesh] = _mesh(data.meshes[node.mesh], node.data, warnings, path)
                for index, name in enumerate(node.materials):
                    meshes[node.mesh].materials.append(None)
                    slots.append((meshes[node.mesh], index, name))
                names[node.mesh] = list(node.materials)
            thing = meshes[node.mesh]
        elif node.kind == "LIGHT":
            thing = bpy.data.lights.new(node.data or node.name, node.light["type"])
            thing.use_shadow = bool(node.light.get("cast_shadows", True))  # FBX CastShadows
        elif node.kind == "CAMERA":
            cam = node.camera
            thing = bpy.data.cameras.new(node.data or node.name)
            if cam["ortho"]:
                thing.type = "ORTHO"
                thing.ortho_scale = max(cam["ortho_size"], 1e-6)
            else:
                thing.sensor_fit = "HORIZONTAL"
                thing.angle = math.radians(min(max(cam["fov_x"], 1.0), 175.0))
            if 0.0 < cam["near"] < cam["far"]:
                thing.clip_start, thing.clip_end = cam["near"], cam["far"]
        obj = bpy.data.objects.new(node.name or "Object", thing)
        collection.objects.link(obj)
        if node.kind == "MESH":  # per-object materials, as the file assigns them to the node
            for index, name in enumerate(node.materials[:len(obj.material_slots)]):
                if names[node.mesh][index] != name:
                    obj.material_slots[index].link = "OBJECT"
                    slots.append((obj, index, name))
        made[node.id] = obj
    context.view_layer.update()  # (after a rollback of Blender's importer's objects)
    for obj in list(context.view_layer.objects):  # the imported ones selected, as Blender does
        if obj is not None:
            obj.select_set(False)
    for node in data.nodes:
        obj = made[node.id]
        if obj.name in context.view_layer.objects:
            obj.select_set(True)
            context.view_layer.objects.active = obj
        if node.parent is not None and node.parent in made:
            obj.parent = made[node.parent]
        obj.matrix_basis = Matrix(node.matrix)
        if not node.visible:
            try:
                obj.hide_set(True)
            except RuntimeError:  # not in the view layer
                obj.hide_viewport = True
    return slots


# -- materials ---------------------------------------------------------------------------------

def _safe_name(name: str) -> str:
    base = os.path.basename(name.replace("\\", "/")) or "texture"
    base = re.sub(r"[^A-Za-z0-9._-]", "_", base)[:100].lstrip(".") or "texture"
    return base


def _image(texture, images, warnings, where, non_color=False):
    """A Blender image of *texture*: its file, else its embedded data (packed), else None
    with one warning per texture.  *non_color*: a scalar map, read as data (Non-Color); a
    texture read both as a colour and as data gets an image of each colour space."""
    key = (texture.name, texture.content is not None, bool(non_color))
    if key not in images:
        images[key] = _load(texture, images, warnings, where, non_color)
    return images[key]


def _load(texture, images, warnings, where, non_color):
    """The image of *texture* in the colour space *non_color* asks: the one Blender's
    importer made (``images[""]``, set to that colour space; a copy where the import reads
    it in the other one too), its file (``native.load_image``), else its embedded data
    (packed), else None with a warning (``None`` is remembered: named once)."""
    base = _safe_name(texture.name)
    made = next((i for i in images.get("", ()) if i.name == base or _safe_name(
        bpy.path.basename(i.filepath)) == base), None)  # Blender's importer read it already
    if made is not None and made.packed_file is None and not os.path.isfile(
            bpy.path.abspath(made.filepath, library=made.library)):
        made = None   # its file is not there (Blender's importer names it anyway): not found
    if made is not None:
        other = images.get((texture.name, texture.content is not None, not non_color))
        image = made.copy() if other is made else made
        if (image.colorspace_settings.name == native.NON_COLOR) != bool(non_color):
            image.colorspace_settings.name = native.NON_COLOR if non_color else "sRGB"
        return image
    image = None
    if texture.resolved is not None:
        image = native.load_image(texture.resolved, images, non_color)
    if image is None and texture.content is not None:
        if len(texture.content) > fbx.MAX_EMBEDDED:
            other = images.get((texture.name, True, not non_color), False)
            if other is not None:   # named once
                warnings.append(f"{where}: embedded texture {texture.name} larger than "
                                f"{fbx.MAX_EMBEDDED >> 20} MiB, left out")
            return None
        with tempfile.TemporaryDirectory() as folder:
            file = os.path.join(folder, _safe_name(texture.name))
            with open(file, "wb") as handle:
                handle.write(texture.content)
            image = native.load_image(file, non_color=non_color, existing=False)
            if image is not None:
                image.pack()
                image.filepath = "//" + _safe_name(texture.name)
                image.name = _safe_name(texture.name)
    if image is None and images.get((texture.name, texture.content is not None,
                                     not non_color), False) is not None:
        warnings.append(f"{where}: texture {texture.name} not found (looked for "
                        f"{' and '.join(texture.candidates) or texture.name}); left out")
    return image


def apply_material(material, source: fbx.Material, warnings: list, images: dict, path) -> None:
    """Give the Phong material *material* the values and textures of *source*."""
    tree = material.node_tree
    lights = tree.nodes[recipe.LIGHTS_NODE]
    where = f"{path} ({source.name})"
    maps = {}
    for name in fbx.COLOURS:
        texture = source.textures.get(name)
        image = _image(texture, images, warnings, where, _data(source, texture)) \
            if texture is not None else None
        if image is not None:
            maps[name] = image
    values = fbx.material_values(source)   # the FBX values as Phong values (core/fbx/phong)
    controls = writer.write(material, writer.Values(
        {name: values[name] for name in fbx.COLOURS}, exponent=values["Exponent"],
        blinn=values["Blinn"], specular_strength=values.get("Specular Strength"), maps=maps))
    keep = set(recipe.RECIPE_NODES) | {socket.node.name for socket in controls.values()}
    keep |= {writer.MAP_NODE + name for name in maps} | {writer.TIMES_NODE + name for name in maps}
    opacity_nodes.set_opacity(material, source.opacity)
    if lights.inputs["Normal"].is_linked:
        tree.links.remove(lights.inputs["Normal"].links[0])
    native.prune_unused(tree, keep)
    texture = source.textures.get("Exponent")
    image = _image(texture, images, warnings, where, non_color=True) \
        if texture is not None else None
    if image is not None:
        native.exponent_map(material, image)
    _opacity_maps(material, source, images, warnings, where)
    _missing_references(material, source, path)
    material[SOURCE_KEY] = path
    if source.unsupported:
        warnings.append(f"{where}: not representable, left out: " + ", ".join(source.unsupported))


def _data(source, texture) -> bool:
    """Whether the colour map *texture* is read as data (Non-Color): Phong Nodes' export
    marks a map whose image was data (X3D's texels) ``NonColor<property>``."""
    return texture is not None and \
        bool(source.user.get(fbx.NON_COLOR_USER + texture.prop, 0.0))


def _missing_references(material, source, path) -> None:
    """The maps whose file is not there (and not embedded) kept on *material*
    (``keys.FBX_MISSING_MAPS``): a file received without its textures keeps its references
    through import → export, as Blender's exporter writes a path whether or not it exists."""
    folder = os.path.dirname(path)
    kept = {}
    for slot, texture in source.textures.items():
        prop = keys.FBX_SLOT_PROPS.get(slot)
        if prop is None or texture.content is not None or texture.resolved is not None:
            continue
        name = texture.name.replace("\\", "/")
        absolute = next((c for c in texture.candidates if os.path.isabs(c)), "") or \
            os.path.join(folder, name)
        near = os.path.normpath(name if os.path.isabs(name) else os.path.join(folder, name))
        kept[prop] = {"path": absolute, "near": near}
    if kept:
        material[keys.FBX_MISSING_MAPS] = kept


def _opacity_maps(material, source, images, warnings, where) -> None:
    """A map on TransparentColor or TransparencyFactor: the opacity 1 − TF·t_f ×
    mean(TC ⊗ t_c), t_c the TransparentColor map's colour (a colour, as the colour maps are
    read), t_f the mean RGB of the TransparencyFactor map (a scalar: read as data), as an
    opacity map (``native.opacity_map``).  A factor of 0 makes the maps change nothing."""
    maps = {key: source.textures.get(key) for key in fbx.OPACITY_MAPS}
    if source.alpha_map:   # Blender's exporter's alpha texture, read as Blender's importer does
        _alpha_map(material, maps, images, warnings, where,
                   source.user.get("OpacityAlphaScale", 1.0))
        return
    if not any(maps.values()) or source.transparency_factor == 0.0:
        return
    tree = material.node_tree
    color = maps["TransparentColor"]
    color = _image(color, images, warnings, where, _data(source, color)) \
        if color is not None else None
    factor = maps["TransparencyFactor"]
    factor = _image(factor, images, warnings, where, non_color=True) \
        if factor is not None else None
    if color is None and factor is None:
        return
    tc = source.transparent_color
    native.straight(color)
    native.straight(factor)
    if color is not None:
        node = native.image_node(tree, "transparent color", color, (-1450.0, 800.0))
        scaled = native._node(tree, native.MAP_NODE + "transparent color x TC",
                              "ShaderNodeVectorMath", (-1150.0, 800.0))
        scaled.operation = "MULTIPLY"
        tree.links.new(compat.output_socket(node, "Color"), compat.input_socket(scaled, "Vector"))
        compat.input_socket(scaled, "Vector_001").default_value = tuple(tc)
        mean_tc = native.mean_rgb(tree, "transparent mean", compat.output_socket(scaled, "Vector"),
                                  (-900.0, 800.0))
    else:
        mean_tc = sum(tc) / 3.0
    tf = source.transparency_factor
    if factor is not None:
        node = native.image_node(tree, "transparency factor", factor, (-1450.0, 500.0))
        tf = native.math(tree, native.MAP_NODE + "transparency factor x TF", "MULTIPLY",
                         native.mean_rgb(tree, "factor mean", compat.output_socket(node, "Color"),
                                         (-1150.0, 500.0)), tf, (-900.0, 500.0))
    transparency = native.math(tree, native.MAP_NODE + "transparency", "MULTIPLY", tf, mean_tc,
                               (-650.0, 650.0))
    native.opacity_map(material, native.math(tree, native.MAP_NODE + "1 - transparency",
                                              "SUBTRACT", 1.0, transparency, (-500.0, 650.0)))


def _alpha_map(material, maps, images, warnings, where, scale=1.0) -> None:
    """The opacity of a file of Blender's exporter: the alpha channel of its map on
    TransparencyFactor (else on TransparentColor), as Blender's importer reads it (the
    image's Alpha output feeds the Principled BSDF's Alpha), times *scale* (Phong Nodes'
    export's ``OpacityAlphaScale``: X3D's alpha × Opacity), as the opacity map."""
    texture = maps["TransparencyFactor"] or maps["TransparentColor"]
    # (the alpha is the same in either colour space: an image the colour maps read as data
    # is used again rather than loaded a second time)
    data = images.get((texture.name, texture.content is not None, True))
    image = data if data is not None else _image(texture, images, warnings, where)
    if image is None:
        return
    tree = material.node_tree
    node = native.image_node(tree, "alpha", image, (-1450.0, 650.0))
    alpha = compat.output_socket(node, "Alpha")
    if scale != 1.0:   # Phong Nodes' export: alpha × k (X3D's alpha × Opacity)
        alpha = native.math(tree, native.MAP_NODE + "alpha x k", "MULTIPLY", alpha, scale,
                            (-1150.0, 650.0))
    native.opacity_map(material, alpha)


# -- lights -------------------------------------------------------------------------------------

def _power_supported() -> bool:
    return "power_k" in getattr(properties, "LIGHT_KEYS", {})


def apply_light(light, source: fbx.Light, warnings: list, path) -> None:
    """Blender light data *light* given the FBX light's values."""
    given = fbx.light_settings(source)   # the FBX values as Phong settings (core/fbx/phong)
    if light.type != given["type"]:
        light.type = given["type"]
    light.color = given["color"]
    # FBX CastShadows: Blender's importer before 5.3 reads "CastShadow" (always its default)
    light.use_shadow = given["cast_shadows"]
    if "spot_size" in given:
        light.spot_size = given["spot_size"]
        light.spot_blend = given["spot_blend"]
    settings = {k: v for k, v in given["settings"].items()
                if k in ("falloff", "intensity") or k in properties.LIGHT_KEYS}
    if not _power_supported():  # before the power falloff existed: stored, 1/d² rendered
        for key in ("falloff", "power_k"):
            if key in settings:
                light[{"falloff": "phong_falloff", "power_k": "phong_power_k"}[key]] = \
                    settings.pop(key)
        if source.decay not in (0, 1, 2):
            warnings.append(f"{path}: light {source.name or source.nodes[0]}: decay 1/d^"
                            f"{source.decay:g} stored but this version renders 1/d²")
    properties.write_light(light, settings)
    light[SOURCE_KEY] = path


# -- the import -------------------------------------------------------------------------------

class FbxImportError(native.InterchangeError, fbx.FbxError):
    """The import failed (the file cannot be read, or building its scene failed): names the
    file; nothing was added to the scene.  A ``core.fbx.FbxError`` too."""

    def __init__(self, path: str, message: str):
        fbx.FbxError.__init__(self, path, message)


def import_file(context, filepath) -> native.ImportResult:
    """Import the FBX file *filepath* into *context*'s scene (``formats.import_file``): the
    new objects, the Phong materials made, the warnings.  Raises :class:`FbxImportError`
    (and leaves the scene as it was) when it cannot.

    A binary file of FBX 7100 and later is read by Blender's own importer while ufbx reads
    its values in the child process (``fbx.start``); other files are built from ufbx."""
    path = os.path.abspath(bpy.path.abspath(filepath))
    blender = _binary_7100(path) and ensure_fbx_addon()
    try:
        reading = fbx.start(path, geometry=not blender)   # FbxError: file not found
    except FbxError as error:
        raise _error(error) from None
    before = native.snapshot()
    objects_before = set(context.scene.objects)
    later, unread = [], False
    try:
        used_blender = False
        if blender:
            try:
                result = bpy.ops.import_scene.fbx(filepath=path)
                used_blender = result == {"FINISHED"}
            except RuntimeError as error:
                lines = [ln.strip() for ln in str(error).splitlines() if ln.strip()]
                said = [ln for ln in lines if "Error" in ln.split(":")[0]] or lines
                last = said[-1][:200] if said else "no message"
                later.append(f"{path}: Blender's FBX importer failed ({last}); "
                             "the scene is built from ufbx")
            if not used_blender:
                native.remove_added(before)
        try:
            data = reading.result()
        except FbxError as error:
            if not used_blender:
                if blender:
                    raise FbxError(path, "neither ufbx nor Blender's FBX importer could read "
                                         f"it ({error})") from None
                raise
            # never refuse what Blender's importer opens: its scene, its materials converted
            # as Apply Phong Material converts them (the file's own values could not be read)
            unread = True
            data = fbx.Scene(path, 7100, False, "", (0.0, 0.0, 0.0), [], [], [
                f"{error}; imported by Blender's FBX importer, its materials converted as "
                "Apply Phong Material does (not the file's own Phong values)"])
        warnings = list(data.warnings) + later
        slots = None
        if not used_blender:
            if not data.nodes:
                data = fbx.read(path, geometry=True)
            slots = _build(context, data, path, warnings)
        new = [o for o in context.scene.objects if o not in objects_before]
        sync = _finish(context, data, new, warnings, path, before, slots,
                       convert_all=unread)
        made = [m for m in native.added(before, "materials") if recipe.is_phong_material(m)]
    except FbxError as error:
        native.remove_added(before)
        raise _error(error) from None
    except Exception as error:  # noqa: BLE001 - any failure: nothing stays, one clear error
        native.remove_added(before)
        raise FbxImportError(path, f"import failed ({type(error).__name__}: {error})") from None
    finally:
        reading.close()
    return native.ImportResult(new, made, warnings, sync)


def _error(error) -> FbxImportError:
    """*error* (a ``core.fbx.FbxError``) as the import's error, its message kept."""
    if isinstance(error, FbxImportError):
        return error
    return FbxImportError(error.path, str(error).removeprefix(f"{error.path}: "))


def _sources(made, data: fbx.Scene) -> dict:
    """{material Blender's importer made: the file's material of that name, or None}: the
    name itself, else without the ``.001`` Blender added where the scene held the name."""
    by_name = {}
    for material in data.materials:
        by_name.setdefault(material.name, material)
    out = {}
    for material in made:
        source = by_name.get(material.name) or by_name.get(_base_name(material.name))
        if source is None:
            same = [m for n, m in by_name.items()
                    if _base_name(n) == _base_name(material.name)]
            source = same[0] if len(same) == 1 else None
        out[material] = source
    return out


def _finish(context, data: fbx.Scene, new, warnings, path, before, slots=None,
            convert_all=False):
    """Lights, Phong materials (of the file's values, under the file's names), the World's
    ambient.  *slots*: the material slots of the scene built from ufbx (``_build``), filled
    with Phong materials made here; without it the materials of Blender's importer are
    replaced (``native.take_place``).  Whatever the import made that nothing uses is removed."""
    others = sorted({m.name for m in data.materials if m.kind == "OTHER"})
    if others:
        made_as = ("as Apply Phong Material makes them from Blender's import (its base colour "
                   "and base colour texture)" if slots is None else
                   "with the default values (Object Color 0.8)")
        warnings.append(f"{path}: materials of other shading models (not Phong or Lambert) "
                        f"are Phong materials made {made_as}: " + ", ".join(others))
    lights_by_node = {}
    for light in data.lights:
        for node in light.nodes:
            lights_by_node.setdefault(node, light)
    for obj in new:
        if obj.type == "LIGHT":
            source = lights_by_node.get(obj.name) or lights_by_node.get(_base_name(obj.name))
            if source is not None:
                apply_light(obj.data, source, warnings, path)
    with sync_mod.session(context.scene, context.view_layer) as sync:
        _materials(sync, data, new, warnings, path, before, slots, convert_all)
    if convert_all:
        return sync
    world = context.scene.world
    if world is None:
        world = context.scene.world = bpy.data.worlds.new("World")
    # AmbientColor, or the World's own intensity and colour that Phong Nodes' export kept
    properties.write_world(world, *fbx.world_ambient(data.ambient, data.user))
    return sync


def _materials(sync, data, new, warnings, path, before, slots, convert_all) -> None:
    """The Phong materials of the import (``_finish``), whatever it made that nothing uses
    removed."""
    meshes = [o for o in new if o.type == "MESH"]
    group = sync.group(*sync.light_set(meshes[0])) if meshes else None
    images = {"": native.added(before, "images")}  # "": the images Blender's importer made
    if slots is not None:  # the scene built from ufbx: Phong materials from birth
        by_name, made = {}, {}
        for material in data.materials:
            by_name.setdefault(material.name, material)
        for target, index, name in slots:
            material = made.get(name)
            if material is None:
                material = made[name] = writer.new_material(name or "Material", group)
                source = by_name.get(name)
                if source is not None and source.kind != "OTHER":
                    apply_material(material, source, warnings, images, path)
            if isinstance(target, bpy.types.Mesh):
                target.materials[index] = material
            else:
                target.material_slots[index].material = material
    elif group is not None:  # Blender's importer's materials, each replaced
        fresh = sorted(native.added(before, "materials"), key=lambda m: m.name)
        sources = _sources(fresh, data)
        for made in fresh:
            if made.users == 0:
                continue   # a material no object uses: removed below
            source = sources[made]
            if convert_all or source is None or source.kind == "OTHER":
                phong = source_materials.from_source(made, made.name, group)
                native.forget_source(phong, made)
            else:
                phong = writer.new_material(made.name, group)
                apply_material(phong, source, warnings, images, path)
            native.take_place(made, phong)
    native.remove_unused(before)
