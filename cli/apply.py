# SPDX-License-Identifier: GPL-3.0-or-later
"""``phong apply FILE.blend -o OUT.blend``: Apply Phong Material, headless, on every scene of
a .blend (or those ``--scenes`` names), written as a new file; its options are in ``args.py``.

Each scene's objects that render with materials (meshes, curves, text, surfaces, and the
objects of the collections its Empties instance) get Phong materials driven by the scene's
lights, by the code of *Object ▸ Apply Phong Material* (``lighting.convert.apply``); a report
per scene says what was converted, what was not and why, and the lights.  OUT.blend is
written whole or not at all (a hidden temporary file beside it, renamed over it), never over
FILE.blend; relative paths (images) are remapped to OUT.blend's folder.

``convert_scenes`` is also ``phong compare FILE.blend --apply``'s first step (each scene
converted in memory, then compared; the file is not written).

Exit codes: 0 OUT.blend written; 1 a conversion failed (nothing written); 2 bad arguments, a
missing or unreadable .blend, OUT.blend not a .blend path, the input file itself, or in a
folder that cannot be written, or nothing in the file takes a Phong material (one line on
stderr, nothing written).
"""

from __future__ import annotations

import os
import sys
import tempfile

from ..core import outputs
from .inputs import BadInput, open_scene_file
from .registered import Registered
from .terminal import terminal


def run(args, state) -> int:
    """``apply`` with the parsed *args*; *state* counts done / total scenes."""
    with Registered() as registered:
        try:
            target = _target(args.file, args.output)
            registered.ensure()
            # with its workspaces and screens: OUT.blend keeps the artist's layout
            names, wanted = open_scene_file(args.file, args.scenes, importers=False,
                                            load_ui=True)
        except BadInput as error:
            print(f"phong: {error}", file=sys.stderr)
            return 2
        wanted = wanted if wanted is not None else names
        state["total"] = len(wanted)
        try:
            reports = convert_scenes(wanted, args.file, state)
        except ApplyFailed as error:
            print(f"phong: {error}", file=sys.stderr)
            return 1
        except BadInput as error:
            print(f"phong: {error}", file=sys.stderr)
            return 2
        say = terminal()
        for name, report in reports:
            print(report_lines(name, report), file=say)
        try:
            _save(target)
        except (RuntimeError, OSError) as error:
            print(f"phong: {target}: not written: {error}", file=sys.stderr)
            return 1
        converted = sum(len(r.converted) for _n, r in reports)
        print(f"phong apply: {converted} object(s) in {len(reports)} scene(s) take Phong "
              f"materials; written: {target}", file=say)
        say.flush()
    return 0


def report_lines(name, report) -> str:
    """A scene's report as printed: its name, then ``Report.text()`` indented."""
    return "\n".join([f"scene {name!r}:", *(f"  {line}" for line in report.text().splitlines())])


class ApplyFailed(Exception):
    """A conversion raised: exit 1 with this line."""


def _target(file: str, output: str) -> str:
    """The absolute path of *output* (OUT.blend), or BadInput saying why it cannot be."""
    target = os.path.abspath(output)
    if not target.lower().endswith(".blend"):
        raise BadInput(f"-o {output}: expected a .blend path")
    if os.path.isdir(target):
        raise BadInput(f"-o {output}: is a folder; expected a .blend path")
    source = os.path.abspath(file)
    if not os.path.isfile(source):
        raise BadInput(f"{file}: no such file")
    if not os.path.splitext(source)[1].lower().startswith(".blend"):
        raise BadInput(f"{file}: not a .blend file (apply reads .blend files; phong compare "
                       "also imports .obj, .dae, .fbx, .wrl and .x3d)")
    if os.path.realpath(source) == os.path.realpath(target):
        raise BadInput(f"-o {output}: is the input file; apply never writes it, choose "
                       "another path")
    # nothing is created before the file is read: the nearest folder that exists must let
    # us write (the missing ones are made when OUT.blend is saved)
    folder = os.path.dirname(target)
    existing = folder
    while not os.path.isdir(existing):
        if os.path.exists(existing):
            raise BadInput(f"-o {output}: {existing} is not a folder")
        existing = os.path.dirname(existing)
    if not os.access(existing, os.W_OK | os.X_OK):
        raise BadInput(f"-o {output}: cannot write to the folder {existing}")
    return target


def convert_scenes(names, file, state=None) -> list:
    """[(scene name, ``convert.Report``)] of Apply Phong Material on every object that
    renders with materials in each scene *names* of the open file; BadInput when no object of
    any of them takes a Phong material, ApplyFailed when a conversion raised."""
    import bpy  # noqa: PLC0415

    from ..addon.lighting import convert  # noqa: PLC0415
    from ..addon.scene import describe  # noqa: PLC0415

    reports = []
    for name in names:
        scene = bpy.data.scenes[name]
        try:
            report = convert.apply(scene, None, describe.view_layer_of(scene))
        except Exception as error:  # noqa: BLE001  (one line, never a traceback)
            raise ApplyFailed(f"{file}: scene {name!r}: Apply Phong Material failed: "
                              f"{error}") from None
        reports.append((name, report))
        if state is not None:
            state["done"] += 1
    if not any(report.converted for _name, report in reports):
        skipped = [f"{n} ({why})" for _s, r in reports for n, why in r.skipped][:3]
        raise BadInput(f"{file}: no object that renders with materials in "
                       + (f"scene {names[0]!r}" if len(names) == 1 else "any scene")
                       + (f"; not converted: {'; '.join(skipped)}" if skipped else ""))
    return reports


def _save(target: str) -> None:
    """Save the open file as *target*, atomically: a hidden file beside it (so that relative
    paths are remapped for *target*'s folder), renamed over it once Blender has written it
    whole; the open file keeps its own path (a copy)."""
    import bpy  # noqa: PLC0415

    folder = os.path.dirname(target)
    os.makedirs(folder, exist_ok=True)
    stem = os.path.basename(target).replace(".", "_")
    # a name that does not exist yet: Blender keeps a backup (.blend1) of a file it overwrites
    with tempfile.NamedTemporaryFile(prefix=outputs.temp_prefix("partial", stem),
                                     suffix=".blend", dir=folder) as handle:
        tmp = handle.name
    try:
        bpy.ops.wm.save_as_mainfile(filepath=tmp, copy=True, check_existing=False,
                                    relative_remap=True)
        if not os.path.isfile(tmp):
            raise RuntimeError(f"Blender did not write {tmp}")
        os.chmod(tmp, 0o644)
        os.replace(tmp, target)
    except BaseException:
        for leftover in (tmp, tmp + "1"):
            if os.path.exists(leftover):
                os.remove(leftover)
        raise
