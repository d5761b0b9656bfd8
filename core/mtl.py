# SPDX-License-Identifier: GPL-3.0-or-later
"""Wavefront MTL material libraries, read without ``bpy`` (issue "Interchange", part 3).

MTL is the classic Phong model written down: ``Ka`` ambient, ``Kd`` diffuse, ``Ks`` specular
reflectivity, ``Ns`` the specular exponent, ``Ke`` emission, ``illum`` the illumination model
(0 colour only, 1 ambient + Lambert, 2 + highlight) and texture maps (``map_Kd`` ...).  The
statements follow Alias|Wavefront's *File Formats*, version 4.2 (1995), chapter 5:

* a colour is ``r [g b]`` (one value: g = b = r); ``spectral`` and ``xyz`` colours are kept
  as statements the model cannot represent;
* a map statement is ``map_Kd [options] file`` with options such as ``-o u [v [w]]``,
  ``-s``, ``-t``, ``-bm mult``, ``-clamp on|off``, ``-mm base gain``; the file name is the rest
  of the line (it may hold spaces) and is resolved relative to the MTL file's folder;
* ``bump`` and ``map_Bump`` are the same statement; keywords are read case-insensitively;
* ``#`` starts a comment, a line ending in ``\\`` continues on the next, CRLF line ends work.

:func:`load` reads one library, :func:`libraries` lists the ``mtllib`` files an OBJ names and
:func:`load_for_obj` reads them all; :func:`dumps` writes materials back (numbers as the
shortest text that reads back as the same float).  Every error is an :class:`MtlError` that names the file
and line; nothing is half-read (an error raises before any result is returned).
"""

from __future__ import annotations

import math
import os
import re
from dataclasses import dataclass, field

#: Canonical keyword for each accepted spelling (lower case).
COLORS = {"ka": "Ka", "kd": "Kd", "ks": "Ks", "ke": "Ke", "tf": "Tf"}
SCALARS = {"ns": "Ns", "ni": "Ni", "d": "d", "tr": "Tr", "sharpness": "sharpness"}
MAPS = {"map_ka": "map_Ka", "map_kd": "map_Kd", "map_ks": "map_Ks", "map_ke": "map_Ke",
        "map_ns": "map_Ns", "map_d": "map_d", "map_bump": "bump", "bump": "bump",
        "disp": "disp", "decal": "decal", "refl": "refl", "map_refl": "refl"}
#: Map options and how many numbers (or words) follow them: (least, most).
MAP_OPTIONS = {"-o": (1, 3), "-s": (1, 3), "-t": (1, 3), "-bm": (1, 1), "-boost": (1, 1),
               "-mm": (2, 2), "-texres": (1, 1), "-blendu": (1, 1), "-blendv": (1, 1),
               "-clamp": (1, 1), "-cc": (1, 1), "-imfchan": (1, 1), "-type": (1, 1)}
_WORD_OPTIONS = {"-blendu", "-blendv", "-clamp", "-cc", "-imfchan", "-type"}
#: Maps the Phong model has an input for.
PHONG_MAPS = ("map_Ka", "map_Kd", "map_Ks", "map_Ke", "bump")


class MtlError(ValueError):
    """A file that cannot be read as MTL (or OBJ ``mtllib``): names the file and line."""

    def __init__(self, path: str, line: int, message: str):
        self.path, self.line = path, line
        super().__init__(f"{path}:{line}: {message}" if line else f"{path}: {message}")


@dataclass
class TextureMap:
    path: str                 # as written in the file
    resolved: str             # absolute, relative paths taken from the MTL file's folder
    options: dict             # option -> tuple of its values, e.g. {"-s": (2.0, 2.0, 1.0)}
    line: int

    @property
    def exists(self) -> bool:
        return os.path.isfile(self.resolved)


@dataclass
class Material:
    name: str
    path: str                 # the MTL file
    line: int                 # of its newmtl statement
    colors: dict = field(default_factory=dict)    # "Kd" -> (r, g, b)
    scalars: dict = field(default_factory=dict)   # "Ns" -> 30.0, ...
    illum: int | None = None
    maps: dict = field(default_factory=dict)      # canonical keyword -> TextureMap
    others: list = field(default_factory=list)    # (line, statement) kept, not understood
    comments: list = field(default_factory=list)  # written before newmtl by dumps()

    def unsupported(self) -> list:
        """What the Phong model cannot represent, one short phrase each (for one warning)."""
        out = []
        d = self.scalars.get("d")
        tr = self.scalars.get("Tr")
        if d is not None and d != 1.0:
            out.append(f"d {d:g} (transparency)")
        if tr is not None and tr != 0.0:
            out.append(f"Tr {tr:g} (transparency)")
        if "Ni" in self.scalars:
            out.append(f"Ni {self.scalars['Ni']:g} (refraction)")
        if "Tf" in self.colors:
            out.append("Tf (transmission filter)")
        if self.illum is not None and self.illum > 2:
            out.append(f"illum {self.illum} (only 0, 1 and 2 are Phong models)")
        for keyword, texture in self.maps.items():
            if keyword not in PHONG_MAPS:
                out.append(f"{keyword} {texture.path}")
        out += [statement for _line, statement in self.others]
        return out

    def missing_textures(self) -> list:
        return [texture for texture in self.maps.values() if not texture.exists]


def _logical_lines(text: str):
    """(line number, text without comment) of each statement; ``\\`` continues a line."""
    pending, start = "", 0
    for number, raw in enumerate(text.splitlines(), start=1):
        line = raw.split("#", 1)[0].rstrip()
        if not pending:
            start = number
        if line.endswith("\\"):
            pending += line[:-1] + " "
            continue
        line, pending = pending + line, ""
        if line.strip():
            yield start, line.strip()
    if pending.strip():
        yield start, pending.strip()


def _number(path, line, keyword, token) -> float:
    try:
        value = float(token)
    except ValueError:
        raise MtlError(path, line, f"{keyword}: {token!r} is not a number") from None
    if not math.isfinite(value):
        raise MtlError(path, line, f"{keyword}: {token!r} is not a finite number")
    return value


def _color(path, line, keyword, args):
    if args and args[0].lower() in ("spectral", "xyz"):
        return None
    if len(args) not in (1, 3):
        raise MtlError(path, line, f"{keyword} needs 1 or 3 numbers (r [g b]), got {len(args)}")
    values = [_number(path, line, keyword, a) for a in args]
    return tuple(values * 3 if len(values) == 1 else values)


def _texture(path, line, keyword, rest) -> TextureMap:
    """A map statement's options and file name (the rest of the line, spaces kept)."""
    tokens = list(re.finditer(r"\S+", rest))
    options, i = {}, 0
    while i < len(tokens) and tokens[i].group().lower() in MAP_OPTIONS:
        option = tokens[i].group().lower()
        least, most = MAP_OPTIONS[option]
        values = []
        i += 1
        while len(values) < most and i < len(tokens) - 1:
            token = tokens[i].group()
            if option in _WORD_OPTIONS:
                values.append(token.lower())
            else:
                try:
                    values.append(_number(path, line, f"{keyword} {option}", token))
                except MtlError:
                    if len(values) < least:
                        raise
                    break
            i += 1
        if len(values) < least:
            raise MtlError(path, line, f"{keyword}: option {option} needs {least} value(s)")
        options[option] = tuple(values)
    if i >= len(tokens):
        raise MtlError(path, line, f"{keyword}: no file name")
    name = rest[tokens[i].start():].strip()
    folder = os.path.dirname(os.path.abspath(path))
    resolved = os.path.normpath(os.path.join(folder, name.replace("\\", "/")))
    return TextureMap(name, resolved, options, line)


def parse(text: str, path: str) -> list:
    """The materials of MTL *text* (read from *path*: named in errors, maps resolved from it)."""
    result, current = [], None
    for line, statement in _logical_lines(text):
        keyword, _, rest = statement.partition(" ")
        rest = rest.strip()
        low = keyword.lower()
        if low == "newmtl":
            if not rest:
                raise MtlError(path, line, "newmtl without a name")
            current = Material(rest, path, line)
            result.append(current)
            continue
        if current is None:
            raise MtlError(path, line, f"{keyword} before any newmtl")
        args = rest.split()
        if low in COLORS:
            value = _color(path, line, keyword, args)
            if value is None:
                current.others.append((line, f"{keyword} {args[0].lower()}"))
            else:
                current.colors[COLORS[low]] = value
        elif low in SCALARS:
            if args and args[0].lower() == "-halo":
                args = args[1:]
            if len(args) != 1:
                raise MtlError(path, line, f"{keyword} needs one number, got {len(args)}")
            value = _number(path, line, keyword, args[0])
            if value < 0 or (low in ("d", "tr") and value > 1):
                raise MtlError(path, line, f"{keyword} {args[0]} is out of range")
            current.scalars[SCALARS[low]] = value
        elif low == "illum":
            if len(args) != 1 or not args[0].isdigit() or int(args[0]) > 10:
                raise MtlError(path, line, f"illum needs an integer from 0 to 10, got {rest!r}")
            current.illum = int(args[0])
        elif low in MAPS:
            current.maps[MAPS[low]] = _texture(path, line, keyword, rest)
        else:
            current.others.append((line, keyword))
    return result


def _read(path: str, named_in: str = "", line: int = 0) -> str:
    try:
        with open(path, "rb") as fh:
            data = fh.read()
    except OSError as error:
        where = named_in or path
        raise MtlError(where, line, f"cannot read {path}: {error.strerror or error}") from None
    try:
        return data.decode("utf-8")
    except UnicodeDecodeError:
        return data.decode("latin-1")  # older exporters write Windows-1252 names


def load(path: str) -> list:
    """The materials of the MTL file *path*."""
    return parse(_read(path), path)


def libraries(obj_path: str) -> list:
    """(MTL path, line) of every ``mtllib`` file that the OBJ file *obj_path* names, relative
    paths taken from the OBJ's folder.  One statement may name several files; a name with
    spaces is accepted when the whole rest of the line names an existing file."""
    folder = os.path.dirname(os.path.abspath(obj_path))
    out = []
    for line, statement in _logical_lines(_read(obj_path)):
        keyword, _, rest = statement.partition(" ")
        if keyword != "mtllib":
            continue
        rest = rest.strip()
        whole = os.path.join(folder, rest.replace("\\", "/"))
        names = [rest] if os.path.isfile(whole) else rest.split()
        if not names:
            raise MtlError(obj_path, line, "mtllib without a file name")
        out += [(os.path.normpath(os.path.join(folder, n.replace("\\", "/"))), line)
                for n in names]
    return out


def load_for_obj(obj_path: str):
    """Every material of the OBJ's libraries: ({name: Material}, warnings).  A missing library
    is an error naming the OBJ file and its ``mtllib`` line; a material defined twice keeps its
    first definition, with a warning."""
    materials, warnings = {}, []
    for path, line in libraries(obj_path):
        if not os.path.isfile(path):
            raise MtlError(obj_path, line, f"material library {path} not found")
        for material in parse(_read(path, obj_path, line), path):
            if material.name in materials:
                first = materials[material.name]
                warnings.append(f"{path}:{material.line}: material {material.name!r} is "
                                f"already defined at {first.path}:{first.line}; kept the first")
                continue
            materials[material.name] = material
    return materials, warnings


# -- writing --------------------------------------------------------------------------

def _number_text(value: float) -> str:
    """The shortest text that reads back as the same float (an exact round trip)."""
    text = repr(float(value))
    return text[:-2] if text.endswith(".0") else text


def _value_text(value) -> str:
    return _number_text(value) if isinstance(value, float) else str(value)


def dumps(materials, header: str = "") -> str:
    """MTL text for *materials* (:class:`Material`: colours, scalars, illum, maps with their
    options; each material's ``comments`` come before its ``newmtl``)."""
    lines = [f"# {line}" if line else "#" for line in header.splitlines()]
    for material in materials:
        if lines:
            lines.append("")
        lines += [f"# {comment}" for comment in material.comments]
        lines.append(f"newmtl {material.name}")
        for key in ("Ka", "Kd", "Ks", "Ke", "Tf"):
            if key in material.colors:
                lines.append(f"{key} " + " ".join(_number_text(v) for v in material.colors[key]))
        for key in ("Ns", "Ni", "d", "Tr", "sharpness"):
            if key in material.scalars:
                lines.append(f"{key} {_number_text(material.scalars[key])}")
        if material.illum is not None:
            lines.append(f"illum {material.illum}")
        for key, texture in material.maps.items():
            options = "".join(
                f"{option} {' '.join(_value_text(v) for v in values)} "
                for option, values in texture.options.items())
            lines.append(f"{key} {options}{texture.path}")
    return "\n".join(lines) + "\n"
