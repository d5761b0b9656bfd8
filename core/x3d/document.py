# SPDX-License-Identifier: GPL-3.0-or-later
"""One file as plain data (:class:`Document`), and the public reading functions :func:`loads`
and :func:`load`, which read one and flatten it.

* :class:`Document` — one file: ``path``, ``encoding`` ("vrml97", "x3d-classic" or
  "x3d-xml"), ``version`` ("2.0", "3.3", "4.0" ...), ``profile``, ``meter`` (metres per length
  unit: X3D 3.3's ``UNIT length``; 1 otherwise), ``root`` (a :class:`Transform`, kind "Scene":
  the file's top-level nodes are its children; ``roots`` is that list), ``headlight`` (the
  first NavigationInfo's, default True), ``navigation_types``, ``viewpoint`` (the bound — first —
  :class:`Viewpoint` or OrthoViewpoint of the file, None without one) and ``viewpoint_matrix``
  (its world matrix: the matrix of the groups above it), ``title`` and ``info`` (WorldInfo),
  ``background`` (Background skyColor[0] or None), ``meta`` ({name: content}), ``warnings``
  (strings: each kind of problem once, with a count), and the flattened scene:
  ``instances`` (:class:`ShapeInstance` list) and ``lights`` (:class:`LightInstance` list),
  computed by :meth:`Document.flatten` (``load`` calls it).
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from .model import NAME_PREFIX, _Notes, Transform, Viewpoint, _eye
from .context import _Reading
from .files import _read_file, parse, resolve_local
from .build import build, finish
from .flatten import _flatten


@dataclass(eq=False)
class Document:
    path: str = ""
    encoding: str = "x3d-xml"
    version: str = "3.3"
    profile: str = "Immersive"
    meter: float = 1.0
    unit_name: str = ""
    root: Transform = field(default_factory=lambda: Transform(kind="Scene"))
    headlight: bool = True
    navigation_types: list = field(default_factory=lambda: ["EXAMINE", "ANY"])
    #: NavigationInfo's avatarSize where it is not the default (0.25 1.6 0.75): browsers clip
    #: what is nearer than avatarSize[0] / 2 to the viewer (the writer's, from the camera)
    avatar_size: tuple | None = None
    viewpoint: Viewpoint | None = None
    viewpoint_matrix: np.ndarray = field(default_factory=_eye)
    title: str = ""
    info: list = field(default_factory=list)
    background: tuple | None = None
    meta: dict = field(default_factory=dict)
    warnings: list = field(default_factory=list)
    instances: list = field(default_factory=list)
    lights: list = field(default_factory=list)

    @property
    def roots(self) -> list:
        return self.root.children

    def warn(self, message: str) -> None:
        if message not in self.warnings:
            self.warnings.append(message)

    def flatten(self):
        """Every shape instance with its world matrix and stable id, and every light
        instance with its world matrix and scope (``instances``, ``lights``; also
        ``viewpoint_matrix``); returns (instances, lights).  At most MAX_INSTANCES."""
        notes = _Notes()
        _flatten(self, notes)
        for line in notes.lines():
            self.warn(line)
        return self.instances, self.lights

    def materials(self) -> list:
        """The distinct materials of the instances, in order of first use."""
        seen, out = set(), []
        for inst in self.instances:
            mat = inst.shape.material
            if mat is not None and id(mat) not in seen:
                seen.add(id(mat))
                out.append(mat)
        return out


# -- the public reading functions -----------------------------------------------------------

def loads(data, path: str = "<string>", resolver=None) -> Document:
    """Read VRML97 / X3D from *data* (bytes or str; gzip or not); *path* names it and is the
    base of relative URLs; *resolver* (url, base folder) → local path or None resolves
    Inline, EXTERNPROTO and texture URLs (default :func:`resolve_local`).  Raises
    X3DError for what is not VRML97 / X3D at all; everything else is a warning."""
    ctx = _Reading(resolver or resolve_local)
    src = parse(ctx, data, path, 0)
    ctx.main = src
    x3d = src.encoding != "vrml97"
    doc = Document(path=path, encoding=src.encoding, version=src.version, profile=src.profile,
                   meter=src.meter, unit_name=src.unit_name, meta=dict(src.meta),
                   navigation_types=["EXAMINE", "ANY"] if x3d else ["WALK", "ANY"])
    ctx.doc = doc
    for node in src.nodes:
        child = build(ctx, node, 1, "", "child")
        if child is not None:
            doc.root.children.append(child)
    exact = {}
    kept = []
    for line in doc.info:
        if line.startswith(NAME_PREFIX) and "=" in line:
            key, _, name = line[len(NAME_PREFIX):].partition("=")
            exact[key] = name
        else:
            kept.append(line)
    if exact:
        doc.info = kept
        for _node, obj in ctx.memo.values():
            if obj is not None and getattr(obj, "name", None) in exact:
                obj.name = exact[obj.name]
    _flatten(doc, ctx.notes)
    finish(ctx, doc)
    return doc


def load(path: str, resolver=None) -> Document:
    """Read the VRML97 / X3D file *path* (``.wrl``, ``.x3dv``, ``.x3d``, gzipped or not);
    raises X3DError for a missing file or one that is not VRML97 / X3D at all."""
    return loads(_read_file(path), path, resolver)
