# SPDX-License-Identifier: GPL-3.0-or-later
"""Numbers and matrices: numeric arrays tokenised in bulk by numpy (never number by number),
non-finite values and huge magnitudes made safe (:data:`MAX_ABS`), and the matrices of
X3D's Transform (:func:`transform_matrix`) and their inverse (:func:`decompose`).
"""

from __future__ import annotations

import math
import re
import warnings as _warnings

import numpy as np


#: Largest magnitude of a number kept (larger ones are clamped, with a warning).
MAX_ABS = 1e30


# -- numbers -------------------------------------------------------------------------------

_NOT_NUMERIC = re.compile(r"[^0-9eE+\-.,\s]")
_NOT_INTEGRAL = re.compile(r"[.eE]")
_NUMERIC_BYTES = np.zeros(256, dtype=bool)
_NUMERIC_BYTES[list(b"0123456789eE+-.,\t\n\r\x0b\x0c ")] = True
_FLOAT_BYTES = np.zeros(256, dtype=bool)
_FLOAT_BYTES[list(b".eE")] = True
_VALUE_BYTES = _NUMERIC_BYTES.copy()
_VALUE_BYTES[list(b",\t\n\r\x0b\x0c ")] = False


def _bulk_numbers(text: str, start: int = 0, end: int | None = None):
    """The numbers of ``text[start:end]`` (whitespace or commas between them) as one numpy
    array, int64 when every one is written as an integer, else float64; None when it holds
    anything that is not a plain decimal number.  numpy checks (a byte table, 64 K characters
    at a time, stopping at the first chunk that is not numbers) and parses at C speed."""
    end = len(text) if end is None else end
    if end - start < 512:
        part = text[start:end]
        if _NOT_NUMERIC.search(part):
            return None
        if "," in part:
            part = part.replace(",", " ")
        if not part.strip():
            return np.zeros(0)
        integral = not _NOT_INTEGRAL.search(part)
        data = part
    else:
        if _NOT_NUMERIC.search(text, start, start + 256):  # most lists of nodes end here
            return None
        chunks, integral, values = [], True, False
        for at in range(start, end, 65536):
            try:
                raw = text[at:min(at + 65536, end)].encode("ascii")
            except UnicodeEncodeError:
                return None
            codes = np.frombuffer(raw, dtype=np.uint8)
            if not _NUMERIC_BYTES[codes].all():
                return None
            integral = integral and not _FLOAT_BYTES[codes].any()
            values = values or bool(_VALUE_BYTES[codes].any())
            chunks.append(raw)
        if not values:
            return np.zeros(0)
        data = b"".join(chunks)
        if b"," in data:
            data = data.replace(b",", b" ")
    try:
        with _warnings.catch_warnings():
            _warnings.simplefilter("error")
            return np.fromstring(data, dtype=np.int64 if integral else np.float64, sep=" ")
    except (ValueError, DeprecationWarning, OverflowError):
        return None


def _word_number(word: str):
    """One number written as *word* (decimal, hexadecimal or nan/inf): a float or int; NaN
    when it cannot be read (the caller replaces non-finite values, with a warning)."""
    try:
        return float(word)
    except ValueError:
        pass
    try:
        return int(word, 0)
    except ValueError:
        return math.nan


def _is_number_word(word: str) -> bool:
    return word[0] in "0123456789+-." or word.lower() in ("nan", "inf", "infinity")


def _numbers_of(words) -> np.ndarray:
    """Numbers of a list of number words (the slow path: small or malformed values)."""
    values = [_word_number(w) for w in words]
    if all(isinstance(v, int) for v in values):
        try:
            return np.array(values, dtype=np.int64)
        except OverflowError:
            pass
    return np.array(values, dtype=np.float64)


def _finite(values, notes, where) -> np.ndarray:
    """*values* as float64 with non-finite numbers replaced by 0 and magnitudes beyond
    MAX_ABS clamped (each with a warning naming *where*)."""
    out = np.asarray(values, dtype=np.float64)
    if out.size <= 16 and all(-MAX_ABS <= v <= MAX_ABS for v in out.flat):
        return out                          # (NaN fails the comparison)
    if out.size and not np.isfinite(out).all():
        out = out.copy()
        bad = ~np.isfinite(out)
        notes.add("numbers that are not finite (NaN, inf) read as 0", where, int(bad.sum()))
        out[bad] = 0.0
    if out.size and np.abs(out).max() > MAX_ABS:
        out = out.copy()
        big = np.abs(out) > MAX_ABS
        notes.add(f"numbers larger than {MAX_ABS:g} clamped", where, int(big.sum()))
        np.clip(out, -MAX_ABS, MAX_ABS, out=out)
    return out


# -- matrices ------------------------------------------------------------------------------

def rotation_matrix(axis, angle) -> np.ndarray:
    """4×4 rotation by *angle* (radians) about *axis* (right-handed); identity for a zero
    axis."""
    axis = np.asarray(axis, dtype=np.float64)[:3]
    norm = float(np.linalg.norm(axis))
    out = np.eye(4)
    if norm == 0.0 or not math.isfinite(norm) or angle == 0.0:
        return out
    x, y, z = axis / norm
    c, s = math.cos(angle), math.sin(angle)
    t = 1.0 - c
    out[:3, :3] = [[t * x * x + c, t * x * y - s * z, t * x * z + s * y],
                   [t * x * y + s * z, t * y * y + c, t * y * z - s * x],
                   [t * x * z - s * y, t * y * z + s * x, t * z * z + c]]
    return out


def _rotation3(axis, angle) -> np.ndarray:
    x, y, z = (float(v) for v in axis[:3])
    norm = math.sqrt(x * x + y * y + z * z)
    if norm == 0.0 or not math.isfinite(norm) or angle == 0.0:
        return np.eye(3)
    x, y, z = x / norm, y / norm, z / norm
    c, s = math.cos(angle), math.sin(angle)
    t = 1.0 - c
    return np.array([[t * x * x + c, t * x * y - s * z, t * x * z + s * y],
                     [t * x * y + s * z, t * y * y + c, t * y * z - s * x],
                     [t * x * z - s * y, t * y * z + s * x, t * z * z + c]])


def transform_matrix(translation=(0, 0, 0), rotation=(0, 0, 1, 0), scale=(1, 1, 1),
                     scale_orientation=(0, 0, 1, 0), center=(0, 0, 0)) -> np.ndarray:
    """A Transform's local matrix exactly as ISO/IEC 14772-1 §6.52 and 19775-1 §10.4.4
    compose it: P' = T × C × R × SR × S × -SR × -C × P (rotations as axis + angle)."""
    out = np.eye(4)
    a = np.diag([float(scale[0]), float(scale[1]), float(scale[2])])
    if scale_orientation[3] != 0.0 and not (scale[0] == scale[1] == scale[2]):
        sr = _rotation3(scale_orientation, scale_orientation[3])
        a = sr @ a @ sr.T
    if rotation[3] != 0.0:
        a = _rotation3(rotation, rotation[3]) @ a
    out[:3, :3] = a
    c = np.array([float(v) for v in center[:3]])
    out[:3, 3] = np.array([float(v) for v in translation[:3]]) + c - a @ c
    return out


def _axis_angle(rot: np.ndarray) -> tuple:
    """(x, y, z, angle) of a 3×3 rotation matrix (angle in [0, π])."""
    m = np.asarray(rot, dtype=np.float64)
    trace = m[0, 0] + m[1, 1] + m[2, 2]
    # quaternion (Shepperd): robust near 0 and π
    if trace > 0:
        s = math.sqrt(trace + 1.0) * 2
        w, x = 0.25 * s, (m[2, 1] - m[1, 2]) / s
        y, z = (m[0, 2] - m[2, 0]) / s, (m[1, 0] - m[0, 1]) / s
    elif m[0, 0] > m[1, 1] and m[0, 0] > m[2, 2]:
        s = math.sqrt(1.0 + m[0, 0] - m[1, 1] - m[2, 2]) * 2
        w, x = (m[2, 1] - m[1, 2]) / s, 0.25 * s
        y, z = (m[0, 1] + m[1, 0]) / s, (m[0, 2] + m[2, 0]) / s
    elif m[1, 1] > m[2, 2]:
        s = math.sqrt(1.0 + m[1, 1] - m[0, 0] - m[2, 2]) * 2
        w, x = (m[0, 2] - m[2, 0]) / s, (m[0, 1] + m[1, 0]) / s
        y, z = 0.25 * s, (m[1, 2] + m[2, 1]) / s
    else:
        s = math.sqrt(1.0 + m[2, 2] - m[0, 0] - m[1, 1]) * 2
        w, x = (m[1, 0] - m[0, 1]) / s, (m[0, 2] + m[2, 0]) / s
        y, z = (m[1, 2] + m[2, 1]) / s, 0.25 * s
    if w < 0:
        w, x, y, z = -w, -x, -y, -z
    sin_half = math.sqrt(x * x + y * y + z * z)
    if sin_half < 1e-15:
        return (0.0, 0.0, 1.0, 0.0)
    angle = 2.0 * math.atan2(sin_half, w)
    return (x / sin_half, y / sin_half, z / sin_half, angle)


def decompose(matrix) -> dict:
    """A 4×4 affine matrix as a Transform's fields (translation, rotation, scale,
    scaleOrientation; center 0) that compose it exactly (up to rounding): the 3×3 part
    A = U·Σ·Vᵀ (SVD) is R·SR·S·SRᵀ with SR = V, S = Σ and R = U·Vᵀ; a mirror gives a
    negative scale."""
    m = np.asarray(matrix, dtype=np.float64)
    a = m[:3, :3]
    u, s, vt = np.linalg.svd(a)
    v = vt.T.copy()
    s = s.copy()
    if np.linalg.det(v) < 0:
        v[:, 2] *= -1
        s[2] *= -1
    if np.linalg.det(u) < 0:
        u[:, 2] *= -1
        s[2] *= -1
    rot = u @ v.T
    if np.allclose(s, s[0], rtol=1e-12, atol=0.0):
        v = np.eye(3)
        rot = a / s[0]
    return {"translation": tuple(m[:3, 3]), "rotation": _axis_angle(rot),
            "scale": tuple(s), "scale_orientation": _axis_angle(v)}
