# SPDX-License-Identifier: GPL-3.0-or-later
"""What the headless commands (demo, compare, bake) read alike: a scene file and its
``--scenes``, and whether a ``--peers`` renderer can run here; ``BadInput`` is a one-line
reason for exit 2 with nothing written.

A scene file is a .blend, opened as it is, or a file of another program imported as Phong
into an empty scene by the extension's own importer (the table of formats,
``addon/interchange/formats.py``: the same code and suffixes as File ▸ Import).  An imported
file that brings no camera gets one that frames its objects (an X3D file without Viewpoint:
the standard's default view moved to frame them, ``addon.scene.framing``), and one that
brings no light a sun at the camera (a headlight), each named on stderr."""

from __future__ import annotations

import os
import sys


class BadInput(Exception):
    """Exit 2 with this one-line reason; nothing has been written."""


def peer_problem(peers) -> str | None:
    """Why a peer cannot run on this machine (what to install), or None."""
    from ..core import threejs, x_ite  # noqa: PLC0415

    for name, module in (("threejs", threejs), ("x_ite", x_ite)):
        problem = module.unavailable() if name in peers else None
        if problem is not None:
            return f"--peers {name}: {problem}"
    return None


def suffix_formats() -> dict:
    """{file suffix: the format that imports it} (``formats.FORMATS``; imports ``bpy``)."""
    from ..addon.interchange import formats  # noqa: PLC0415

    return {suffix: fmt for fmt in formats.FORMATS if fmt.importer is not None
            for suffix in fmt.suffixes}


def import_into(context, path, fmt) -> list:
    """Import *path* as *fmt* (``formats.Format``) into *context*'s scene; returns the
    warnings.  BadInput when nothing could be imported (its message names the file)."""
    from ..addon.interchange import formats  # noqa: PLC0415

    try:
        result = fmt.importer(context, path)
    except formats.InterchangeError as error:
        raise BadInput(str(error)) from None
    if not result.objects:
        raise BadInput("; ".join([f"{path}: no mesh in the file", *result.warnings]))
    return result.warnings


#: A scene custom property an importer sets where the file asks for no light at all (X3D's
#: NavigationInfo headlight FALSE): no sun is added at the camera then.
NO_DEFAULT_LIGHT = "phong_x3d_no_headlight"
#: A scene custom property an imported file's scene gets where ``phong compare`` framed its
#: objects (the file has no camera or Viewpoint): what was done, a note of the comparison.
FRAMED_KEY = "phong_framed"


def open_scene_file(file: str, scenes_arg, importers: bool = True,
                    load_ui: bool = False) -> tuple:
    """Open *file*: (its scene names, the names *scenes_arg* ("a,b") gives, or None without
    it); BadInput (exit 2) for a missing or unreadable file or an unknown scene.  Without
    *importers* only .blend files are read; *load_ui*: with the file's own workspaces and
    screens (for a file that is saved again)."""
    import bpy  # noqa: PLC0415

    path = os.path.abspath(file)
    if not os.path.isfile(path):
        raise BadInput(f"{file}: no such file")
    suffix = os.path.splitext(path)[1].lower()
    readers = suffix_formats() if importers else {}
    if suffix in readers:
        _import_into_empty_file(path, readers[suffix])
    else:
        if suffix != ".blend" and importers:
            known = ", ".join([".blend", *readers])
            raise BadInput(f"{file}: not a file this command reads ({known})")
        try:
            bpy.ops.wm.open_mainfile(filepath=path, load_ui=load_ui)
        except RuntimeError as error:
            reason = str(error).strip().splitlines()[-1] if str(error).strip() else "unreadable"
            raise BadInput(f"{file}: cannot open as a .blend file ({reason})") from None
    names = [scene.name for scene in bpy.data.scenes]
    if not scenes_arg:
        return names, None
    wanted = [n.strip() for n in scenes_arg.split(",") if n.strip()]
    unknown = [n for n in wanted if n not in names]
    if unknown or not wanted:
        raise BadInput(f"--scenes: no scene {', '.join(map(repr, unknown)) or '(none given)'} "
                       f"in {file}; it has {', '.join(map(repr, names))}")
    return names, wanted


def _import_into_empty_file(path, fmt) -> None:
    import bpy  # noqa: PLC0415

    bpy.ops.wm.read_homefile(use_empty=True)
    context = bpy.context
    scene = context.scene
    scene.name = os.path.splitext(os.path.basename(path))[0] or "Imported"
    for warning in import_into(context, path, fmt):
        print(f"phong: {os.path.basename(path)}: {warning}", file=sys.stderr)
    framed = _frame(scene)
    if framed is not None:
        said, scene[FRAMED_KEY] = framed
        print(f"phong: {os.path.basename(path)} {said}", file=sys.stderr)
    if not any(obj.type == "LIGHT" for obj in scene.objects) and not scene.get(NO_DEFAULT_LIGHT):
        _headlight(scene)
        print(f"phong: {os.path.basename(path)} has no light: added a sun at the camera",
              file=sys.stderr)


def _frame(scene) -> tuple | None:
    """Frame the imported objects where the file gave no view of its own: a new camera
    looking from the front, right and above (a three-quarter view, so no plane of the axes
    is seen edge-on) where there is no camera, X3D's default Viewpoint moved along its own
    direction where the file has no Viewpoint.  Returns (what was done, the comparison's
    note), or None."""
    from ..addon.interchange import x3d_import  # noqa: PLC0415
    from ..addon.scene import framing  # noqa: PLC0415

    objects = framing.visible_meshes(scene)
    if scene.camera is None:
        framing.add_camera(scene, objects)
        return ("has no camera: added one that frames its objects",
                "framed: the file has no camera")
    if scene.camera.get(x3d_import.DEFAULT_VIEWPOINT_KEY) and framing.frame(scene, scene.camera,
                                                                            objects):
        return ("has no Viewpoint: X3D's default view moved along its direction to frame its "
                "objects", "framed: the file has no Viewpoint")
    return None


def _headlight(scene) -> None:
    import bpy  # noqa: PLC0415

    light = bpy.data.objects.new("Headlight", bpy.data.lights.new("Headlight", "SUN"))
    scene.collection.objects.link(light)
    light.matrix_world = scene.camera.matrix_world.copy()
    from ..addon.lighting import sync  # noqa: PLC0415

    sync.relink_scene(scene)
