# SPDX-License-Identifier: GPL-3.0-or-later
"""Does Apply keep the look of real files?  For each .blend of tests/data/blend/ (other
people's files, tests/data/README.md): its window scene rendered by Cycles with direct light
only (max bounces 0), with its own materials; Apply Phong Material on every object that
renders (``lighting.convert.apply``); the same render again.  The figure: the median over the
pixels an object covers (alpha 1, the World's background transparent) of the brightness
ratio after / before (R+G+B), per file.  The project's aim: 0.8-1.25x where the file's
materials are diffuse.  A file without a camera gets the camera ``phong compare`` gives it
(its camera object, else one framing what renders), before the first render.

    .venv/bin/python -m phong_nodes.benchmarks.real_files            # ~2 min, 2 cores
    .venv/bin/python -m phong_nodes.benchmarks.real_files --files godot_player.blend

Writes ``real_files_results.json`` beside this file (or ``--out``).
"""

from __future__ import annotations

import argparse
import json
import os
import sys
import tempfile
import time
import types

HERE = os.path.dirname(os.path.abspath(__file__))
DATA = os.path.join(os.path.dirname(HERE), "tests", "data", "blend")
HEIGHT = 48
SAMPLES = 32
#: a pixel counts where the object covers it whole and the first render is not black
ALPHA_MIN = 0.999
DARK = 1e-4


def _material_kind(material) -> str:
    """'diffuse', or what else the material is (metallic, glass, emissive, no nodes, the
    surface shader's type)."""
    if material is None:
        return "none"
    tree = material.node_tree
    if tree is None:
        return "no nodes"
    output = next((n for n in tree.nodes if n.bl_idname == "ShaderNodeOutputMaterial"
                   and n.is_active_output), None)
    if output is None or not output.inputs["Surface"].is_linked:
        return "no surface"
    shader = output.inputs["Surface"].links[0].from_node
    if shader.bl_idname == "ShaderNodeBsdfDiffuse":
        return "diffuse"
    if shader.bl_idname != "ShaderNodeBsdfPrincipled":
        return shader.bl_idname.replace("ShaderNode", "")

    def value(name):
        socket = shader.inputs.get(name)
        return None if socket is None or socket.is_linked else socket.default_value

    kinds = []
    if (value("Metallic") or 0.0) > 0.5 or shader.inputs["Metallic"].is_linked:
        kinds.append("metallic")
    if (value("Transmission Weight") or 0.0) > 0.5:
        kinds.append("glass")
    strength = value("Emission Strength") or 0.0
    colour = value("Emission Color")
    if strength > 0 and colour is not None and max(colour[:3]) > 0:
        kinds.append("emissive")
    return "+".join(kinds) or "diffuse"


def _render(scene, path):
    """(RGB, alpha) of Cycles' picture of *scene*."""
    from phong_nodes.addon.scene import render  # noqa: PLC0415
    from phong_nodes.core import compare  # noqa: PLC0415

    render.render_exr(scene, path)
    combined = compare.read_exr(path)["Combined"]
    os.remove(path)
    return combined[..., :3].astype("float64"), combined[..., 3].astype("float64")


def _settings(scene):
    from phong_nodes.addon import compat  # noqa: PLC0415
    from phong_nodes.addon.scene import render  # noqa: PLC0415

    aspect = scene.render.resolution_x / max(scene.render.resolution_y, 1)
    render.plain_picture(scene, max(1, round(HEIGHT * aspect)), HEIGHT)
    scene.render.film_transparent = True  # the alpha says which pixels an object covers
    scene.render.engine = "CYCLES"
    cycles = scene.cycles
    for attr, value in {"device": "CPU", "samples": SAMPLES, "use_denoising": False,
                        "use_adaptive_sampling": False, "max_bounces": 0, "seed": 0,
                        "use_animated_seed": False, "shading_system": False}.items():
        if hasattr(cycles, attr):
            setattr(cycles, attr, value)
    compat.set_multilayer_exr(scene.render.image_settings, setattr)


def measure(path: str) -> dict:
    """The figures of one file (its window scene)."""
    import bpy  # noqa: PLC0415
    import numpy as np  # noqa: PLC0415

    from phong_nodes.addon.lighting import convert  # noqa: PLC0415
    from phong_nodes.cli import runs  # noqa: PLC0415

    bpy.ops.wm.open_mainfile(filepath=path, load_ui=False)
    scene = bpy.context.scene
    rendering = convert.rendered_objects(scene)
    materials = {}
    for obj in rendering:
        for slot in getattr(obj, "material_slots", ()):
            if slot.material is not None:
                materials[slot.material.name] = _material_kind(slot.material)
    kinds = sorted(set(materials.values()))
    notes = []
    if scene.camera is None:
        cameras = sorted((o for o in scene.objects if o.type == "CAMERA"), key=lambda o: o.name)
        if cameras:
            scene.camera = cameras[0]
            notes.append(f"camera: its camera object {cameras[0].name!r}")
        else:
            from phong_nodes.addon.scene import framing  # noqa: PLC0415

            framing.add_camera(scene, [o for o in rendering if o.type in convert.KINDS])
            notes.append("framed: the scene has no camera")
    _settings(scene)
    folder = tempfile.mkdtemp(prefix="phong_real_files_")
    t0 = time.perf_counter()
    before, alpha = _render(scene, os.path.join(folder, "before.exr"))
    report = convert.apply(scene)
    after, alpha_after = _render(scene, os.path.join(folder, "after.exr"))
    seconds = time.perf_counter() - t0
    covered = (alpha >= ALPHA_MIN) & (alpha_after >= ALPHA_MIN)
    b, a = before.sum(axis=2), after.sum(axis=2)
    lit = covered & (b > DARK)
    ratios = a[lit] / b[lit]
    ok = bool(lit.any())
    return {
        "scene": scene.name,
        "camera": scene.camera.name if scene.camera else None,
        "notes": notes,
        "resolution": [int(before.shape[1]), int(before.shape[0])],
        "samples": SAMPLES,
        "materials": materials,
        "diffuse": bool(kinds) and kinds == ["diffuse"],
        "converted": len(report.converted),
        "skipped": len(report.skipped),
        "lights": {name: bpy.data.objects[name].data.type for name in report.lights},
        "pixels_covered": int(covered.sum()),
        "pixels_compared": int(lit.sum()),
        "pixels_dark_before": int((covered & (b <= DARK)).sum()),
        "median_ratio": float(np.median(ratios)) if ok else None,
        "p10_ratio": float(np.percentile(ratios, 10)) if ok else None,
        "p90_ratio": float(np.percentile(ratios, 90)) if ok else None,
        "mean_brightness_before": float(b[covered].mean() / 3) if covered.any() else None,
        "mean_brightness_after": float(a[covered].mean() / 3) if covered.any() else None,
        "in_aim": (0.8 <= float(np.median(ratios)) <= 1.25) if ok else None,
        "seconds": seconds,
    }


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--files", nargs="*", help="names in tests/data/blend (default: all)")
    parser.add_argument("--out", default=os.path.join(HERE, "real_files_results.json"))
    args = parser.parse_args(argv)
    from . import measure as bench  # noqa: PLC0415  (imports bpy)

    bench.worker_setup()
    import bpy  # noqa: PLC0415

    names = args.files or sorted(n for n in os.listdir(DATA) if n.endswith(".blend"))
    results = {}
    for name in names:
        results[name] = measure(os.path.join(DATA, name))
        r = results[name]
        median = "-" if r["median_ratio"] is None else f"{r['median_ratio']:.3f}"
        print(f"{name}: median after/before {median} over {r['pixels_compared']} pixels "
              f"({'diffuse' if r['diffuse'] else 'not only diffuse'}: "
              f"{sorted(set(r['materials'].values()))}), lights {sorted(r['lights'].values())}",
              flush=True)
    data = {"meta": {"bpy": ".".join(map(str, bpy.app.version)), "height": HEIGHT,
                     "samples": SAMPLES, "max_bounces": 0, "aim": [0.8, 1.25]},
            "files": results}
    with open(args.out, "w", encoding="utf-8") as handle:
        json.dump(data, handle, indent=2)
    print(f"wrote {args.out}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
