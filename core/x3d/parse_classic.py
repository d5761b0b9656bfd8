# SPDX-License-Identifier: GPL-3.0-or-later
"""ClassicVRML (VRML97 and X3D classic) into the generic node graph: a tokeniser that reads
numeric arrays in bulk, PROTO / EXTERNPROTO declarations, ROUTEs named once, headers
(PROFILE, COMPONENT, UNIT, META); nodes nested deeper than :data:`MAX_DEPTH` are skipped
by counting their brackets.
"""

from __future__ import annotations

import re

import numpy as np

from .numeric import _bulk_numbers, _is_number_word, _numbers_of, _word_number
from .model import MAX_DEPTH
from .graph import (
    _ACCESS, _EOF, _IMPLIED, _IS, _KNOWN, _MISSING, _N, _NO_VALUE, _Proto, _Scope, _Use, unit)


# -- ClassicVRML (VRML97 and X3D classic) -------------------------------------------------

_STRIP = re.compile(r'"(?:[^"\\]|\\.)*"|#[^\n\r]*', re.S)
_TOKEN = re.compile(r'[\s,]*(?:([{}\[\]])|"((?:[^"\\]|\\.)*)"|([^\s,{}\[\]"]+)|("))', re.S)
_BLOCK = re.compile(r'[{}\[\]"]')
_UNESCAPE = re.compile(r"\\(.)", re.S)
_STRING_END = re.compile(r'(?:[^"\\]|\\.)*"', re.S)
_OPENERS = np.array([ord("{"), ord("[")], dtype=np.uint32)
_CLOSERS = np.array([ord("}"), ord("]")], dtype=np.uint32)


def _strip_comments(text: str) -> str:
    if "#" not in text:
        return text
    return _STRIP.sub(lambda m: m.group(0) if m.group(0)[0] == '"' else " ", text)


class _Classic:
    """A recursive-descent reader of the classic encoding over one string; nesting is bounded
    by MAX_DEPTH (deeper blocks are skipped by counting brackets, not by recursion)."""

    def __init__(self, text, src, ctx):
        self.text = text
        self.pos = 0
        self.src = src
        self.notes = ctx.notes
        self.ctx = ctx              # the reading context: its counts of ignored and too deep nodes
        self.scope = src.scope
        self.truncated = False
        self.line_at, self.line_no = 0, 1
        self.peeked = None          # (position, token, position after): the last peek

    # tokens --------------------------------------------------------------------------
    def next(self):
        if self.peeked is not None and self.peeked[0] == self.pos:
            _start, token, self.pos = self.peeked
            self.peeked = None
            return token
        m = _TOKEN.match(self.text, self.pos)
        if m is None:
            self.pos = len(self.text)
            return _EOF
        self.pos = m.end()
        if m.group(1) is not None:
            return (m.group(1), None)
        if m.group(3) is not None:
            return ("w", m.group(3))
        if m.group(2) is not None:
            s = m.group(2)
            return ("s", _UNESCAPE.sub(r"\1", s) if "\\" in s else s)
        # an unterminated string: the rest of the file
        rest = self.text[self.pos:]
        self.pos = len(self.text)
        self.truncated = True
        return ("s", rest)

    def peek(self):
        pos = self.pos
        if self.peeked is not None and self.peeked[0] == pos:
            return self.peeked[1]
        tok = self.next()
        self.peeked = (pos, tok, self.pos)
        self.pos = pos
        return tok

    def line(self) -> int:
        """The line of the current position (for warnings), counted from the last one asked
        for, so that asking as the reading goes on costs the file's length once."""
        pos = self.pos
        if pos >= self.line_at:
            self.line_no += self.text.count("\n", self.line_at, pos)
        else:
            self.line_no -= self.text.count("\n", pos, self.line_at)
        self.line_at = pos
        return self.line_no

    def skip_block(self, opener):
        """Skip to the bracket closing *opener* (already read), counting brackets without
        recursion: 64 K characters at a time with numpy where they hold no string."""
        depth = 1
        text = self.text
        n = len(text)
        while depth:
            chunk = text[self.pos:self.pos + 65536]
            if not chunk:
                self.truncated = True
                return
            if '"' not in chunk:
                codes = np.frombuffer(chunk.encode("utf-32-le"), dtype=np.uint32)
                change = (np.isin(codes, _OPENERS).astype(np.int64)
                          - np.isin(codes, _CLOSERS).astype(np.int64))
                level = depth + np.cumsum(change)
                closed = np.flatnonzero(level <= 0)
                if len(closed):
                    self.pos += int(closed[0]) + 1
                    return
                depth = int(level[-1])
                self.pos += len(chunk)
                continue
            m = _BLOCK.search(text, self.pos)
            if m is None:
                self.pos = n
                self.truncated = True
                return
            c = m.group(0)
            self.pos = m.end()
            if c == '"':
                end = _STRING_END.match(text, self.pos)
                if end is None:
                    self.pos = n
                    self.truncated = True
                    return
                self.pos = end.end()
            elif c in "{[":
                depth += 1
            else:
                depth -= 1

    # statements ------------------------------------------------------------------------
    def statements(self, out, depth, end=None):
        """Read statements into *out* until *end* ("}" of a PROTO body) or the end of file."""
        while True:
            kind, value = self.peek()
            if kind == "eof":
                if end is not None:
                    self.truncated = True
                return
            if kind == end:
                self.next()
                return
            if kind != "w":
                self.next()
                self.notes.add("unexpected symbols skipped", f"'{kind}' line {self.line()}")
                if kind in "{[":
                    self.skip_block(kind)
                continue
            if value in ("PROTO", "EXTERNPROTO"):
                self.next()
                self.proto(depth, extern=value == "EXTERNPROTO")
            elif value == "ROUTE":
                self.next()
                self.route()
            elif value in ("PROFILE", "COMPONENT", "META", "UNIT", "IMPORT", "EXPORT"):
                self.next()
                self.header_statement(value)
            else:
                node = self.node(depth)
                if node is not None:
                    out.append(node)

    def route(self):
        """ROUTE a.b TO c.d (spaces around the dots tolerated): skipped, counted."""
        self.ctx.ignored["ROUTE"] = self.ctx.ignored.get("ROUTE", 0) + 1
        for _ in range(8):
            kind, value = self.peek()
            if kind != "w":
                return
            self.next()
            if value == "TO":
                kind, target = self.next()
                if kind != "w":
                    return
                if target.endswith("."):                # "c. d"
                    self.next()
                elif "." not in target and self.peek()[0] == "w" \
                        and self.peek()[1].startswith("."):
                    if self.next()[1] == ".":           # "c . d"
                        self.next()
                return

    def header_statement(self, keyword):
        if keyword == "PROFILE":
            self.src.profile = self.next()[1] or ""
        elif keyword == "COMPONENT":
            self.next()
            if self.peek()[1] == ":":
                self.next()
                self.next()
        elif keyword == "META":
            key, value = self.next(), self.next()
            if key[0] == "s" and value[0] == "s":
                self.src.meta[key[1]] = value[1]
        elif keyword == "UNIT":
            words = [self.next() for _ in range(3)]
            if all(w[0] == "w" for w in words):
                category, name, factor = (w[1] for w in words)
                unit(self.notes, self.src, category, name, factor)
            else:
                self.notes.add("UNIT statements that could not be read", f"line {self.line()}")
        elif keyword == "IMPORT":           # IMPORT inline.exported AS name
            self.next()
            if self.peek()[1] == "AS":
                self.next()
                self.next()
        elif keyword == "EXPORT":           # EXPORT name [AS other]
            self.next()
            if self.peek()[1] == "AS":
                self.next()
                self.next()

    # PROTO ----------------------------------------------------------------------------
    def proto(self, depth, extern=False):
        kind, name = self.next()
        if kind != "w":
            self.notes.add("PROTO statements that could not be read", f"line {self.line()}")
            return
        proto = _Proto(name, self.src)
        if self.next()[0] != "[":
            self.notes.add("PROTO statements that could not be read", f"{name} line {self.line()}")
            return
        while True:
            kind, value = self.next()
            if kind in ("]", "eof"):
                if kind == "eof":
                    self.truncated = True
                break
            if kind != "w" or value not in _ACCESS:
                self.notes.add("PROTO interface declarations that could not be read",
                               f"{name} line {self.line()}")
                if kind in ("{", "["):
                    self.skip_block(kind)
                continue
            ftype, fname = self.next()[1], self.next()[1]
            default = _MISSING
            if not extern and value not in _NO_VALUE:
                default = self.value(depth + 1, fname)
            proto.fields[fname] = (value, ftype, default)
        self.scope.protos[name] = proto     # visible to instances from here on
        if extern:
            urls = self.value(depth + 1, "url")
            proto.extern_urls = [u for u in urls if isinstance(u, str)] \
                if isinstance(urls, list) else []
            return
        if self.next()[0] != "{":
            self.notes.add("PROTO statements that could not be read", f"{name} line {self.line()}")
            return
        outer = self.scope
        self.scope = _Scope(outer)
        proto.defs = self.scope.defs
        self.statements(proto.body, depth + 1, end="}")
        self.scope = outer

    # nodes ----------------------------------------------------------------------------
    def node(self, depth, field_name=None):
        """A node statement (``DEF n Type {...}``, ``USE n``, ``Type {...}``); None when there
        is none (with a warning) or it is nested too deep."""
        kind, word = self.next()
        if kind != "w":
            return None
        if word == "USE":
            kind, name = self.next()
            if kind != "w":
                return None
            found = self.scope.defs.get(name)
            return found if found is not None else _Use(name, self.scope)
        name = None
        if word == "DEF":
            kind, name = self.next()
            if kind != "w":
                return None
            if self.peek()[0] == "{":     # DEF without a node type: its field implies one
                self.notes.add("DEF without a node type: the type its field implies",
                               f"{name} line {self.line()}")
                type_ = _IMPLIED.get(field_name or "", "Group")
            else:
                kind, type_ = self.next()
        else:
            type_ = word
        if self.peek()[0] != "{":
            self.notes.add("words that are not nodes skipped", f"{type_} line {self.line()}")
            return None
        self.next()
        if depth > MAX_DEPTH:
            self.ctx.too_deep += 1
            self.skip_block("{")
            return None
        proto = self.scope.proto(type_)
        if proto is None and type_ not in _KNOWN:
            proto = self.scope.proto_ci(type_)
            if proto is not None:
                self.notes.add("node and field names read regardless of case",
                               f"{type_} → {proto.name}")
        node = _N(type_, name, proto, self.src)
        self.body(node, depth)
        if name is not None:
            self.scope.defs[name] = node
        return node

    def body(self, node, depth):
        fields = node.fields
        while True:
            kind, value = self.next()
            if kind == "}":
                return
            if kind == "eof":
                self.truncated = True
                return
            if kind != "w":
                self.notes.add("unexpected symbols skipped", f"'{kind}' line {self.line()}")
                if kind in "{[":
                    self.skip_block(kind)
                continue
            if value == "ROUTE":
                self.route()
                continue
            if value in ("PROTO", "EXTERNPROTO"):
                self.proto(depth, extern=value == "EXTERNPROTO")
                continue
            if value in _ACCESS and self.peek()[0] == "w":
                # a Script / shader field declaration: access type name [value | IS name]
                self.next()                     # the field's type
                fname = self.next()[1]
                if self.peek()[1] == "IS":
                    self.next()
                    fields[fname] = _IS(self.next()[1])
                elif value not in _NO_VALUE:
                    fields[fname] = self.value(depth + 1, fname)
                continue
            result = self.value(depth + 1, value)
            if result is _MISSING:
                self.notes.add("fields without a value skipped", f"{node.type}.{value} line "
                                                                   f"{self.line()}")
                continue
            fields[value] = result

    def value(self, depth, field_name=None):
        """A field value of any type, read by its form: ``[...]``, numbers, strings, a
        boolean, NULL, ``IS name``, or a node."""
        kind, word = self.peek()
        if kind == "[":
            self.next()
            return self.multiple(depth, field_name)
        if kind == "s":
            out = []
            while self.peek()[0] == "s":
                out.append(self.next()[1])
            return out
        if kind == "{":                     # a node with neither type nor DEF
            self.next()
            if depth > MAX_DEPTH:
                self.ctx.too_deep += 1
                self.skip_block("{")
                return None
            type_ = _IMPLIED.get(field_name or "", "Group")
            self.notes.add("nodes without a type: the type their field implies",
                           f"{field_name} line {self.line()}")
            node = _N(type_, None, None, self.src)
            self.body(node, depth)
            return node
        if kind != "w":
            return _MISSING
        if _is_number_word(word):
            words = []
            while True:
                kind, word = self.peek()
                if kind != "w" or not _is_number_word(word):
                    break
                self.next()
                words.append(word)
            joined = " ".join(words)
            values = _bulk_numbers(joined)
            return values if values is not None else _numbers_of(words)
        if word in ("TRUE", "FALSE", "true", "false"):
            self.next()
            return word in ("TRUE", "true")
        if word == "NULL":
            self.next()
            return None
        if word == "IS":
            self.next()
            return _IS(self.next()[1])
        if word in ("DEF", "USE"):
            return self.node(depth, field_name)
        pos = self.pos
        self.next()
        follows = self.peek()[0]
        self.pos = pos
        if follows == "{":
            return self.node(depth, field_name)
        return _MISSING

    def multiple(self, depth, field_name):
        """``[ ... ]``: a numeric array in one numpy call when the brackets hold only
        numbers, else item by item (nodes, strings, booleans, numbers)."""
        text = self.text
        end = text.find("]", self.pos)
        if end >= 0:
            values = _bulk_numbers(text, self.pos, end)
            if values is not None:
                self.pos = end + 1
                return values
        items = []
        while True:
            kind, word = self.peek()
            if kind == "]":
                self.next()
                break
            if kind == "eof":
                self.truncated = True
                break
            if kind == "}":                 # a missing "]": let the node end
                self.notes.add("unclosed brackets closed", f"line {self.line()}")
                break
            if kind in ("[", "{"):
                self.next()
                self.notes.add("unexpected brackets skipped", f"line {self.line()}")
                self.skip_block(kind)
                continue
            if kind == "s":
                self.next()
                items.append(word)
                continue
            if _is_number_word(word):
                self.next()
                items.append(_word_number(word))
                continue
            if word in ("TRUE", "FALSE", "true", "false"):
                self.next()
                items.append(word in ("TRUE", "true"))
                continue
            if word == "NULL":
                self.next()
                continue
            node = self.node(depth, field_name)
            if node is not None:
                items.append(node)
        if items and all(isinstance(i, (int, float)) and not isinstance(i, bool)
                         for i in items):
            if all(isinstance(i, int) for i in items):
                try:
                    return np.array(items, dtype=np.int64)
                except OverflowError:
                    pass
            return np.array(items, dtype=np.float64)
        return items
