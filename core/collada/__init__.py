# SPDX-License-Identifier: GPL-3.0-or-later
"""COLLADA (.dae) files read and written without ``bpy``.

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

The package, each module importing only those before it (``tests/test_layout.py``):
``model`` (the document as plain data, its units and axes, image URIs), ``context`` (one
reading's context: the document, the elements by id, the decimal commas met; every function
of the reading is handed it, so each module's dependencies are its imports), ``numbers``
(numbers of an element's text), ``geometry`` (meshes), ``effects`` (materials and their
effects), ``lights_cameras`` (lights and cameras), ``nodes`` (the scene graph and its
transforms), ``read`` (:func:`load`, :func:`parse_bytes`), ``write`` (:func:`dumps`); the XML
hardening is ``core/xmlsafe.py``, shared with X3D.  Every name callers use is imported here:
``collada.load(path)``.
"""

from .model import (
    LIGHT_KINDS, MAX_BYTES, MAX_INDICES, NS14, NS15, OPAQUE_MODES, PROFILE, TECHNIQUE_COLORS,
    TECHNIQUES, UP_AXES, Camera, ColladaError, Document, Instance, Light, Material, Mesh, Node,
    Texture, attenuation, drop_degenerate, to_blender, _uri_path, uri_quote)
from .numbers import BULK
from .nodes import TRANSFORMS, lookat, rotation, skew, transform
from .read import load, parse_bytes
from .write import dumps, fmt, ncname

__all__ = [
    "LIGHT_KINDS", "MAX_BYTES", "MAX_INDICES", "NS14", "NS15", "OPAQUE_MODES", "PROFILE",
    "TECHNIQUE_COLORS", "TECHNIQUES", "UP_AXES", "Camera", "ColladaError", "Document", "Instance",
    "Light", "Material", "Mesh", "Node", "Texture", "attenuation", "drop_degenerate",
    "to_blender", "uri_quote", "BULK", "TRANSFORMS", "load", "lookat", "parse_bytes",
    "rotation", "skew", "transform", "dumps", "fmt", "ncname",
]
