# SPDX-License-Identifier: GPL-3.0-or-later
"""Files: reading one (at most :data:`MAX_BYTES`, gzip found by its magic bytes), resolving
the URLs that name others (:func:`resolve_local`), and a file's encoding sniffed and its
text handed to its parser (:func:`parse`: headers, UNIT; :func:`parse_file`: Inline and
EXTERNPROTO files, parsed once a reading, nested at most :data:`MAX_INLINE_DEPTH` deep).
"""

from __future__ import annotations

import os
import re
import zlib

from .. import xmlsafe
from ..xmlsafe import local as _local, unquote as _unquote
from .model import X3DError
from .graph import _Source, unit
from .parse_classic import _Classic, _strip_comments
from .parse_xml import _Xml, _xml_root


#: Largest file read, in bytes (also the largest decompressed size of a gzipped file).
MAX_BYTES = 1 << 30
#: Deepest nesting of Inline files (and EXTERNPROTO files).
MAX_INLINE_DEPTH = 8


# -- reading files -------------------------------------------------------------------------

_GZIP_MAGIC = b"\x1f\x8b"
_HEADER = re.compile(r"#\s*(VRML|X3D)\s+V(\d+(?:\.\d+)?)[ \t]*([^\r\n]*)", re.I)


def _read_file(path: str) -> bytes:
    try:
        size = os.path.getsize(path)
        if size > MAX_BYTES:
            raise X3DError(path, f"{size} bytes: larger than {MAX_BYTES} bytes; refused")
        with open(path, "rb") as handle:
            return handle.read(MAX_BYTES + 1)
    except OSError as error:
        raise X3DError(path, error.strerror or str(error)) from None


def _gunzip(data: bytes, path: str, notes) -> bytes:
    """*data* decompressed when it is gzip (by its magic bytes, whatever the file's name;
    members one after the other), at most MAX_BYTES; a stream that breaks off keeps what
    decompressed, with a warning."""
    if not data.startswith(_GZIP_MAGIC):
        return data
    parts, total, rest = [], 0, data
    while rest.startswith(_GZIP_MAGIC):
        stream = zlib.decompressobj(16 + zlib.MAX_WBITS)
        try:
            chunk = stream.decompress(rest, MAX_BYTES + 1 - total)
        except zlib.error as error:
            if not total:
                raise X3DError(path, f"gzip data that cannot be decompressed ({error})") from None
            notes.add("gzip streams that break off: the part decompressed is read",
                      os.path.basename(path))
            break
        parts.append(chunk)
        total += len(chunk)
        if total > MAX_BYTES or stream.unconsumed_tail:
            raise X3DError(path, f"decompresses to more than {MAX_BYTES} bytes; refused")
        if not stream.eof:
            if not total:
                raise X3DError(path, "gzip data that ends before anything decompressed")
            notes.add("gzip streams that break off: the part decompressed is read",
                      os.path.basename(path))
            break
        rest = stream.unused_data
    return b"".join(parts)


def resolve_local(url: str, base: str) -> str | None:
    """The default resolver: the local file a URL names, relative to the folder *base* of the
    file that names it (``file:`` URLs and Windows paths included, percent-escapes decoded,
    a ``#fragment`` dropped); None for a URL of another scheme (http, urn, data: nothing is
    fetched).  A resolver is any callable (url, base) → path or None."""
    url = url.strip()
    if not url:
        return None
    lower = url.lower()
    if lower.startswith("file:"):
        path = url[5:]
        if path.startswith("//"):
            path = "/" + path[2:].partition("/")[2]
        if re.match(r"^/[A-Za-z]:", path):
            path = path[1:]
    elif re.match(r"^[a-z][a-z0-9+.\-]+:", lower) and not re.match(r"^[a-z]:[\\/]", lower):
        return None
    else:
        path = url
    path = path.split("#", 1)[0]
    if not path:
        return None
    if "%" in path and not os.path.exists(os.path.join(base, path)):
        path = _unquote(path)
    path = path.replace("\\", "/")
    if not os.path.isabs(path) and not re.match(r"^[A-Za-z]:/", path):
        path = os.path.join(base, path)
    return os.path.normpath(path)


# files of a reading ----------------------------------------------------------------

def parse(ctx, data, path, depth=0):
    """A file's bytes (gzip or not) into a _Source: its top-level nodes and PROTOs."""
    if isinstance(data, str):
        data = data.encode("utf-8")
    if len(data) > MAX_BYTES:
        raise X3DError(path, f"{len(data)} bytes: larger than {MAX_BYTES} bytes; refused")
    data = _gunzip(data, path, ctx.notes)
    head = data[:256].lstrip(b"\xef\xbb\xbf \t\r\n")
    if head.startswith(b"<"):
        return parse_xml(ctx, data, path, depth)
    try:
        text = data.decode("utf-8")
    except UnicodeDecodeError:
        text = data.decode("latin-1")
        ctx.notes.add("files that are not UTF-8, read as Latin-1", os.path.basename(path))
    text = text.lstrip("\ufeff \t\r\n")
    first = text.split("\n", 1)[0]
    match = _HEADER.match(first)
    header = True
    if match is None:
        header = False
        lower = path.lower()
        classic = lower.endswith((".x3dv", ".x3dvz", ".x3dv.gz"))
        encoding, version = ("x3d-classic", "3.0") if classic else ("vrml97", "2.0")
    else:
        kind, version = match.group(1).upper(), match.group(2)
        if kind == "VRML" and not version.startswith("2"):
            raise X3DError(path, f"a VRML {version} file: VRML 1.0 is not read (only VRML97 "
                                 "'#VRML V2.0 utf8' and X3D)")
        encoding = "vrml97" if kind == "VRML" else "x3d-classic"
        text = text[len(first):]
    src = _Source(path, encoding, version, depth)
    parser = _Classic(_strip_comments(text), src, ctx)
    parser.statements(src.nodes, 1)
    if parser.truncated:
        ctx.notes.add("files that end inside a node, a list or a string (truncated?): "
                      "what came before is read", os.path.basename(path))
    if not header:
        if not src.nodes and not src.scope.protos:
            raise X3DError(path, "not a VRML97 or X3D file (no '#VRML V2.0 utf8' or "
                                 "'#X3D' header, and no node)")
        ctx.notes.add("files without a '#VRML V2.0 utf8' header, read as " + encoding,
                      os.path.basename(path))
    return src


def parse_xml(ctx, data, path, depth):
    xmlsafe.refuse_entities(data, path, X3DError)
    root = _xml_root(data, path, ctx.notes)
    tag = _local(root.tag)
    if tag.lower() != "x3d":
        raise X3DError(path, f"not an X3D file (its root element is <{tag}>)")
    src = _Source(path, "x3d-xml", root.get("version", "3.0"), depth)
    src.profile = root.get("profile", "")
    scene = None
    for child in root:
        ctag = _local(child.tag).lower()
        if ctag == "head":
            for item in child:
                itag = _local(item.tag).lower()
                if itag == "meta" and item.get("name") is not None:
                    src.meta[item.get("name")] = item.get("content", "")
                elif itag == "unit":
                    unit(ctx.notes, src, item.get("category", ""), item.get("name", ""),
                         item.get("conversionFactor", ""))
        elif ctag == "scene" and scene is None:
            scene = child
    if scene is None:
        ctx.notes.add("X3D files without a <Scene>", os.path.basename(path))
    else:
        _Xml(src, ctx).statements(scene, src.nodes, 1, src.scope)
    return src


def parse_file(ctx, path, depth):
    """An Inline or EXTERNPROTO file (parsed once, cached by real path); None (with a
    warning) when it cannot be read."""
    real = os.path.realpath(path)
    if real in ctx.files:
        return ctx.files[real]
    ctx.files[real] = None
    if depth > MAX_INLINE_DEPTH:
        ctx.notes.add(f"Inline / EXTERNPROTO files nested deeper than {MAX_INLINE_DEPTH} "
                      "left out", os.path.basename(path))
        return None
    try:
        src = parse(ctx, _read_file(real), real, depth)
    except X3DError as error:
        ctx.notes.add("Inline / EXTERNPROTO files that could not be read", str(error))
        return None
    ctx.files[real] = src
    return src
