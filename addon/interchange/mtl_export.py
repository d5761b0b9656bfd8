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
from .. import compat
from ..lighting import materials as recipe
from .obj_import import ILLUM_KEY

HEADER = "Phong materials written by Phong Nodes (docs/model.md: MTL illum 2 with Ka = Kd)"


def mtl_name(material) -> str:
    """The name of *material* in an MTL file: the name of the material it was made from (its
    source, so that import ▸ export keeps the file's names), spaces replaced by underscores as
    Blender's OBJ exporter writes them in usemtl."""
    source = recipe.source_of(material)
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


def _input(material, name):
    node = material.node_tree.nodes.get(recipe.LIGHTS_NODE)
    return node.inputs[name] if node is not None else None


def _plain(value):
    return tuple(value) if hasattr(value, "__len__") else float(value)


def _source(material, input_name, control):
    """(value, node feeding the input when it is not the control) of a recipe input."""
    node = material.node_tree.nodes.get(control)
    value = _plain(compat.value_output(node).default_value) if node is not None else None
    socket = _input(material, input_name)
    if socket is None:
        return value, None
    if not socket.is_linked:
        return _plain(socket.default_value), None
    upstream = socket.links[0].from_node
    return value, (None if upstream.name == control else upstream)


def _rgb(value):
    return tuple(float(v) for v in value[:3])


def _image_path(image, mtl_folder) -> str:
    path = bpy.path.abspath(image.filepath, library=image.library)
    try:
        return os.path.relpath(path, mtl_folder)
    except ValueError:  # another drive (Windows)
        return path


def _map_or_value(material, input_name, control, mtl_folder, warnings):
    """(colour, image path or None, map options) of a colour input: its control's value, or
    an image texture's file (colour 1: MTL multiplies a map by its colour) with the
    ``-o`` / ``-s`` of its placement (:func:`_placement`)."""
    color, feeder = _source(material, input_name, control)
    if feeder is None:
        return color, None, {}
    if feeder.bl_idname == "ShaderNodeTexImage" and feeder.image and not feeder.image.packed_file:
        return ((1.0, 1.0, 1.0), _image_path(feeder.image, mtl_folder),
                _placement(material, feeder, warnings))
    multiplied = _colour_times_map(feeder)
    if multiplied is not None and not multiplied[1].image.packed_file:
        return (multiplied[0], _image_path(multiplied[1].image, mtl_folder),
                _placement(material, multiplied[1], warnings))
    if feeder.bl_idname == "ShaderNodeRGB":
        return tuple(compat.value_output(feeder).default_value), None, {}
    what = (f"packed image {feeder.image.name!r} (unpack it to write a map)"
            if getattr(feeder, "image", None) is not None else f"node {feeder.name!r}")
    warnings.append(f"{material.name}: {input_name} comes from {what}; the control's value "
                    "is written")
    return color, None, {}


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


def _colour_times_map(node):
    """(colour, Image Texture node) when *node* is the OBJ importer's colour x map (a Vector
    Math Multiply of an RGB node and an Image Texture), else None."""
    if node.bl_idname != "ShaderNodeVectorMath" or node.operation != "MULTIPLY":
        return None
    a, b = compat.input_socket(node, "Vector"), compat.input_socket(node, "Vector_001")
    if not (a.is_linked and b.is_linked):
        return None
    rgb, texture = a.links[0].from_node, b.links[0].from_node
    if rgb.bl_idname != "ShaderNodeRGB" or texture.bl_idname != "ShaderNodeTexImage" \
            or texture.image is None:
        return None
    return tuple(compat.value_output(rgb).default_value), texture


def to_mtl(material, mtl_folder, name=None):
    """(mtl.Material, warnings) for the Phong material *material* (named *name* in the MTL,
    :func:`mtl_name` by default)."""
    out = mtl.Material(name or mtl_name(material), "", 0)
    warnings = []
    read_as = material.get(ILLUM_KEY)      # the model an imported material was read as
    only = _colour_only(material, mtl_folder) if read_as in (None, 0) else None
    if only is not None:      # MTL illum 0: Kd is the colour, lights play no part
        out.colors["Kd"], image, options = only
        if image is not None:
            out.maps["map_Kd"] = mtl.TextureMap(image, "", options, 0)
        out.illum = 0
        _opacity(material, out)
        return out, warnings
    color, image, options = _map_or_value(material, "Object Color", "phong_object_color",
                                          mtl_folder, warnings)
    out.colors["Kd"] = _rgb(color)
    if image is not None:
        out.maps["map_Kd"] = mtl.TextureMap(image, "", options, 0)
    ambient = _input(material, recipe.AMBIENT_INPUT)
    object_color = _input(material, "Object Color")
    if ambient is not None and not ambient.is_linked:
        out.colors["Ka"] = _rgb(ambient.default_value)
    elif ambient is None or (object_color.is_linked and
                             ambient.links[0].from_socket == object_color.links[0].from_socket):
        out.colors["Ka"] = out.colors["Kd"]          # the seeds' model: Ka = Kd
        if image is not None:
            out.maps["map_Ka"] = mtl.TextureMap(image, "", dict(options), 0)
    else:
        ka, ka_image, ka_options = _map_or_value(material, recipe.AMBIENT_INPUT,
                                                 "phong_object_color", mtl_folder, warnings)
        out.colors["Ka"] = _rgb(ka)
        if ka_image is not None:
            out.maps["map_Ka"] = mtl.TextureMap(ka_image, "", ka_options, 0)
    specular, feeder_s = _source(material, "Specular Color", "phong_specular_color")
    exponent, feeder_e = _source(material, "Exponent", "phong_exponent")
    blinn, feeder_b = _source(material, "Blinn", "phong_blinn")
    irradiant, feeder_i = _source(material, "Irradiant Color", "phong_irradiant_color")
    for name, feeder in (("Specular Color", feeder_s), ("Exponent", feeder_e),
                         ("Blinn", feeder_b), ("Irradiant Color", feeder_i)):
        if feeder is not None:
            warnings.append(f"{material.name}: {name} comes from node {feeder.name!r}; "
                            "the control's value is written")
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


def _colour_only(material, mtl_folder):
    """(colour, image path or None) of the Irradiant Color when it is the material's only
    colour (Object, Ambient Object and Specular Color black and fed by their controls or
    by nothing): MTL's illum 0, which the importer reads into Irradiant Color alone; else
    None."""
    for input_name, control in (("Object Color", "phong_object_color"),
                                (recipe.AMBIENT_INPUT, recipe.AMBIENT_CONTROL),
                                ("Specular Color", "phong_specular_color")):
        socket = _input(material, input_name)
        if socket is None:
            return None
        if socket.is_linked:
            upstream = socket.links[0].from_node
            if upstream.bl_idname != "ShaderNodeRGB":
                return None
            value = compat.value_output(upstream).default_value
        else:
            value = socket.default_value
        if any(float(v) != 0.0 for v in tuple(value)[:3]):
            return None
    notes = []
    color, image, options = _map_or_value(material, "Irradiant Color", "phong_irradiant_color",
                                          mtl_folder, notes)
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


def export_obj(phong_by_name, filepath, selection_only=False) -> list:
    """Blender's own OBJ export of the scene (geometry, ``usemtl`` names, its MTL), whose MTL
    then gets the exact entry of every Phong material (*phong_by_name*: material name ->
    material), named as :func:`mtl_names` (the OBJ's ``usemtl`` lines renamed to match);
    the other materials keep Blender's entries.  Returns the warnings."""
    result = bpy.ops.wm.obj_export(filepath=filepath, export_materials=True,
                                   export_selected_objects=selection_only)
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
