# SPDX-License-Identifier: GPL-3.0-or-later
"""The Phong parts of a binary FBX file rewritten in place: no ``bpy``.

Blender's own FBX exporter writes the scene (meshes, armatures, animation, units, axes ...);
its materials are Principled guesses and its lights physical.  :func:`rewrite` takes the
bytes it wrote and plain data of the Phong materials, lights and ambient (by name) and returns
the same file with, for each of them, the ``Properties70`` of the FBX object (and a
material's ``ShadingModel``) replaced:

* a material: ShadingModel "Phong" or "Lambert"; DiffuseColor, AmbientColor, SpecularColor,
  EmissiveColor, ShininessExponent and Shininess, every factor 1 (ReflectionFactor 0: the
  Phong model has no mirror term, and Blender's importer makes a material with
  ReflectionFactor 1 fully metallic), the opacity triple Opacity o, TransparencyFactor
  1 − o, TransparentColor white (with a map on either: the factor and colour of the SDK's
  rule, 1 − TransparencyFactor·t_f × mean(TransparentColor ⊗ t_c));
* a material's maps: a Texture and a Video object each (the image file's absolute and
  relative paths, whether or not the file is there; its bytes as the Video's Content where
  the export embeds them), connected to the property it maps
  (DiffuseColor ... ShininessExponent, TransparencyFactor, TransparentColor) as Blender's
  exporter connects them;
* a light: LightType, Color, Intensity, DecayType, CastShadows, and a spot's OuterAngle and
  InnerAngle;
* GlobalSettings' AmbientColor;
* what FBX cannot say as user properties (flag "U", names :data:`USER`\\ + key) that
  ``read`` reads back; ``phong`` says what each value is.

Every value is written on the object itself, never left to a template.  Every other node
keeps its bytes: the file is walked by its node headers only (a node's properties, the
compressed arrays of meshes included, are copied as they are), and the headers after the
first change get their new end offsets.  Binary FBX 7.x (7100-7400: 32-bit headers, 7500+:
64-bit) as Blender writes it; the footer's alignment padding is recomputed as Blender's
``encode_bin`` writes it.  Anything else is a :class:`FbxWriteError`.
"""

from __future__ import annotations

import struct

from .model import PROPERTY_OF, USER, Light, Material
from .phong import WRITTEN_TYPES

MAGIC = b"Kaydara FBX Binary  \x00\x1a\x00"
#: Blender's footer id (``encode_bin._FOOT_ID``), followed by 4 zero bytes, the padding to 16
#: bytes, the version, 120 zero bytes and :data:`FOOT_MAGIC`.
FOOT_ID = b"\xfa\xbc\xab\x09\xd0\xc8\xd4\x66\xb1\x76\xfb\x83\x1c\xf7\x26\x7e"
FOOT_MAGIC = b"\xf8\x5a\x8c\x6a\xde\xf5\xd9\x7e\xec\xe9\x0c\xe3\x75\x8f\x29\x0b"


class FbxWriteError(ValueError):
    """A file that is not a binary FBX this module can rewrite."""


# -- the node tree ------------------------------------------------------------------------------

class _Node:
    __slots__ = ("name", "start", "end", "props_end", "count", "children", "sentinel",
                 "new_props", "new_count", "edited")

    def __init__(self, name, start, end, props_end, count):
        self.name, self.start, self.end, self.props_end, self.count = (
            name, start, end, props_end, count)
        self.children = []
        self.sentinel = False
        self.new_props = None      # bytes of the properties, replaced
        self.new_count = None
        self.edited = False        # this node or one below it changed


class _Reader:
    def __init__(self, data: bytes):
        if data[:23] != MAGIC or len(data) < 27:
            raise FbxWriteError("not a binary FBX file")
        self.data = data
        self.version = struct.unpack_from("<I", data, 23)[0]
        if self.version < 7100:
            raise FbxWriteError(f"binary FBX {self.version}: only 7100 and later are rewritten")
        self.wide = self.version >= 7500
        self.head = struct.Struct("<3Q" if self.wide else "<3I")
        self.null = self.head.size + 1

    def node(self, pos):
        """The node at *pos* (None at a null record) and the position after it."""
        end, count, length = self.head.unpack_from(self.data, pos)
        if end == 0:
            return None, pos + self.null
        name_len = self.data[pos + self.head.size]
        name_at = pos + self.head.size + 1
        props_end = name_at + name_len + length
        if not pos < props_end <= end <= len(self.data):
            raise FbxWriteError(f"corrupt node at byte {pos}")
        node = _Node(bytes(self.data[name_at:name_at + name_len]), pos, end, props_end, count)
        inner = props_end
        while inner < end:
            if end - inner == self.null and not any(self.data[inner:end]):
                node.sentinel = True
                break
            child, inner = self.node(inner)
            if child is None:
                node.sentinel = True
                break
            node.children.append(child)
        return node, end

    def top(self):
        nodes, pos = [], 27
        while True:
            if pos + self.null > len(self.data):
                raise FbxWriteError("the file ends inside its node list")
            node, pos = self.node(pos)
            if node is None:
                return nodes, pos
            nodes.append(node)

    def props(self, node) -> list:
        """The properties of *node* (numbers and strings; arrays as None)."""
        data, pos = self.data, node.start + self.head.size + 1 + len(node.name)
        out = []
        for _ in range(node.count):
            kind = chr(data[pos])
            pos += 1
            if kind in "SR":
                (size,) = struct.unpack_from("<I", data, pos)
                value = bytes(data[pos + 4:pos + 4 + size])
                out.append(value.decode("utf-8", "replace") if kind == "S" else value)
                pos += 4 + size
            elif kind in _SCALARS:
                fmt = _SCALARS[kind]
                out.append(struct.unpack_from(fmt, data, pos)[0])
                pos += struct.calcsize(fmt)
            elif kind in "fdlibc":
                size = struct.unpack_from("<3I", data, pos)[2]
                out.append(None)
                pos += 12 + size
            else:
                raise FbxWriteError(f"unknown property type {kind!r} in {node.name!r}")
        return out


_SCALARS = {"Y": "<h", "C": "<?", "I": "<i", "F": "<f", "D": "<d", "L": "<q"}


def _prop(kind, value) -> bytes:
    if kind == "R":
        raw = bytes(value)
        return b"R" + struct.pack("<I", len(raw)) + raw
    if kind == "S":
        raw = value.encode("utf-8") if isinstance(value, str) else bytes(value)
        return b"S" + struct.pack("<I", len(raw)) + raw
    return kind.encode() + struct.pack(_SCALARS[kind], value)


def p_node(name, ptype, label, flags, values, kinds) -> "_Synthetic":
    """A ``P`` node (a property: name, type, label, flags, *values* of the FBX property
    types *kinds*), placed by :func:`_emit`."""
    props = b"".join([_prop("S", name), _prop("S", ptype), _prop("S", label),
                      _prop("S", flags)] + [_prop(k, v) for k, v in zip(kinds, values)])
    return _Synthetic(b"P", props, 4 + len(values))


class _Synthetic:
    """A node made here (*children*: nodes below it, then a null record)."""
    __slots__ = ("name", "props", "count", "children")

    def __init__(self, name, props, count, children=None):
        self.name, self.props, self.count = name, props, count
        self.children = children


def _made(name: bytes, values, kinds, children=None) -> _Synthetic:
    """A node *name* with properties *values* of FBX types *kinds* (and *children*)."""
    return _Synthetic(name, b"".join(_prop(k, v) for k, v in zip(kinds, values)),
                      len(values), children)


def color(name, value, ptype="Color", label="") -> tuple:
    return (name, ptype, label, "A", tuple(float(v) for v in value[:3]), "DDD")


def number(name, value, ptype="Number", label="") -> tuple:
    return (name, ptype, label, "A", (float(value),), "D")


def enum(name, value, ptype="enum") -> tuple:
    return (name, ptype, "", "", (int(value),), "I")


def user(key, value) -> tuple:
    return (USER + key, "double", "Number", "U", (float(value),), "D")


def material_props(m: Material) -> list:
    """The properties of a Phong material, in the order they are written."""
    zero = (0.0, 0.0, 0.0)
    out = [("ShadingModel", "KString", "", "", ("Lambert" if m.lambert else "Phong",), "S"),
           color("DiffuseColor", m.colors["Object Color"]), number("DiffuseFactor", 1.0),
           color("AmbientColor", m.colors["Ambient Object Color"]),
           number("AmbientFactor", 1.0),
           color("EmissiveColor", m.colors["Irradiant Color"]), number("EmissiveFactor", 1.0),
           color("SpecularColor", zero if m.lambert else m.colors["Specular Color"]),
           number("SpecularFactor", 1.0),
           number("ShininessExponent", m.exponent), number("Shininess", m.exponent),
           color("ReflectionColor", zero), number("ReflectionFactor", 0.0),
           color("TransparentColor", m.transparent_color or (1.0, 1.0, 1.0)),
           number("TransparencyFactor", 1.0 - m.opacity if m.transparency_factor is None
                  else m.transparency_factor),
           number("Opacity", m.opacity)]
    return out + [user(k, v) for k, v in sorted(m.user.items())]


def light_props(light: Light) -> list:
    out = [enum("LightType", WRITTEN_TYPES[light.type]), color("Color", light.color),
           number("Intensity", 100.0 * light.intensity), enum("DecayType", light.decay),
           enum("CastShadows", 1 if light.cast_shadows else 0, "bool")]
    if light.type == "SPOT":
        out += [number("OuterAngle", light.outer_angle), number("InnerAngle", light.inner_angle)]
    return out + [user(k, v) for k, v in sorted(light.user.items())]


# -- the rewrite --------------------------------------------------------------------------------

def _object_name(raw) -> str:
    """The name of an FBX object ("name\\x00\\x01Class" in binary files)."""
    if isinstance(raw, bytes):
        raw = raw.decode("utf-8", "replace")
    return raw.split("\x00\x01")[0]


def _set_props(reader, node, props: list) -> None:
    """*node*'s Properties70 child gets *props* (P tuples): those it holds are replaced in
    place, the others added after them; every other P keeps its bytes."""
    block = next((c for c in node.children if c.name == b"Properties70"), None)
    if block is None:
        raise FbxWriteError(f"{node.name.decode()} without Properties70")
    wanted = {p[0]: p for p in props}
    children = []
    for child in block.children:
        name = reader.props(child)[0] if child.name == b"P" else None
        if name in wanted:
            children.append(p_node(*wanted.pop(name)))
        elif name is not None and name.startswith(USER):
            continue   # an earlier rewrite's user property: written anew or gone
        else:
            children.append(child)
    children += [p_node(*p) for p in props if p[0] in wanted]
    block.children = children
    block.edited = node.edited = True


def _set_string_child(reader, node, name: bytes, value: str) -> None:
    for index, child in enumerate(node.children):
        if child.name == name:
            node.children[index] = _Synthetic(name, _prop("S", value), 1)
            node.edited = True


def rewrite(data: bytes, materials: dict | None = None, lights: dict | None = None,
            ambient=None, ambient_user: dict | None = None, force: bool = False) -> tuple:
    """(the new bytes of the binary FBX *data*, the names not found) with the Phong
    *materials* ({name: :class:`Material`}), *lights* ({light data name: :class:`Light`}),
    the scene's *ambient* colour (or None) and GlobalSettings' user properties
    *ambient_user* written (see the module's docstring).  *force* re-encodes every node
    header (a test of the walk: the result is the same bytes)."""
    reader = _Reader(data)
    try:
        top, after = reader.top()
    except (struct.error, IndexError) as error:
        raise FbxWriteError(f"corrupt node list ({error})") from None
    materials, lights = dict(materials or {}), dict(lights or {})
    found, links = set(), []   # links: (material id, property, Texture)
    for section in top:
        if section.name == b"Objects":
            for obj in list(section.children):
                if obj.name not in (b"Material", b"NodeAttribute"):
                    continue
                values = reader.props(obj)
                name = _object_name(values[1]) if len(values) > 1 else ""
                if obj.name == b"Material" and name in materials:
                    m = materials[name]
                    _set_props(reader, obj, material_props(m))
                    _set_string_child(reader, obj, b"ShadingModel",
                                      "Lambert" if m.lambert else "Phong")
                    links += sorted(((values[0], PROPERTY_OF[key], t)
                                     for key, t in m.textures.items()), key=lambda x: x[1])
                    section.edited = True
                    found.add(("material", name))
                elif obj.name == b"NodeAttribute" and len(values) > 2 and \
                        values[2] == "Light" and name in lights:
                    _set_props(reader, obj, light_props(lights[name]))
                    section.edited = True
                    found.add(("light", name))
        elif section.name == b"GlobalSettings" and ambient is not None:
            _set_props(reader, section, [color("AmbientColor", ambient, "ColorRGB", "Color")]
                       + [user(k, v) for k, v in sorted((ambient_user or {}).items())])
    if links:
        _add_textures(reader, top, links)
    missing = [f"material {n}" for n in materials if ("material", n) not in found] + \
              [f"light {n}" for n in lights if ("light", n) not in found]
    chunks = [memoryview(data)[:27]]
    pos = 27
    for node in top:
        pos = _emit(reader, node, pos, chunks, force)
    chunks.append(bytes(reader.null))
    pos += reader.null
    chunks.append(_footer(reader, data, after, pos))
    return b"".join(chunks), missing


def _ids(reader, objects) -> set:
    return {v for obj in objects.children if not isinstance(obj, _Synthetic)
            for v in reader.props(obj)[:1] if isinstance(v, int)}


def _add_textures(reader, top, links) -> None:
    """A Texture and a Video object per image file of *links* ((material id, property,
    Texture)), as Blender's exporter writes them (TextureVideoClip, Clip), connected: Video
    to Texture (OO), Texture to the material's property (OP); the Definitions' counts."""
    objects = next(n for n in top if n.name == b"Objects")
    connections = next((n for n in top if n.name == b"Connections"), None)
    if connections is None:
        raise FbxWriteError("no Connections section")
    taken = _ids(reader, objects)
    next_id = [max(taken, default=1 << 40) + 1]

    def new_id():
        while next_id[0] in taken or next_id[0] >= 1 << 63:
            next_id[0] = (next_id[0] + 7919) % (1 << 62) + 1
        taken.add(next_id[0])
        return next_id[0]

    made = {}
    for material, prop, texture in links:
        key = texture.path
        if key not in made:
            video_id, texture_id = new_id(), new_id()
            name = texture.name.replace("\x00", "")
            video = _made(b"Video", (video_id, f"{name}\x00\x01Video", "Clip"), "LSS", [
                _made(b"Type", ("Clip",), "S"),
                _made(b"Properties70", (), "", [p_node("Path", "KString", "XRefUrl", "",
                                                       (texture.path,), "S")]),
                _made(b"UseMipMap", (0,), "I"),
                _made(b"Filename", (texture.path,), "S"),
                _made(b"RelativeFilename", (texture.relative,), "S")]
                + ([_made(b"Content", (texture.content,), "R")] if texture.content else []))
            tex = _made(b"Texture", (texture_id, f"{name}\x00\x01Texture", ""), "LSS", [
                _made(b"Type", ("TextureVideoClip",), "S"),
                _made(b"Version", (202,), "I"),
                _made(b"TextureName", (f"{name}\x00\x01Texture",), "S"),
                _made(b"Media", (f"{name}\x00\x01Video",), "S"),
                _made(b"FileName", (texture.path,), "S"),
                _made(b"RelativeFilename", (texture.relative,), "S")])
            objects.children += [tex, video]
            connections.children.append(_made(b"C", ("OO", video_id, texture_id), "SLL"))
            made[key] = texture_id
        connections.children.append(_made(b"C", ("OP", made[key], material, prop), "SLLS"))
    objects.edited = connections.edited = True
    _count(reader, top, {b"Texture": len(made), b"Video": len(made)})


def _count(reader, top, added: dict) -> None:
    """The Definitions section's counts with *added* objects ({type: how many})."""
    definitions = next((n for n in top if n.name == b"Definitions"), None)
    if definitions is None:
        return
    for child in definitions.children:
        if child.name != b"ObjectType" or isinstance(child, _Synthetic):
            continue
        kind = reader.props(child)[0].encode()
        if kind in added:
            for j, grand in enumerate(child.children):
                if grand.name == b"Count":
                    child.children[j] = _made(b"Count", (reader.props(grand)[0]
                                                         + added.pop(kind),), "I")
                    child.edited = definitions.edited = True
    for kind, count in added.items():
        definitions.children.append(_made(b"ObjectType", (kind.decode(),), "S",
                                          [_made(b"Count", (count,), "I")]))
        definitions.edited = True


def _emit(reader, node, pos, chunks, force) -> int:
    """Append the bytes of *node* placed at *pos*; returns the position after it."""
    data = reader.data
    if isinstance(node, _Synthetic):
        inner = pos + reader.head.size + 1 + len(node.name) + len(node.props)
        header = len(chunks)
        chunks.append(None)
        chunks.append(bytes((len(node.name),)) + node.name + node.props)
        if node.children is not None:
            for child in node.children:
                inner = _emit(reader, child, inner, chunks, force)
            chunks.append(bytes(reader.null))
            inner += reader.null
        chunks[header] = reader.head.pack(inner, node.count, len(node.props))
        return inner
    if not node.edited and not force and pos == node.start:
        chunks.append(memoryview(data)[node.start:node.end])
        return node.end
    name_at = node.start + reader.head.size + 1
    props = memoryview(data)[name_at + len(node.name):node.props_end]
    header = len(chunks)
    chunks.append(None)
    chunks.append(bytes((len(node.name),)) + node.name)
    chunks.append(props)
    inner = pos + reader.head.size + 1 + len(node.name) + len(props)
    for child in node.children:
        inner = _emit(reader, child, inner, chunks, force)
    if node.sentinel:
        chunks.append(bytes(reader.null))
        inner += reader.null
    chunks[header] = reader.head.pack(inner, node.count, len(props))
    return inner


def _footer(reader, data, after, pos) -> bytes:
    """The footer after the top-level null record, its alignment padding recomputed for the
    new length as Blender's ``encode_bin`` writes it; another program's footer as it was."""
    tail = bytes(data[after:])
    if not tail.startswith(FOOT_ID + b"\x00" * 4) or not tail.endswith(FOOT_MAGIC):
        return tail
    ofs = pos + len(FOOT_ID) + 4
    pad = ((ofs + 15) & ~15) - ofs or 16
    return (FOOT_ID + b"\x00" * 4 + b"\x00" * pad + struct.pack("<I", reader.version)
            + b"\x00" * 120 + FOOT_MAGIC)
