# SPDX-License-Identifier: GPL-3.0-or-later
"""The scene written as COLLADA 1.4.1 (``core/collada.dumps``): metres, Z up.

Objects are nodes (their parent-relative matrices), meshes ``<polylist>`` with corner
normals, UV maps and colour attributes, Phong materials ``profile_COMMON`` with their
controls (the inverse of ``collada_import``: Irradiant Color → emission, Ambient Object
Color → ambient, Object Color → diffuse, Specular Color → specular, Exponent → shininess,
Blinn → blinn; an image texture feeding an input → its ``<texture>``), lights with their
Phong attenuation and cone (``falloff_angle`` the full cone), the World's Phong ambient as
an ambient light, cameras.  Other materials are written as lambert with their base colour
(one warning).  The file is written to a temporary name and renamed: never half-written.
"""

from __future__ import annotations

import math
import os

import bpy
import numpy as np

from ...core import collada
from .. import compat
from ..lighting import feeds as feed_reader
from ..lighting import properties, recipe, sources
from . import keys


def _feed(feed, name, material, warnings):
    """(colour, image texture node or None) of the lights-group input *name* fed by *feed*
    (``feeds.feeds``): its value, or an image texture alone (colour white)."""
    if feed.other is None:
        value = feed.value
        return (value if isinstance(value, tuple) else (float(value),) * 3), None
    if feed.other == feed.texture:
        return (1.0, 1.0, 1.0), feed.texture
    warnings.append(f"material {material.name}: {name} is fed by a {feed.other.bl_idname} "
                    "node, which COLLADA cannot say; written black")
    return (0.0, 0.0, 0.0), None


def material_of(material, warnings) -> collada.Material:
    out = collada.Material(material.name, material.name)
    if not recipe.is_phong_material(material):
        color = sources.base_color(material) or (0.8, 0.8, 0.8)
        out.technique = "lambert"
        out.colors["diffuse"] = (*color[:3], 1.0)
        warnings.append(f"material {material.name} is not a Phong material: written as "
                        "lambert with its base colour")
        return out
    tree = material.node_tree
    feeds = feed_reader.feeds(material)
    blinn = float(feeds["Blinn"].value)
    technique = material.get(keys.COLLADA_TECHNIQUE)
    if technique not in collada.TECHNIQUES:
        technique = "blinn" if blinn >= 0.5 else "phong"
    elif technique in ("phong", "blinn"):
        technique = "blinn" if blinn >= 0.5 else "phong"
    if 0.0 < blinn < 1.0:
        warnings.append(f"material {material.name}: Blinn {blinn:g} between Phong and Blinn "
                        f"written as {technique}")
    out.technique = technique
    for socket_name, element in keys.COLLADA_INPUTS.items():
        color, texture = _feed(feeds[socket_name], socket_name, material, warnings)
        out.colors[element] = (*color, 1.0)
        if texture is not None:
            path = bpy.path.abspath(texture.image.filepath) or texture.image.name
            uv = texture.inputs["Vector"].links[0].from_node \
                if texture.inputs["Vector"].is_linked else None
            texcoord = uv.uv_map if uv is not None and uv.bl_idname == "ShaderNodeUVMap" \
                else "UVMap"
            out.textures[element] = collada.Texture(path, path, texcoord, texture.image.name)
    out.shininess = float(feeds["Exponent"].value)
    opacity = feeds["Opacity"].value
    mode = material.get(keys.COLLADA_OPAQUE)
    mapped = _transparent_texture(tree, feeds["Opacity"])
    if mode in collada.OPAQUE_MODES and mapped is not None:   # the file's opacity map
        out.opaque, out.textures["transparent"] = mode, mapped
        if keys.COLLADA_TRANSPARENCY in material.keys():
            out.transparency = float(material[keys.COLLADA_TRANSPARENCY])
        return out
    if mode in collada.OPAQUE_MODES and keys.COLLADA_TRANSPARENT in material.keys():
        # the file's own transparency, unless Opacity was changed since the import (an
        # invisible material imported opaque keeps its file's values)
        out.opaque = mode
        out.transparent = tuple(float(c) for c in material[keys.COLLADA_TRANSPARENT])
        if keys.COLLADA_TRANSPARENCY in material.keys():
            out.transparency = float(material[keys.COLLADA_TRANSPARENCY])
        read = min(max(out.opacity(), 0.0), 1.0)
        if abs(read - opacity) <= 1e-6 or (read <= 0.0 and opacity == 1.0):
            return out
        out.transparent, out.transparency = None, None
    if opacity < 1.0:
        out.opaque, out.transparent, out.transparency = "A_ONE", (1.0, 1.0, 1.0, 1.0), opacity
    return out


def _transparent_texture(tree, feed):
    """The collada.Texture of an imported ``<transparent><texture>`` that still feeds the
    material's opacity map (*feed*: its Opacity in ``feeds.feeds``;
    ``collada_import.transparent_map``), or None."""
    node = tree.nodes.get(keys.COLLADA_TEXTURE_NODE + "transparent")
    mix = tree.nodes.get(recipe.OPACITY_MIX)
    if node is None or node.image is None or feed.other is None or \
            mix is None or not compat.input_socket(mix, "Fac").is_linked or \
            compat.input_socket(mix, "Fac").links[0].from_node.name != recipe.OPACITY_MAP:
        return None
    path = bpy.path.abspath(node.image.filepath) or node.image.name
    uv = node.inputs["Vector"].links[0].from_node if node.inputs["Vector"].is_linked else None
    texcoord = uv.uv_map if uv is not None and uv.bl_idname == "ShaderNodeUVMap" else "UVMap"
    return collada.Texture(path, path, texcoord, node.image.name)


def export(context, filepath, use_selection=False) -> list:
    """Write *context*'s scene to *filepath*; returns the warnings."""
    warnings: list = []
    doc = document(context, use_selection, warnings)
    folder = os.path.dirname(os.path.abspath(filepath))
    for material in doc.materials.values():
        for texture in material.textures.values():   # relative to the file, as a URI
            try:
                path = os.path.relpath(texture.resolved, folder)
            except ValueError:   # another drive
                path = texture.resolved
            texture.path = collada.uri_quote(path)
    text = collada.dumps(doc)
    temp = filepath + ".part"
    try:
        with open(temp, "w", encoding="utf-8") as handle:
            handle.write(text)
        os.replace(temp, filepath)
    finally:
        if os.path.exists(temp):
            os.remove(temp)
    return warnings


def document(context, use_selection, warnings) -> collada.Document:
    scene = context.scene
    doc = collada.Document(filepath_or(scene), meter=1.0, up_axis="Z_UP")
    doc.scene_name = scene.name
    chosen = [o for o in scene.objects
              if o.type in ("MESH", "LIGHT", "CAMERA", "EMPTY")
              and (not use_selection or o.select_get())]
    keep = set(chosen)
    roots = [o for o in chosen if o.parent not in keep]
    for obj in sorted(roots, key=lambda o: o.name):
        doc.nodes.append(_node(obj, keep, doc, warnings, root=True))
    world = scene.world
    if world is not None and properties.AMBIENT_COLOR[0] in world.keys():
        intensity = float(world.get(properties.AMBIENT_INTENSITY[0],
                                    properties.AMBIENT_INTENSITY[1]))
        color = tuple(intensity * float(c) for c in world[properties.AMBIENT_COLOR[0]])
        if any(color):
            name = "Ambient"
            doc.lights[name] = collada.Light(name, name, "ambient", color)
            doc.nodes.append(collada.Node(name, name, np.eye(4),
                                          instances=[collada.Instance("light", name)]))
    return doc


def filepath_or(scene) -> str:
    return bpy.data.filepath or scene.name


def _node(obj, keep, doc, warnings, root):
    matrix = np.array(obj.matrix_world if root else obj.matrix_local, dtype=np.float64)
    node = collada.Node(obj.name, obj.name, matrix)
    if obj.type == "MESH":
        key = obj.data.name
        if key not in doc.meshes:
            doc.meshes[key] = _mesh(obj.data)
        if obj.modifiers:
            warnings.append(f"object {obj.name}: modifiers not applied")
        inst = collada.Instance("geometry", key)
        symbols = doc.meshes[key].symbols
        for index, slot in enumerate(obj.material_slots):
            material = slot.material   # the object's own when the slot links to the object
            if material is None or index >= len(symbols) or not symbols[index]:
                continue
            if material.name not in doc.materials:
                doc.materials[material.name] = material_of(material, warnings)
            inst.bindings[symbols[index]] = material.name
            uv = {t.texcoord: _uv_set(obj.data, t.texcoord)
                  for t in doc.materials[material.name].textures.values()}
            inst.uv_bindings[symbols[index]] = uv
        node.instances.append(inst)
    elif obj.type == "LIGHT":
        light = obj.data
        if light.type in ("SUN", "POINT", "SPOT", "AREA") and light.name not in doc.lights:
            doc.lights[light.name] = _light(light, warnings)
        if light.type in ("SUN", "POINT", "SPOT", "AREA"):
            node.instances.append(collada.Instance("light", light.name))
        else:
            warnings.append(f"light {light.name}: {light.type} lights have no COLLADA kind; "
                            "left out")
    elif obj.type == "CAMERA":
        if obj.data.name not in doc.cameras:
            doc.cameras[obj.data.name] = _camera(obj.data)
        node.instances.append(collada.Instance("camera", obj.data.name))
    for child in sorted(obj.children, key=lambda o: o.name):
        if child in keep:
            node.children.append(_node(child, keep, doc, warnings, root=False))
    return node


def _uv_set(mesh, name):
    names = [layer.name for layer in mesh.uv_layers]
    return names.index(name) if name in names else 0


def _mesh(mesh) -> collada.Mesh:
    n = len(mesh.vertices)
    positions = np.zeros(n * 3, dtype=np.float32)
    mesh.vertices.foreach_get("co", positions)
    faces = len(mesh.polygons)
    sizes = np.zeros(faces, dtype=np.int32)
    mesh.polygons.foreach_get("loop_total", sizes)
    material_index = np.zeros(faces, dtype=np.int32)
    mesh.polygons.foreach_get("material_index", material_index)
    loops = len(mesh.loops)
    corners = np.zeros(loops, dtype=np.int32)
    mesh.loops.foreach_get("vertex_index", corners)
    normals = np.zeros(loops * 3, dtype=np.float32)
    if hasattr(mesh, "corner_normals"):
        mesh.corner_normals.foreach_get("vector", normals)
    else:
        mesh.calc_normals_split()
        mesh.loops.foreach_get("normal", normals)
    # the symbols: the mesh's own materials' names (each slot binds its object's material)
    symbols = [m.name if m is not None else f"slot{i}" for i, m in enumerate(mesh.materials)] \
        or [""]
    out = collada.Mesh(mesh.name, mesh.name, positions.reshape(-1, 3).astype(np.float64),
                       sizes.astype(np.int64), [min(int(i), len(symbols) - 1)
                                                for i in material_index],
                       symbols, corners.astype(np.int64), normals.reshape(-1, 3))
    edges = np.zeros(len(mesh.edges) * 2, dtype=np.int32)
    mesh.edges.foreach_get("vertices", edges)
    loop_edges = np.zeros(loops, dtype=np.int32)
    mesh.loops.foreach_get("edge_index", loop_edges)
    loose = np.ones(len(mesh.edges), dtype=bool)
    loose[loop_edges] = False
    if loose.any():   # loose edges as <lines>; a mesh of lines only: its first slot's material
        out.edges = edges.reshape(-1, 2)[loose].astype(np.int64)
        out.edge_symbol = symbols[0] if not faces and mesh.materials else ""
    for index, layer in enumerate(mesh.uv_layers):
        uv = np.zeros(loops * 2, dtype=np.float32)
        layer.data.foreach_get("uv", uv)
        out.uvs[index] = uv.reshape(-1, 2)
    for index, attribute in enumerate(a for a in mesh.color_attributes if a.domain == "CORNER"):
        color = np.zeros(loops * 4, dtype=np.float32)
        attribute.data.foreach_get("color", color)
        out.colors[index] = color.reshape(-1, 4)
    return out


def _light(light, warnings) -> collada.Light:
    # an Area light is the spot that draws it in Phong: a 180° cone, cos^1 (a Lambertian
    # emitter's far field), which COLLADA's spot (falloff_angle, falloff_exponent) says exactly
    kind = {"SUN": "directional", "POINT": "point", "SPOT": "spot", "AREA": "spot"}[light.type]

    settings = properties.settings_of(light)  # i0 its own or its Power's

    def value(attr):  # the light's Phong setting, its default where it has none
        return float(settings[attr])

    intensity = value("intensity")
    out = collada.Light(light.name, light.name, kind,
                        tuple(intensity * float(c) for c in properties.light_color(light)))
    factors = (value("diffuse"), value("specular"))
    if factors != (1.0, 1.0):
        warnings.append(f"light {light.name}: Diffuse {factors[0]:g} / Specular {factors[1]:g} "
                        "factors have no COLLADA counterpart; written as 1")
    if kind in ("point", "spot"):
        out.constant, out.linear, out.quadratic = (value("constant"), value("linear"),
                                                    value("quadratic"))
        if properties.falloff_of(light) == "POWER":
            k = value("power_k")
            # 1/d^k for k = 0, 1, 2 is 1/(c + l·d + q·d²) with one term 1
            terms = {0.0: (1.0, 0.0, 0.0), 1.0: (0.0, 1.0, 0.0), 2.0: (0.0, 0.0, 1.0)}
            if k not in terms:
                warnings.append(f"light {light.name}: power falloff 1/d^{k:g} has no COLLADA "
                                "counterpart; written as 1/d²")
            out.constant, out.linear, out.quadratic = terms.get(k, (0.0, 0.0, 1.0))
    if kind == "spot":
        spot_size = properties.light_values(light)["spot_size"]
        out.falloff_angle = math.degrees(spot_size)
        out.falloff_exponent = value("edge_exponent")
    return out


def _camera(camera) -> collada.Camera:
    out = collada.Camera(camera.name, camera.name,
                         "orthographic" if camera.type == "ORTHO" else "perspective")
    vertical = camera.sensor_fit == "VERTICAL"
    if camera.type == "ORTHO":
        half = camera.ortho_scale / 2.0
        out.ymag, out.xmag = (half, None) if vertical else (None, half)
    else:
        angle = math.degrees(camera.angle)
        out.yfov, out.xfov = (angle, None) if vertical else (None, angle)
    out.znear, out.zfar = camera.clip_start, camera.clip_end
    return out
