# SPDX-License-Identifier: GPL-3.0-or-later
"""What every importer leaves behind, as Blender's own importers leave it.

An import adds exactly the file's materials, under the file's names (Blender's ``.001``
only where the file already holds the name), each a Phong material from birth, and nothing
else: no Principled copy, no unused material, no image nothing uses.  OBJ and binary FBX
take their geometry from Blender's own importers, which make Principled materials; those are
replaced here: the Phong material takes every user of the importer's material
(``user_remap``), the importer's material is removed and the Phong material takes its name.
An imported material has no "original" to restore (Apply Phong Material on a user's own
materials keeps its source, see ``lighting/sources.py``).

Only data blocks that did not exist before the import are ever touched (:func:`snapshot`).

Every importer answers alike (``formats.py`` holds the table of formats): its
``import_file(context, filepath, **options)`` returns an :class:`ImportResult` (objects,
materials, warnings) or raises an :class:`InterchangeError` (its message names the file) with
the scene as it was; the images of every format come through :func:`load_image`.

Also what importers and exporters share of Blender's own side: :func:`ensure_fbx_addon`
(Blender's FBX add-on, whose importer and exporter both serve) and :func:`image_components`
(an image file's channels, read from its header).
"""

from __future__ import annotations

import os
from dataclasses import dataclass, field

import bpy

from .. import compat
from ..lighting import opacity as opacity_nodes
from ..lighting import recipe, sources, writer

@dataclass
class ImportResult:
    """What an import made: its objects, its Phong materials, its warnings (each a line that
    names what it is about), and the ``lighting.sync.Sync`` run that finished it (its lights,
    for the operators' report of unsupported or missing lights)."""

    objects: list = field(default_factory=list)
    materials: list = field(default_factory=list)
    warnings: list = field(default_factory=list)
    sync: object = None


class InterchangeError(RuntimeError):
    """A file that cannot be imported: the message names the file and what is wrong; nothing
    was added to the scene.  Each format's own error (``X3DImportError``,
    ``ColladaImportError``, ...) is one of these."""


#: The ``bpy.data`` collections an import may add to.
KINDS = ("objects", "meshes", "materials", "images", "node_groups", "lights", "cameras",
         "collections", "worlds", "textures", "armatures", "actions", "curves")


def snapshot() -> dict:
    """{collection name: the set of its data blocks} of every kind an import may add to."""
    return {kind: set(getattr(bpy.data, kind)) for kind in KINDS if hasattr(bpy.data, kind)}


def added(before: dict, kind: str) -> list:
    """The data blocks of *kind* that did not exist at *before*."""
    return [block for block in getattr(bpy.data, kind) if block not in before[kind]]


#: The order in which a failed import removes what it added (users before what they use).
ROLLBACK_ORDER = ("objects", "collections", "meshes", "lights", "cameras", "materials", "images",
                  "node_groups", "worlds", "textures", "armatures", "actions", "curves")


def remove_added(before: dict, kinds=ROLLBACK_ORDER) -> None:
    """Remove every data block of *kinds* that did not exist at *before* (a failed import's
    rollback: the materials the Sync copied, lights groups and images included)."""
    for kind in kinds:
        if kind not in before:
            continue
        collection = getattr(bpy.data, kind)
        for block in added(before, kind):
            try:
                collection.remove(block)
            except (ReferenceError, RuntimeError):
                pass


def restore_keys(owner, values: dict) -> None:
    """Put back *owner*'s custom properties as *values* ({key: value, or None where the key
    was absent}) held them."""
    for key, value in values.items():
        if value is None:
            if key in owner.keys():
                del owner[key]
        else:
            owner[key] = value


def set_attribute(mesh, name, data_type, domain, key, values, fallback) -> None:
    """*values* into the attribute *name* of *mesh* at once (``foreach_set`` of the attribute
    data: the corners' vertices, the faces' material index, a UV map), made when missing;
    *fallback(values)* where Blender holds it otherwise."""
    attribute = mesh.attributes.get(name)
    if attribute is None and not name.startswith("."):
        attribute = mesh.attributes.new(name, data_type, domain)
    if attribute is None or attribute.data_type != data_type or attribute.domain != domain:
        fallback(values)
    else:
        attribute.data.foreach_set(key, values)


def take_place(old, new) -> None:
    """The Phong material *new* in the place of the importer's material *old*: every user
    of *old* uses *new*, *old* is removed and *new* takes its name (the file's name, with
    the ``.001`` Blender gave it where the file already held that name)."""
    name = old.name
    old.user_remap(new)
    bpy.data.materials.remove(old)
    new.name = name


def forget_source(material, source) -> None:
    """A Phong material made from the importer's material *source*
    (``sources.from_source``, which keeps the source with a fake user) as a material of its
    own: it names no source to restore, and the source keeps no fake user (it is removed)."""
    for key in (sources.SOURCE_KEY, sources.SOURCE_TOKEN, sources.EMPTY_SOURCE_KEY):
        if key in material.keys():
            del material[key]
    if source is not None:
        source.use_fake_user = False


def remove_unused(before: dict) -> list:
    """Remove the materials and then the images that the import added and that nothing uses
    (a material the file defines for no object, the images only the importer's materials
    used); returns their names.  Data blocks that existed before are never touched."""
    gone = []
    for kind in ("materials", "images"):
        collection = getattr(bpy.data, kind)
        for block in added(before, kind):
            if block.users == 0 or (block.users == 1 and block.use_fake_user):
                gone.append(block.name)
                collection.remove(block)
    return gone


# -- maps on the opacity and the exponent ------------------------------------------------------

#: Node names of the map chains (+ a suffix per chain); the chain of the opacity ends in
#: ``recipe.OPACITY_MAP``.
MAP_NODE = "phong_map:"
MEAN = (1.0 / 3.0, 1.0 / 3.0, 1.0 / 3.0)
NON_COLOR = "Non-Color"


def load_image(path, cache=None, non_color=False, straight_alpha=False, existing=True):
    """The one image loader of the importers: the Blender image of the file *path*, or None
    where Blender cannot read it (or it has no pixels; the caller warns).

    * One rule for the colour space: a colour map keeps the colour space Blender gives the
      file (sRGB for 8-bit images); a map whose texel is a number (*non_color*: bump,
      exponent, opacity maps, and X3D's textures, whose texel is the colour in the
      standard's equation as diffuseColor's numbers are) is Non-Color.  A file read both
      ways gets one image of each colour space, so that neither changes the other.
      *straight_alpha*: its colour read apart from its alpha (:func:`straight`).
    * One cache: *cache* ({(path, non_color): image or None}, one per import) loads each
      file once per colour space; *existing*: an image of the same file already in the file,
      of the same colour space (and alpha mode), is used rather than loaded again, as
      Blender's ``check_existing`` does (X3D renames its images: it loads its own)."""
    path = os.path.normpath(os.path.abspath(path))
    key = (path, bool(non_color))
    if cache is not None and key in cache:
        return cache[key]
    image = None
    if existing:
        image = next((i for i in bpy.data.images if i.source == "FILE" and i.library is None
                      and os.path.normpath(bpy.path.abspath(i.filepath)) == path
                      and (i.colorspace_settings.name == NON_COLOR) == bool(non_color)
                      and (not straight_alpha or i.alpha_mode == "CHANNEL_PACKED")), None)
    if image is None:
        try:
            image = bpy.data.images.load(path, check_existing=False)
        except RuntimeError:
            image = None
        if image is not None and (image.size[0] == 0 or image.size[1] == 0):
            bpy.data.images.remove(image)
            image = None
        if image is not None and non_color:
            image.colorspace_settings.name = NON_COLOR
        if straight_alpha:
            straight(image)
    if cache is not None:
        cache[key] = image
    return image


def _node(tree, name, kind, location):
    node = recipe.named_node(tree, name, kind, location)
    node.label = name.removeprefix(MAP_NODE)
    return node


def image_node(tree, key, image, location):
    """An Image Texture node of *image* (named ``phong_map:<key>``); returns it."""
    node = _node(tree, MAP_NODE + key, "ShaderNodeTexImage", location)
    node.image = image
    return node


def straight(image) -> None:
    """*image*'s colour read apart from its alpha (Blender's Channel Packed alpha mode): a map
    whose RGB is read as a number (a mean) must not be multiplied by its alpha, which the
    Image Texture node's Color output otherwise is in a render (measured: Cycles 5.3 gives
    linear(sRGB × alpha) for an 8-bit RGBA PNG)."""
    if image is not None and image.alpha_mode != "CHANNEL_PACKED":
        image.alpha_mode = "CHANNEL_PACKED"


def mean_rgb(tree, key, color, location):
    """mean(r, g, b) of the colour output *color*: a Vector Math Dot Product with
    (1/3, 1/3, 1/3) (exact to float32, in every engine alike); returns its Value output."""
    node = _node(tree, MAP_NODE + key, "ShaderNodeVectorMath", location)
    node.operation = "DOT_PRODUCT"
    tree.links.new(color, compat.input_socket(node, "Vector"))
    compat.input_socket(node, "Vector_001").default_value = MEAN
    return compat.output_socket(node, "Value")


def math(tree, name, operation, a, b, location, clamp=False):
    """A Math node *operation* of *a* and *b* (each an output socket or a number); returns
    its Value output."""
    node = recipe.named_node(tree, name, "ShaderNodeMath", location)
    node.operation = operation
    node.use_clamp = clamp
    for identifier, value in (("Value", a), ("Value_001", b)):
        socket = compat.input_socket(node, identifier)
        if isinstance(value, (int, float)):
            socket.default_value = float(value)
        else:
            tree.links.new(value, socket)
    return compat.output_socket(node, "Value")


def exponent_map(material, image) -> None:
    """The lights group's Exponent = the Exponent control × mean(RGB) of *image* (a scalar
    map: read as data, Non-Color); the control keeps the file's value for export."""
    tree = material.node_tree
    lights = tree.nodes[recipe.LIGHTS_NODE]
    straight(image)
    texture = image_node(tree, "exponent map", image, (-1450.0, -1400.0))
    mean = mean_rgb(tree, "exponent map mean", compat.output_socket(texture, "Color"),
                    (-1150.0, -1400.0))
    value = writer.control_output(material, "Exponent")
    product = math(tree, MAP_NODE + "exponent x map", "MULTIPLY", value, mean,
                   (-900.0, -1400.0))
    tree.links.new(product, lights.inputs["Exponent"])


def opacity_map(material, opacity, location=(-400.0, 600.0)) -> None:
    """*opacity* (an output socket: the file's formula of its maps) clamped to [0, 1] as the
    material's opacity map (``recipe.OPACITY_MAP``): it feeds the Mix Shader's Fac in place
    of the Opacity control, which keeps the file's value."""
    tree = material.node_tree
    math(tree, recipe.OPACITY_MAP, "MULTIPLY", opacity, 1.0, location, clamp=True)
    tree.nodes[recipe.OPACITY_MAP].label = "Opacity map"
    opacity_nodes.apply_opacity(material)


# -- Blender's own FBX add-on and image files (read by importers and exporters alike) -------

def ensure_fbx_addon() -> bool:
    """Whether Blender's FBX add-on (io_scene_fbx: its importer and exporter) is enabled,
    enabling it where it is not."""
    if hasattr(bpy.ops.import_scene, "fbx"):
        try:
            bpy.ops.import_scene.fbx.get_rna_type()
            return True
        except (KeyError, AttributeError):
            pass
    try:
        import addon_utils
        addon_utils.enable("io_scene_fbx", default_set=False)
    except Exception:  # noqa: BLE001 - any failure means: build from ufbx
        return False
    try:
        bpy.ops.import_scene.fbx.get_rna_type()
        return True
    except (KeyError, AttributeError):
        return False


def image_components(path: str) -> int | None:
    """How many channels the image file *path* holds (1 grey, 2 grey + alpha, 3 RGB, 4 RGBA),
    read from its header (PNG, JPEG, GIF, BMP), or None for another format.  VRML97 / X3D
    decide by it whether a texture replaces the diffuse colour or multiplies it, and
    Blender's own image reports differ between releases (4.2 gives a grey + alpha PNG 32
    bits, 5.3 16)."""
    try:
        with open(path, "rb") as handle:
            head = handle.read(1 << 16)
    except OSError:
        return None
    if head[:8] == b"\x89PNG\r\n\x1a\n" and len(head) > 25:
        return {0: 1, 2: 3, 3: 3, 4: 2, 6: 4}.get(head[25])
    if head[:3] == b"GIF":
        return 3
    if head[:2] == b"BM" and len(head) > 30:
        return 4 if int.from_bytes(head[28:30], "little") == 32 else 3
    if head[:2] == b"\xff\xd8":   # JPEG: the components of the first SOFn segment
        at = 2
        while at + 9 < len(head):
            if head[at] != 0xFF:
                return None
            marker = head[at + 1]
            if marker in (0xD8, 0x01) or 0xD0 <= marker <= 0xD7:
                at += 2
                continue
            length = int.from_bytes(head[at + 2:at + 4], "big")
            if 0xC0 <= marker <= 0xCF and marker not in (0xC4, 0xC8, 0xCC):
                return head[at + 9] if at + 9 < len(head) else None
            at += 2 + length
    return None


def prune_unused(tree, keep) -> None:
    """Remove the nodes an importer's own material left in *tree* that feed nothing any more
    (their names not in *keep*; frames and Material Outputs stay): what the OBJ and FBX
    imports do after the writer has made the tree a Phong material."""
    while True:
        doomed = [n for n in tree.nodes if n.name not in keep and n.bl_idname != "NodeFrame"
                  and not n.bl_idname.startswith("ShaderNodeOutput")
                  and not any(o.is_linked for o in n.outputs)]
        if not doomed:
            return
        for node in doomed:
            tree.nodes.remove(node)
