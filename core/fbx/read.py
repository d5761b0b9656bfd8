# SPDX-License-Identifier: GPL-3.0-or-later
"""FBX Phong and Lambert materials, lights and the scene ambient, read without ``bpy``.

The file is read by ufbx (PyPI ``ufbx``, bundled with the extension as wheels); this module
turns what it reads into plain data, by the FBX SDK's rules:

* every value comes from the object itself, else from the file's ``PropertyTemplate`` (the
  ``Definitions`` section), else from the FBX SDK class default (:data:`SURFACE_DEFAULTS`,
  :data:`LIGHT_DEFAULTS`: the values the FBX SDK writes in its own templates, e.g. Maya's
  ``FbxSurfacePhong`` and ``FbxLight`` templates); :attr:`Material.sources` says which;
* Object Color = DiffuseColor × DiffuseFactor, Ka = AmbientColor × AmbientFactor, Specular =
  SpecularColor × SpecularFactor (Lambert: black), Exponent = ShininessExponent (else the
  legacy Shininess), Irradiant = EmissiveColor × EmissiveFactor, opacity = the stored
  ``Opacity``, else 1 − TransparencyFactor × mean(TransparentColor) (the FBX SDK's rule);
* a texture connected to a property multiplies it: a colour by the texture's colour, a
  scalar (TransparencyFactor, ShininessExponent) by the mean of its RGB; with a map on
  TransparentColor or TransparencyFactor the opacity is that formula with the maps (a stored
  ``Opacity`` is one number and cannot hold a map);
* a light's colour, Intensity / 100, DecayType as the falloff 1/dᵏ (k = 0, 1, 2, 3) and a
  spot's OuterAngle / InnerAngle (FBX 6.1: ``Cone angle`` / ``HotSpot``), full cone angles in
  degrees;
* the scene ambient is GlobalSettings' AmbientColor;
* a material of a shading model ufbx does not know ("Blinn" of 3ds Max: shader type UNKNOWN)
  that holds a Phong property is read as FbxSurfacePhong (Blinn on for "Blinn"); a file of
  Blender's exporter has its alpha texture on TransparencyFactor (:attr:`Material.alpha_map`);
* the user properties ``PhongNodes|...`` that Phong Nodes' export writes (``write``)
  are read into ``user`` of materials, lights and the scene.

Its data model is ``model``'s (the writer's too); what the values mean to the Phong model
(the falloff of a DecayType, the edge of a spot) is ``phong``.

ufbx 0.0.5 gives every property of an element (``props.props``) and finds a property through
the template (``props.find_prop``).  Its Python binding is fragile: some of its objects crash
the garbage collector (``Shader``, ``Texture.content``, list iterators, a ``props.defaults``
with no template, any element once its scene is freed; measured on this project's files).
So ufbx runs in a child process (:func:`read`): the child reads the file with the garbage
collector off, sends plain data back (JSON, and its numpy arrays in an .npz of plain arrays) and ends
with ``os._exit``; a crash, a time-out (:data:`TIME_LIMIT`) or the memory limit
(:data:`MEMORY_LIMIT`, POSIX) of the child is one :class:`FbxError` in Blender, the one
exception class of this module, and leaves Blender as it was.
"""

from __future__ import annotations

import json
import math
import os
import subprocess
import sys
import tempfile
import time
from dataclasses import asdict

if __package__:
    from .model import (ALIASES, LIGHT_DEFAULTS, LIGHT_TYPES, OPACITY_MAPS, SLOTS,
                        SURFACE_DEFAULTS, TEXTURE_SLOTS, USER, FbxError, Light, Material,
                        MeshData, Node, Scene, Texture)
else:   # the child process (:class:`Reading`) runs this file as a script: ``model`` beside it
    from model import (ALIASES, LIGHT_DEFAULTS, LIGHT_TYPES, OPACITY_MAPS, SLOTS,
                       SURFACE_DEFAULTS, TEXTURE_SLOTS, USER, FbxError, Light, Material,
                       MeshData, Node, Scene, Texture)

#: Embedded textures larger than this are left out (bounded memory), with a warning.
MAX_EMBEDDED = 256 * 1024 * 1024
#: Limits of the child process that reads a file: seconds, and bytes of address space.
TIME_LIMIT = 300.0
MEMORY_LIMIT = 8 * 1024 ** 3
_NO_VALUE = 0x4000 | 0x10000  # ufbx PropFlags NOT_FOUND | NO_VALUE


def _ufbx():
    try:
        import ufbx
    except ImportError as error:  # the wheel is missing for this platform
        raise FbxError("ufbx", f"the ufbx module is not available ({error})") from None
    return ufbx


def load(path: str, **options):
    """The ufbx scene of *path* (in the child process; raises :class:`FbxError`)."""
    ufbx = _ufbx()
    if not os.path.isfile(path):
        raise FbxError(path, "file not found")
    try:
        return ufbx.load_file(path, **options)
    except ufbx.UfbxError as error:
        raise FbxError(path, f"not readable as FBX ({type(error).__name__}: {error})") from None
    except (OSError, ValueError, MemoryError) as error:
        raise FbxError(path, f"not readable as FBX ({error})") from None


def items(ufbx_list) -> list:
    """The elements of a ufbx list, by index (ufbx 0.0.5's list iterators are not used); the
    list and its elements are held until the (child) process ends: ufbx 0.0.5 returns some
    objects with a reference too few, freed while still in use otherwise."""
    out = [ufbx_list[i] for i in range(len(ufbx_list))]
    _HOLD.append(ufbx_list)
    _HOLD.extend(out)
    return out


#: ufbx objects held for the life of the child process (see :func:`items`).
_HOLD: list = []


def _finite(value) -> bool:
    return all(math.isfinite(v) for v in (value if isinstance(value, tuple) else (value,)))


def _value(prop, width):
    v = prop.value_vec4
    return (float(v.x), float(v.y), float(v.z)) if width == 3 else float(v.x)


def lookup(props, names, default, width, own=None):
    """(value, source) of the first of *names* on the element, else in its template, else
    *default* ("default").  A non-finite value counts as absent."""
    own = own if own is not None else {p.name: p for p in items(props.props)}
    for name in names:
        prop = own.get(name)
        if prop is not None and not prop.flags & _NO_VALUE:
            value = _value(prop, width)
            if _finite(value):
                return value, "object"
    for name in names:
        prop = props.find_prop(name)
        if prop is not None and name not in own and not prop.flags & _NO_VALUE:
            value = _value(prop, width)
            if _finite(value):
                return value, "template"
    return default, "default"


def user_props(own: dict) -> dict:
    """{key: value} of the :data:`USER` properties among *own* ({name: ufbx prop}) that hold
    a finite number."""
    out = {}
    for name, prop in own.items():
        if name.startswith(USER) and not prop.flags & _NO_VALUE:
            value = float(prop.value_vec4.x)
            if math.isfinite(value):
                out[name[len(USER):]] = value
    return out


def _texture(prop_name, index, textures, base) -> Texture:
    """The texture *index* (typed id) of the scene's *textures*, connected to *prop_name*."""
    texture = textures[index]
    if texture.type.name != "FILE":  # layered or procedural: its first file texture
        files = [t.typed_id for t in items(texture.file_textures)]
        texture = textures[files[0]] if files else texture
    # the embedded file is read from the Video (``Texture.content`` crashes ufbx 0.0.5)
    video = texture.video
    content = bytes(video.content) if video is not None and len(video.content) else None
    filename, relative = texture.filename, texture.relative_filename
    absolute = texture.absolute_filename
    candidates = []
    for path in (filename, absolute,
                 os.path.join(base, relative) if relative else "",
                 os.path.join(base, os.path.basename(relative.replace("\\", "/")))
                 if relative else "",
                 os.path.join(base, os.path.basename(absolute.replace("\\", "/")))
                 if absolute else ""):
            if path and path not in candidates:
                candidates.append(path)
    name = relative or absolute or filename or texture.name
    return Texture(name=name, candidates=tuple(candidates), content=content, prop=prop_name,
                   element=texture.name)


#: Properties that only a Phong surface has: a material of a shading model ufbx does not
#: know ("Blinn" of 3ds Max, "Anisotropic" ...) that holds one is read as FbxSurfacePhong.
PHONG_ONLY = ("SpecularColor", "SpecularFactor", "ShininessExponent", "Shininess")
#: The start of the Creator of a file of Blender's own FBX exporter.
BLENDER_CREATOR = "Blender (stable FBX IO)"


def phong_like(kind, own) -> bool:
    """Whether a material of ufbx shader type *kind* whose own properties are *own* (names)
    is read as FbxSurfacePhong: ufbx's FBX_PHONG, or a shading model ufbx does not know
    (UNKNOWN) with a property of :data:`PHONG_ONLY` on the material itself."""
    ufbx = _ufbx()
    if kind == ufbx.ShaderType.FBX_PHONG:
        return True
    return kind == ufbx.ShaderType.UNKNOWN and any(name in own for name in PHONG_ONLY)


def read_material(mat, base="", textures=None, blender=False) -> Material:
    """The Phong values of the ufbx material *mat* (``base``: the file's folder; *textures*:
    the scene's textures, ``items(scene.textures)``, for the material's maps; *blender*: the
    file was written by Blender's exporter, whose map on TransparencyFactor is an alpha
    texture: :attr:`Material.alpha_map`)."""
    ufbx = _ufbx()
    shading = mat.shading_model_name or ""
    kind = mat.shader_type
    own = {p.name: p for p in items(mat.props.props)}
    # (``mat.shader`` is not touched: ufbx 0.0.5's Shader object crashes the garbage collector)
    if kind != ufbx.ShaderType.FBX_LAMBERT and not phong_like(kind, own):
        return Material(name=mat.name, kind="OTHER", shading=shading or kind.name)
    lambert = kind == ufbx.ShaderType.FBX_LAMBERT
    out = Material(name=mat.name, kind="LAMBERT" if lambert else "PHONG", shading=shading,
                   blinn=shading.strip().lower() == "blinn", user=user_props(own))
    if "Blinn" in out.user:   # (the control's own value: fbx_import reads out.user)
        out.blinn = out.user["Blinn"] > 0.0
    if lambert and "Exponent" in out.user:   # a Phong material written as Lambert
        out.exponent = max(out.user["Exponent"], 0.0)

    def get(name, width):
        value, source = lookup(mat.props, (name,), SURFACE_DEFAULTS[name], width, own)
        out.raw[name], out.sources[name] = value, source
        return value

    for slot, (color_name, factor_name) in SLOTS.items():
        if lambert and slot == "Specular Color":
            out.colors[slot] = (0.0, 0.0, 0.0)
            continue
        color, factor = get(color_name, 3), get(factor_name, 1)
        out.colors[slot] = tuple(c * factor for c in color)
    if not lambert:
        exponent, source = lookup(mat.props, ("ShininessExponent",), None, 1, own)
        if source == "default":
            exponent, source = lookup(mat.props, ("Shininess",),
                                      SURFACE_DEFAULTS["ShininessExponent"], 1, own)
        out.raw["ShininessExponent"], out.sources["ShininessExponent"] = exponent, source
        out.exponent = max(float(exponent), 0.0)
    opacity, source = lookup(mat.props, ("Opacity",), None, 1, own)
    tc, tf = get("TransparentColor", 3), get("TransparencyFactor", 1)
    out.transparent_color, out.transparency_factor = tuple(tc), float(tf)
    if opacity is None:
        opacity = 1.0 - tf * sum(tc) / 3.0
    else:
        out.raw["Opacity"], out.sources["Opacity"] = opacity, source
    out.opacity = min(max(float(opacity), 0.0), 1.0)
    if not lambert:
        rc, rf = get("ReflectionColor", 3), get("ReflectionFactor", 1)
        if rf * max(rc) > 0.0:
            out.unsupported.append("reflection (ReflectionColor × ReflectionFactor)")
    # (a MaterialTexture's texture object crashes ufbx 0.0.5 when kept: only its id is taken)
    links = [(link.material_prop, link.texture.typed_id) for link in items(mat.textures)]
    for prop, index in links:
        slot = TEXTURE_SLOTS.get(prop)
        if slot is None or (lambert and slot in ("Specular Color", "Exponent")):
            out.unsupported.append(f"texture on {prop}")
            continue
        if textures is None:
            textures = items(mat.scene.textures)
        out.textures[slot] = _texture(prop, index, textures, base)
    # Blender's exporter writes its alpha texture on TransparencyFactor (with the factor
    # 1 − alpha, 0 for an opaque one: by the SDK's rule the map would change nothing), and
    # Blender's importer reads a map there as the opacity's alpha texture: read it so
    # (Phong Nodes' export marks maps that follow the SDK's rule: ``TransparencyMaps``)
    out.alpha_map = blender and any(key in out.textures for key in OPACITY_MAPS) and \
        not out.user.get("TransparencyMaps")
    return out


def read_light(light) -> Light:
    ufbx = _ufbx()
    own = {p.name: p for p in items(light.props.props)}
    sources = {}

    def get(name, width):
        value, source = lookup(light.props, ALIASES.get(name, (name,)), LIGHT_DEFAULTS[name],
                               width, own)
        sources[name] = source
        return value

    fbx_type = int(round(get("LightType", 1)))
    decay = int(round(get("DecayType", 1)))
    del ufbx
    return Light(
        name=light.name, nodes=tuple(n.name for n in items(light.instances)), fbx_type=fbx_type,
        type={0: "POINT", 1: "SUN", 2: "SPOT"}.get(fbx_type, "POINT"),
        color=tuple(get("Color", 3)), intensity=get("Intensity", 1) / 100.0,
        decay=decay if decay in (0, 1, 2, 3) else 2,
        outer_angle=get("OuterAngle", 1), inner_angle=get("InnerAngle", 1), sources=sources,
        user=user_props(own), cast_shadows=bool(get("CastShadows", 1)))




def from_scene(scene, path: str) -> Scene:
    """Plain data of a loaded ufbx *scene* (see :func:`read`)."""
    base = os.path.dirname(os.path.abspath(path))
    warnings = []
    textures = items(scene.textures)
    blender = (scene.metadata.creator or "").startswith(BLENDER_CREATOR)
    materials = [read_material(m, base, textures, blender) for m in items(scene.materials)]
    lights = []
    for light in items(scene.lights):
        item = read_light(light)
        if item.fbx_type not in (0, 1, 2):
            what = LIGHT_TYPES.get(item.fbx_type, f"type {item.fbx_type}")
            warnings.append(f"{path}: light {item.name}: {what.lower()} light imported as a "
                            "point light (the Phong model has point, directional and spot)")
        if item.decay != int(round(lookup(light.props, ("DecayType",), 0, 1)[0])):
            warnings.append(f"{path}: light {item.name}: unknown DecayType, read as quadratic")
        lights.append(item)
    ambient = tuple(float(c) for c in scene.settings.ambient_color)
    if not _finite(ambient):
        ambient = (0.0, 0.0, 0.0)
    meta = scene.metadata
    return Scene(path, int(meta.version), bool(meta.ascii), meta.creator, ambient,
                 materials, lights, warnings,
                 user=user_props({p.name: p for p in items(scene.settings.props.props)}))


# -- geometry (read in the child process) -------------------------------------------------

def _matrix(m) -> tuple:
    cols = (m.c0, m.c1, m.c2, m.c3)
    return tuple(tuple(float(getattr(c, axis)) for c in cols) for axis in "xyz") + (
        (0.0, 0.0, 0.0, 1.0),)


def _mesh_data(umesh):
    import numpy as np
    faces = np.asarray(umesh.faces, dtype=np.int64).reshape(-1, 2)  # (index_begin, count)
    starts, sizes = faces[:, 0], faces[:, 1]
    keep = sizes >= 3  # points and lines are no faces
    sizes, starts = sizes[keep], starts[keep]
    firsts = np.cumsum(sizes) - sizes
    loops = np.repeat(starts, sizes) + np.arange(int(sizes.sum())) - np.repeat(firsts, sizes)
    indices = np.asarray(umesh.vertex_indices, dtype=np.int64)
    materials = (np.asarray(umesh.face_material, dtype=np.int64)[keep]
                 if len(umesh.face_material) else np.zeros(len(sizes), dtype=np.int64))

    def per_loop(attr, width):
        if not attr.exists:
            return None
        values = np.asarray(attr.values, dtype=np.float64).reshape(-1, width)
        return values[np.asarray(attr.indices, dtype=np.int64)[loops]]

    uvs = [(s.name or "UVMap", per_loop(s.vertex_uv, 2)) for s in items(umesh.uv_sets)]
    colors = [(s.name or "Color", per_loop(s.vertex_color, 4)) for s in items(umesh.color_sets)]
    return MeshData(
        positions=np.asarray(umesh.vertices, dtype=np.float64).reshape(-1, 3),
        loop_vertex=indices[loops].astype(np.int32), face_sizes=sizes.astype(np.int32),
        face_material=materials.astype(np.int32), normals=per_loop(umesh.vertex_normal, 3),
        uvs=[(n, a) for n, a in uvs if a is not None],
        colors=[(n, a) for n, a in colors if a is not None])


def _geometry(scene, out: Scene) -> None:
    ufbx = _ufbx()
    for node in items(scene.nodes):
        if node.is_root:
            continue
        parent = node.parent
        top = parent is None or parent.is_root
        item = Node(id=int(node.element_id), name=node.name,
                    parent=None if top else int(parent.element_id),
                    matrix=_matrix(node.node_to_world if top else node.node_to_parent),
                    kind="EMPTY", data="", visible=bool(node.visible))
        mesh, light, camera = node.mesh, node.light, node.camera
        if mesh is not None:
            item.kind, item.data, item.mesh = "MESH", mesh.name or node.name, int(mesh.element_id)
            if item.mesh not in out.meshes:
                out.meshes[item.mesh] = _mesh_data(mesh)
            item.materials = tuple(m.name for m in items(node.materials))
        elif light is not None:
            item.kind, item.data = "LIGHT", light.name or node.name
            read = read_light(light)
            item.light = {"type": read.type, "cast_shadows": read.cast_shadows}
        elif camera is not None:
            item.kind, item.data = "CAMERA", camera.name or node.name
            item.camera = {
                "ortho": camera.projection_mode == ufbx.ProjectionMode.ORTHOGRAPHIC,
                "fov_x": float(camera.field_of_view_deg.x),
                "ortho_size": float(camera.orthographic_size.x),
                "near": float(camera.near_plane), "far": float(camera.far_plane)}
        out.nodes.append(item)


# -- the child process and its parent -------------------------------------------------------

def _child(path: str, result: str, geometry: bool) -> None:
    """Read *path* with ufbx, write the plain data (or {"error": ...}) to *result*."""
    import gc
    gc.disable()  # ufbx 0.0.5's objects crash the collector; this process is short-lived
    try:
        options = {"ignore_animation": True}
        if geometry:
            ufbx = _ufbx()
            options.update(
                target_axes=ufbx.axes_right_handed_z_up, target_unit_meters=1.0,
                target_camera_axes=ufbx.axes_right_handed_y_up,
                target_light_axes=ufbx.axes_right_handed_y_up,
                geometry_transform_handling=ufbx.GeometryTransformHandling.MODIFY_GEOMETRY,
                generate_missing_normals=True)
        else:
            options["ignore_geometry"] = True
        scene = load(path, **options)
        data = from_scene(scene, path)
        if geometry:
            _geometry(scene, data)
        payload = {"scene": {k: v for k, v in data.__dict__.items()
                             if k not in ("materials", "lights", "nodes")},
                   "materials": [asdict(m) for m in data.materials],
                   "lights": [asdict(l) for l in data.lights],
                   "nodes": [asdict(n) for n in data.nodes]}
        payload["scene"]["meshes"] = {k: asdict(m) for k, m in data.meshes.items()}
    except FbxError as error:
        payload = {"error": str(error)}
    except Exception as error:  # noqa: BLE001 - anything else: one message for the parent
        payload = {"error": f"{path}: not readable as FBX ({type(error).__name__}: {error})"}
    _write_payload(payload, result)
    os._exit(0)


# The child's answer: JSON for the structure (a tuple as {"()": [...]}, an array as
# {"[]": name}, bytes as {"b": name}), one .npz of the arrays (numpy's np.load refuses object
# arrays by default) and a file per embedded texture: plain data only, nothing that runs
# code when it is read.

def _write_payload(payload, result: str) -> None:
    np = sys.modules.get("numpy")   # imported only where geometry was read (0.1 s otherwise)
    arrays, blobs = {}, {}

    def plain(value):
        if isinstance(value, (bytes, bytearray)):  # an embedded texture's file
            name = f"b{len(blobs)}"
            blobs[name] = bytes(value)
            return {"b": name}
        if np is not None and isinstance(value, np.ndarray):
            name = f"a{len(arrays)}"
            arrays[name] = value
            return {"[]": name}
        if isinstance(value, dict):
            return {str(k): plain(v) for k, v in value.items()}
        if isinstance(value, tuple):
            return {"()": [plain(v) for v in value]}
        if isinstance(value, list):
            return [plain(v) for v in value]
        if np is not None and isinstance(value, np.generic):
            return value.item()
        return value

    text = json.dumps(plain(payload), allow_nan=True)
    if arrays:
        np.savez(result + ".npz", **arrays)
    for name, data in blobs.items():
        with open(f"{result}.{name}", "wb") as handle:
            handle.write(data)
    with open(result + ".json", "w", encoding="utf-8") as handle:  # written last: complete
        handle.write(text)


def _read_payload(result: str):
    with open(result + ".json", encoding="utf-8") as handle:
        text = handle.read()
    arrays = {}
    if os.path.isfile(result + ".npz"):
        import numpy as np

        with np.load(result + ".npz") as archive:
            arrays = {name: archive[name] for name in archive.files}

    def blob(name):
        with open(f"{result}.{name}", "rb") as handle:
            return handle.read()

    def typed(value):
        if isinstance(value, dict):
            if set(value) == {"[]"}:
                return arrays[value["[]"]]
            if set(value) == {"b"}:
                return blob(value["b"])
            if set(value) == {"()"}:
                return tuple(typed(v) for v in value["()"])
            return {k: typed(v) for k, v in value.items()}
        if isinstance(value, list):
            return [typed(v) for v in value]
        return value

    return typed(json.loads(text))


def _limits():  # runs in the child before it starts (POSIX)
    try:
        import resource
        resource.setrlimit(resource.RLIMIT_AS, (MEMORY_LIMIT, MEMORY_LIMIT))
    except (ImportError, ValueError, OSError):
        pass


def _python() -> str:
    """The Python interpreter for the child: Blender's own (``sys.executable`` is it since
    Blender 2.91), or the one running this module."""
    return sys.executable


class Reading:
    """A read of an FBX file by ufbx under way in a child process (:func:`start`), so that
    the caller can do other work meanwhile (Blender's own importer reads the same file);
    :meth:`result` waits for it, :meth:`close` ends it."""

    def __init__(self, path: str, geometry: bool = False, timeout: float | None = None):
        self.path = os.path.abspath(path)
        if not os.path.isfile(self.path):
            raise FbxError(self.path, "file not found")
        self.limit = TIME_LIMIT if timeout is None else timeout
        self.folder = tempfile.TemporaryDirectory(prefix="phong_fbx_")
        self.output = os.path.join(self.folder.name, "result")
        env = dict(os.environ)
        env["PYTHONPATH"] = os.pathsep.join(p for p in sys.path if p)
        command = [_python(), "-s", os.path.abspath(__file__),
                   self.path, self.output, "1" if geometry else "0"]
        self.started = time.monotonic()
        try:
            self.process = subprocess.Popen(
                command, env=env, stdin=subprocess.DEVNULL, stdout=subprocess.DEVNULL,
                stderr=subprocess.PIPE, preexec_fn=_limits if os.name == "posix" else None)
        except OSError as error:
            self.folder.cleanup()
            raise FbxError(self.path, f"could not start the FBX reader ({error})") from None

    def result(self) -> Scene:
        """The plain data of the file; raises :class:`FbxError` (and ends the child)."""
        try:
            left = self.limit - (time.monotonic() - self.started)
            try:
                _out, err = self.process.communicate(timeout=max(left, 1e-3))
            except subprocess.TimeoutExpired:
                self.process.kill()
                self.process.communicate()
                raise FbxError(self.path, f"reading took longer than {self.limit:g} s") from None
            if not os.path.isfile(self.output + ".json"):
                tail = err.decode("utf-8", "replace").strip().splitlines()[-1:] or [""]
                raise FbxError(self.path, f"the FBX reader stopped (exit status "
                                          f"{self.process.returncode}) {tail[0][:200]}".strip())
            payload = _read_payload(self.output)
        finally:
            self.close()
        if "error" in payload:
            raise FbxError(self.path, payload["error"].removeprefix(f"{self.path}: "))
        return _rebuild(payload)

    def close(self) -> None:
        """End the child (when it still runs) and remove its folder."""
        if self.process.poll() is None:
            self.process.kill()
            self.process.communicate()
        self.folder.cleanup()


def start(path: str, geometry: bool = False, timeout: float | None = None) -> Reading:
    """Start reading the FBX file *path* (see :func:`read`) in a child process; raises
    :class:`FbxError` for a missing file."""
    return Reading(path, geometry, timeout)


def read(path: str, geometry: bool = False, timeout: float | None = None) -> Scene:
    """Materials, lights and ambient of the FBX file *path* (with *geometry*: its nodes and
    meshes too, Z up and metres), read by ufbx in a child process; raises :class:`FbxError`."""
    return start(path, geometry, timeout).result()


def _rebuild(payload) -> Scene:
    materials = []
    for m in payload["materials"]:
        m = dict(m)
        m["textures"] = {k: Texture(**t) for k, t in m["textures"].items()}
        materials.append(Material(**m))
    info = dict(payload["scene"])
    meshes = {int(k): MeshData(**v) for k, v in info.pop("meshes").items()}  # JSON keys
    return Scene(**info, materials=materials,
                 lights=[Light(**l) for l in payload["lights"]],
                 nodes=[Node(**n) for n in payload["nodes"]], meshes=meshes)


if __name__ == "__main__":  # the child process of read()
    _child(sys.argv[1], sys.argv[2], sys.argv[3] == "1")
