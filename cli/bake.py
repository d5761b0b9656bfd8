# SPDX-License-Identifier: GPL-3.0-or-later
"""``phong bake``: Bake Phong Lighting on every scene of a .blend and write glTF (the headless
form of Export glTF with Baked Phong Lighting); its options are in ``args.py``.

Per scene, into ``DIR/<scene>/``: ``<scene>.glb`` (KHR_materials_unlit with the baked
texture or COLOR_0), the baked images (``textures/``, target image), ``metrics.json``
(what was baked, seconds per object, the check, ``ok``) and, with ``--peers threejs``, the check:
the .glb rendered by three.js's GLTFLoader in headless Chromium against Cycles rendering the
baked scene (``check/sheet.png``).  One line per object is printed as it is baked.  The
.blend itself is not changed.

Exit codes as ``compare``: 0 every scene baked and exported (and its check passed); 1 a bake,
export or check failed; 2 bad arguments, a missing or unreadable .blend, no Phong material
(nothing is written then); 130 / 143 interrupted (finished scene folders stay complete).
"""

from __future__ import annotations

import json
import os
import shutil
import sys
import tempfile
import time

from ..core import outputs, report, scenes
from .inputs import BadInput, open_scene_file, peer_problem
from .registered import Registered
from .terminal import check_interrupt, terminal


def _scenes(args):
    """(the scene names of args.file this shard bakes, those of the whole run, objects_of);
    BadInput: exit 2."""
    import bpy  # noqa: PLC0415

    from ..addon.baking import lighting  # noqa: PLC0415
    from ..addon.scene import describe  # noqa: PLC0415

    names, wanted = open_scene_file(args.file, args.scenes, importers=False)

    def objects_of(name):
        scene = bpy.data.scenes[name]
        layer = describe.view_layer_of(scene)
        return [o for o in layer.objects if lighting.has_phong(o) and not o.hide_render]

    if wanted is None:
        wanted = [n for n in names if objects_of(n)]
    if not wanted or not all(objects_of(n) for n in wanted):
        empty = next((n for n in wanted if not objects_of(n)), None)
        raise BadInput(f"{args.file}: " + (f"scene {empty!r} has" if empty else "no scene has")
                       + " no object with a Phong material (Apply Phong Material first)")
    settings = _settings(args, "//", pack=True)  # where images go is checked later
    for name in wanted:
        try:
            lighting.check(bpy.data.scenes[name], objects_of(name), settings)
        except lighting.BakeError as error:
            raise BadInput(f"{args.file}: scene {name!r}: {error}") from None
    try:
        return scenes.shard(wanted, args.shard), wanted, objects_of
    except scenes.SceneError as error:
        raise BadInput(str(error)) from None


def _settings(args, directory, pack=None):
    from ..addon.baking import lighting  # noqa: PLC0415

    return lighting.Settings(target=args.target.upper(), term=args.term.upper(),
                             view=args.view.upper(), resolution=args.resolution,
                             file_format=args.format.upper(), directory=directory,
                             pack=bool(pack) if pack is not None else False,
                             smart_uv=args.smart_uv, refuse_package=False)


def run(args, state) -> int:
    """The bake command with the parsed *args*; *state* counts done / total scenes for the
    interrupt message."""
    problem = peer_problem(args.peers)
    if problem is not None:
        print(f"phong: {problem}", file=sys.stderr)
        return 2
    with Registered() as registered:
        registered.ensure()
        try:
            mine, every, objects_of = _scenes(args)
        except BadInput as error:
            print(f"phong: {error}", file=sys.stderr)
            return 2
        out = os.path.abspath(args.out)
        problem = outputs.output_problem(out, refuse_package=False)
        if problem is not None:
            print(f"phong: {problem}", file=sys.stderr)
            return 2
        outputs.clean_stale(out)
        # of every scene, so that each shard names the same folder for a scene
        folders = dict(zip(every, outputs.distinct(outputs.clean_name(n, "scene")
                                                   for n in every)))
        report.write_run(out, [folders[name] for name in every], "bake")  # for report DIR
        state["total"] = len(mine)
        say = terminal()
        source = f" from {args.shard_source}" if args.shard_source else ""
        shard = f" (shard {args.shard}{source})" if args.shard else ""
        print(f"phong bake: {len(mine)} scene(s) of {args.file}{shard}, target {args.target}, "
              f"{args.term}, view {args.view} -> {out}", file=say)
        failed, checks = [], []
        start = time.perf_counter()
        for number, name in enumerate(mine, start=1):
            check_interrupt()
            print(f"[{number}/{len(mine)}] {name}", file=say)
            try:
                metrics = _bake_scene(name, folders[name], objects_of(name), args, out, say)
            except KeyboardInterrupt:
                raise
            except Exception as error:  # noqa: BLE001  (one bad scene must not hide the others)
                print(f"phong: {name}: bake failed: {error}", file=sys.stderr)
                failed.append(name)
                continue
            verdict = metrics.get("check", {}).get("verdict")
            if verdict is not None:
                checks.append(verdict["ok"])
                print(f"      glTF in three.js against Cycles: {verdict['value']} "
                      f"{'OK' if verdict['ok'] else 'FAIL'} ({verdict['rule']})", file=say)
                if not verdict["ok"]:
                    failed.append(name)
            state["done"] += 1
        ok = not failed
        print(f"\n{'every scene baked and exported' if ok else 'FAILED: ' + ', '.join(failed)}"
              f"; {len(mine) - len(failed)} of {len(mine)} scene(s) in "
              f"{time.perf_counter() - start:.1f} s -> {out}", file=say)
        say.flush()
        return 0 if ok else 1


def _bake_scene(name, folder, objects, args, out, say) -> dict:
    """Bake, export (and check) one scene into out/<scene>/ (whole or not at all)."""
    import bpy  # noqa: PLC0415

    from ..addon.baking import gltf  # noqa: PLC0415

    scene = bpy.data.scenes[name]
    bpy.context.window.scene = scene
    os.makedirs(out, exist_ok=True)
    tmp = tempfile.mkdtemp(prefix=outputs.temp_prefix("partial", folder), dir=out)
    try:
        t0 = time.perf_counter()
        textures = os.path.join(tmp, "textures")
        settings = _settings(args, textures)
        lines = []

        def progress(done, total, obj_name):
            seconds = time.perf_counter() - t0
            lines.append({"object": obj_name, "done_s": seconds})
            print(f"      [{done}/{total}] {obj_name} ({seconds:.2f} s)", file=say)
            check_interrupt()

        glb = os.path.join(tmp, f"{folder}.glb")
        result = gltf.export(glb, scene, objects, settings, rebake=True, progress=progress)
        metrics = {"scene": name, "file": os.path.abspath(args.file), "target": args.target,
                   "term": args.term, "view": args.view,
                   "resolution": args.resolution if args.target == "image" else None,
                   "format": args.format if args.target == "image" else None,
                   "objects": lines, "warnings": result["warnings"],
                   "glb": os.path.basename(glb), "bake_s": time.perf_counter() - t0}
        for warning in result["warnings"]:
            print(f"      warning: {warning}", file=say)
        if args.peers:
            from ..addon.baking import check  # noqa: PLC0415

            check_interrupt()
            metrics["check"] = check.check(scene, objects, glb, os.path.join(tmp, "check"),
                                           args.check_height)
        metrics["ok"] = metrics.get("check", {}).get("verdict", {}).get("ok", True)
        with open(os.path.join(tmp, "metrics.json"), "w", encoding="utf-8") as handle:
            json.dump(metrics, handle, indent=2, ensure_ascii=False)
        outputs.replace_dir(tmp, os.path.join(out, folder))
    except BaseException:
        shutil.rmtree(tmp, ignore_errors=True)
        raise
    return metrics
