# SPDX-License-Identifier: GPL-3.0-or-later
"""COLLADA written: :func:`dumps`, the Phong materials as ``profile_COMMON`` techniques with
exact names in our ``<extra>`` (:data:`~.model.PROFILE`).
"""

from __future__ import annotations

import os
import re
import xml.etree.ElementTree as ET

import numpy as np

from .model import NS14, PROFILE, TECHNIQUE_COLORS, Document, Mesh, Node


# -- writing -------------------------------------------------------------------------------

def fmt(value) -> str:
    """The shortest decimal that reads back as the same float32 (Blender's precision)."""
    value = np.float32(value)
    if value == 0.0:
        return "0"
    if 1e-4 <= abs(value) < 1e9:
        return np.format_float_positional(value, unique=True, trim="-")
    return np.format_float_scientific(value, unique=True, trim="-")


def _join(values) -> str:
    return " ".join(fmt(v) for v in values)


def _sub(parent, tag, text=None, **attrib):
    element = ET.SubElement(parent, tag, {k.rstrip("_"): str(v) for k, v in attrib.items()})
    if text is not None:
        element.text = text
    return element


def ncname(text: str) -> str:
    """*text* as an XML NCName (what COLLADA 1.4.1's ``name`` attributes must be): other
    characters become "_", and a name that cannot start so gets a "_" in front.  Where this
    changes the name, :func:`_exact_name` writes the name itself in an ``<extra>``."""
    out = re.sub(r"[^A-Za-z0-9_.\-]", "_", text)
    return out if re.match(r"[A-Za-z_]", out) else "_" + out


def _exact_name(element, name: str) -> None:
    """``<extra><technique profile="phong_nodes"><name>`` *name* when the ``name``
    attribute could not hold it (the last child, as the schema wants)."""
    if ncname(name) != name:
        technique = _sub(_sub(element, "extra"), "technique", profile=PROFILE)
        _sub(technique, "name", name)


def _symbols(mesh) -> dict:
    """{material symbol: its NCName}, distinct within the mesh."""
    out, used = {}, set()
    for symbol in mesh.symbols:
        name = ncname(symbol) if symbol else ""
        base, n = name, 1
        while name in used:
            n += 1
            name = f"{base}_{n}"
        used.add(name)
        out[symbol] = name
    return out


def _xml_id(text: str, used: set) -> str:
    base = re.sub(r"[^A-Za-z0-9_.-]", "_", text) or "id"
    if not re.match(r"[A-Za-z_]", base):
        base = "_" + base
    ident, n = base, 1
    while ident in used:
        n += 1
        ident = f"{base}_{n}"
    used.add(ident)
    return ident


def dumps(doc: Document) -> str:
    """COLLADA 1.4.1 text of *doc* (valid against the 1.4.1 schema): units and axes as
    given (the exporter writes metres, Z up), materials as profile_COMMON, lights,
    cameras, meshes as ``<polylist>`` and the visual scene's node tree."""
    ET.register_namespace("", NS14)
    root = ET.Element("COLLADA", {"xmlns": NS14, "version": "1.4.1"})
    asset = _sub(root, "asset")
    contributor = _sub(asset, "contributor")
    _sub(contributor, "authoring_tool", "Phong Nodes")
    _sub(asset, "created", "1970-01-01T00:00:00")
    _sub(asset, "modified", "1970-01-01T00:00:00")
    _sub(asset, "unit", name="meter", meter=fmt(doc.meter))
    _sub(asset, "up_axis", doc.up_axis)
    used: set = set()
    ids = {}
    for kind, table in (("camera", doc.cameras), ("light", doc.lights),
                        ("material", doc.materials), ("geometry", doc.meshes)):
        for key in table:
            ids[(kind, key)] = _xml_id(key, used)
    image_ids = {}
    if doc.cameras:
        lib = _sub(root, "library_cameras")
        for key, cam in doc.cameras.items():
            element = _sub(lib, "camera", id=ids[("camera", key)], name=ncname(cam.name))
            common = _sub(_sub(element, "optics"), "technique_common")
            kind = _sub(common, cam.kind)
            x, y = ("xfov", "yfov") if cam.kind == "perspective" else ("xmag", "ymag")
            # the schema: x [y | aspect_ratio] | y [aspect_ratio], then znear, zfar
            wanted = [x] if getattr(cam, x) is not None else []
            if getattr(cam, y) is not None and (not wanted or cam.aspect_ratio is None):
                wanted.append(y)
            if cam.aspect_ratio is not None and len(wanted) < 2:
                wanted.append("aspect_ratio")
            for attr in wanted + ["znear", "zfar"]:
                _sub(kind, attr, fmt(getattr(cam, attr)))
            _exact_name(element, cam.name)
    if doc.lights:
        lib = _sub(root, "library_lights")
        for key, light in doc.lights.items():
            element = _sub(lib, "light", id=ids[("light", key)], name=ncname(light.name))
            kind = _sub(_sub(element, "technique_common"), light.kind)
            _sub(kind, "color", _join(light.color[:3]))
            if light.kind in ("point", "spot"):
                _sub(kind, "constant_attenuation", fmt(light.constant))
                _sub(kind, "linear_attenuation", fmt(light.linear))
                _sub(kind, "quadratic_attenuation", fmt(light.quadratic))
            if light.kind == "spot":
                _sub(kind, "falloff_angle", fmt(light.falloff_angle))
                _sub(kind, "falloff_exponent", fmt(light.falloff_exponent))
            _exact_name(element, light.name)
    textures = [(key, element, tex) for key, mat in doc.materials.items()
                for element, tex in mat.textures.items()]
    if textures:
        lib = _sub(root, "library_images")
        for _key, _element, tex in textures:
            if tex.path in image_ids:
                continue
            image_ids[tex.path] = _xml_id(tex.image_id or os.path.basename(tex.path), used)
            image = _sub(lib, "image", id=image_ids[tex.path],
                         name=ncname(tex.image_id or os.path.basename(tex.path)))
            _sub(image, "init_from", tex.path.replace("\\", "/"))
    if doc.materials:
        effects = _sub(root, "library_effects")
        for key, mat in doc.materials.items():
            effect_id = _xml_id(ids[("material", key)] + "-effect", used)
            mat.effect_id = effect_id
            effect = _sub(effects, "effect", id=effect_id)
            profile = _sub(effect, "profile_COMMON")
            for element, tex in mat.textures.items():
                surface = _sub(profile, "newparam", sid=f"{element}-surface")
                s = _sub(surface, "surface", type="2D")
                _sub(s, "init_from", image_ids[tex.path])
                sampler = _sub(profile, "newparam", sid=f"{element}-sampler")
                _sub(_sub(sampler, "sampler2D"), "source", f"{element}-surface")
            shading = _sub(_sub(profile, "technique", sid="common"), mat.technique)
            for element in ("emission", "ambient", "diffuse", "specular"):
                if element not in TECHNIQUE_COLORS[mat.technique]:
                    continue
                if element == "specular" and mat.technique in ("constant", "lambert"):
                    continue
                holder = _sub(shading, element)
                if element in mat.textures:
                    tex = mat.textures[element]
                    _sub(holder, "texture", texture=f"{element}-sampler",
                         texcoord=tex.texcoord or "UVMap")
                else:
                    _sub(holder, "color", _join(mat.color(element)) + " 1", sid=element)
                if element == "specular":
                    shininess = _sub(shading, "shininess")
                    _sub(shininess, "float", fmt(mat.shininess or 0.0), sid="shininess")
            if mat.transparent is not None or "transparent" in mat.textures:
                holder = _sub(shading, "transparent", opaque=mat.opaque)
                if "transparent" in mat.textures:   # an opacity map
                    _sub(holder, "texture", texture="transparent-sampler",
                         texcoord=mat.textures["transparent"].texcoord or "UVMap")
                else:
                    _sub(holder, "color", _join(mat.transparent[:4]))
                _sub(_sub(shading, "transparency"), "float",
                     fmt(1.0 if mat.transparency is None else mat.transparency))
        lib = _sub(root, "library_materials")
        for key, mat in doc.materials.items():
            element = _sub(lib, "material", id=ids[("material", key)], name=ncname(mat.name))
            _sub(element, "instance_effect", url="#" + mat.effect_id)
            _exact_name(element, mat.name)
    if doc.meshes:
        lib = _sub(root, "library_geometries")
        for key, mesh in doc.meshes.items():
            _write_mesh(lib, ids[("geometry", key)], mesh)
    scene_id = _xml_id(doc.scene_name or "Scene", used)
    visual = _sub(_sub(root, "library_visual_scenes"), "visual_scene", id=scene_id,
                  name=ncname(doc.scene_name or "Scene"))
    for node in doc.nodes:
        _write_node(visual, node, doc, ids, used)
    _exact_name(visual, doc.scene_name or "Scene")
    _sub(_sub(root, "scene"), "instance_visual_scene", url="#" + scene_id)
    ET.indent(root, space=" ")
    return '<?xml version="1.0" encoding="utf-8"?>\n' + ET.tostring(root, encoding="unicode") + "\n"


def _write_source(parent, ident, values, params):
    source = _sub(parent, "source", id=ident)
    flat = np.asarray(values, dtype=np.float64).reshape(-1)
    _sub(source, "float_array", " ".join(fmt(v) for v in flat), id=ident + "-array",
         count=len(flat))
    accessor = _sub(_sub(source, "technique_common"), "accessor", source="#" + ident + "-array",
                    count=len(flat) // len(params), stride=len(params))
    for name in params:
        _sub(accessor, "param", name=name, type="float")


def _write_mesh(lib, ident, mesh: Mesh):
    geometry = _sub(lib, "geometry", id=ident, name=ncname(mesh.name))
    element = _sub(geometry, "mesh")
    _write_source(element, ident + "-positions", mesh.positions, "XYZ")
    inputs = []
    if mesh.normals is not None:
        _write_source(element, ident + "-normals", mesh.normals, "XYZ")
        inputs.append(("NORMAL", ident + "-normals", None))
    for channel, uv in sorted(mesh.uvs.items()):
        _write_source(element, f"{ident}-uv{channel}", uv, "ST")
        inputs.append(("TEXCOORD", f"{ident}-uv{channel}", channel))
    for channel, colors in sorted(mesh.colors.items()):
        _write_source(element, f"{ident}-color{channel}", colors, "RGBA")
        inputs.append(("COLOR", f"{ident}-color{channel}", channel))
    vertices = _sub(element, "vertices", id=ident + "-vertices")
    _sub(vertices, "input", semantic="POSITION", source=f"#{ident}-positions")
    starts = np.concatenate([[0], np.cumsum(mesh.face_sizes)]).astype(np.int64)
    symbols = np.asarray(mesh.face_symbols, dtype=np.int64)
    names = _symbols(mesh)
    for index, symbol in enumerate(mesh.symbols):
        faces = np.nonzero(symbols == index)[0]
        if not len(faces):
            continue
        attrib = {"count": len(faces)}
        if symbol:
            attrib["material"] = names[symbol]
        poly = _sub(element, "polylist", **attrib)
        _sub(poly, "input", semantic="VERTEX", source=f"#{ident}-vertices", offset=0)
        for offset, (semantic, source, channel) in enumerate(inputs, start=1):
            extra = {} if channel is None else {"set": channel}
            _sub(poly, "input", semantic=semantic, source="#" + source, offset=offset, **extra)
        corners = np.concatenate([np.arange(starts[f], starts[f + 1]) for f in faces])
        _sub(poly, "vcount", " ".join(str(int(n)) for n in mesh.face_sizes[faces]))
        columns = [mesh.corners[corners]] + [corners] * len(inputs)
        table = np.stack(columns, axis=1).reshape(-1)
        _sub(poly, "p", " ".join(str(int(v)) for v in table))
    if mesh.edges is not None and len(mesh.edges):   # loose edges
        attrib = {"count": len(mesh.edges)}
        if mesh.edge_symbol:
            attrib["material"] = names.get(mesh.edge_symbol, ncname(mesh.edge_symbol))
        lines = _sub(element, "lines", **attrib)
        _sub(lines, "input", semantic="VERTEX", source=f"#{ident}-vertices", offset=0)
        _sub(lines, "p", " ".join(str(int(v)) for v in np.asarray(mesh.edges).reshape(-1)))
    _exact_name(geometry, mesh.name)


def _write_node(parent, node: Node, doc, ids, used):
    element = _sub(parent, "node", id=_xml_id(node.id or node.name, used),
                   name=ncname(node.name), type="NODE")
    _sub(element, "matrix", _join(np.asarray(node.matrix, dtype=np.float64).reshape(-1)),
         sid="transform")
    order = ("camera", "controller", "geometry", "light", "node")   # the schema's order
    for inst in sorted(node.instances, key=lambda i: order.index(i.kind)):
        kind = inst.kind
        target = ids.get((kind, inst.url), inst.url)
        child = _sub(element, f"instance_{kind}", url="#" + target)
        if kind == "geometry" and inst.bindings:
            mesh = doc.meshes.get(inst.url)
            names = _symbols(mesh) if mesh is not None else {}
            common = _sub(_sub(child, "bind_material"), "technique_common")
            for symbol, material in inst.bindings.items():
                im = _sub(common, "instance_material", symbol=names.get(symbol, ncname(symbol)),
                          target="#" + ids.get(("material", material), material))
                for semantic, channel in inst.uv_bindings.get(symbol, {}).items():
                    _sub(im, "bind_vertex_input", semantic=semantic, input_semantic="TEXCOORD",
                         input_set=channel)
    for child in node.children:
        _write_node(element, child, doc, ids, used)
    _exact_name(element, node.name)
