# SPDX-License-Identifier: GPL-3.0-or-later
"""Wavefront MTL material libraries, read without ``bpy`` (issue "Interchange", part 3).

MTL is the classic Phong model written down: ``Ka`` ambient, ``Kd`` diffuse, ``Ks`` specular
reflectivity, ``Ns`` the specular exponent, ``Ke`` emission, ``illum`` the illumination model
(0 colour only, 1 ambient + Lambert, 2 + highlight) and texture maps (``map_Kd`` ...).  The
statements follow Alias|Wavefront's *File Formats*, version 4.2 (1995), chapter 5:

* a colour is ``r [g b]`` (one value: g = b = r); ``spectral`` and ``xyz`` colours are kept
  as statements the model cannot represent;
* a map statement is ``map_Kd [options] file`` with the options of :data:`MAP_OPTIONS`; the
  file name is the rest of the line (it may hold spaces) and is looked up as other readers
  do (:func:`find_file`);
* ``bump`` and ``map_Bump`` are the same statement; keywords are read case-insensitively;
* ``#`` starts a comment, a line ending in ``\\`` continues on the next, CRLF line ends work;
  a keyword and its values are separated by any whitespace (spaces or tabs).

Other programs' files are read the way other readers read them: a library is refused only
when it cannot be read at all (a missing file).  A statement the Phong model does not use
(``d``, ``Ni``, ``Tr``, ``Tf`` ...) never refuses a file whatever its value; a statement it
uses whose value cannot be read is left out, and a value out of its range is clamped (``Ns``
below 0 reads as 0), each with one warning naming file and line (``warnings`` of
:func:`parse`).  :func:`dumps` writes materials back (numbers as the shortest decimal that
reads back as the same float32, Blender's precision).
"""

from __future__ import annotations

import math
import mmap
import os
import re
from dataclasses import dataclass, field

import numpy as np

#: Canonical keyword for each accepted spelling (lower case).
COLORS = {"ka": "Ka", "kd": "Kd", "ks": "Ks", "ke": "Ke", "tf": "Tf", "kt": "Tf"}
SCALARS = {"ns": "Ns", "ni": "Ni", "d": "d", "tr": "Tr", "sharpness": "sharpness"}
MAPS = {"map_ka": "map_Ka", "map_kd": "map_Kd", "map_ks": "map_Ks", "map_ke": "map_Ke",
        "map_ns": "map_Ns", "map_d": "map_d", "map_bump": "bump", "bump": "bump",
        "disp": "disp", "decal": "decal", "refl": "refl", "map_refl": "refl"}
#: Colours and scalars the Phong model reads; the others never refuse nor warn on their own.
USED = {"Ka", "Kd", "Ks", "Ke", "Ns"}
#: Map options (File Formats 4.2, and ``-colorspace`` of tinyobjloader and others) and how
#: many values follow them: (least, most, words or numbers).
MAP_OPTIONS = {"-o": (1, 3, False), "-s": (1, 3, False), "-t": (1, 3, False),
               "-bm": (1, 1, False), "-boost": (1, 1, False), "-mm": (2, 2, False),
               "-texres": (1, 1, True), "-blendu": (1, 1, True), "-blendv": (1, 1, True),
               "-clamp": (1, 1, True), "-cc": (1, 1, True), "-imfchan": (1, 1, True),
               "-type": (1, 1, True), "-colorspace": (1, 1, True)}
#: Option values that change nothing in the picture (those of the file format's defaults).
NEUTRAL_OPTIONS = {"-o": (0.0, 0.0, 0.0), "-s": (1.0, 1.0, 1.0), "-t": (0.0, 0.0, 0.0),
                   "-mm": (0.0, 1.0), "-blendu": ("on",), "-blendv": ("on",),
                   "-clamp": ("off",), "-cc": ("off",)}
#: Options that change no pixel of a render (mip-mapping and resolution hints), and
#: colour spaces that are Blender's own for colour maps.
UNSEEN_OPTIONS = {"-boost", "-texres", "-type", "-imfchan"}
#: Options the importer applies: -bm (bump strength), -o and -s (the map's placement).
APPLIED_OPTIONS = {"-bm", "-o", "-s"}
SRGB_NAMES = {"srgb", "srgb_texture", "srgb texture", "default"}
#: Maps the Phong model has an input for.
PHONG_MAPS = ("map_Ka", "map_Kd", "map_Ks", "map_Ke", "bump")
#: Illumination models that let light through, reflect with Fresnel or refract (where
#: ``Ni`` and ``Tf`` matter).
SEE_THROUGH_ILLUM = {4, 5, 6, 7, 9}


class MtlError(ValueError):
    """A file that cannot be read as MTL (or OBJ ``mtllib``): names the file and line."""

    def __init__(self, path: str, line: int, message: str):
        self.path, self.line = path, line
        super().__init__(f"{path}:{line}: {message}" if line else f"{path}: {message}")


@dataclass
class TextureMap:
    path: str                 # as written in the file
    resolved: str             # where it was found, or the first place looked at
    options: dict             # option -> tuple of its values, e.g. {"-s": (2.0, 2.0, 1.0)}
    line: int
    looked_at: tuple = ()     # every place looked at, in order

    @property
    def exists(self) -> bool:
        return os.path.isfile(self.resolved)

    def placement(self):
        """(offset, scale) of ``-o`` and ``-s`` (u, v, w, the file format's defaults filled
        in), which the importer applies to the map's UV coordinates (uv × scale + offset, as
        Blender's own OBJ importer and three.js's MTLLoader do); None when both are
        neutral."""
        offset = _padded("-o", self.options.get("-o", ()))
        scale = _padded("-s", self.options.get("-s", ()))
        if offset == NEUTRAL_OPTIONS["-o"] and scale == NEUTRAL_OPTIONS["-s"]:
            return None
        return offset, scale

    def unapplied_options(self, keyword: str) -> list:
        """The options that change the picture and that the importer does not apply."""
        out = []
        for option, values in self.options.items():
            # -bm: applied to a bump map, meaningless for the others (File Formats 4.2);
            # -o and -s: applied (placement)
            if option in UNSEEN_OPTIONS or option in APPLIED_OPTIONS or \
                    NEUTRAL_OPTIONS.get(option) == _padded(option, values):
                continue
            if option == "-colorspace" and (keyword == "bump" or
                                            str(values[0]).lower() in SRGB_NAMES):
                continue
            out.append(f"{option} {' '.join(_value_text(v) for v in values)}")
        return out


def _padded(option, values):
    """-o/-s/-t with their missing v, w filled in as the file format defines."""
    if option in ("-o", "-t"):
        return tuple(values) + (0.0,) * (3 - len(values))
    if option == "-s":
        return tuple(values) + (1.0,) * (3 - len(values))
    return tuple(values)


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

    def transparency(self):
        """How much light the material lets through (0 opaque), as readers take d and Tr:
        ``d`` wins over ``Tr`` (tinyobjloader, Blender), values clamped to 0..1."""
        if "d" in self.scalars:
            return 1.0 - min(max(self.scalars["d"], 0.0), 1.0)
        if "Tr" in self.scalars:
            return min(max(self.scalars["Tr"], 0.0), 1.0)
        return 0.0

    def unsupported(self) -> list:
        """What the Phong model cannot show, one short phrase each (for one warning).  Values
        that change nothing in the picture (``d 1``, ``Tr 0``, ``Ni`` and ``Tf`` of an
        opaque material) are not named."""
        out = []
        see_through = self.transparency() > 0.0 or self.illum in SEE_THROUGH_ILLUM
        if self.transparency() > 0.0:
            key = "d" if "d" in self.scalars else "Tr"
            out.append(f"{key} {_value_text(self.scalars[key])} (transparency)")
        if see_through and "Ni" in self.scalars and self.scalars["Ni"] != 1.0:
            out.append(f"Ni {_value_text(self.scalars['Ni'])} (refraction)")
        if see_through and self.colors.get("Tf", (1.0, 1.0, 1.0)) != (1.0, 1.0, 1.0):
            out.append("Tf (transmission filter)")
        if self.illum is not None and self.illum > 2:
            out.append(f"illum {self.illum} (only 0, 1 and 2 are Phong models)")
        for keyword, texture in self.maps.items():
            if keyword not in PHONG_MAPS:
                out.append(f"{keyword} {texture.path}")
            else:
                out += [f"{keyword} {option} (not applied)"
                        for option in texture.unapplied_options(keyword)]
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


def _statement(text: str):
    """(keyword, rest): split at the first whitespace of any kind (space, tab)."""
    parts = text.split(None, 1)
    return parts[0], (parts[1].strip() if len(parts) > 1 else "")


class _Skip(Exception):
    """A statement that cannot be read: left out, with a warning when the model uses it."""


def _number(keyword, token) -> float:
    try:
        value = float(token)
    except ValueError:
        raise _Skip(f"{keyword}: {token!r} is not a number") from None
    if not math.isfinite(value):
        raise _Skip(f"{keyword}: {token!r} is not a finite number")
    return value


def _color(keyword, args):
    if args and args[0].lower() in ("spectral", "xyz"):
        return None
    if len(args) not in (1, 3):
        raise _Skip(f"{keyword} needs 1 or 3 numbers (r [g b]), got {len(args)}")
    values = [_number(keyword, a) for a in args]
    return tuple(values * 3 if len(values) == 1 else values)


def _illum(args):
    """``illum 2``, and ``illum 2.0`` as some exporters (Tinkercad) write it."""
    try:
        value = float(args[0]) if len(args) == 1 else math.nan
    except ValueError:
        value = math.nan
    if not (value.is_integer() and 0 <= value <= 10):
        raise _Skip(f"illum {' '.join(args)!r} is not an illumination model (0 to 10); "
                    "read as illum 2")
    return int(value)


def _is_option(token: str) -> bool:
    if not token.startswith("-") or len(token) < 2:
        return False
    try:
        float(token)
    except ValueError:
        return True
    return False


def _options(keyword, tokens, i, end, notes):
    """The run of known options from tokens[i], each with at most its arity of values taken
    from tokens[:end]: ({option: values}, index after the run)."""
    options = {}
    while i < len(tokens) and tokens[i].group().lower() in MAP_OPTIONS:
        option = tokens[i].group().lower()
        least, most, words = MAP_OPTIONS[option]
        values, i, bad = [], i + 1, None
        while len(values) < most and i < end:
            token = tokens[i].group()
            try:
                values.append(token.lower() if words else _number(option, token))
            except _Skip:
                if len(values) < least:
                    bad, i = token, i + 1
                break
            i += 1
        if len(values) >= least:
            options[option] = tuple(values)
        elif bad is not None:
            notes.append(f"{keyword}: option {option} needs a number, got {bad!r}; "
                         "option left out")
        else:
            notes.append(f"{keyword}: option {option} needs {least} value(s); option left out")
    return options, i


def _texture(path, keyword, rest, notes, line) -> TextureMap:
    """A map statement's options and file name.  The name is the rest of the line after the
    options (it may hold spaces; the last word always is the name, never an option's value);
    known options after the name (``bump b.png -bm 1.5``, as tinyobjloader reads them) are
    options too; an unknown option ends the options with a note, the name being the last
    word."""
    tokens = list(re.finditer(r"\S+", rest))
    options, i = _options(keyword, tokens, 0, len(tokens) - 1, notes)
    if i >= len(tokens):
        raise _Skip(f"{keyword}: no file name")
    if _is_option(tokens[i].group()) and i < len(tokens) - 1:
        skipped = " ".join(t.group() for t in tokens[i:-1])
        notes.append(f"{keyword}: unknown option {tokens[i].group()}: {skipped!r} left out, "
                     f"file name {tokens[-1].group()!r}")
        i = len(tokens) - 1
    name = rest[tokens[i].start():].strip()
    after = next((j for j in range(i + 1, len(tokens))
                  if tokens[j].group().lower() in MAP_OPTIONS), None)
    if after is not None and not find_file(path, name)[1]:
        name = rest[tokens[i].start():tokens[after].start()].strip()
        more, j = _options(keyword, tokens, after, len(tokens), notes)
        options.update(more)
        if j < len(tokens):
            notes.append(f"{keyword}: {rest[tokens[j].start():]!r} after the file name "
                         "left out")
    places, found = find_file(path, name)
    return TextureMap(name, found or places[0], options, line, tuple(places))


_DRIVE = re.compile(r"^[A-Za-z]:[\\/]")


def find_file(base_path: str, name: str):
    """(places looked at, the first that is a file or None) for the file *name* written in
    the file *base_path* (a texture of an MTL, a library of an OBJ), as other readers look:
    the name relative to *base_path*'s folder (or as it is, when absolute), ``\\`` read as
    ``/``; then its bare file name in that folder (Windows paths such as
    ``C:\\Users\\...\\tex.png`` or ``.\\tex.jpg``, or a path from another folder)."""
    folder = os.path.dirname(os.path.abspath(base_path))
    written = name.replace("\\", "/")
    places = []
    if not _DRIVE.match(name) and not written.startswith("//"):
        places.append(os.path.normpath(os.path.join(folder, written)))
    bare = os.path.join(folder, written.rsplit("/", 1)[-1])
    if bare not in places:
        places.append(bare)
    return places, next((p for p in places if os.path.isfile(p)), None)


def parse(text: str, path: str, warnings: list | None = None) -> list:
    """The materials of MTL *text* (read from *path*: named in warnings, maps resolved from
    it).  What is left out or changed is appended to *warnings* (``path:line: ...``)."""
    warnings = [] if warnings is None else warnings
    result, current, skipping = [], None, False
    for line, statement in _logical_lines(text):
        keyword, rest = _statement(statement)
        low = keyword.lower()
        if low == "newmtl":
            current, skipping = None, not rest
            if not rest:
                warnings.append(f"{path}:{line}: newmtl without a name; its statements are "
                                "left out")
                continue
            current = Material(rest, path, line)
            result.append(current)
            continue
        if current is None:
            if not skipping:
                warnings.append(f"{path}:{line}: {keyword} before any newmtl; left out")
            continue
        notes = []
        try:
            _statement_into(current, path, line, keyword, low, rest, notes)
        except _Skip as skip:
            canonical = COLORS.get(low) or SCALARS.get(low) or MAPS.get(low) or low
            if canonical in USED or canonical in PHONG_MAPS or low == "illum":
                notes.append(f"{skip}; left out" if low != "illum" else str(skip))
        warnings += [f"{path}:{line}: {note}" for note in notes]
    return result


def _statement_into(current, path, line, keyword, low, rest, notes):
    args = rest.split()
    if low in COLORS:
        value = _color(keyword, args)
        if value is None:
            current.others.append((line, f"{keyword} {args[0].lower()}"))
        else:
            current.colors[COLORS[low]] = value
    elif low in SCALARS:
        if args and args[0].lower() == "-halo":
            args = args[1:]
        if len(args) != 1:
            raise _Skip(f"{keyword} needs one number, got {len(args)}")
        value = _number(keyword, args[0])
        if low == "ns" and value < 0:
            notes.append(f"Ns {args[0]} is below 0; read as 0")
            value = 0.0
        current.scalars[SCALARS[low]] = value
    elif low == "illum":
        current.illum = None          # a later unreadable illum is read as none (2)
        current.illum = _illum(args)
    elif low in MAPS:
        mine = []
        current.maps[MAPS[low]] = _texture(path, keyword, rest, mine, line)
        if MAPS[low] in PHONG_MAPS:
            notes += mine
    else:
        current.others.append((line, keyword))


def _read(path: str, named_in: str = "", line: int = 0) -> str:
    try:
        with open(path, "rb") as fh:
            data = fh.read()
    except OSError as error:
        where = named_in or path
        raise MtlError(where, line, f"cannot read {path}: {error.strerror or error}") from None
    try:
        return data.decode("utf-8-sig")
    except UnicodeDecodeError:
        return data.decode("latin-1")  # older exporters write Windows-1252 names


def load(path: str, warnings: list | None = None) -> list:
    """The materials of the MTL file *path* (what is left out appended to *warnings*)."""
    return parse(_read(path), path, warnings)


def _obj_head(obj_path: str) -> str:
    """The text of the OBJ file *obj_path* up to the end of the last line that holds
    ``mtllib`` (and the lines a ``\\`` at its end continues it with): no statement after
    it can name a library, so the vertices and faces of a large file are never decoded
    (found in the mapped file by ``rfind``; decoded as :func:`_read` decodes)."""
    try:
        with open(obj_path, "rb") as handle:
            size = os.fstat(handle.fileno()).st_size
            if not size:
                return ""
            with mmap.mmap(handle.fileno(), 0, access=mmap.ACCESS_READ) as view:
                last = view.rfind(b"mtllib")
                if last < 0:
                    return ""
                end = view.find(b"\n", last)
                while end >= 0:   # a line ending in a backslash goes on in the next one
                    line = view[view.rfind(b"\n", 0, end) + 1:end]
                    if not line.split(b"#", 1)[0].rstrip().endswith(b"\\"):
                        break
                    end = view.find(b"\n", end + 1)
                data = view[:size if end < 0 else end + 1]
    except (OSError, ValueError) as error:
        raise MtlError(obj_path, 0, f"cannot read {obj_path}: "
                       f"{getattr(error, 'strerror', None) or error}") from None
    try:
        return data.decode("utf-8-sig")
    except UnicodeDecodeError:
        return data.decode("latin-1")


def libraries(obj_path: str) -> list:
    """(MTL path, line) of every ``mtllib`` file that the OBJ file *obj_path* names, looked up
    as :func:`find_file` does (the first place looked at when it is nowhere).  One statement
    may name several files; a name with spaces is accepted when the whole rest of the line
    names an existing file.  Only the head of the file that can hold ``mtllib`` is read
    (:func:`_obj_head`)."""
    out = []
    for line, statement in _logical_lines(_obj_head(obj_path)):
        keyword, rest = _statement(statement)
        if keyword != "mtllib":
            continue
        names = [rest] if find_file(obj_path, rest)[1] else rest.split()
        if not names:
            raise MtlError(obj_path, line, "mtllib without a file name")
        for name in names:
            places, found = find_file(obj_path, name)
            out.append((found or places[0], line))
    return out


def load_for_obj(obj_path: str):
    """Every material of the OBJ's libraries: ({name: Material}, warnings).  A missing library
    is an error naming the OBJ file and its ``mtllib`` line; a material defined twice keeps its
    first definition, with a warning."""
    materials, warnings = {}, []
    for path, line in libraries(obj_path):
        if not os.path.isfile(path):
            raise MtlError(obj_path, line, f"material library {path} not found")
        for material in parse(_read(path, obj_path, line), path, warnings):
            if material.name in materials:
                first = materials[material.name]
                warnings.append(f"{path}:{material.line}: material {material.name!r} is "
                                f"already defined at {first.path}:{first.line}; kept the first")
                continue
            materials[material.name] = material
    return materials, warnings


# -- writing --------------------------------------------------------------------------

def _number_text(value: float) -> str:
    """The shortest decimal that reads back as the same float32 (Blender's precision)."""
    return np.format_float_positional(np.float32(value), unique=True, trim="-")


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
