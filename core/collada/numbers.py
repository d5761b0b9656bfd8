# SPDX-License-Identifier: GPL-3.0-or-later
"""Numbers of an element's text: floats (decimal commas repaired, with one warning), integers,
one number; long texts read by numpy's C parsers first (:data:`BULK`).  Each function is
handed the reading context (``context._Reading``) for its warnings.
"""

from __future__ import annotations

import warnings

import numpy as np


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


def floats(ctx, element, where, expected=None):
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
                ctx.commas.append(where)
            else:
                ctx.doc.warn(f"{where}: {what} read as numbers")
            break
    if values is None:
        ctx.doc.warn(f"{where}: numbers that cannot be read; left out")
        return None
    if not np.all(np.isfinite(values)):
        ctx.doc.warn(f"{where}: NaN or infinite numbers read as 0")
        values = np.nan_to_num(values, nan=0.0, posinf=0.0, neginf=0.0)
    return values


def ints(ctx, element, where):
    text = (element.text or "") if element is not None else ""
    values = _bulk_ints(text) if len(text) >= BULK else None
    if values is not None:
        return values
    try:
        return np.array(text.split(), dtype=np.int64)
    except (ValueError, OverflowError):
        values = floats(ctx, element, where)
        if values is None or np.any(values != np.round(values)):
            ctx.doc.warn(f"{where}: indices that are not integers; left out")
            return None
        return values.astype(np.int64)


def number(ctx, element, where, default=None):
    values = floats(ctx, element, where) if element is not None else None
    if values is None or not len(values):
        return default
    return float(values[0])
