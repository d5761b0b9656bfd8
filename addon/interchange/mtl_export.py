# SPDX-License-Identifier: GPL-3.0-or-later
"""Phong materials written as Wavefront MTL (File ▸ Export ▸ Phong Materials (.mtl)).

The seeds' model is MTL's illumination model 2 with Ka = Kd: its ambient term is
i_a·Cl_a ⊗ Object Color (docs/model.md §Ambient), so a Phong material is written as

    Kd = Object Color        Ka = Ambient Object Color (= Kd unless the material links its own)
    Ks = Specular Color      Ns = Exponent     Ke = Irradiant Color
    d = Opacity (written only below 1)
    illum 2 (1 when Specular Color is black, unless the material was imported from illum 2)
    illum 0 with Kd = Irradiant Color when that is the only colour (as an MTL illum 0
            material is imported), unless the material was imported from illum 1 or 2

MTL's highlight is Blinn's (h·n)^Ns: a material whose Blinn control is below 1 (the seeds'
(r·v)^e, or a mix) gets a comment in the file and the export one warning naming it.  An
image texture feeding Object Color (or Ambient Object Color) is written as ``map_Kd`` (or
``map_Ka``) with colour 1, since MTL multiplies a map by its colour, its path relative to the
MTL file; other node chains cannot be written and are named in a warning.  A material is
written with the name of the material it was made from (so import ▸ export keeps the names
of the file), spaces replaced by underscores, as Blender's OBJ exporter writes them in
``usemtl``; numbers as the shortest decimal that reads back as the same float32.
"""

from __future__ import annotations

import os

import bpy

from ...core import mtl, outputs
from ..lighting import feeds as feed_reader
from ..lighting import recipe, sources
from .keys import MTL_ILLUM

HEADER = "Phong materials written by Phong Nodes (docs/model.md: MTL illum 2 with Ka = Kd)"


def mtl_name(material) -> str:
    """The name of *material* in an MTL file: the name of the material it was made from (its
    source, so that import ▸ export keeps the file's names), spaces replaced by underscores as
    Blender's OBJ exporter writes them in usemtl."""
    source = sources.source_of(material)
    return (source.name if source is not None else material.name).replace(" ", "_")


def mtl_names(phong_materials, taken=()) -> dict:
    """{material: its name in the MTL}: :func:`mtl_name`, or the Phong material's own name
    (spaces → ``_``) where that is *taken* by another material or an earlier Phong one (two
    light sets of one source)."""
    used, out = set(taken), {}
    for material in phong_materials:
        name = mtl_name(material)
        if name in used:
            name = material.name.replace(" ", "_")
        used.add(name)
        out[material] = name
    return out


def _rgb(value):
    return tuple(float(v) for v in value[:3])


def _image_path(image, mtl_folder) -> str:
    path = bpy.path.abspath(image.filepath, library=image.library)
    try:
        return os.path.relpath(path, mtl_folder)
    except ValueError:  # another drive (Windows)
        return path


def _map_or_value(material, input_name, feed, mtl_folder, warnings):
    """(colour, image path or None, map options) of the colour input *input_name* fed by
    *feed* (``feeds.feeds``): its value, or an image texture's file (alone: colour 1,
    since MTL multiplies a map by its colour; the importers' colour × map: that colour) with
    the ``-o`` / ``-s`` of its placement (:func:`_placement`)."""
    if feed.other is None:
        return feed.value, None, {}
    texture = feed.texture
    if texture is not None and not texture.image.packed_file:
        color = (1.0, 1.0, 1.0) if feed.other == texture else feed.value
        return (color, _image_path(texture.image, mtl_folder),
                _placement(material, texture, warnings))
    image = getattr(feed.other, "image", None)
    what = (f"packed image {image.name!r} (unpack it to write a map)"
            if image is not None else f"node {feed.other.name!r}")
    warnings.append(f"{material.name}: {input_name} comes from {what}; the control's value "
                    "is written")
    return feed.value, None, {}


def _placement(material, texture, warnings) -> dict:
    """The map options ``-o`` / ``-s`` of the Image Texture *texture*: a Point Mapping node
    without rotation in front of it (what the importer and Blender's own OBJ importer make);
    {} when its Vector input is free.  Other placements are named in a warning."""
    socket = texture.inputs["Vector"]
    if not socket.is_linked:
        return {}
    mapping = socket.links[0].from_node
    if mapping.bl_idname != "ShaderNodeMapping" or mapping.vector_type != "POINT" or \
            any(float(v) for v in mapping.inputs["Rotation"].default_value) or \
            any(mapping.inputs[k].is_linked for k in ("Location", "Rotation", "Scale")):
        warnings.append(f"{material.name}: the map {texture.image.name!r} is placed by node "
                        f"{mapping.name!r}, which MTL cannot write (only a Point Mapping's "
                        "Location and Scale: -o, -s); the map is written unplaced")
        return {}
    options = {}
    offset = tuple(float(v) for v in mapping.inputs["Location"].default_value)
    scale = tuple(float(v) for v in mapping.inputs["Scale"].default_value)
    if offset != (0.0, 0.0, 0.0):
        options["-o"] = offset
    if scale != (1.0, 1.0, 1.0):
        options["-s"] = scale
    return options


def to_mtl(material, mtl_folder, name=None):
    """(mtl.Material, warnings) for the Phong material *material* (named *name* in the MTL,
    :func:`mtl_name` by default)."""
    out = mtl.Material(name or mtl_name(material), "", 0)
    warnings = []
    read_as = material.get(MTL_ILLUM)      # the model an imported material was read as
    feeds = feed_reader.feeds(material)
    only = _colour_only(material, feeds, mtl_folder) if read_as in (None, 0) else None
    if only is not None:      # MTL illum 0: Kd is the colour, lights play no part
        out.colors["Kd"], image, options = only
        if image is not None:
            out.maps["map_Kd"] = mtl.TextureMap(image, "", options, 0)
        out.illum = 0
        _opacity(material, out)
        return out, warnings
    color, image, options = _map_or_value(material, "Object Color", feeds["Object Color"],
                                          mtl_folder, warnings)
    out.colors["Kd"] = _rgb(color)
    if image is not None:
        out.maps["map_Kd"] = mtl.TextureMap(image, "", options, 0)
    ambient = feeds.get(recipe.AMBIENT_INPUT)
    if ambient is None or (ambient.other is not None and
                           ambient.socket == feeds["Object Color"].socket):
        out.colors["Ka"] = out.colors["Kd"]          # the seeds' model: Ka = Kd
        if image is not None:
            out.maps["map_Ka"] = mtl.TextureMap(image, "", dict(options), 0)
    else:
        ka, ka_image, ka_options = _map_or_value(material, recipe.AMBIENT_INPUT, ambient,
                                                 mtl_folder, warnings)
        out.colors["Ka"] = _rgb(ka)
        if ka_image is not None:
            out.maps["map_Ka"] = mtl.TextureMap(ka_image, "", ka_options, 0)
    for name in ("Specular Color", "Exponent", "Blinn", "Irradiant Color"):
        feeder = feeds[name].other
        if feeder is not None:
            warnings.append(f"{material.name}: {name} comes from node {feeder.name!r}; "
                            "the control's value is written")
    specular, exponent = feeds["Specular Color"].value, feeds["Exponent"].value
    blinn, irradiant = feeds["Blinn"].value, feeds["Irradiant Color"].value
    out.colors["Ks"] = _rgb(specular)
    out.colors["Ke"] = _rgb(irradiant)
    out.scalars["Ns"] = float(exponent)
    out.illum = 2 if any(out.colors["Ks"]) or read_as == 2 else 1
    if out.illum == 2 and float(blinn) < 1.0:
        kind = "the Phong highlight (r·v)^Ns" if float(blinn) == 0.0 else \
            f"a mix of Phong and Blinn highlights (Blinn {float(blinn):g})"
        out.comments.append(f"this material uses {kind}; MTL illum 2 is Blinn's (h·n)^Ns")
        warnings.append(f"{material.name}: {kind}, written as MTL illum 2, which is Blinn's")
    _opacity(material, out)
    return out, warnings


def _opacity(material, out) -> None:
    """MTL ``d`` for a material whose Opacity is below 1 (opaque ones write none)."""
    value = recipe.opacity(material)
    if value < 1.0:
        out.scalars["d"] = value


def _colour_only(material, feeds, mtl_folder):
    """(colour, image path or None) of the Irradiant Color when it is the material's only
    colour (Object, Ambient Object and Specular Color black and fed by a value: a control
    or nothing): MTL's illum 0, which the importer reads into Irradiant Color alone; else
    None."""
    for input_name in ("Object Color", recipe.AMBIENT_INPUT, "Specular Color"):
        feed = feeds.get(input_name)
        if feed is None or feed.other is not None:
            return None
        value = feed.value if isinstance(feed.value, tuple) else (feed.value,)
        if any(v != 0.0 for v in value):
            return None
    notes = []
    color, image, options = _map_or_value(material, "Irradiant Color",
                                          feeds["Irradiant Color"], mtl_folder, notes)
    if notes or (image is None and not any(float(v) for v in tuple(color)[:3])):
        return None
    return _rgb(color), image, options


def export(phong_materials, filepath) -> list:
    """Write *phong_materials* to *filepath* (atomically); returns the warnings."""
    folder = os.path.dirname(os.path.abspath(filepath))
    written, warnings = [], []
    names = mtl_names(phong_materials)
    for material in phong_materials:
        entry, notes = to_mtl(material, folder, names[material])
        written.append(entry)
        warnings += notes
    outputs.write_file(filepath, mtl.dumps(written, header=HEADER))
    return warnings


def export_library(context, filepath, use_selection=False) -> list:
    """Every Phong material of the file (*use_selection*: those of the selected objects) as
    the MTL library *filepath*; returns the warnings.  ValueError when there is none."""
    if use_selection:
        found = {slot.material for obj in (context.selected_objects or [])
                 for slot in obj.material_slots if recipe.is_phong_material(slot.material)}
        chosen = [m for m in recipe.phong_materials() if m in found]
        where = "the selected objects have"
    else:
        chosen = recipe.phong_materials()
        where = "the file has"
    if not chosen:
        raise ValueError(f"{where} no Phong material; run Apply Phong Material first")
    return export(chosen, filepath)


def export_obj(context, filepath, use_selection=False) -> list:
    """Blender's own OBJ export of *context*'s scene (geometry, ``usemtl`` names, its MTL),
    whose MTL then gets the exact entry of every Phong material, named as :func:`mtl_names`
    (the OBJ's ``usemtl`` lines renamed to match); the other materials keep Blender's
    entries.  Returns the warnings."""
    phong_by_name = {m.name: m for m in recipe.phong_materials()}
    result = bpy.ops.wm.obj_export(filepath=filepath, export_materials=True,
                                   export_selected_objects=use_selection)
    if result != {"FINISHED"}:
        raise RuntimeError(f"Blender's OBJ exporter returned {sorted(result)}")
    mtl_path = os.path.splitext(filepath)[0] + ".mtl"
    if not os.path.isfile(mtl_path):   # no material at all: nothing to replace
        return []
    folder = os.path.dirname(os.path.abspath(mtl_path))
    by_written_name = {m.name.replace(" ", "_"): m for m in phong_by_name.values()}
    entries = mtl.load(mtl_path)
    phong = [by_written_name[e.name] for e in entries if e.name in by_written_name]
    names = mtl_names(phong, taken={e.name for e in entries if e.name not in by_written_name})
    out, warnings, renamed = [], [], {}
    for entry in entries:
        material = by_written_name.get(entry.name)
        if material is None:
            out.append(entry)
            continue
        exact, notes = to_mtl(material, folder, names[material])
        out.append(exact)
        warnings += notes
        if exact.name != entry.name:
            renamed[entry.name] = exact.name
    if renamed:
        _rename_usemtl(filepath, renamed)
    outputs.write_file(mtl_path, mtl.dumps(
        out, header=HEADER + "; other materials as Blender wrote them"))
    return warnings


def _rename_usemtl(obj_path, renamed) -> None:
    """Rewrite the ``usemtl`` lines of Blender's OBJ file with the names of *renamed*."""
    with open(obj_path, "rb") as fh:
        lines = fh.read().split(b"\n")
    for index, line in enumerate(lines):
        if line.startswith(b"usemtl "):
            name = line[7:].decode("utf-8").rstrip("\r")
            if name in renamed:
                lines[index] = b"usemtl " + renamed[name].encode("utf-8")
    outputs.write_file(obj_path, b"\n".join(lines))
