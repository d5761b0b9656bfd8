# SPDX-License-Identifier: GPL-3.0-or-later
"""The XML hardening that COLLADA (``core/collada/``) and X3D (``core/x3d/``) share.

* :func:`refuse_entities`: a document type that declares an entity (internal or external) is
  refused before parsing, found by expat itself (so in any encoding) before the root element;
  nothing is expanded (no "billion laughs") and no external entity is ever resolved (expat
  resolves none by itself).
* :func:`local`: an element's or attribute's name without its namespace (``{uri}name``).
* :func:`unquote`: percent-escapes decoded as UTF-8 (a URL or an image's URI); a malformed one
  is kept as written.  Not urllib: the extension imports no network module.
"""

from __future__ import annotations

import re
import xml.parsers.expat as expat


class _Started(Exception):
    """The root element began: no entity was declared before it."""


def refuse_entities(data: bytes, path: str, error) -> None:
    """``error(path, message)`` raised when the document type of *data* declares an entity
    (internal or external), found by expat before the root element; nothing is expanded.
    A parse error is left to the parse itself to report."""
    scan = expat.ParserCreate()

    def declared(*_args):
        raise error(path, "declares XML entities (<!DOCTYPE ... <!ENTITY>); refused "
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


def local(tag) -> str:
    """*tag* without its namespace; "" for what is not a name (a comment's tag)."""
    return tag.rsplit("}", 1)[-1] if isinstance(tag, str) else ""


def unquote(text: str) -> str:
    """Percent-escapes decoded as UTF-8; a malformed one is kept as written."""
    raw = text.encode("utf-8", "surrogateescape")
    decoded = re.sub(rb"%([0-9A-Fa-f]{2})", lambda m: bytes([int(m.group(1), 16)]), raw)
    return decoded.decode("utf-8", "replace")
