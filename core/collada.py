# SPDX-License-Identifier: GPL-3.0-or-later
"""COLLADA (.dae) files read and written without ``bpy`` (issue 26).

COLLADA's ``profile_COMMON`` is the Phong model written down: ``<constant>``, ``<lambert>``,
``<phong>`` and ``<blinn>`` give emission + ambient·Ka + diffuse·max(N·L, 0) +
specular·max(R·V or N·H, 0)^shininess, and its lights are ambient, directional, point with
1/(c + l·d + q·d²) and spot with ``falloff_angle`` / ``falloff_exponent``.  This module reads
a file into plain data (:func:`load` → :class:`Document`) and writes one back
(:func:`dumps`); ``addon/interchange/collada_import.py`` and ``collada_export.py`` are the
Blender side.

Why the standard library's ``xml.etree.ElementTree`` and not pycollada: pycollada 0.9.3
refuses some real files in its strict load, ignores ``<setparam>``, lacks A_ZERO / RGB_ONE,
reads a missing ``<transparency>`` under RGB_ZERO as 0, drops COLLADA 1.5 texture chains and
builds ``<lookat>`` wrongly; reading the few elements the Phong model needs is shorter than
owning those differences.  Hardening: a document type declaring entities is refused before
parsing (no "billion laughs", no external entity is ever resolved: expat resolves none by
itself), counts are never trusted for allocation (arrays are as long as their text), and
every index is checked against its source.

Reading is liberal, as other readers are: namespaces (1.4, 1.5 or none) are ignored,
decimal commas are repaired, a material's ``name`` is kept (else its ``id``), an unbound
material symbol is looked up by id and name, a texture may name a sampler, a surface, an
image or a file; anything that cannot be read is left out with one warning naming it
(``Document.warnings``), and only a file that is not COLLADA XML at all is refused
(:class:`ColladaError`).
"""

from __future__ import annotations

import math
import os
import re
import warnings
import xml.etree.ElementTree as ET
import xml.parsers.expat as expat
from dataclasses import dataclass, field

import numpy as np

NS14 = "http://www.collada.org/2005/11/COLLADASchema"
NS15 = "http://www.collada.org/2008/03/COLLADASchema"
TECHNIQUES = ("constant", "lambert", "phong", "blinn")
#: colour elements of each technique (the others contribute nothing: black)
TECHNIQUE_COLORS = {"constant": ("emission",),
                    "lambert": ("emission", "ambient", "diffuse"),
                    "phong": ("emission", "ambient", "diffuse", "specular"),
                    "blinn": ("emission", "ambient", "diffuse", "specular")}
OPAQUE_MODES = ("A_ONE", "RGB_ZERO", "A_ZERO", "RGB_ONE")
LIGHT_KINDS = ("ambient", "directional", "point", "spot")
#: Blender's axes (Z up) from the file's: the up axis's rotation (right, up, in kept).
UP_AXES = {
    "Z_UP": np.eye(3),
    "Y_UP": np.array([[1.0, 0.0, 0.0], [0.0, 0.0, -1.0], [0.0, 1.0, 0.0]]),
    "X_UP": np.array([[0.0, -1.0, 0.0], [0.0, 0.0, -1.0], [1.0, 0.0, 0.0]]),
}
#: Largest file read (bytes): far more than any real COLLADA file holds in text.
MAX_BYTES = 1 << 31
#: Largest number of values one primitive may index (bounded memory on absurd counts).
MAX_INDICES = 200_000_000



def _unquote(text: str) -> str:
    """Percent-escapes decoded as UTF-8 (an image's URI); a malformed one is kept as written.
    (Not urllib: the extension imports no network module.)"""
    raw = text.encode("utf-8", "surrogateescape")
    decoded = re.sub(rb"%([0-9A-Fa-f]{2})", lambda m: bytes([int(m.group(1), 16)]), raw)
    return decoded.decode("utf-8", "replace")


def uri_quote(path: str) -> str:
    """*path* as a URI reference for ``<init_from>``: / separators, every byte outside
    letters, digits and ``-._~/:`` percent-escaped (UTF-8); ``_uri_path`` reads it back."""
    safe = set(b"abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ0123456789-._~/:")
    return "".join(chr(b) if b in safe else f"%{b:02X}"
                   for b in path.replace("\\", "/").encode("utf-8"))


def _uri_path(written: str) -> str:
    """The file path of an image reference: a relative or absolute path, or a file: URI
    (``file:///C:/a%20b.png``, ``file://host/x.png``, ``file:/x.png``), percent-decoded."""
    path = written
    if path.lower().startswith("file:"):
        path = path[5:]
        if path.startswith("//"):
            path = "/" + path[2:].partition("/")[2]  # the host part is dropped
        if re.match(r"^/[A-Za-z]:", path):
            path = path[1:]
    return _unquote(path)


class ColladaError(ValueError):
    """A file that cannot be read as COLLADA at all; names the file."""

    def __init__(self, path: str, message: str):
        self.path = path
        super().__init__(f"{path}: {message}")


# -- the document ------------------------------------------------------------------------

@dataclass
class Texture:
    """A texture of a material: the image file as written, where it was found, and the
    texture coordinate set name of the effect (``texcoord``)."""
    path: str
    resolved: str
    texcoord: str = ""
    image_id: str = ""

    @property
    def exists(self) -> bool:
        return os.path.isfile(self.resolved)


@dataclass
class Material:
    id: str
    name: str
    technique: str = "phong"          # constant, lambert, phong or blinn
    colors: dict = field(default_factory=dict)    # element -> (r, g, b, a)
    textures: dict = field(default_factory=dict)  # element -> Texture
    shininess: float | None = None
    opaque: str = "A_ONE"
    transparent: tuple | None = None  # (r, g, b, a), None when absent
    transparency: float | None = None
    effect_id: str = ""
    transparent_texture: Texture | None = None   # <transparent><texture> (issue 35)

    def color(self, element) -> tuple:
        """The colour of *element* (RGB) as the technique uses it: black when the effect
        leaves it out or the technique has no such term."""
        if element not in TECHNIQUE_COLORS[self.technique]:
            return (0.0, 0.0, 0.0)
        return tuple(self.colors.get(element, (0.0, 0.0, 0.0, 1.0))[:3])

    def texture(self, element):
        if element not in TECHNIQUE_COLORS[self.technique]:
            return None
        return self.textures.get(element)

    def opacity(self) -> float:
        """The spec's opacity (1.4.1 §7 "Determining Transparency", 1.5 adds A_ZERO and
        RGB_ONE): A_ONE a·t, RGB_ZERO 1 − mean(rgb)·t, A_ZERO 1 − a·t, RGB_ONE mean(rgb)·t,
        with t = ``<transparency>`` (1 when absent); 1 when ``<transparent>`` is absent.  The
        RGB modes are per channel in the spec; their mean is the one opacity Blender draws
        (:meth:`opacity_channels` tells whether they differ)."""
        channels = self.opacity_channels()
        return float(np.mean(channels)) if self.opaque.startswith("RGB") else channels[0]

    def opacity_channels(self) -> tuple:
        """Per channel (see :meth:`opacity`); a ``<transparent>`` texture counts as a white
        opaque texel here (the map itself: :meth:`opacity_of_texel`)."""
        if self.transparent is None and self.transparent_texture is None:
            return (1.0, 1.0, 1.0)
        t = 1.0 if self.transparency is None else float(self.transparency)
        r, g, b, a = self.transparent if self.transparent is not None else (1.0, 1.0, 1.0, 1.0)
        if self.opaque == "RGB_ZERO":
            return tuple(1.0 - c * t for c in (r, g, b))
        if self.opaque == "RGB_ONE":
            return tuple(c * t for c in (r, g, b))
        if self.opaque == "A_ZERO":
            return (1.0 - a * t,) * 3
        return (a * t,) * 3

    def opacity_of_texel(self, rgba) -> float:
        """The opacity where the ``<transparent>`` texture's texel is *rgba*: the spec's
        formulas of :meth:`opacity` with the texel for the colour, the RGB modes' mean taken
        (what the imported material computes per pixel)."""
        t = 1.0 if self.transparency is None else float(self.transparency)
        r, g, b, a = (float(v) for v in rgba)
        mean = (r + g + b) / 3.0
        return {"A_ONE": a * t, "A_ZERO": 1.0 - a * t, "RGB_ZERO": 1.0 - mean * t,
                "RGB_ONE": mean * t}[self.opaque]


@dataclass
class Light:
    id: str
    name: str
    kind: str                       # ambient, directional, point, spot
    color: tuple = (1.0, 1.0, 1.0)
    constant: float = 1.0
    linear: float = 0.0
    quadratic: float = 0.0
    falloff_angle: float = 180.0    # degrees, the full cone (as every writer writes it)
    falloff_exponent: float = 0.0


@dataclass
class Camera:
    id: str
    name: str
    kind: str = "perspective"       # or orthographic
    xfov: float | None = None       # degrees
    yfov: float | None = None
    xmag: float | None = None
    ymag: float | None = None
    aspect_ratio: float | None = None
    znear: float = 0.1
    zfar: float = 1000.0


@dataclass
class Mesh:
    """A geometry's polygons: positions (n, 3), then per face its corner count and material
    symbol, per corner its position index, normal, texture coordinates and colours."""
    id: str
    name: str
    positions: np.ndarray
    face_sizes: np.ndarray          # (faces,) int
    face_symbols: np.ndarray        # (faces,) index into symbols
    symbols: list                   # material symbols in order of first use
    corners: np.ndarray             # (corners,) position indices
    normals: np.ndarray | None = None          # (corners, 3)
    uvs: dict = field(default_factory=dict)    # set number -> (corners, 2)
    colors: dict = field(default_factory=dict)  # set number -> (corners, 4)
    from_strips: bool = False       # faces of <tristrips> / <trifans> (stitched strips)
    edges: np.ndarray | None = None  # (edges, 2) position indices of <lines> / <linestrips>
    edge_symbol: str = ""           # the material symbol written on <lines> (export)


def drop_degenerate(mesh: "Mesh") -> int:
    """Remove from *mesh* the faces that use one vertex twice (the stitches between
    triangle strips, which Blender's meshes cannot hold); returns how many."""
    sizes = np.asarray(mesh.face_sizes, dtype=np.int64)
    if not len(sizes):
        return 0
    if np.all(sizes == 3):   # triangles (the usual case): three comparisons, no sort
        corners = mesh.corners.reshape(-1, 3)
        keep = ((corners[:, 0] != corners[:, 1]) & (corners[:, 1] != corners[:, 2])
                & (corners[:, 0] != corners[:, 2]))
    else:
        face_of = np.repeat(np.arange(len(sizes)), sizes)
        keys = face_of * (int(mesh.corners.max(initial=0)) + 1) + mesh.corners
        unique_faces = face_of[np.unique(keys, return_index=True)[1]]
        keep = np.bincount(unique_faces, minlength=len(sizes)) == sizes
    dropped = int((~keep).sum())
    if not dropped:
        return 0
    corner_keep = np.repeat(keep, sizes)
    mesh.face_sizes = sizes[keep]
    mesh.face_symbols = np.asarray(mesh.face_symbols)[keep]
    mesh.corners = mesh.corners[corner_keep]
    if mesh.normals is not None:
        mesh.normals = mesh.normals[corner_keep]
    mesh.uvs = {k: v[corner_keep] for k, v in mesh.uvs.items()}
    mesh.colors = {k: v[corner_keep] for k, v in mesh.colors.items()}
    return dropped


@dataclass
class Instance:
    kind: str                       # geometry, light, camera, node
    url: str
    bindings: dict = field(default_factory=dict)    # symbol -> material id
    uv_bindings: dict = field(default_factory=dict)  # symbol -> {texcoord semantic: set}


@dataclass
class Node:
    id: str
    name: str
    matrix: np.ndarray              # 4x4, local, in the file's units and axes
    children: list = field(default_factory=list)
    instances: list = field(default_factory=list)


@dataclass
class Document:
    path: str
    version: str = "1.4.1"
    meter: float = 1.0
    up_axis: str = "Y_UP"
    materials: dict = field(default_factory=dict)   # id -> Material
    lights: dict = field(default_factory=dict)
    cameras: dict = field(default_factory=dict)
    meshes: dict = field(default_factory=dict)
    library_nodes: dict = field(default_factory=dict)  # id -> Node
    nodes: list = field(default_factory=list)   # roots of the visual scene
    scene_name: str = ""
    warnings: list = field(default_factory=list)

    def warn(self, message: str) -> None:
        if message not in self.warnings:
            self.warnings.append(message)

    def axes(self) -> np.ndarray:
        """4x4 matrix from the file's axes to Blender's (Z up)."""
        out = np.eye(4)
        out[:3, :3] = UP_AXES[self.up_axis]
        return out


# -- parsing helpers -----------------------------------------------------------------------

def _local(tag) -> str:
    return tag.rsplit("}", 1)[-1] if isinstance(tag, str) else ""


def _strip_namespaces(root) -> None:
    for element in root.iter():
        element.tag = _local(element.tag)
        if element.attrib and any("}" in k for k in element.attrib):
            element.attrib = {_local(k): v for k, v in element.attrib.items()}


def _name(element, default=""):
    """An element's exact name (our ``<extra>``), else its ``name``, else *default*."""
    exact = element.find(f"extra/technique[@profile='{PROFILE}']/name")
    if exact is not None and exact.text:
        return exact.text
    return element.get("name") or default


def _ref(url) -> str:
    """The id a URL (``#id``) or an IDREF names."""
    url = (url or "").strip()
    return url[1:] if url.startswith("#") else url


#: Texts shorter than this are read by the plain path (``str.split``); longer ones by numpy's
#: C parsers first (:func:`_bulk_floats`, :func:`_bulk_ints`), with the plain path behind.
BULK = 2048


def _bulk_floats(text: str):
    """The numbers of a long *text* of plain whitespace-separated decimals, read by numpy's C
    parser (``loadtxt``, correctly rounded as ``float()``), or None where it cannot read the
    text: the caller's liberal path reads it then (decimal commas, ...)."""
    flat = text.replace("\n", " ").replace("\r", " ").replace("\t", " ")
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("error")
            return np.loadtxt([flat], dtype=np.float64, comments=None, ndmin=1)
    except (ValueError, TypeError, UserWarning, DeprecationWarning):
        return None


def _bulk_ints(text: str):
    """The integers of a long *text* read by numpy's C parser (``fromstring``), or None
    where it cannot read the text (the caller's path reads it then)."""
    if not text.strip():
        return np.zeros(0, np.int64)   # (fromstring reads blank text as [-1])
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("error")
            return np.fromstring(text, dtype=np.int64, sep=" ")
    except (ValueError, TypeError, DeprecationWarning):
        return None


class _Reader:
    def __init__(self, doc: Document, root):
        self.doc = doc
        self.root = root
        self.ids = {}
        for element in root.iter():
            ident = element.get("id")
            if ident is not None:
                self.ids.setdefault(ident, element)
        self.commas = []   # where decimal commas were read (one warning at the end)

    # numbers ------------------------------------------------------------------------
    def floats(self, element, where, expected=None):
        """The numbers of *element*'s text (decimal commas repaired with one warning)."""
        text = (element.text or "") if element is not None else ""
        values = _bulk_floats(text) if len(text) >= BULK else None
        if values is None:
            words = text.split()
            try:
                values = np.array(words, dtype=np.float64) if words else np.zeros(0)
            except ValueError:
                values = None
        if values is None and "," in text:
            dotted = text.replace(",", ".").split()
            spaced = text.replace(",", " ").split()
            for candidate, what in ((dotted, "decimal commas"), (spaced, "commas between numbers")):
                if expected is not None and len(candidate) != expected and candidate is dotted \
                        and len(spaced) == expected:
                    continue
                try:
                    values = np.array(candidate, dtype=np.float64)
                except ValueError:
                    continue
                if what == "decimal commas":
                    self.commas.append(where)
                else:
                    self.doc.warn(f"{where}: {what} read as numbers")
                break
        if values is None:
            self.doc.warn(f"{where}: numbers that cannot be read; left out")
            return None
        if not np.all(np.isfinite(values)):
            self.doc.warn(f"{where}: NaN or infinite numbers read as 0")
            values = np.nan_to_num(values, nan=0.0, posinf=0.0, neginf=0.0)
        return values

    def ints(self, element, where):
        text = (element.text or "") if element is not None else ""
        values = _bulk_ints(text) if len(text) >= BULK else None
        if values is not None:
            return values
        try:
            return np.array(text.split(), dtype=np.int64)
        except (ValueError, OverflowError):
            values = self.floats(element, where)
            if values is None or np.any(values != np.round(values)):
                self.doc.warn(f"{where}: indices that are not integers; left out")
                return None
            return values.astype(np.int64)

    def number(self, element, where, default=None):
        values = self.floats(element, where) if element is not None else None
        if values is None or not len(values):
            return default
        return float(values[0])

    # asset ----------------------------------------------------------------------------
    def asset(self):
        asset = self.root.find("asset")
        if asset is None:
            return
        unit = asset.find("unit")
        if unit is not None and unit.get("meter") is not None:
            text = unit.get("meter").strip()
            if "," in text and "." not in text:
                self.commas.append("<unit meter>")
                text = text.replace(",", ".")
            try:
                meter = float(text)
            except ValueError:
                meter = float("nan")
            if not math.isfinite(meter) or meter <= 0.0:
                self.doc.warn(f"<unit meter=\"{unit.get('meter')}\"> is not a length; read as 1")
            else:
                self.doc.meter = meter
        up = asset.find("up_axis")
        if up is not None and up.text:
            axis = up.text.strip().upper()
            if axis in UP_AXES:
                self.doc.up_axis = axis
            else:
                self.doc.warn(f"<up_axis>{up.text.strip()}</up_axis> unknown; read as Y_UP")

    # sources ---------------------------------------------------------------------------
    def source(self, ident, where):
        """(values (count, stride) of the source *ident*, stride) or None."""
        element = self.ids.get(_ref(ident))
        if element is None or element.tag != "source":
            self.doc.warn(f"{where}: source {ident} not found; left out")
            return None
        array = element.find("float_array")
        accessor = element.find("technique_common/accessor")
        values = self.floats(array, f"{where}: source {element.get('id')}",
                             _int_attr(array, "count")) if array is not None else None
        if values is None:
            if array is None:
                self.doc.warn(f"{where}: source {element.get('id')} has no float_array; left out")
            return None
        stride = _int_attr(accessor, "stride") or 1
        offset = _int_attr(accessor, "offset") or 0
        if accessor is not None and accessor.get("source") and \
                _ref(accessor.get("source")) not in (array.get("id"), None) and \
                self.ids.get(_ref(accessor.get("source"))) is not None:
            other = self.ids[_ref(accessor.get("source"))]
            if other.tag == "float_array":
                values = self.floats(other, f"{where}: {other.get('id')}")
                if values is None:
                    return None
        stride = max(stride, 1)
        usable = (len(values) - offset) // stride
        count = _int_attr(accessor, "count")
        if count is not None and 0 <= count < usable:
            usable = count
        if usable <= 0:
            return np.zeros((0, stride)), stride
        block = values[offset:offset + usable * stride].reshape(usable, stride)
        return block, stride

    # geometry ----------------------------------------------------------------------------
    def mesh(self, geometry):
        ident = geometry.get("id", "")
        name = _name(geometry, ident)
        where = f"geometry {name}"
        mesh = geometry.find("mesh")
        if mesh is None:
            kinds = [_local(c.tag) for c in geometry if _local(c.tag) not in ("asset", "extra")]
            self.doc.warn(f"{where}: {', '.join(kinds) or 'nothing'} (not a <mesh>); left out")
            return None
        vertices = mesh.find("vertices")
        positions, vertex_extra = None, {}
        if vertices is not None:
            for inp in vertices.findall("input"):
                semantic = (inp.get("semantic") or "").upper()
                got = self.source(inp.get("source"), where)
                if got is None:
                    continue
                if semantic == "POSITION":
                    positions = got[0]
                else:
                    vertex_extra[semantic] = got[0]
        if positions is not None and len(positions) == 0:
            positions = np.zeros((0, 3))
        if positions is not None and positions.shape[1] == 2:
            self.doc.warn(f"{where}: 2D positions read with z = 0")
            positions = np.hstack([positions, np.zeros((len(positions), 1))])
        if positions is None or positions.shape[1] < 3:
            self.doc.warn(f"{where}: no positions; left out")
            return None
        positions = positions[:, :3].copy()
        acc = {"sizes": [], "face_symbols": [], "symbols": [], "corners": [], "normals": [],
               "uvs": {}, "colors": {}, "n_corners": 0, "has_normals": False, "edges": []}
        for prim in mesh:
            kind = prim.tag
            if kind in ("lines", "linestrips"):
                self.lines(prim, kind, positions, acc, where)
                continue
            if kind not in ("triangles", "polylist", "polygons", "tristrips", "trifans"):
                continue
            self.primitive(prim, kind, positions, vertex_extra, acc, where)
        edges = np.concatenate(acc["edges"]) if acc["edges"] else None
        if not acc["sizes"]:
            empty = np.zeros(0, np.int64)
            return Mesh(ident, name, positions, empty, np.zeros(0, np.int32), acc["symbols"],
                        empty.copy(), edges=edges)
        total = acc["n_corners"]
        out = Mesh(ident, name, positions, np.concatenate(acc["sizes"]),
                   np.concatenate(acc["face_symbols"]), acc["symbols"],
                   np.concatenate(acc["corners"]))
        out.from_strips = acc.get("strips", False)
        out.edges = edges
        if acc["has_normals"]:
            out.normals = np.concatenate(acc["normals"])
        for key, target in (("uvs", out.uvs), ("colors", out.colors)):
            width = 2 if key == "uvs" else 4
            for channel, parts in acc[key].items():
                full = np.zeros((total, width)) if key == "uvs" else np.ones((total, width))
                for start, block in parts:
                    full[start:start + len(block)] = block
                target[channel] = full
        return out

    def lines(self, prim, kind, positions, acc, where):
        """``<lines>`` (a pair of vertices per line) and ``<linestrips>`` (one ``<p>`` per
        strip) as edges between positions (loose edges in Blender, as Blender's own OBJ and
        4.2's COLLADA importers keep lines); their material symbol becomes a slot of the
        mesh.  A line with an index out of range, or from a vertex to itself, is left out."""
        symbol = prim.get("material", "")
        label = f"{where}: <{kind} material=\"{symbol}\">"
        offsets = []
        for inp in prim.findall("input"):
            try:
                offsets.append(((inp.get("semantic") or "").upper(), int(inp.get("offset", "0"))))
            except ValueError:
                self.doc.warn(f"{label}: an input's offset is not a number; left out")
                return
        vertex = [offset for semantic, offset in offsets if semantic == "VERTEX"]
        if not vertex:
            self.doc.warn(f"{label}: no VERTEX input; left out")
            return
        stride = max(offset for _semantic, offset in offsets) + 1
        if stride > 64:
            self.doc.warn(f"{label}: {stride} index offsets; left out")
            return
        strips = []
        for p in prim.findall("p"):
            values = self.ints(p, label)
            if values is None:
                return
            strips.append(values[:len(values) - len(values) % stride].reshape(-1, stride)
                          [:, vertex[0]])
        if sum(len(v) for v in strips) > MAX_INDICES:
            self.doc.warn(f"{label}: more than {MAX_INDICES} indices; left out")
            return
        if kind == "lines":
            points = np.concatenate(strips) if strips else np.zeros(0, np.int64)
            pairs = points[:len(points) - len(points) % 2].reshape(-1, 2)
        else:
            pairs = np.concatenate([np.stack([v[:-1], v[1:]], axis=1) for v in strips
                                    if len(v) >= 2] or [np.zeros((0, 2), np.int64)])
        outside = np.any((pairs < 0) | (pairs >= len(positions)), axis=1)
        if np.any(outside):
            self.doc.warn(f"{label}: {int(outside.sum())} line(s) with position indices out "
                          "of range left out")
        pairs = pairs[~outside & (pairs[:, 0] != pairs[:, 1])]
        if not len(pairs):
            return
        acc["edges"].append(pairs)
        if symbol and symbol not in acc["symbols"]:
            acc["symbols"].append(symbol)

    def primitive(self, prim, kind, positions, vertex_extra, acc, where):
        symbol = prim.get("material", "")
        label = f"{where}: <{kind} material=\"{symbol}\">"
        inputs = []
        for inp in prim.findall("input"):
            try:
                offset = int(inp.get("offset", "0"))
                channel = int(inp.get("set", "0") or 0)
            except ValueError:
                self.doc.warn(f"{label}: an input's offset or set is not a number; left out")
                continue
            inputs.append(((inp.get("semantic") or "").upper(), inp.get("source"), offset, channel))
        vertex = [i for i in inputs if i[0] == "VERTEX"]
        if not vertex:
            self.doc.warn(f"{label}: no VERTEX input; left out")
            return
        stride = max(i[2] for i in inputs) + 1
        if stride > 64:
            self.doc.warn(f"{label}: {stride} index offsets; left out")
            return
        # index lists: one per polygon (polygons), strip/fan, or the whole <p>
        lists = []
        for p in prim.findall("p"):
            values = self.ints(p, label)
            if values is None:
                return
            lists.append(values)
        if prim.findall("ph"):
            self.doc.warn(f"{label}: polygons with holes (<ph>) imported without their holes")
            for ph in prim.findall("ph"):
                values = self.ints(ph.find("p"), label)
                if values is not None:
                    lists.append(values)
        if sum(len(v) for v in lists) > MAX_INDICES:
            self.doc.warn(f"{label}: more than {MAX_INDICES} indices; left out")
            return
        if not lists:
            return
        lists = [v[:len(v) - len(v) % stride].reshape(-1, stride) for v in lists]
        if kind == "triangles":
            rows = np.concatenate(lists)
            rows = rows[:len(rows) - len(rows) % 3]
            sizes = np.full(len(rows) // 3, 3, np.int64)
        elif kind == "polylist":
            vcount = self.ints(prim.find("vcount"), label) if prim.find("vcount") is not None \
                else None
            rows = np.concatenate(lists)
            if vcount is None or np.any(vcount < 0) or vcount.sum() > len(rows):
                self.doc.warn(f"{label}: <vcount> does not match <p>; left out")
                return
            sizes = vcount.astype(np.int64)
            rows = rows[:int(sizes.sum())]
        elif kind == "polygons":
            rows = np.concatenate(lists)
            sizes = np.array([len(v) for v in lists], np.int64)
        else:
            parts, size_parts = [], []
            for strip in lists:
                n = len(strip) - 2
                if n <= 0:
                    continue
                k = np.arange(n)
                if kind == "trifans":
                    tri = np.stack([np.zeros(n, np.int64), k + 1, k + 2], axis=1)
                else:   # strip: every other triangle turned to keep its winding
                    even = (k % 2) == 0
                    tri = np.stack([k, np.where(even, k + 1, k + 2),
                                    np.where(even, k + 2, k + 1)], axis=1)
                parts.append(strip[tri.reshape(-1)])
                size_parts.append(np.full(n, 3, np.int64))
            if not parts:
                return
            acc["strips"] = True
            rows = np.concatenate(parts)
            sizes = np.concatenate(size_parts)
        keep = sizes >= 3
        if not np.all(keep):
            self.doc.warn(f"{label}: {int((~keep).sum())} face(s) with fewer than 3 corners "
                          "left out")
            mask = np.repeat(keep, sizes)
            rows, sizes = rows[mask], sizes[keep]
        if not len(sizes):
            return
        # check every index against its source
        vertex_offset = vertex[0][2]
        position_index = rows[:, vertex_offset]
        sources = {}
        for semantic, source, offset, channel in inputs:
            if semantic not in ("NORMAL", "TEXCOORD", "COLOR"):
                continue    # VERTEX above; TANGENT, CUSTOM ... the model does not read
            got = self.source(source, label)
            if got is None:
                continue
            sources[(semantic, channel, offset)] = got[0]
        bad = (position_index < 0) | (position_index >= len(positions))
        if np.any(bad):
            face_of = np.repeat(np.arange(len(sizes)), sizes)
            bad_faces = np.unique(face_of[bad])
            self.doc.warn(f"{label}: {len(bad_faces)} face(s) with position indices out of "
                          "range left out")
            keep = np.ones(len(sizes), bool)
            keep[bad_faces] = False
            mask = np.repeat(keep, sizes)
            rows, sizes = rows[mask], sizes[keep]
            position_index = rows[:, vertex_offset]
            if not len(sizes):
                return
        start = acc["n_corners"]
        if symbol not in acc["symbols"]:
            acc["symbols"].append(symbol)
        acc["sizes"].append(sizes)
        acc["face_symbols"].append(np.full(len(sizes), acc["symbols"].index(symbol), np.int32))
        acc["corners"].append(position_index)
        normals = None
        missing = []
        for (semantic, channel, offset), data in sources.items():
            index = rows[:, offset]
            outside = (index < 0) | (index >= len(data))
            if np.any(outside):   # the corner keeps its position; this value is left out
                missing.append(f"{int(outside.sum())} {semantic}")
                data = np.vstack([data, np.full((1, data.shape[1]),
                                                1.0 if semantic == "COLOR" else 0.0)])
                index = np.where(outside, len(data) - 1, index)
            if semantic == "NORMAL" and normals is None and data.shape[1] >= 3:
                normals = data[index, :3]
            elif semantic == "TEXCOORD" and data.shape[1] >= 2:
                acc["uvs"].setdefault(channel, []).append((start, data[index, :2]))
            elif semantic == "COLOR" and data.shape[1] >= 3:
                block = np.ones((len(index), 4))
                block[:, :min(4, data.shape[1])] = data[index, :4]
                acc["colors"].setdefault(channel, []).append((start, block))
        if normals is None and "NORMAL" in vertex_extra and \
                len(vertex_extra["NORMAL"]) >= len(positions):
            normals = vertex_extra["NORMAL"][position_index, :3]
        if normals is not None:
            if not acc["has_normals"] and start:
                acc["normals"].insert(0, np.zeros((start, 3)))
            acc["has_normals"] = True
            acc["normals"].append(normals)
        elif acc["has_normals"]:
            acc["normals"].append(np.zeros((len(rows), 3)))
        acc["n_corners"] += len(rows)
        if missing:
            self.doc.warn(f"{label}: indices out of range for {', '.join(missing)} corner "
                          "value(s); those values left out (zero normal, UV (0, 0), white)")

    # effects and materials -------------------------------------------------------------
    def params(self, *scopes):
        """{sid: newparam element} of *scopes* (later scopes win)."""
        out = {}
        for scope in scopes:
            if scope is None:
                continue
            for param in scope.findall("newparam"):
                if param.get("sid"):
                    out[param.get("sid")] = param
        return out

    def material(self, element):
        ident = element.get("id", "")
        name = _name(element, ident)
        where = f"material {name}"
        out = Material(ident, name)
        inst = element.find("instance_effect")
        effect = self.ids.get(_ref(inst.get("url"))) if inst is not None else None
        if effect is None or effect.tag != "effect":
            self.doc.warn(f"{where}: effect {inst.get('url') if inst is not None else '(none)'} "
                          "not found; imported black")
            out.technique = "lambert"
            return out
        out.effect_id = effect.get("id", "")
        profile = effect.find("profile_COMMON")
        if profile is None:
            profiles = [c.tag for c in effect if c.tag.startswith("profile_")]
            self.doc.warn(f"{where}: no profile_COMMON ({', '.join(profiles) or 'no profile'}); "
                          "imported black")
            out.technique = "lambert"
            return out
        technique_element = profile.find("technique")
        shading = None
        if technique_element is not None:
            shading = next((c for c in technique_element if c.tag in TECHNIQUES), None)
        if shading is None:
            self.doc.warn(f"{where}: no constant, lambert, phong or blinn technique; "
                          "imported black")
            out.technique = "lambert"
            return out
        out.technique = shading.tag
        params = self.params(effect, profile, technique_element)
        setparams = {}
        if inst is not None:
            for setparam in inst.findall("setparam"):
                if setparam.get("ref"):
                    setparams[setparam.get("ref")] = setparam
        context = (params, setparams, where)
        for child in shading:
            tag = child.tag
            if tag in ("emission", "ambient", "diffuse", "specular", "transparent"):
                color, texture = self.color_or_texture(child, context)
                if tag == "transparent":
                    mode = (child.get("opaque") or "A_ONE").strip().upper()
                    if mode not in OPAQUE_MODES:
                        self.doc.warn(f"{where}: <transparent opaque=\"{mode}\"> unknown; "
                                      "read as A_ONE")
                        mode = "A_ONE"
                    out.opaque = mode
                    if texture is not None:
                        out.transparent_texture = texture
                    elif color is not None:
                        out.transparent = color
                    continue
                if color is not None:
                    out.colors[tag] = color
                if texture is not None:
                    out.textures[tag] = texture
                    out.colors.setdefault(tag, (1.0, 1.0, 1.0, 1.0))
            elif tag in ("shininess", "transparency"):
                value = self.float_value(child, context)
                if value is not None:
                    setattr(out, tag, value)
        return out

    def _param_value(self, ref, context, kinds):
        params, setparams, where = context
        source = setparams.get(ref) if ref in setparams else params.get(ref)
        if source is None:
            return None
        for kind in kinds:
            value = source.find(kind)
            if value is not None:
                return self.floats(value, f"{where}: <{kind}> of {ref}")
        return None

    def color_or_texture(self, element, context):
        where = context[2]
        color = element.find("color")
        if color is not None:
            values = self.floats(color, f"{where}: <{element.tag}>")
            if values is not None and len(values) >= 3:
                a = float(values[3]) if len(values) >= 4 else 1.0
                return (float(values[0]), float(values[1]), float(values[2]), a), None
            self.doc.warn(f"{where}: <{element.tag}> colour that cannot be read; left out")
            return None, None
        param = element.find("param")
        if param is not None:
            values = self._param_value(param.get("ref", ""), context,
                                       ("float4", "float3", "color", "float"))
            if values is not None and len(values) >= 3:
                a = float(values[3]) if len(values) >= 4 else 1.0
                return (float(values[0]), float(values[1]), float(values[2]), a), None
            if values is not None and len(values) == 1:
                v = float(values[0])
                return (v, v, v, 1.0), None
            self.doc.warn(f"{where}: <{element.tag}> parameter {param.get('ref')} not found; "
                          "left out")
            return None, None
        texture = element.find("texture")
        if texture is not None:
            found = self.texture(texture.get("texture", ""), texture.get("texcoord", ""),
                                 context)
            if found is None:
                self.doc.warn(f"{where}: <{element.tag}> texture {texture.get('texture')} not "
                              "resolved to an image; left out")
            return None, found
        return None, None

    def float_value(self, element, context):
        where = context[2]
        value = element.find("float")
        if value is not None:
            return self.number(value, f"{where}: <{element.tag}>")
        param = element.find("param")
        if param is not None:
            values = self._param_value(param.get("ref", ""), context, ("float",))
            if values is not None and len(values):
                return float(values[0])
            self.doc.warn(f"{where}: <{element.tag}> parameter {param.get('ref')} not found; "
                          "left out")
        return None

    def texture(self, name, texcoord, context, depth=0):
        """The Texture a ``<texture texture=...>`` names: the spec's sampler → surface →
        image chain (setparam first), 1.5's instance_image, or (as other readers accept)
        an image id, image name or a file name."""
        params, setparams, where = context
        if depth > 8:
            return None
        param = setparams.get(name) if name in setparams else params.get(name)
        if param is not None:
            sampler = next((c for c in param if c.tag.startswith("sampler")), None)
            surface = param.find("surface")
            if sampler is not None:
                inst = sampler.find("instance_image")
                if inst is not None:
                    return self.image(_ref(inst.get("url")), texcoord, where)
                src = sampler.find("source")
                if src is not None and src.text:
                    return self.texture(src.text.strip(), texcoord, context, depth + 1)
            if surface is not None:
                init = surface.find("init_from")
                if init is not None and init.text and init.text.strip():
                    return self.image(init.text.strip(), texcoord, where)
                inst = surface.find("init_from/ref")
                if inst is not None and inst.text:
                    return self.image(inst.text.strip(), texcoord, where)
                # init_planar / init_volume / init_cube: <all ref="image"/> (or the first face)
                ref = next((e.get("ref") for e in surface.iter() if e.get("ref")), None)
                if ref:
                    return self.image(ref, texcoord, where)
        return self.image(name, texcoord, where, liberal=True)

    def image(self, ident, texcoord, where, liberal=False):
        element = self.ids.get(ident)
        if element is None or element.tag != "image":
            element = next((i for i in self.root.iter("image") if i.get("name") == ident), None)
        if element is None:
            if liberal and os.path.splitext(ident)[1]:
                return self.texture_file(ident, texcoord, ident)
            return None
        init = element.find("init_from")
        text = None
        if init is not None:
            ref = init.find("ref")
            text = ref.text if ref is not None else init.text
        if not text or not text.strip():
            self.doc.warn(f"{where}: image {ident} has no file; left out")
            return None
        return self.texture_file(text.strip(), texcoord, element.get("id", ident))

    def texture_file(self, written, texcoord, image_id):
        folder = os.path.dirname(os.path.abspath(self.doc.path))
        path = _uri_path(written)
        candidates = []
        if os.path.isabs(path):
            candidates.append(path)
        candidates.append(os.path.normpath(os.path.join(folder, path.replace("\\", "/"))))
        candidates.append(os.path.join(folder, os.path.basename(path.replace("\\", "/"))))
        resolved = next((c for c in candidates if os.path.isfile(c)), candidates[0])
        return Texture(written, resolved, texcoord, image_id)

    # lights and cameras --------------------------------------------------------------------
    def light(self, element):
        ident = element.get("id", "")
        name = _name(element, ident)
        common = element.find("technique_common")
        kind_element = next((c for c in common if c.tag in LIGHT_KINDS), None) \
            if common is not None else None
        if kind_element is None:
            self.doc.warn(f"light {name}: no ambient, directional, point or spot; left out")
            return None
        where = f"light {name}"
        out = Light(ident, name, kind_element.tag)
        color = kind_element.find("color")
        values = self.floats(color, f"{where}: <color>") if color is not None else None
        if values is not None and len(values) >= 3:
            out.color = tuple(float(v) for v in values[:3])
        for attr, tag in (("constant", "constant_attenuation"),
                          ("linear", "linear_attenuation"),
                          ("quadratic", "quadratic_attenuation"),
                          ("falloff_angle", "falloff_angle"),
                          ("falloff_exponent", "falloff_exponent")):
            child = kind_element.find(tag)
            if child is not None:
                value = self.number(child, f"{where}: <{tag}>")
                if value is not None:
                    setattr(out, attr, value)
        if out.kind in ("point", "spot"):
            if min(out.constant, out.linear, out.quadratic) < 0.0:
                self.doc.warn(f"{where}: negative attenuation read as 0")
                out.constant, out.linear, out.quadratic = (max(v, 0.0) for v in (
                    out.constant, out.linear, out.quadratic))
        return out

    def camera(self, element):
        ident = element.get("id", "")
        name = _name(element, ident)
        common = element.find("optics/technique_common")
        kind = next((c for c in common if c.tag in ("perspective", "orthographic")), None) \
            if common is not None else None
        if kind is None:
            self.doc.warn(f"camera {name}: no perspective or orthographic optics; left out")
            return None
        out = Camera(ident, name, kind.tag)
        for attr in ("xfov", "yfov", "xmag", "ymag", "aspect_ratio", "znear", "zfar"):
            child = kind.find(attr)
            if child is not None:
                value = self.number(child, f"camera {name}: <{attr}>")
                if value is not None:
                    setattr(out, attr, value)
        return out

    # scene -----------------------------------------------------------------------------------
    def node(self, element, depth=0):
        ident = element.get("id", "")
        name = _name(element, ident) or element.get("sid") or "node"
        matrix = np.eye(4)
        for child in element:
            local = transform(child, self, f"node {name}")
            if local is not None:
                matrix = matrix @ local
        out = Node(ident, name, matrix)
        if depth > 256:
            self.doc.warn(f"node {name}: nested more than 256 deep; the rest left out")
            return out
        for child in element:
            tag = child.tag
            if tag == "node":
                out.children.append(self.node(child, depth + 1))
            elif tag in ("instance_geometry", "instance_light", "instance_camera",
                         "instance_node", "instance_controller"):
                kind = tag.removeprefix("instance_")
                inst = Instance(kind, _ref(child.get("url")))
                if kind == "controller":
                    self.doc.warn(f"node {name}: <instance_controller> (skinning) imported as "
                                  "its skin's mesh at rest")
                    controller = self.ids.get(inst.url)
                    skin = controller.find("skin") if controller is not None else None
                    if skin is None:
                        continue
                    inst = Instance("geometry", _ref(skin.get("source")))
                for im in child.iter("instance_material"):
                    symbol = im.get("symbol", "")
                    inst.bindings[symbol] = _ref(im.get("target"))
                    uv = {}
                    for bvi in im.findall("bind_vertex_input"):
                        try:
                            uv[bvi.get("semantic", "")] = int(bvi.get("input_set", "0") or 0)
                        except ValueError:
                            pass
                    inst.uv_bindings[symbol] = uv
                out.instances.append(inst)
        return out


TRANSFORMS = ("matrix", "translate", "rotate", "scale", "lookat", "skew")


def transform(element, reader, where):
    """The 4x4 matrix of one transform element (None for other elements)."""
    tag = element.tag
    if tag not in TRANSFORMS:
        return None
    sizes = {"matrix": 16, "translate": 3, "rotate": 4, "scale": 3, "lookat": 9, "skew": 7}
    values = reader.floats(element, f"{where}: <{tag}>")
    if values is None or len(values) < sizes[tag]:
        reader.doc.warn(f"{where}: <{tag}> with fewer than {sizes[tag]} numbers; left out")
        return None
    v = values[:sizes[tag]]
    out = np.eye(4)
    if tag == "matrix":
        out = v.reshape(4, 4).copy()
    elif tag == "translate":
        out[:3, 3] = v
    elif tag == "scale":
        out[:3, :3] = np.diag(v)
    elif tag == "rotate":
        out[:3, :3] = rotation(v[:3], math.radians(v[3]))
    elif tag == "lookat":
        out = lookat(v[0:3], v[3:6], v[6:9])
    else:
        out[:3, :3] = skew(math.radians(v[0]), v[1:4], v[4:7])
    return out


def rotation(axis, angle) -> np.ndarray:
    axis = np.asarray(axis, dtype=np.float64)
    length = np.linalg.norm(axis)
    if length == 0.0:
        return np.eye(3)
    x, y, z = axis / length
    c, s = math.cos(angle), math.sin(angle)
    t = 1.0 - c
    return np.array([[t * x * x + c, t * x * y - s * z, t * x * z + s * y],
                     [t * x * y + s * z, t * y * y + c, t * y * z - s * x],
                     [t * x * z - s * y, t * y * z + s * x, t * z * z + c]])


def lookat(eye, interest, up) -> np.ndarray:
    """The spec's ``<lookat>``: the node at *eye*, its −Z towards *interest*, +Y towards
    *up* (as gluLookAt's inverse: a camera or light there looks at the interest point)."""
    eye, interest, up = (np.asarray(a, dtype=np.float64) for a in (eye, interest, up))
    z = eye - interest
    out = np.eye(4)
    out[:3, 3] = eye
    if np.linalg.norm(z) == 0.0:
        return out
    z = z / np.linalg.norm(z)
    x = np.cross(up, z)
    if np.linalg.norm(x) < 1e-12:    # up along the view: any perpendicular
        x = np.cross((1.0, 0.0, 0.0) if abs(z[0]) < 0.9 else (0.0, 1.0, 0.0), z)
    x = x / np.linalg.norm(x)
    y = np.cross(z, x)
    out[:3, 0], out[:3, 1], out[:3, 2] = x, y, z
    return out


def skew(angle, rotate_axis, translate_axis) -> np.ndarray:
    """RenderMan's skew (the spec's ``<skew>``): points move parallel to *translate_axis*
    by an amount proportional to their distance along the component of *rotate_axis*
    perpendicular to it, so that *rotate_axis* turns by *angle*."""
    a = np.asarray(rotate_axis, dtype=np.float64)
    b = np.asarray(translate_axis, dtype=np.float64)
    if np.linalg.norm(a) == 0.0 or np.linalg.norm(b) == 0.0:
        return np.eye(3)
    b = b / np.linalg.norm(b)
    a = a / np.linalg.norm(a)
    a1 = a - np.dot(a, b) * b       # the part of a perpendicular to b
    if np.linalg.norm(a1) < 1e-12:
        return np.eye(3)
    a1 = a1 / np.linalg.norm(a1)
    an1, an2 = np.dot(a, a1), np.dot(a, b)
    rx = an1 * math.cos(angle) - an2 * math.sin(angle)
    ry = an1 * math.sin(angle) + an2 * math.cos(angle)
    if rx <= 1e-12:
        return np.eye(3)
    alpha = 0.0 if an1 == 0.0 else (ry / rx - an2 / an1)
    return np.eye(3) + alpha * np.outer(b, a1)


def _int_attr(element, name):
    if element is None or element.get(name) is None:
        return None
    try:
        return int(element.get(name).strip())
    except ValueError:
        return None


# -- reading ------------------------------------------------------------------------------

class _Started(Exception):
    """The root element began: no entity was declared before it."""


def _refuse_entities(data: bytes, path: str) -> None:
    """ColladaError when the document type declares an entity (internal or external), found
    by expat itself (so in any encoding) before the root element; nothing is expanded."""
    scan = expat.ParserCreate()

    def declared(*_args):
        raise ColladaError(path, "declares XML entities (<!DOCTYPE ... <!ENTITY>); refused "
                                 "(entity expansion and external entities are not read)")

    def started(*_args):
        raise _Started

    scan.EntityDeclHandler = declared
    scan.UnparsedEntityDeclHandler = declared
    scan.StartElementHandler = started
    try:
        scan.Parse(data, True)
    except (_Started, expat.ExpatError):   # a parse error is reported by the parse itself
        return


def parse_bytes(data: bytes, path: str = "<bytes>") -> Document:
    """Read COLLADA from *data*; raises ColladaError for what is not COLLADA XML."""
    _refuse_entities(data, path)
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
    reader = _Reader(doc, root)
    reader.asset()
    for element in root.iter("material"):
        if element.get("id") is None and element.get("name") is None:
            continue
        material = reader.material(element)
        doc.materials.setdefault(material.id or material.name, material)
    lights = list(root.iter("light"))
    defined = {e.get("id") for e in lights if e.find("technique_common") is not None}
    for element in lights:
        if element.find("technique_common") is None and element.get("id") in defined:
            continue    # an empty twin of a light defined elsewhere (Maya's exporter)
        light = reader.light(element)
        if light is not None:
            doc.lights.setdefault(light.id or light.name, light)
    for element in root.iter("camera"):
        camera = reader.camera(element)
        if camera is not None:
            doc.cameras.setdefault(camera.id or camera.name, camera)
    for element in root.iter("geometry"):
        mesh = reader.mesh(element)
        if mesh is not None:
            doc.meshes.setdefault(mesh.id or mesh.name, mesh)
    for lib in root.findall("library_nodes"):
        for element in lib.findall("node"):
            node = reader.node(element)
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
        doc.nodes = [reader.node(n) for n in chosen.findall("node")]
    if reader.commas:
        places = list(dict.fromkeys(reader.commas))
        more = f" and {len(places) - 3} more" if len(places) > 3 else ""
        doc.warn(f"decimal commas read as decimal points ({', '.join(places[:3])}{more})")
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


# -- converting units and axes -------------------------------------------------------------

def to_blender(doc: Document, matrix: np.ndarray, root: bool) -> np.ndarray:
    """A node's local matrix in Blender's metres: the translation times ``meter`` (the
    geometry is scaled by :func:`scale_positions`), and for a root node the up axis's
    rotation in front."""
    out = np.array(matrix, dtype=np.float64)
    out[:3, 3] *= doc.meter
    return doc.axes() @ out if root else out


def attenuation(doc: Document, light: Light) -> tuple:
    """(constant, linear, quadratic) with d in metres: 1/(c + l·d + q·d²) with d in the
    file's units equals 1/(c + l'·d' + q'·d'²) with d' = d·meter: l' = l/m, q' = q/m²."""
    m = doc.meter
    return light.constant, light.linear / m, light.quadratic / (m * m)


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


PROFILE = "phong_nodes"   # the <technique profile> of our <extra>: an exact name


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
                if "transparent" in mat.textures:   # an opacity map (issue 35)
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
