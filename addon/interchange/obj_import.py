# SPDX-License-Identifier: GPL-3.0-or-later
"""Wavefront OBJ imported with its MTL materials as exact Phong materials.

Blender's own OBJ importer reads the geometry (and makes Principled approximations of the
materials); the MTL libraries are read first by ``core/mtl.py``, so a missing library refuses the
import before anything is added.  Every material of the importer is then replaced by a Phong
material with the MTL's values, term by term:

    illum 0   colour only: Irradiant Color = Kd (Object Color, Ambient, Specular black)
    illum 1   Ka ambient + Kd Lambert: Specular Color black
    illum 2   + Ks (h·n)^Ns highlight: Blinn = 1 (MTL's highlight is Blinn's)
    Ke        Irradiant Color (illum 1 and 2)
    d / Tr    Opacity (d, else 1 - Tr; ``opacity.set_opacity``): the pixel is
              d × Phong colour + (1 - d) × what is behind

A colour missing from the MTL is black (MTL's formula has no other default); a missing Ns
keeps the recipe's 30.  ``map_Ka``, ``map_Kd``, ``map_Ks`` and ``map_Ke`` multiply their colour
(MTL: "the map value is multiplied by the K value"), ``bump``/``map_Bump`` goes through a Bump
node (strength ``-bm``) into Normal; a map's ``-o`` / ``-s`` place it on the UV coordinates
through a Mapping node (uv × s + o), as Blender's own importer does.  What the model cannot show (``Material.unsupported``:
refraction, other illumination models, other maps, map options not applied) is reported once
per material; a missing texture file is named in one warning, with every material it is left
out of.  Only an unreadable library refuses the import (``core/mtl.py`` reads the rest as other
readers do, with a warning for what it leaves out or changes).

Each material of the import is a Phong material from birth, under the MTL's name (``.001``
where the scene already holds it, as Blender's importer names it), and the import adds nothing
else (``native.py``): no Principled copy, no material or image that nothing uses.
"""

from __future__ import annotations

import os

import bpy

from ...core import mtl
from ..lighting import opacity, recipe, writer
from ..lighting import sync as sync_mod
from . import keys, native

#: lights-group input -> (MTL colour, MTL map)
COLOR_INPUTS = {
    "Object Color": ("Kd", "map_Kd"),
    recipe.AMBIENT_INPUT: ("Ka", "map_Ka"),
    "Specular Color": ("Ks", "map_Ks"),
    "Irradiant Color": ("Ke", "map_Ke"),
}
MAP_NODE = writer.MAP_NODE         # + input name: the Image Texture of a map
MULTIPLY_NODE = writer.TIMES_NODE  # + input name: colour x map
BUMP_NODE = "phong_mtl_bump"
MAPPING_NODE = "phong_mtl_place:"  # + input name: the map's -o / -s (a Mapping node)
UV_NODE = "phong_mtl_uv"           # the UV coordinates the Mapping nodes read
BLACK = (0.0, 0.0, 0.0)
#: Custom property of an imported Phong material: the MTL illumination model it was read as
#: (0, 1 or 2), so that export writes it back (``mtl_export.to_mtl``).
ILLUM_KEY = keys.MTL_ILLUM


def _mtl_name(material, by_name):
    """The MTL material a Blender material was imported from (the importer may add .001)."""
    if material.name in by_name:
        return by_name[material.name]
    base, dot, suffix = material.name.rpartition(".")
    return by_name.get(base) if dot and suffix.isdigit() else None


def values(source: mtl.Material) -> dict:
    """{lights-group input: colour}, {lights-group input: TextureMap or None} and the
    scalars of *source*, term by term."""
    colors = {name: tuple(source.colors.get(key, BLACK)) for name, (key, _m) in
              COLOR_INPUTS.items()}
    maps = {name: source.maps.get(map_key) for name, (_k, map_key) in COLOR_INPUTS.items()}
    illum = 2 if source.illum is None else source.illum
    if illum == 0:  # colour only: Kd and its map, as light the object gives itself
        colors = {name: BLACK for name in colors}
        maps = {name: None for name in maps}
        colors["Irradiant Color"] = tuple(source.colors.get("Kd", BLACK))
        maps["Irradiant Color"] = source.maps.get("map_Kd")
    elif illum == 1:
        colors["Specular Color"] = BLACK
    return {"colors": colors, "maps": maps, "exponent": source.scalars.get("Ns"),
            "blinn": 1.0, "illum": illum}


def _image(texture, missing, where, non_color=False):
    """The image of *texture* (``native.load_image``: a bump map as data, the colour maps
    as colours; an image of the file already there in that colour space is used), or None
    when its file is missing or unreadable (recorded in *missing*: one warning per file,
    naming every material that uses it)."""
    image = native.load_image(texture.resolved, non_color=non_color) if texture.exists else None
    if image is None:
        missing.setdefault(texture.resolved, (texture, []))[1].append(where)
    return image


def missing_warnings(missing) -> list:
    """One warning per missing texture file: where it is first named, the places looked at
    and the materials it is left out of."""
    out = []
    for texture, users in missing.values():
        looked = " and ".join(texture.looked_at or (texture.resolved,))
        names = sorted({name for _where, name in users})
        problem = (f"not readable by Blender ({texture.resolved})" if texture.exists else
                   f"not found (looked for {looked})")
        out.append(f"{users[0][0]}: texture {texture.path} {problem}; "
                   f"left out of {', '.join(names)}")
    return out


def apply_mtl(material, source: mtl.Material, warnings: list, missing: dict) -> None:
    """Give the Phong material *material* the values and maps of *source* (missing texture
    files are recorded in *missing*, see :func:`missing_warnings`)."""
    tree = material.node_tree
    lights = tree.nodes[recipe.LIGHTS_NODE]
    wanted = values(source)
    where = f"{source.path}:{source.line} ({source.name})"
    user = (where, source.name)
    images = {name: _image(texture, missing, user) for name, texture in wanted["maps"].items()
              if texture is not None}
    images = {name: image for name, image in images.items() if image is not None}
    controls = writer.write(material, writer.Values(
        wanted["colors"], exponent=30.0 if wanted["exponent"] is None else wanted["exponent"],
        blinn=wanted["blinn"], maps=images))
    keep = set(recipe.RECIPE_NODES) | {socket.node.name for socket in controls.values()}
    for name in images:
        keep |= {MAP_NODE + name, MULTIPLY_NODE + name}
        keep |= _placed(tree, name, wanted["maps"][name].placement())
    material[ILLUM_KEY] = min(wanted["illum"], 2)
    bump = source.maps.get("bump")
    image = _image(bump, missing, user, non_color=True) if bump is not None else None
    if image is not None:
        keep |= _bump(tree, lights, image, bump.options.get("-bm", (1.0,))[0])
        keep |= _placed(tree, "bump", bump.placement())
    elif lights.inputs["Normal"].is_linked:
        tree.links.remove(lights.inputs["Normal"].links[0])
    opacity.set_opacity(material, 1.0 - source.transparency())  # d, else 1 - Tr
    native.prune_unused(tree, keep)
    problems = [p for p in source.unsupported() if not p.endswith("(transparency)")]
    if source.illum is not None and source.illum > 2:
        problems = [p for p in problems if not p.startswith("illum")] + [
            f"illum {source.illum} (imported as illum 2)"]
    if problems:
        warnings.append(f"{where}: not representable, left out: " + ", ".join(problems))


def _placed(tree, name, placement) -> set:
    """The map *name*'s ``-o`` / ``-s`` (*placement*: (offset, scale), or None) as a Mapping
    node (Point: Location, Scale) on the UV coordinates in front of its Image Texture, as
    Blender's own OBJ importer places a map; returns the names of the nodes to keep."""
    texture = tree.nodes[MAP_NODE + name]
    if placement is None:
        for link in list(texture.inputs["Vector"].links):
            tree.links.remove(link)
        return set()
    offset, scale = placement
    uv = tree.nodes.get(UV_NODE) or tree.nodes.new("ShaderNodeTexCoord")
    uv.name = UV_NODE
    uv.location = (-1750.0, 200.0)
    mapping = tree.nodes.get(MAPPING_NODE + name) or tree.nodes.new("ShaderNodeMapping")
    mapping.name = MAPPING_NODE + name
    mapping.label = f"{name} map: -o / -s"
    mapping.vector_type = "POINT"
    mapping.location = (texture.location.x - 300.0, texture.location.y)
    mapping.inputs["Location"].default_value = offset
    mapping.inputs["Rotation"].default_value = (0.0, 0.0, 0.0)
    mapping.inputs["Scale"].default_value = scale
    tree.links.new(uv.outputs["UV"], mapping.inputs["Vector"])
    tree.links.new(mapping.outputs["Vector"], texture.inputs["Vector"])
    return {UV_NODE, MAPPING_NODE + name}


def _bump(tree, lights, image, strength) -> set:
    texture = tree.nodes.get(MAP_NODE + "bump") or tree.nodes.new("ShaderNodeTexImage")
    texture.name = MAP_NODE + "bump"
    texture.image = image
    texture.location = (-1150.0, -1100.0)
    bump = tree.nodes.get(BUMP_NODE) or tree.nodes.new("ShaderNodeBump")
    bump.name = BUMP_NODE
    bump.location = (-600.0, -1100.0)
    bump.inputs["Strength"].default_value = min(max(float(strength), 0.0), 1.0)
    tree.links.new(texture.outputs["Color"], bump.inputs["Height"])
    tree.links.new(bump.outputs["Normal"], lights.inputs["Normal"])
    return {MAP_NODE + "bump", BUMP_NODE}


class ObjImportError(native.InterchangeError):
    """The import failed (a missing or unreadable OBJ file or MTL library, Blender's importer
    failed); nothing was added to the file."""


def import_file(context, filepath) -> native.ImportResult:
    """Import *filepath* (``formats.import_file``): its new mesh objects, Phong materials
    and warnings (one names a file without a mesh).  Raises :class:`ObjImportError` (nothing
    imported) for a missing or unreadable OBJ file or library, or when Blender's importer
    fails.

    Blender's importer makes the geometry and a Principled material per ``usemtl`` name (with
    ``.001`` where the file already holds the name); each of those is replaced by a Phong
    material of the MTL's values under the same name (``native.take_place``), and what the
    importer made that nothing uses any more (its images) is removed: the file's materials
    are added, nothing else."""
    try:
        if not os.path.isfile(filepath):
            raise mtl.MtlError(filepath, 0, "file not found")
        by_name, warnings = mtl.load_for_obj(filepath)
    except mtl.MtlError as error:
        raise ObjImportError(f"{error}; nothing imported") from None
    before = native.snapshot()
    try:
        result = bpy.ops.wm.obj_import(filepath=filepath)
        if result != {"FINISHED"}:
            raise ObjImportError(f"Blender's OBJ importer returned {sorted(result)}")
        return _replace_materials(context, filepath, before, by_name, warnings)
    except ObjImportError:
        native.remove_added(before)
        raise
    except Exception as error:  # noqa: BLE001 - any failure: nothing stays, one clear error
        native.remove_added(before)
        raise ObjImportError(f"{filepath}: import failed ({type(error).__name__}: {error}); "
                             "nothing imported") from None


def _replace_materials(context, filepath, before, by_name, warnings) -> native.ImportResult:
    new = [o for o in native.added(before, "objects") if o.type == "MESH"]
    done, missing = {}, {}
    with sync_mod.session(context.scene, context.view_layer) as sync:
        group = sync.group(*sync.light_set(new[0])) if new else None
        for made in sorted(native.added(before, "materials"), key=lambda m: m.name):
            source = _mtl_name(made, by_name)
            if made.users == 0 or group is None:
                continue   # a material no object uses: removed below
            phong = writer.new_material(made.name, group)
            if source is not None:
                apply_mtl(phong, source, warnings, missing)
            else:  # a usemtl name that no library defines: Blender's default, as Phong
                warnings.append(f"{filepath}: material {made.name!r} is defined in no MTL "
                                "library; a default Phong material used")
            native.take_place(made, phong)
            done[phong.name] = phong
        for obj in new:  # an object without a material gets a default one, as Apply gives
            if not obj.material_slots or any(s.material is None for s in obj.material_slots):
                sync.apply(obj)
        native.remove_unused(before)
        warnings += missing_warnings(missing)
    if not new:
        warnings.append(f"no mesh in {filepath}")
    return native.ImportResult(new, list(done.values()), warnings, sync)
