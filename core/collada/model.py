# SPDX-License-Identifier: GPL-3.0-or-later
"""The COLLADA document as plain data (:class:`Document`: materials of the ``profile_COMMON``
techniques, lights, cameras, meshes, nodes), its units and axes (:func:`to_blender`,
:func:`attenuation`), the image URIs as written and read (:func:`uri_quote`,
:func:`_uri_path`), and :class:`ColladaError`.
"""

from __future__ import annotations

import os
import re
from dataclasses import dataclass, field

import numpy as np

from ..xmlsafe import unquote as _unquote


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
PROFILE = "phong_nodes"   # the <technique profile> of our <extra>: an exact name


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
    transparent_texture: Texture | None = None   # <transparent><texture>: an opacity map

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
