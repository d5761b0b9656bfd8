# SPDX-License-Identifier: GPL-3.0-or-later
"""Imports that feel native (issue 35): every importer adds exactly the file's materials under
the file's names, each a Phong material from birth, and nothing else; importing twice gives
Blender's ``.001``; the user's own data blocks are never touched.  Every texture slot a file
maps reaches the model (FBX TransparentColor / TransparencyFactor / ShininessExponent maps,
COLLADA ``<transparent><texture>``), checked on rendered pixels against the file's formula
worked out here from the texels written by the test; COLLADA lines are loose edges; an
instancing bomb ends in seconds with one warning; an FBX file can be dropped on the viewport.

What is expected is read from the files here, independently of the importers: the ``usemtl``
names of an OBJ, the materials an FBX file connects to its models (Blender's own
``io_scene_fbx.parse_fbx`` for binary files, a text reading of ASCII ones), the materials a
COLLADA file binds (ElementTree)."""

from __future__ import annotations

import math
import os
import re
import struct
import time
import xml.etree.ElementTree as ET
import zlib

import numpy as np
import pytest

import blender_env as be
from phong_scene import render

DATA = os.path.join(os.path.dirname(os.path.abspath(__file__)), "data")
KINDS = ("materials", "meshes", "images", "node_groups")


def _state(bpy):
    return {kind: set(getattr(bpy.data, kind)) for kind in KINDS}


def _added(bpy, before):
    return {kind: set(getattr(bpy.data, kind)) - before[kind] for kind in KINDS}


# -- what each file defines, read here ---------------------------------------------------------

def _obj_materials(path):
    """The materials an OBJ file's faces use: its ``usemtl`` names."""
    return {line.split(None, 1)[1].strip() for line in open(path, encoding="utf-8")
            if line.split(None, 1)[:1] == ["usemtl"]}


def _fbx_used_materials(path):
    """The names of the materials an FBX file connects to a model (``C: "OO",material,model``),
    from Blender's own parser (binary) or the text (ASCII)."""
    with open(path, "rb") as handle:
        binary = handle.read(20).startswith(b"Kaydara FBX Binary")
    materials, models, links = {}, set(), []
    if binary:
        be.import_bpy()
        from io_scene_fbx import parse_fbx  # noqa: PLC0415

        root, _version = parse_fbx.parse(path)
        for section in root.elems:
            if section.id == b"Objects":
                for obj in section.elems:
                    if not obj.props:
                        continue
                    if isinstance(obj.props[0], int):   # FBX 7: id, "name\x00\x01Class"
                        ident, name = obj.props[0], obj.props[1].split(b"\x00\x01")[0]
                    else:                               # FBX 6.1: "name\x00\x01Class"
                        ident, name = obj.props[0], obj.props[0].split(b"\x00\x01")[0]
                    if obj.id == b"Material":
                        materials[ident] = name.decode()
                    elif obj.id == b"Model":
                        models.add(ident)
            if section.id == b"Connections":
                links += [(c.props[1], c.props[2]) for c in section.elems
                          if c.props[0] == b"OO"]
    else:
        text = open(path, encoding="utf-8", errors="replace").read()
        for ident, name in re.findall(r'^\s*Material: (\d+), "Material::([^"]*)"', text, re.M):
            materials[int(ident)] = name
        models = {int(i) for i in re.findall(r'^\s*Model: (\d+), "Model::', text, re.M)}
        links = [(int(a), int(b)) for a, b in re.findall(r'C: "OO",(\d+),(\d+)', text)]
    return {materials[a] for a, b in links if a in materials and b in models}


def _dae_bound_materials(path):
    """The names (else ids) of the materials a COLLADA file binds to its geometry."""
    root = ET.parse(path).getroot()
    for element in root.iter():
        element.tag = element.tag.rsplit("}", 1)[-1]
    by_id = {m.get("id"): m.get("name") or m.get("id") for m in root.iter("material")}
    return {by_id[im.get("target").lstrip("#")] for im in root.iter("instance_material")}


# -- every importer: the file's materials, Phong, nothing else ---------------------------------

FILES = [
    ("obj", "obj/illum.obj"),                                      # Blender's OBJ importer
    ("obj", "obj/blender_tile.obj"),
    ("fbx", "fbx/maya_cube_7500_binary.fbx"),                      # Blender's FBX importer
    ("fbx", "fbx/maya_material_chart_7700_binary.fbx"),
    ("fbx", "fbx/blender_293_embedded_textures_7400_binary.fbx"),
    ("fbx", "fbx/maya_phong_properties_7700_ascii.fbx"),           # ufbx: ASCII
    ("fbx", "fbx/maya_cube_6100_binary.fbx"),                      # ufbx: FBX 6.1
    ("dae", "collada/hand_lit.dae"),
    ("dae", "collada/cts_instances_of_same_node.dae"),
]


def _expected(kind, path):
    return {"obj": _obj_materials, "fbx": _fbx_used_materials,
            "dae": _dae_bound_materials}[kind](path)


def _import(bpy, kind, path):
    op = {"obj": bpy.ops.phong.import_obj, "fbx": bpy.ops.phong.import_fbx,
          "dae": bpy.ops.phong.import_collada}[kind]
    assert op(filepath=path) == {"FINISHED"}


def _blender_name(name, taken):
    """The name Blender gives a new data block named *name* where *taken* are held: the name,
    else its base with the first free .001, .002 ... (a name ending in .001 counts on)."""
    if name not in taken:
        return name
    base, dot, number = name.rpartition(".")
    if not (dot and number.isdigit() and len(number) == 3):
        base = name
    return next(f"{base}.{k:03d}" for k in range(1, 1000) if f"{base}.{k:03d}" not in taken)


def _is_phong_group(group):
    """A group of the library (stamped) or a lights group the extension generated."""
    return bool(group.get("phong_nodes_group")) or group.name.startswith("Phong Lights ")


@pytest.mark.parametrize("kind, name", FILES, ids=[n.split("/")[-1] for _k, n in FILES])
def test_an_import_adds_the_files_materials_as_phong_and_nothing_else(bpy_clean, kind, name):
    """Into an empty file: the materials added are exactly the ones the file uses, under its
    names, each a Phong material with no source to restore; every image added is used by one
    of them; every node group added is a Phong group; the meshes are the objects' meshes.
    A second import gives Blender's .001 names and again nothing else."""
    bpy = bpy_clean
    path = os.path.join(DATA, name)
    wanted = _expected(kind, path)
    assert wanted, "each file uses materials"
    before = _state(bpy)
    _import(bpy, kind, path)
    added = _added(bpy, before)
    assert {m.name for m in added["materials"]} == wanted
    for material in added["materials"]:
        assert material.get("phong_nodes_material"), material.name
        assert not {"phong_source", "phong_source_key"} & set(material.keys()), material.name
        assert not material.use_fake_user and material.users >= 1, material.name
    used_images = {node.image for m in added["materials"] for node in m.node_tree.nodes
                   if node.bl_idname == "ShaderNodeTexImage" and node.image is not None}
    assert added["images"] == used_images, "no image that nothing uses"
    assert all(_is_phong_group(g) for g in added["node_groups"]), added["node_groups"]
    meshes = {o.data for o in bpy.data.objects if o.type == "MESH"}
    assert added["meshes"] == meshes
    # again: Blender's names for a name the file already holds, and nothing else
    names = {kind: {b.name for b in blocks} for kind, blocks in added.items()}
    second = _state(bpy)
    _import(bpy, kind, path)
    again = _added(bpy, second)
    assert {m.name for m in again["materials"]} == {_blender_name(n, names["materials"])
                                                    for n in wanted}
    assert all(m.get("phong_nodes_material") for m in again["materials"])
    assert {g.name for g in again["node_groups"]} <= names["node_groups"], \
        "the lights group and the library groups are shared"
    assert len(again["images"]) == len(added["images"])


def test_the_users_own_data_blocks_are_never_touched(bpy_clean):
    """A material of the user's named as one of the file's, with a fake user and a custom
    property, and an unused image of the user's: after the OBJ and FBX imports they are as
    they were, and the imported materials are named with .001."""
    bpy = bpy_clean
    mine = bpy.data.materials.new("shiny")
    mine.use_fake_user = True
    mine["mine"] = 7
    lambert = bpy.data.materials.new("lambert1")
    image = bpy.data.images.new("unused of mine", 4, 4)
    _import(bpy, "obj", os.path.join(DATA, "obj/illum.obj"))
    _import(bpy, "fbx", os.path.join(DATA, "fbx/maya_cube_7500_binary.fbx"))
    _import(bpy, "fbx", os.path.join(DATA, "fbx/maya_cube_7500_ascii.fbx"))
    assert bpy.data.materials["shiny"] == mine and mine["mine"] == 7 and mine.use_fake_user
    assert not mine.get("phong_nodes_material") and mine.users == 1
    assert bpy.data.materials["lambert1"] == lambert and not lambert.get("phong_nodes_material")
    assert bpy.data.images["unused of mine"] == image and image.users == 0
    assert {"shiny.001", "lambert1.001", "lambert1.002"} <= set(bpy.data.materials.keys())
    assert bpy.data.objects["shiny"].active_material.name == "shiny.001"


def test_an_mtl_material_no_face_uses_is_left_out(bpy_clean, tmp_path):
    bpy = bpy_clean
    (tmp_path / "two.mtl").write_text("newmtl used\nKd 1 0 0\nnewmtl spare\nKd 0 1 0\n")
    (tmp_path / "one.obj").write_text("mtllib two.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\n"
                                      "usemtl used\nf 1 2 3\n")
    before = _state(bpy)
    _import(bpy, "obj", str(tmp_path / "one.obj"))
    assert {m.name for m in _added(bpy, before)["materials"]} == {"used"}


# -- FBX maps: TransparentColor, TransparencyFactor, ShininessExponent ------------------------

def _png(path, rows, alpha=False):
    """An 8-bit RGB(A) PNG of *rows* (top row first, each a list of pixel tuples), written
    here with zlib (independent of Blender)."""
    height, width = len(rows), len(rows[0])
    channels = 4 if alpha else 3
    raw = b"".join(b"\x00" + bytes(v for pixel in row for v in pixel[:channels])
                   for row in rows)

    def chunk(kind, data):
        return (struct.pack(">I", len(data)) + kind + data
                + struct.pack(">I", zlib.crc32(kind + data) & 0xFFFFFFFF))

    header = struct.pack(">IIBBBBB", width, height, 8, 6 if alpha else 2, 0, 0, 0)
    path.write_bytes(b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", header)
                     + chunk(b"IDAT", zlib.compress(raw)) + chunk(b"IEND", b""))


def _blocks(size, quads):
    """A size x size image of four blocks: *quads* = (bottom-left, bottom-right, top-left,
    top-right) pixel values; returns the rows top first."""
    half = size // 2
    bottom = [quads[0]] * half + [quads[1]] * half
    top = [quads[2]] * half + [quads[3]] * half
    return [top] * half + [bottom] * half


def _srgb_to_linear(c):
    c = np.asarray(c, dtype=np.float64) / 255.0
    return np.where(c <= 0.04045, c / 12.92, ((c + 0.055) / 1.055) ** 2.4)


SUN_TILT = math.radians(40.0)
FBX_MAPS = {
    # TransparentColor map (colour, sRGB): channels 0 or 255, exact in any colour space
    "TransparentColor": [(255, 0, 0), (255, 255, 0), (0, 0, 0), (255, 255, 255)],
    # TransparencyFactor map (data): four greys
    "TransparencyFactor": [(64, 64, 64), (255, 255, 255), (128, 128, 128), (0, 0, 0)],
    # ShininessExponent map (data)
    "ShininessExponent": [(32, 32, 32), (255, 255, 255), (128, 128, 128), (64, 64, 64)],
}
TC, TF, SE = (1.0, 0.5, 1.0), 0.8, 8.0
KD, KS, KE = (0.3, 0.4, 0.5), (1.0, 0.9, 0.8), (0.05, 0.0, 0.1)

FBX_MAPS_FILE = '''; FBX 7.4.0 project file
; written by tests/test_import_native.py: a plane with UVs, a Phong material whose
; TransparentColor, TransparencyFactor and ShininessExponent are mapped
FBXHeaderExtension:  {{
	FBXHeaderVersion: 1003
	FBXVersion: 7400
}}
GlobalSettings:  {{
	Version: 1000
	Properties70:  {{
		P: "UpAxis", "int", "Integer", "",2
		P: "UpAxisSign", "int", "Integer", "",1
		P: "FrontAxis", "int", "Integer", "",1
		P: "FrontAxisSign", "int", "Integer", "",-1
		P: "CoordAxis", "int", "Integer", "",0
		P: "CoordAxisSign", "int", "Integer", "",1
		P: "UnitScaleFactor", "double", "Number", "",100
	}}
}}
Objects:  {{
	Geometry: 100, "Geometry::Plane", "Mesh" {{
		Vertices: *12 {{
			a: -1,-1,0,1,-1,0,1,1,0,-1,1,0
		}}
		PolygonVertexIndex: *4 {{
			a: 0,1,2,-4
		}}
		GeometryVersion: 124
		LayerElementNormal: 0 {{
			Version: 101
			MappingInformationType: "ByPolygonVertex"
			ReferenceInformationType: "Direct"
			Normals: *12 {{
				a: 0,0,1,0,0,1,0,0,1,0,0,1
			}}
		}}
		LayerElementUV: 0 {{
			Version: 101
			Name: "UVMap"
			MappingInformationType: "ByPolygonVertex"
			ReferenceInformationType: "Direct"
			UV: *8 {{
				a: 0,0,1,0,1,1,0,1
			}}
		}}
		LayerElementMaterial: 0 {{
			Version: 101
			MappingInformationType: "AllSame"
			ReferenceInformationType: "IndexToDirect"
			Materials: *1 {{
				a: 0
			}}
		}}
		Layer: 0 {{
			Version: 100
			LayerElement:  {{
				Type: "LayerElementNormal"
				TypedIndex: 0
			}}
			LayerElement:  {{
				Type: "LayerElementUV"
				TypedIndex: 0
			}}
			LayerElement:  {{
				Type: "LayerElementMaterial"
				TypedIndex: 0
			}}
		}}
	}}
	Model: 200, "Model::Plane", "Mesh" {{
		Version: 232
		Shading: T
	}}
	Material: 300, "Material::mapped", "" {{
		Version: 102
		ShadingModel: "phong"
		Properties70:  {{
			P: "DiffuseColor", "Color", "", "A",{kd}
			P: "AmbientColor", "Color", "", "A",0,0,0
			P: "SpecularColor", "Color", "", "A",{ks}
			P: "ShininessExponent", "Number", "", "A",{se}
			P: "EmissiveColor", "Color", "", "A",{ke}
			P: "TransparentColor", "Color", "", "A",{tc}
			P: "TransparencyFactor", "Number", "", "A",{tf}
		}}
	}}
{textures}}}
Connections:  {{
	C: "OO",200,0
	C: "OO",100,200
	C: "OO",300,200
{connections}}}
'''


def _fbx_maps_file(tmp_path):
    textures, connections = "", ""
    for index, (prop, quads) in enumerate(FBX_MAPS.items()):
        file = f"{prop}.png"
        _png(tmp_path / file, _blocks(16, quads))
        ident = 800 + index
        textures += (f'\tTexture: {ident}, "Texture::{prop}", "" {{\n'
                     f'\t\tType: "TextureVideoClip"\n\t\tVersion: 202\n'
                     f'\t\tTextureName: "Texture::{prop}"\n\t\tFileName: "{file}"\n'
                     f'\t\tRelativeFilename: "{file}"\n\t}}\n')
        connections += f'\tC: "OP",{ident},300, "{prop}"\n'
    text = FBX_MAPS_FILE.format(
        kd=",".join(map(str, KD)), ks=",".join(map(str, KS)), ke=",".join(map(str, KE)),
        tc=",".join(map(str, TC)), tf=TF, se=SE, textures=textures, connections=connections)
    path = tmp_path / "maps.fbx"
    path.write_text(text, encoding="utf-8")
    return str(path)


def _fbx_maps_expected():
    """Per block (bottom-left, bottom-right, top-left, top-right): the pixel over the black
    world, opacity × colour, with the FBX SDK's opacity 1 − TF·t_f × mean(TC ⊗ t_c) (t_c the
    TransparentColor map's colour decoded from sRGB, t_f the mean of the TransparencyFactor
    map's data) and Phong's colour Ke + cos θ·Kd + (r·v)^e·Ks, e = SE × mean of the
    ShininessExponent map's data, r·v = cos θ (a sun tilted by θ, the view from above, no
    ambient light)."""
    out = []
    for block in range(4):
        t_c = _srgb_to_linear(FBX_MAPS["TransparentColor"][block])
        t_f = np.mean(FBX_MAPS["TransparencyFactor"][block]) / 255.0
        opacity = min(max(1.0 - TF * t_f * np.mean(np.array(TC) * t_c), 0.0), 1.0)
        exponent = SE * np.mean(FBX_MAPS["ShininessExponent"][block]) / 255.0
        cos = math.cos(SUN_TILT)
        colour = np.minimum(np.array(KE) + cos * np.array(KD) + cos ** exponent * np.array(KS),
                            1.0)
        out.append(opacity * colour)
    return out


def _block_pixels(size, pixels=16, margin=2):
    """{block: (rows, columns) of the pixels of an image of *pixels*² covering the plane that
    sample that block's texels with no other texel in reach (bilinear filtering)}."""
    texel = pixels / size
    inner = [i for i in range(pixels) if margin * texel <= i % (pixels / 2) < pixels / 2 -
             margin * texel]
    low = [i for i in inner if i < pixels / 2]
    high = [i for i in inner if i >= pixels / 2]
    return {0: (low, low), 1: (low, high), 2: (high, low), 3: (high, high)}


@pytest.mark.cycles
def test_fbx_opacity_and_exponent_maps_render_the_files_formula(bpy_clean, tmp_path):
    """A plane whose TransparentColor, TransparencyFactor and ShininessExponent are mapped
    (ASCII FBX written here: the ufbx path), lit by a tilted sun over the black world: every
    pixel inside a block of the maps equals opacity × colour of the file's formula (Cycles,
    1e-4)."""
    bpy = bpy_clean
    pixels = 32
    scene = be.new_scene("fbx maps", pixels, pixels)
    bpy.context.window.scene = scene
    sun = bpy.data.objects.new("Sun", bpy.data.lights.new("Sun", "SUN"))
    sun.data.phong.intensity = 1.0  # the seeds' i of its own, not its strength's
    scene.collection.objects.link(sun)
    sun.rotation_euler = (0.0, SUN_TILT, 0.0)
    path = _fbx_maps_file(tmp_path)
    assert bpy.ops.phong.import_fbx(filepath=path) == {"FINISHED"}
    scene.world.phong.ambient_intensity = 0.0
    be.add_ortho_camera(scene, (0.0, 0.0), 2.0, 2.0)
    material = bpy.data.materials["mapped"]
    assert material.surface_render_method == "BLENDED"
    images = {node.image.name: node.image.colorspace_settings.name
              for node in material.node_tree.nodes if node.bl_idname == "ShaderNodeTexImage"}
    assert images == {"TransparentColor.png": "sRGB", "TransparencyFactor.png": "Non-Color",
                      "ShininessExponent.png": "Non-Color"}
    passes, _seconds = render(bpy, scene, str(tmp_path / "maps.exr"))
    got = passes["Combined"][..., :3].astype(np.float64)
    worst, checked = 0.0, 0
    for block, (rows, columns) in _block_pixels(16, pixels).items():
        want = _fbx_maps_expected()[block]
        for r in rows:
            for c in columns:
                worst = max(worst, float(np.abs(got[r, c] - want).max()))
                checked += 1
    be.report(f"[fbx maps cycles] max |Combined - formula| = {worst:.2e} on {checked} pixels")
    assert checked >= 4 * 16 and worst <= 1e-4, worst
    values = sorted(float(v) for v in np.unique(np.round(np.array(_fbx_maps_expected()), 4)))
    assert len(values) > 4, "the blocks differ: each map reaches the picture"


def test_blender_293_maps_of_the_exponent_and_the_transparency_factor(bpy_clean):
    """Blender 2.93's exporter connects its roughness texture to ShininessExponent and its
    alpha texture to TransparencyFactor (tests/data/fbx, binary: Blender's importer's
    scene): the exponent is the control (the file's ShininessExponent) × the map's mean RGB,
    read as data; the opacity is the alpha channel of the TransparencyFactor map, as
    Blender's importer reads it (its Principled Alpha fed by the same image's Alpha output),
    though the file's TransparencyFactor is 0 (issue 45): the texels' alpha, decoded here
    from the PNG embedded in the file, reach the opacity map (a cut-out: test_fbx_export's
    alpha texture written by Blender 5's exporter)."""
    bpy = bpy_clean
    path = os.path.join(DATA, "fbx", "blender_293_embedded_textures_7400_binary.fbx")
    from io_scene_fbx import parse_fbx  # noqa: PLC0415
    root, _version = parse_fbx.parse(path)
    objects = next(e for e in root.elems if e.id == b"Objects")
    videos = {}
    for video in (e for e in objects.elems if e.id == b"Video"):
        name = next(e for e in video.elems if e.id == b"RelativeFilename").props[0]
        content = next((e for e in video.elems if e.id == b"Content"), None)
        videos[name.decode().replace("\\", "/").split("/")[-1]] = content.props[0]
    material = next(e for e in objects.elems if e.id == b"Material")
    props = {p.props[0]: p.props[4:] for p in next(
        e for e in material.elems if e.id == b"Properties70").elems}
    definitions = next(e for e in root.elems if e.id == b"Definitions")
    template = next(t for o in definitions.elems for t in o.elems
                    if t.id == b"PropertyTemplate" and t.props[0] == b"FbxSurfacePhong")
    template = {p.props[0]: p.props[4:] for p in template.elems[0].elems}
    factor = props.get(b"TransparencyFactor", template[b"TransparencyFactor"])
    assert tuple(factor) == (0.0,), "the SDK's rule would read the map as opaque"
    texels = _png_rows_bytes(videos["checkerboard_weight.png"])
    assert texels.shape[2] == 4   # (its alpha is 255 throughout: opaque, in both readers)
    assert bpy.ops.phong.import_fbx(filepath=path) == {"FINISHED"}
    from phong_nodes.addon import compat  # noqa: PLC0415

    tree = bpy.data.materials["Material.001"].node_tree
    product = tree.nodes["phong_lights"].inputs["Exponent"].links[0].from_node
    assert product.bl_idname == "ShaderNodeMath" and product.operation == "MULTIPLY"
    feeds = {link.from_node.name for socket in product.inputs for link in socket.links}
    assert "phong_exponent" in feeds
    mean = next(tree.nodes[n] for n in feeds if n != "phong_exponent")
    assert mean.operation == "DOT_PRODUCT" and tuple(
        compat.input_socket(mean, "Vector_001").default_value) == pytest.approx((1 / 3,) * 3)
    image = compat.input_socket(mean, "Vector").links[0].from_node.image
    assert image.name == "checkerboard_roughness.png"
    assert image.colorspace_settings.name == "Non-Color" and image.packed_file is not None
    # the opacity: the Mix Shader's Fac <- clamp(alpha of the TransparencyFactor map)
    mix = tree.nodes["phong_opacity_mix"]
    clamp = compat.input_socket(mix, "Fac").links[0].from_node
    assert clamp.name == "phong_opacity_map" and clamp.use_clamp
    link = compat.input_socket(clamp, "Value").links[0]
    assert link.from_socket.identifier == "Alpha"
    alpha_image = link.from_node.image
    assert alpha_image.packed_file is not None
    width, height = alpha_image.size
    pixels = np.array(alpha_image.pixels[:], np.float64).reshape(height, width, 4)
    np.testing.assert_allclose(pixels[::-1, :, 3], texels[..., 3] / 255.0, atol=1e-6)
    # Blender's own importer reads it the same way (the peer the issue names)
    for m in list(bpy.data.materials):
        bpy.data.materials.remove(m)
    assert bpy.ops.import_scene.fbx(filepath=path) == {"FINISHED"}
    principled = next(n for m in bpy.data.materials if m.node_tree
                      for n in m.node_tree.nodes if n.bl_idname == "ShaderNodeBsdfPrincipled")
    theirs = principled.inputs["Alpha"].links[0]
    assert theirs.from_socket.identifier == "Alpha"
    theirs_pixels = np.array(theirs.from_node.image.pixels[:], np.float64).reshape(
        height, width, 4)
    np.testing.assert_allclose(theirs_pixels[..., 3], pixels[..., 3], atol=1e-6)


# -- COLLADA <transparent><texture> ------------------------------------------------------------

def _png_rows(path):
    """The texels of an 8-bit RGB / RGBA PNG (filters 0-4), top row first, decoded here."""
    return _png_rows_bytes(open(path, "rb").read())


def _png_rows_bytes(data):
    """The texels of the 8-bit RGB / RGBA PNG *data* (filters 0-4), top row first."""
    pos, idat, header = 8, b"", None
    while pos < len(data):
        length, = struct.unpack(">I", data[pos:pos + 4])
        kind, body = data[pos + 4:pos + 8], data[pos + 8:pos + 8 + length]
        if kind == b"IHDR":
            header = struct.unpack(">IIBBBBB", body)
        elif kind == b"IDAT":
            idat += body
        pos += 12 + length
    width, height, depth, colour = header[:4]
    assert depth == 8 and colour in (2, 6)
    channels = 3 if colour == 2 else 4
    raw, stride = zlib.decompress(idat), width * channels
    rows, previous = [], bytearray(stride)
    for y in range(height):
        kind, line = raw[y * (stride + 1)], bytearray(raw[y * (stride + 1) + 1:(y + 1) * (stride + 1)])
        for x in range(stride):
            left = line[x - channels] if x >= channels else 0
            up, corner = previous[x], previous[x - channels] if x >= channels else 0
            if kind == 1:
                line[x] = (line[x] + left) & 255
            elif kind == 2:
                line[x] = (line[x] + up) & 255
            elif kind == 3:
                line[x] = (line[x] + (left + up) // 2) & 255
            elif kind == 4:
                p = left + up - corner
                best = min((abs(p - left), 0, left), (abs(p - up), 1, up),
                           (abs(p - corner), 2, corner))[2]
                line[x] = (line[x] + best) & 255
        rows.append(np.frombuffer(bytes(line), np.uint8).reshape(width, channels))
        previous = line
    return np.array(rows)


@pytest.mark.cycles
def test_khronos_transparent_texture_renders_rgb_zero(bpy_clean, tmp_path):
    """Khronos's _reference_image_checkerboard (tests/data/collada): a white <constant>
    quad whose <transparent opaque="RGB_ZERO"> is checkerboard.png with <transparency>0.5:
    every pixel over the black world equals the spec's opacity 1 − mean(texel rgb)·0.5
    (texels decoded here from the PNG) times the white emission (Cycles, 1e-4)."""
    bpy = bpy_clean
    pixels = 60
    scene = be.new_scene("dae checker", pixels, pixels)
    bpy.context.window.scene = scene
    camera = be.add_ortho_camera(scene, (0.0, 0.0), 1.5, 1.5)
    camera.location = (0.0, -10.0, 0.0)
    camera.rotation_euler = (math.pi / 2, 0.0, 0.0)   # looking along +Y, Z up
    path = os.path.join(DATA, "collada", "cts_reference_image_checkerboard.dae")
    capfd_free = bpy.ops.phong.import_collada(filepath=path)
    assert capfd_free == {"FINISHED"}
    root = ET.parse(path).getroot()
    transparent = next(e for e in root.iter() if e.tag.endswith("transparent"))
    assert transparent.get("opaque") == "RGB_ZERO"
    t = float(next(e for e in root.iter() if e.tag.endswith("transparency"))[0].text)
    texels = _png_rows(os.path.join(DATA, "collada", "checkerboard.png"))[..., :3]
    linear = _srgb_to_linear(texels)   # (the file's colour texture, read as a colour)
    size = texels.shape[0]
    passes, _seconds = render(bpy, scene, str(tmp_path / "checker.exr"))
    got = passes["Combined"][..., :3].astype(np.float64)
    worst, checked = 0.0, 0
    for r in range(pixels):
        for c in range(pixels):
            u, v = (c + 0.5) / pixels, (r + 0.5) / pixels   # the quad spans the picture
            x, y = u * size - 0.5, (1.0 - v) * size - 0.5   # texel coordinates, top row 0
            x0, y0 = int(math.floor(x)), int(math.floor(y))
            near = linear[max(y0 - 1, 0):y0 + 3, max(x0 - 1, 0):x0 + 3].reshape(-1, 3)
            if np.ptp(near, axis=0).max() > 0:
                continue   # bilinear filtering across a square's edge
            want = 1.0 - near[0].mean() * t
            worst = max(worst, float(np.abs(got[r, c] - want).max()))
            checked += 1
    be.report(f"[collada transparent texture cycles] max |Combined - spec| = {worst:.2e} on "
              f"{checked} pixels")
    assert checked >= pixels * pixels // 2 and worst <= 1e-4, (checked, worst)


def _transparent_dae(mode, t, image):
    return f'''<?xml version="1.0"?>
<COLLADA xmlns="http://www.collada.org/2005/11/COLLADASchema" version="1.4.1">
<asset><unit meter="1"/><up_axis>Z_UP</up_axis></asset>
<library_images><image id="img"><init_from>{image}</init_from></image></library_images>
<library_effects><effect id="fx"><profile_COMMON>
<newparam sid="surf"><surface type="2D"><init_from>img</init_from></surface></newparam>
<newparam sid="samp"><sampler2D><source>surf</source></sampler2D></newparam>
<technique sid="common"><constant><emission><color>0.9 0.6 0.3 1</color></emission>
<transparent opaque="{mode}"><texture texture="samp" texcoord="UV0"/></transparent>
<transparency><float>{t}</float></transparency></constant></technique>
</profile_COMMON></effect></library_effects>
<library_materials><material id="glass" name="glass"><instance_effect url="#fx"/></material>
</library_materials>
<library_geometries><geometry id="quad"><mesh>
<source id="p"><float_array id="pa" count="12">-1 -1 0 1 -1 0 1 1 0 -1 1 0</float_array>
<technique_common><accessor source="#pa" count="4" stride="3"/></technique_common></source>
<source id="uv"><float_array id="uva" count="8">0 0 1 0 1 1 0 1</float_array>
<technique_common><accessor source="#uva" count="4" stride="2"/></technique_common></source>
<vertices id="v"><input semantic="POSITION" source="#p"/></vertices>
<polylist count="1" material="m"><input semantic="VERTEX" source="#v" offset="0"/>
<input semantic="TEXCOORD" source="#uv" offset="0" set="0"/><vcount>4</vcount>
<p>0 1 2 3</p></polylist></mesh></geometry></library_geometries>
<library_visual_scenes><visual_scene id="vs"><node id="n" name="Quad">
<instance_geometry url="#quad"><bind_material><technique_common>
<instance_material symbol="m" target="#glass"/></technique_common></bind_material>
</instance_geometry></node></visual_scene></library_visual_scenes>
<scene><instance_visual_scene url="#vs"/></scene></COLLADA>'''


#: RGBA texels of the four blocks (bottom-left, bottom-right, top-left, top-right)
TEXELS = [(255, 0, 0, 255), (0, 255, 255, 64), (255, 255, 0, 128), (0, 0, 255, 0)]


@pytest.mark.cycles
@pytest.mark.parametrize("mode", ["A_ONE", "A_ZERO", "RGB_ZERO", "RGB_ONE"])
def test_collada_transparent_texture_modes_render_the_spec(bpy_clean, tmp_path, mode):
    """<transparent opaque=MODE><texture> with <transparency>0.75 over an RGBA texture of four
    blocks: the pixel over the black world is the emission times the spec's opacity of the
    texel (A_ONE a·t, A_ZERO 1 − a·t, RGB_ZERO 1 − mean(rgb)·t, RGB_ONE mean(rgb)·t; the
    RGB of 0 / 255 channels, exact in any colour space)."""
    bpy = bpy_clean
    pixels, t = 32, 0.75
    scene = be.new_scene(f"dae {mode}", pixels, pixels)
    bpy.context.window.scene = scene
    be.add_ortho_camera(scene, (0.0, 0.0), 2.0, 2.0)
    _png(tmp_path / "mask.png", _blocks(16, TEXELS), alpha=True)
    (tmp_path / "glass.dae").write_text(_transparent_dae(mode, t, "mask.png"))
    assert bpy.ops.phong.import_collada(filepath=str(tmp_path / "glass.dae")) == {"FINISHED"}
    assert "phong_opacity_map" in bpy.data.materials["glass"].node_tree.nodes
    passes, _seconds = render(bpy, scene, str(tmp_path / f"{mode}.exr"))
    got = passes["Combined"][..., :3].astype(np.float64)
    emission = np.array((0.9, 0.6, 0.3))
    worst = 0.0
    for block, (rows, columns) in _block_pixels(16, pixels).items():
        r, g, b, a = (v / 255.0 for v in TEXELS[block])
        mean = (r + g + b) / 3.0
        opacity = {"A_ONE": a * t, "A_ZERO": 1.0 - a * t, "RGB_ZERO": 1.0 - mean * t,
                   "RGB_ONE": mean * t}[mode]
        for row in rows:
            for column in columns:
                worst = max(worst, float(np.abs(got[row, column] - opacity * emission).max()))
    be.report(f"[collada transparent {mode} cycles] max |Combined - spec| = {worst:.2e}")
    assert worst <= 1e-4, worst


def test_transparent_texture_with_zero_transparency_changes_nothing(bpy_clean, tmp_path, capfd):
    """t = 0: RGB_ZERO is opaque whatever the texture (no map); A_ONE is wholly invisible,
    imported opaque with the usual warning (Literal Transparency keeps it at 0)."""
    bpy = bpy_clean
    _png(tmp_path / "mask.png", _blocks(4, TEXELS), alpha=True)
    for mode in ("RGB_ZERO", "A_ONE"):
        be.reset_empty_file()
        (tmp_path / "glass.dae").write_text(_transparent_dae(mode, 0, "mask.png"))
        capfd.readouterr()
        assert bpy.ops.phong.import_collada(filepath=str(tmp_path / "glass.dae")) == {"FINISHED"}
        logged = "".join(capfd.readouterr())
        nodes = bpy.data.materials["glass"].node_tree.nodes
        assert "phong_opacity_map" not in nodes and "phong_opacity_mix" not in nodes
        assert ("wholly invisible" in logged) == (mode == "A_ONE")
        assert not [i for i in bpy.data.images], "no image that nothing uses"


def test_transparent_texture_is_exported_back(bpy_clean, tmp_path):
    """Import ▸ export ▸ import of Khronos's checkerboard: the written file names the same
    texture under <transparent opaque="RGB_ZERO"> with <transparency>0.5 (read back with
    ElementTree here), validates against the 1.4.1 schema, and imports as the same opacity
    map."""
    from test_collada import _valid  # noqa: PLC0415

    bpy = bpy_clean
    path = os.path.join(DATA, "collada", "cts_reference_image_checkerboard.dae")
    assert bpy.ops.phong.import_collada(filepath=path) == {"FINISHED"}
    out = tmp_path / "again.dae"
    assert bpy.ops.phong.export_collada(filepath=str(out)) == {"FINISHED"}
    text = out.read_text()
    _valid(text)
    root = ET.fromstring(text)
    for element in root.iter():
        element.tag = element.tag.rsplit("}", 1)[-1]
    transparent = next(root.iter("transparent"))
    assert transparent.get("opaque") == "RGB_ZERO" and transparent.find("texture") is not None
    assert float(next(root.iter("transparency")).find("float").text) == 0.5
    image = next(root.iter("image")).find("init_from").text
    assert os.path.samefile(tmp_path / image, os.path.join(DATA, "collada", "checkerboard.png"))
    be.reset_empty_file()
    assert bpy.ops.phong.import_collada(filepath=str(out)) == {"FINISHED"}
    (material,) = [m for m in bpy.data.materials if m.get("phong_nodes_material")]
    assert "phong_opacity_map" in material.node_tree.nodes


# -- COLLADA lines ------------------------------------------------------------------------------

def test_sketchup_lines_become_loose_edges_with_their_material(bpy_clean, tmp_path):
    """turtlebot's r200.dae (SketchUp 8, tests/data/collada): its <lines> are loose edges of
    their meshes, as many as the file's pairs (counted here), and their material
    (edge_color..., bound to the lines' symbol) is the slot of the line-only meshes."""
    bpy = bpy_clean
    path = os.path.join(DATA, "collada", "turtlebot_r200_sketchup.dae")
    root = ET.parse(path).getroot()
    for element in root.iter():
        element.tag = element.tag.rsplit("}", 1)[-1]
    pairs = {}
    for geometry in root.iter("geometry"):
        for lines in geometry.iter("lines"):
            stride = max(int(i.get("offset")) for i in lines.findall("input")) + 1
            count = len(lines.find("p").text.split()) // stride // 2
            pairs[geometry.get("id")] = pairs.get(geometry.get("id"), 0) + count
    assert sum(pairs.values()) == 5 and len(pairs) == 4
    assert bpy.ops.phong.import_collada(filepath=path) == {"FINISHED"}
    for obj in bpy.data.objects:
        if obj.type != "MESH":
            continue
        mesh = obj.data
        used = set()
        for polygon in mesh.polygons:
            used |= set(polygon.edge_keys)
        loose = [e for e in mesh.edges if tuple(sorted(e.vertices)) not in used]
        if not mesh.polygons:
            assert loose and [s.material.name for s in obj.material_slots] == [
                "edge_color6291111255"], obj.name
    lines_only = [o for o in bpy.data.objects if o.type == "MESH" and not o.data.polygons]
    assert sorted(len(o.data.edges) for o in lines_only) == sorted(pairs.values())
    assert bpy.data.materials["edge_color6291111255"].get("phong_nodes_material")
    # exported back: each line-only mesh as <lines> with its material, read back the same
    out = tmp_path / "r200.dae"
    assert bpy.ops.phong.export_collada(filepath=str(out)) == {"FINISHED"}
    be.reset_empty_file()
    assert bpy.ops.phong.import_collada(filepath=str(out)) == {"FINISHED"}
    again = [o for o in bpy.data.objects if o.type == "MESH" and not o.data.polygons]
    assert sorted(len(o.data.edges) for o in again) == sorted(pairs.values())
    assert {s.material.name for o in again for s in o.material_slots} == {
        "edge_color6291111255"}


def test_lines_beside_faces_and_linestrips(bpy_clean, tmp_path):
    """A triangle with a <lines> pair and a <linestrips> of three points in one mesh: three
    face edges and three loose edges (a line along a face edge is that edge), the lines'
    material a second slot."""
    bpy = bpy_clean
    text = '''<?xml version="1.0"?><COLLADA xmlns="http://www.collada.org/2005/11/COLLADASchema"
version="1.4.1"><asset><up_axis>Z_UP</up_axis></asset>
<library_effects><effect id="fx"><profile_COMMON><technique sid="c"><lambert><diffuse>
<color>1 0 0 1</color></diffuse></lambert></technique></profile_COMMON></effect></library_effects>
<library_materials><material id="paint" name="paint"><instance_effect url="#fx"/></material>
<material id="ink" name="ink"><instance_effect url="#fx"/></material></library_materials>
<library_geometries><geometry id="g"><mesh><source id="p"><float_array id="pa" count="15">
0 0 0 1 0 0 0 1 0 2 2 0 3 3 0</float_array><technique_common><accessor source="#pa" count="5"
stride="3"/></technique_common></source><vertices id="v"><input semantic="POSITION" source="#p"/>
</vertices><triangles count="1" material="face"><input semantic="VERTEX" source="#v" offset="0"/>
<p>0 1 2</p></triangles><lines count="2" material="line"><input semantic="VERTEX" source="#v"
offset="0"/><p>0 1 2 3</p></lines><linestrips count="1" material="line"><input semantic="VERTEX"
source="#v" offset="0"/><p>2 3 4 0</p></linestrips></mesh></geometry></library_geometries>
<library_visual_scenes><visual_scene id="vs"><node name="Wire"><instance_geometry url="#g">
<bind_material><technique_common><instance_material symbol="face" target="#paint"/>
<instance_material symbol="line" target="#ink"/></technique_common></bind_material>
</instance_geometry></node></visual_scene></library_visual_scenes>
<scene><instance_visual_scene url="#vs"/></scene></COLLADA>'''
    (tmp_path / "wire.dae").write_text(text)
    assert bpy.ops.phong.import_collada(filepath=str(tmp_path / "wire.dae")) == {"FINISHED"}
    obj = bpy.data.objects["Wire"]
    edges = sorted(tuple(sorted(e.vertices)) for e in obj.data.edges)
    # faces: 0-1, 1-2, 0-2; lines: 0-1 (a face edge), 2-3; strip: 2-3, 3-4, 0-4
    assert edges == [(0, 1), (0, 2), (0, 4), (1, 2), (2, 3), (3, 4)]
    assert [s.material.name for s in obj.material_slots] == ["paint", "ink"]
    assert len(obj.data.polygons) == 1
    # export writes the loose edges back as <lines>; import ▸ export ▸ import keeps them
    out = tmp_path / "again.dae"
    assert bpy.ops.phong.export_collada(filepath=str(out)) == {"FINISHED"}
    from test_collada import _valid  # noqa: PLC0415

    _valid(out.read_text())
    be.reset_empty_file()
    assert bpy.ops.phong.import_collada(filepath=str(out)) == {"FINISHED"}
    again = bpy.data.objects["Wire"]
    positions = [tuple(v.co) for v in again.data.vertices]
    assert sorted(tuple(sorted(positions[i] for i in e.vertices)) for e in again.data.edges) == \
        sorted(tuple(sorted(tuple(obj_co) for obj_co in pair)) for pair in (
            ((0, 0, 0), (1, 0, 0)), ((0, 0, 0), (0, 1, 0)), ((0, 0, 0), (3, 3, 0)),
            ((1, 0, 0), (0, 1, 0)), ((0, 1, 0), (2, 2, 0)), ((2, 2, 0), (3, 3, 0))))


# -- instancing bomb ---------------------------------------------------------------------------

@pytest.mark.slow
def test_an_instancing_bomb_ends_in_seconds_with_one_warning(bpy_clean, tmp_path, capfd):
    """The issue's 4 KB file: 40 library nodes, each instantiating the next one twice, the
    last one a triangle: 2^41 objects asked for.  The import ends within seconds with one
    warning naming that number, and the first MAX_NODES objects (the part that fits)."""
    bpy = bpy_clean
    from phong_nodes.addon.interchange import collada_import  # noqa: PLC0415

    nodes = "".join(f'<node id="n{i}"><instance_node url="#n{i + 1}"/>'
                    f'<instance_node url="#n{i + 1}"/></node>' for i in range(40))
    text = f'''<?xml version="1.0"?><COLLADA xmlns="http://www.collada.org/2005/11/COLLADASchema"
version="1.4.1"><library_geometries><geometry id="tri"><mesh><source id="p"><float_array
id="pa" count="9">0 0 0 1 0 0 0 1 0</float_array><technique_common><accessor source="#pa"
count="3" stride="3"/></technique_common></source><vertices id="v"><input semantic="POSITION"
source="#p"/></vertices><triangles count="1"><input semantic="VERTEX" source="#v" offset="0"/>
<p>0 1 2</p></triangles></mesh></geometry></library_geometries><library_nodes>{nodes}
<node id="n40"><instance_geometry url="#tri"/></node></library_nodes><library_visual_scenes>
<visual_scene id="vs"><node id="root"><instance_node url="#n0"/></node></visual_scene>
</library_visual_scenes><scene><instance_visual_scene url="#vs"/></scene></COLLADA>'''
    path = tmp_path / "bomb.dae"
    path.write_text(text)
    assert os.path.getsize(path) < 5000
    capfd.readouterr()
    start = time.perf_counter()
    assert bpy.ops.phong.import_collada(filepath=str(path)) == {"FINISHED"}
    seconds = time.perf_counter() - start
    logged = "".join(capfd.readouterr())
    asked = 1 + sum(2 ** k for k in range(41))   # the root, then n0 ... n40 doubling
    limit = collada_import.MAX_NODES
    be.report(f"[collada instancing bomb] {seconds:.1f} s, {len(bpy.data.objects)} objects")
    assert logged.count(f"would make {asked:,} objects, more than {limit:,}; the first "
                        f"{limit:,} imported") == 1
    assert logged.count("Warning") == 1, logged
    assert len(bpy.data.objects) == limit and seconds < 30.0


# -- drag and drop -----------------------------------------------------------------------------

def test_fbx_file_handler(bpy_clean):
    bpy = bpy_clean
    if hasattr(bpy.types, "FileHandler"):
        handler = bpy.types.PHONG_FH_fbx
        assert handler.bl_import_operator == "phong.import_fbx"
        assert handler.bl_file_extensions == ".fbx"
    # a dropped file's path is set before invoke; a path from an earlier run must not be
    prop = bpy.ops.phong.import_fbx.get_rna_type().properties["filepath"]
    assert prop.is_skip_save
