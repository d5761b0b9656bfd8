# SPDX-License-Identifier: GPL-3.0-or-later
"""X3D's XML encoding into the same generic node graph as the classic one: the root element
(XML that breaks off keeps what came before), nodes, containerField, PROTO declarations and
instances, and MFString attributes with or without quotes.  Entities are refused before
parsing (``core.xmlsafe``).
"""

from __future__ import annotations

import re
import xml.etree.ElementTree as ET

from ..xmlsafe import local as _local
from .model import MAX_DEPTH, X3DError
from .graph import (
    _CONTAINER, _IS, _KNOWN_LOWER, _MISSING, _N, _XML_SKIP, _Proto, _Raw, _Scope, _Use)
from .parse_classic import _UNESCAPE


def _xml_root(data: bytes, path: str, notes):
    """The root element; XML that breaks off (a truncated file) keeps what came before, with
    a warning; XML with no element at all is an X3DError."""
    parser = ET.XMLPullParser(events=("start",))
    root = None
    try:
        parser.feed(data)
        for _event, element in parser.read_events():
            root = element
            break
        parser.close()
    except ET.ParseError as error:
        if root is None:
            for _event, element in parser.read_events():
                root = element
                break
        if root is None:
            raise X3DError(path, f"not well-formed XML ({error})") from None
        notes.add("XML that is not well-formed: the part before the error is read", str(error))
    return root


class _Xml:
    """X3D's XML encoding into the same generic nodes as the classic one."""

    def __init__(self, src, ctx):
        self.src = src
        self.notes = ctx.notes
        self.ctx = ctx              # the reading context: its counts of ignored and too deep nodes

    def statements(self, parent, out, depth, scope):
        for element in parent:
            tag = _local(element.tag)
            if not tag or tag.startswith("Metadata"):
                continue
            if tag == "ROUTE":
                self.ctx.ignored["ROUTE"] = self.ctx.ignored.get("ROUTE", 0) + 1
            elif tag == "ProtoDeclare":
                self.proto(element, depth, scope)
            elif tag == "ExternProtoDeclare":
                self.extern(element, scope)
            elif tag in ("IMPORT", "EXPORT", "component", "unit", "meta", "head", "field",
                         "IS", "fieldValue"):
                continue
            else:
                node = self.node(element, depth, scope)
                if node is not None:
                    out.append(node)

    def node(self, element, depth, scope):
        tag = _local(element.tag)
        use = element.get("USE")
        if use is not None:
            found = scope.defs.get(use)
            return found if found is not None else _Use(use, scope)
        if depth > MAX_DEPTH:
            self.ctx.too_deep += 1
            return None
        if tag == "ProtoInstance":
            return self.instance(element, depth, scope)
        name = element.get("DEF")
        proto = scope.proto(tag)
        node = _N(tag, name, proto, self.src)
        for key, value in element.attrib.items():
            key = _local(key)
            if (key not in _XML_SKIP or (key == "style" and tag in ("FontStyle",
                                                                     "ScreenFontStyle"))) \
                    and not key.startswith("xmlns"):
                node.fields[key] = _Raw(value)
        self.children(element, node, depth, scope)
        if name is not None:
            scope.defs[name] = node
        return node

    def children(self, element, node, depth, scope):
        for child in element:
            tag = _local(child.tag)
            if not tag or tag.startswith("Metadata") or tag in ("field", "fieldValue"):
                continue
            if tag == "IS":
                self.connect(child, node)
                continue
            if tag == "ROUTE":
                self.ctx.ignored["ROUTE"] = self.ctx.ignored.get("ROUTE", 0) + 1
                continue
            if tag in ("ProtoDeclare", "ExternProtoDeclare"):
                continue
            value = self.node(child, depth + 1, scope)
            if value is None:
                continue
            container = child.get("containerField") or self.container(tag)
            held = node.fields.get(container)
            if not isinstance(held, list):      # (an IS on the same field is kept beside)
                held = [held] if isinstance(held, _IS) else []
                node.fields[container] = held
            held.append(value)

    @staticmethod
    def container(tag):
        if tag in _CONTAINER:
            return _CONTAINER[tag]
        canonical = _KNOWN_LOWER.get(tag.lower())
        return _CONTAINER.get(canonical, "children")

    @staticmethod
    def connect(element, node):
        for connect in element:
            if _local(connect.tag) == "connect":
                node_field, proto_field = connect.get("nodeField"), connect.get("protoField")
                if node_field and proto_field:
                    held = node.fields.get(node_field)
                    if isinstance(held, list):  # child nodes given too: both are kept
                        held.append(_IS(proto_field))
                    else:
                        node.fields[node_field] = _IS(proto_field)

    def instance(self, element, depth, scope):
        name = element.get("name") or ""
        proto = scope.proto(name)
        if proto is None and name:
            proto = scope.proto_ci(name)
            if proto is not None:
                self.notes.add("node and field names read regardless of case",
                               f"{name} → {proto.name}")
        node = _N(name or "ProtoInstance", element.get("DEF"), proto, self.src)
        for child in element:
            tag = _local(child.tag)
            if tag == "fieldValue":
                fname = child.get("name")
                if not fname:
                    continue
                if "value" in child.attrib:
                    node.fields[fname] = _Raw(child.get("value"))
                else:
                    nodes = [self.node(c, depth + 1, scope) for c in child
                             if _local(c.tag) and not _local(c.tag).startswith("Metadata")]
                    node.fields[fname] = [n for n in nodes if n is not None]
            elif tag == "IS":
                self.connect(child, node)
        if node.name is not None:
            scope.defs[node.name] = node
        return node

    def interface(self, element, proto, depth, scope, extern=False):
        for child in element:
            if _local(child.tag) != "field":
                continue
            fname = child.get("name")
            if not fname:
                continue
            access = child.get("accessType", "inputOutput")
            ftype = child.get("type", "")
            default = _MISSING
            if not extern and access not in ("inputOnly", "outputOnly"):
                if "value" in child.attrib:
                    default = _Raw(child.get("value"))
                else:
                    nodes = [self.node(c, depth + 1, scope) for c in child
                             if _local(c.tag) and not _local(c.tag).startswith("Metadata")]
                    nodes = [n for n in nodes if n is not None]
                    if nodes or ftype.upper().startswith("MF"):
                        default = nodes
                    elif ftype.upper() == "SFNODE":
                        default = None
            proto.fields[fname] = (access, ftype, default)

    def proto(self, element, depth, scope):
        name = element.get("name")
        if not name:
            self.notes.add("PROTO statements that could not be read", "a ProtoDeclare without name")
            return
        proto = _Proto(name, self.src)
        inner = _Scope(scope)
        proto.defs = inner.defs
        for child in element:
            tag = _local(child.tag)
            if tag == "ProtoInterface":
                self.interface(child, proto, depth, scope)
        scope.protos[name] = proto
        for child in element:
            if _local(child.tag) == "ProtoBody":
                self.statements(child, proto.body, depth + 1, inner)

    def extern(self, element, scope):
        name = element.get("name")
        if not name:
            return
        proto = _Proto(name, self.src)
        self.interface(element, proto, 0, scope, extern=True)
        proto.extern_urls = _mfstring(element.get("url", ""))
        scope.protos[name] = proto


_QUOTED = re.compile(r'"((?:[^"\\]|\\.)*)"', re.S)


def _mfstring(text: str) -> list:
    """An MFString written in XML: quoted strings (escapes \\" and \\\\), or — as some writers
    write it — one string without quotes."""
    if '"' in text:
        return [_UNESCAPE.sub(r"\1", s) if "\\" in s else s for s in _QUOTED.findall(text)]
    text = text.strip()
    return [text] if text else []
