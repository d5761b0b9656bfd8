# SPDX-License-Identifier: GPL-3.0-or-later
"""COLLADA read: :func:`load` and :func:`parse_bytes` into a :class:`~.model.Document`: the
file parsed (hardened), its asset (unit, up axis), then its materials (``effects``), lights
and cameras (``lights_cameras``), geometries (``geometry``) and scene (``nodes``), each part
handed one reading context (``context._Reading``).

Hardening: a document type declaring entities is refused before parsing (``core.xmlsafe``),
counts are never trusted for allocation (arrays are as long as their text), and every index
is checked against its source.  Reading is liberal: namespaces (1.4, 1.5 or none) are
ignored, decimal commas are repaired, an unbound material symbol is looked up by id and
name, a texture may name a sampler, a surface, an image or a file.
"""

from __future__ import annotations

import math
import os
import xml.etree.ElementTree as ET

from .. import xmlsafe
from ..wording import name_list
from ..xmlsafe import local as _local
from .model import MAX_BYTES, UP_AXES, ColladaError, Document
from .context import _Reading, _ref
from .geometry import read_mesh
from .effects import read_material
from .lights_cameras import read_camera, read_light
from .nodes import read_node


def _strip_namespaces(root) -> None:
    for element in root.iter():
        element.tag = _local(element.tag)
        if element.attrib and any("}" in k for k in element.attrib):
            element.attrib = {_local(k): v for k, v in element.attrib.items()}


def read_asset(ctx):
    """The ``<asset>``'s unit (metres per unit) and up axis into the document."""
    asset = ctx.root.find("asset")
    if asset is None:
        return
    unit = asset.find("unit")
    if unit is not None and unit.get("meter") is not None:
        text = unit.get("meter").strip()
        if "," in text and "." not in text:
            ctx.commas.append("<unit meter>")
            text = text.replace(",", ".")
        try:
            meter = float(text)
        except ValueError:
            meter = float("nan")
        if not math.isfinite(meter) or meter <= 0.0:
            ctx.doc.warn(f"<unit meter=\"{unit.get('meter')}\"> is not a length; read as 1")
        else:
            ctx.doc.meter = meter
    up = asset.find("up_axis")
    if up is not None and up.text:
        axis = up.text.strip().upper()
        if axis in UP_AXES:
            ctx.doc.up_axis = axis
        else:
            ctx.doc.warn(f"<up_axis>{up.text.strip()}</up_axis> unknown; read as Y_UP")


# -- reading ------------------------------------------------------------------------------

def parse_bytes(data: bytes, path: str = "<bytes>") -> Document:
    """Read COLLADA from *data*; raises ColladaError for what is not COLLADA XML."""
    xmlsafe.refuse_entities(data, path, ColladaError)
    try:
        parser = ET.XMLParser()
        parser.feed(data)
        root = parser.close()
    except ET.ParseError as error:
        raise ColladaError(path, f"not well-formed XML ({error})") from None
    _strip_namespaces(root)
    if root.tag != "COLLADA":
        raise ColladaError(path, f"not a COLLADA file (its root element is <{root.tag}>)")
    doc = Document(path, version=root.get("version", "1.4.1"))
    ctx = _Reading(doc, root)
    read_asset(ctx)
    for element in root.iter("material"):
        if element.get("id") is None and element.get("name") is None:
            continue
        material = read_material(ctx, element)
        doc.materials.setdefault(material.id or material.name, material)
    lights = list(root.iter("light"))
    defined = {e.get("id") for e in lights if e.find("technique_common") is not None}
    for element in lights:
        if element.find("technique_common") is None and element.get("id") in defined:
            continue    # an empty twin of a light defined elsewhere (Maya's exporter)
        light = read_light(ctx, element)
        if light is not None:
            doc.lights.setdefault(light.id or light.name, light)
    for element in root.iter("camera"):
        camera = read_camera(ctx, element)
        if camera is not None:
            doc.cameras.setdefault(camera.id or camera.name, camera)
    for element in root.iter("geometry"):
        mesh = read_mesh(ctx, element)
        if mesh is not None:
            doc.meshes.setdefault(mesh.id or mesh.name, mesh)
    for lib in root.findall("library_nodes"):
        for element in lib.findall("node"):
            node = read_node(ctx, element)
            doc.library_nodes.setdefault(node.id, node)
    scenes = {s.get("id"): s for s in root.iter("visual_scene")}
    chosen = None
    inst = root.find("scene/instance_visual_scene")
    if inst is not None:
        chosen = scenes.get(_ref(inst.get("url")))
        if chosen is None:
            doc.warn(f"<instance_visual_scene url=\"{inst.get('url')}\"> not found; "
                     "the first visual scene read")
    if chosen is None and scenes:
        chosen = next(iter(scenes.values()))
    if chosen is not None:
        doc.scene_name = chosen.get("name") or chosen.get("id") or ""
        doc.nodes = [read_node(ctx, n) for n in chosen.findall("node")]
    if ctx.commas:
        places = list(dict.fromkeys(ctx.commas))
        doc.warn(f"decimal commas read as decimal points ({name_list(places, quote=False)})")
    return doc


def load(path: str) -> Document:
    """Read the COLLADA file *path*; raises ColladaError for a missing file or one that is
    not COLLADA XML (everything else: ``Document.warnings``)."""
    try:
        size = os.path.getsize(path)
        if size > MAX_BYTES:
            raise ColladaError(path, f"{size} bytes: larger than {MAX_BYTES} bytes; refused")
        with open(path, "rb") as handle:
            data = handle.read()
    except OSError as error:
        raise ColladaError(path, error.strerror or str(error)) from None
    return parse_bytes(data, path)
