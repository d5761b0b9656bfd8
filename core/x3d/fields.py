# SPDX-License-Identifier: GPL-3.0-or-later
"""Typed field access on the generic node graph: numbers, vectors, angles (the file's UNIT
angle applied), rotations, indices, booleans, strings and nodes, each with its default and a
warning where the value cannot be read; names that differ only in case are matched (one
warning), and a node's type is read as its canonical one (:func:`type_of`).  Each function
is handed the reading context (:class:`~.context._Reading`) for its notes.
"""

from __future__ import annotations

import numpy as np

from .numeric import _bulk_numbers, _finite, _numbers_of
from .graph import _CASE, _KNOWN, _KNOWN_LOWER, _MISSING, _N, _Raw, _Use
from .parse_xml import _mfstring


def field(ctx, n, name):
    fields = n.fields
    if name in fields:
        return fields[name]
    if fields:
        lower = name.lower()
        for key, value in fields.items():
            if key.lower() == lower:
                ctx.notes.add(_CASE, f"{key} → {name}")
                return value
    return _MISSING


def where(n, name):
    return f"{n.type}.{name}" + (f" ('{n.name}')" if n.name else "")


def numbers(ctx, n, name):
    """The numbers of a field as float64 (None when absent); a value of another kind is
    a warning."""
    value = field(ctx, n, name)
    if value is _MISSING or value is None:
        return None
    if isinstance(value, np.ndarray):
        arr = value
    elif isinstance(value, _Raw):
        arr = _bulk_numbers(value)
        if arr is None:
            arr = _numbers_of(value.replace(",", " ").split() or ["0"]) if value.strip() \
                else np.zeros(0)
    elif isinstance(value, bool):
        arr = np.array([float(value)])
    elif isinstance(value, (int, float)):
        arr = np.array([value], dtype=np.float64)
    elif isinstance(value, list) and all(isinstance(v, (int, float)) for v in value):
        arr = np.array([float(v) for v in value])
    else:
        ctx.notes.add("fields whose value is not numbers: defaults used", where(n, name))
        return None
    return _finite(arr, ctx.notes, where(n, name))


def vec(ctx, n, name, default):
    arr = numbers(ctx, n, name)
    if arr is None:
        return default
    if len(arr) < len(default):
        ctx.notes.add("fields with too few numbers: defaults used", where(n, name))
        return default
    return tuple(float(v) for v in arr[:len(default)])


def num(ctx, n, name, default):
    return vec(ctx, n, name, (default,))[0]


def angle(ctx, n, name, default):
    """An angle field in radians (the file's UNIT angle applied); *default* is radians."""
    arr = numbers(ctx, n, name)
    if arr is None or not len(arr):
        return default
    return float(arr[0]) * (n.src.angle if n.src is not None else 1.0)


def rotation(ctx, n, name):
    x, y, z, a = vec(ctx, n, name, (0.0, 0.0, 1.0, 0.0))
    if a != 0.0 and x == y == z == 0.0:
        ctx.notes.add("rotations about a zero axis read as none", where(n, name))
        return (0.0, 0.0, 1.0, 0.0)
    return (x, y, z, a * (n.src.angle if n.src is not None else 1.0))


def ints(ctx, n, name):
    """An integer array field (int64; empty when absent); numbers that are not integers
    become an index that is out of range (so the face using them is dropped)."""
    value = field(ctx, n, name)
    if value is _MISSING or value is None:
        return np.zeros(0, np.int64)
    if isinstance(value, np.ndarray) and value.dtype == np.int64:
        return value
    arr = numbers(ctx, n, name)
    if arr is None:
        return np.zeros(0, np.int64)
    whole = np.round(arr)
    bad = whole != arr
    if bad.any():
        ctx.notes.add("indices that are not integers read as out of range",
                      where(n, name), int(bad.sum()))
        whole[bad] = 2.0 ** 62
    return np.clip(whole, -(2.0 ** 62), 2.0 ** 62).astype(np.int64)


def flag(ctx, n, name, default):
    value = field(ctx, n, name)
    if value is _MISSING or value is None:
        return default
    if isinstance(value, bool):
        return value
    if isinstance(value, _Raw):
        word = value.strip().strip('"').lower()
        if word in ("true", "false"):
            return word == "true"
    elif isinstance(value, list) and value and isinstance(value[0], (bool, str)):
        first = value[0]
        if isinstance(first, bool):
            return first
        if first.lower() in ("true", "false"):
            return first.lower() == "true"
    elif isinstance(value, np.ndarray) and len(value) == 1:
        return bool(value[0])
    ctx.notes.add("booleans that could not be read: defaults used", where(n, name))
    return default


def strings(ctx, n, name):
    value = field(ctx, n, name)
    if value is _MISSING or value is None:
        return []
    if isinstance(value, _Raw):
        return _mfstring(value)
    if isinstance(value, list):
        return [v for v in value if isinstance(v, str)]
    return []


def string(ctx, n, name, default=""):
    value = field(ctx, n, name)
    if isinstance(value, _Raw):
        text = str(value)
        if len(text) >= 2 and text[0] == text[-1] == '"':
            text = text[1:-1]
        return text
    if isinstance(value, list) and value and isinstance(value[0], str):
        return value[0]
    return default


def node_value(ctx, n, name):
    value = field(ctx, n, name)
    if isinstance(value, list):
        value = next((v for v in value if isinstance(v, (_N, _Use))), None)
    return value if isinstance(value, (_N, _Use)) else None


def node_values(ctx, n, name):
    value = field(ctx, n, name)
    if isinstance(value, (_N, _Use)):
        return [value]
    if isinstance(value, list):
        return [v for v in value if isinstance(v, (_N, _Use))]
    return []


def type_of(ctx, n):
    written = n.type
    if written in ctx.canon:
        return ctx.canon[written]
    if written in _KNOWN:
        canonical = written
    else:
        canonical = _KNOWN_LOWER.get((written or "").lower())
        if canonical is not None:
            ctx.notes.add(_CASE, f"{written} → {canonical}")
    ctx.canon[written] = canonical
    return canonical
