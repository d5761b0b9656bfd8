# SPDX-License-Identifier: GPL-3.0-or-later
"""What one light costs Cycles: the nodes a Phong material's Cycles output holds once Blender
has inlined its groups (``Material.inline_shader_nodes``, Blender 5+), per light, for each
light type and lighting model, with the light casting shadows.  Cycles spends about 14 µs per
inlined node per material before the first sample (benchmarks/README.md), so the count is
the cost; this test fails if a count grows past the one measured on the release
(``tests/data/node_counts.json``, regenerated after an intended change with
``PHONG_UPDATE_SNAPSHOTS=1``; a release not measured there is skipped, saying so)."""

from __future__ import annotations

import json
import os

import pytest

import blender_env as be

DATA = os.path.join(os.path.dirname(os.path.abspath(__file__)), "data", "node_counts.json")
MODELS = ("seeds", "threejs", "x3d")
KINDS = ("POINT", "SPOT", "SUN", "AREA")
#: The seeds' model with a material's Blinn other than the default 0: exactly 1 (Blinn-Phong's
#: highlight alone) and between (the blend of both), each counted as a model of its own.
BLINNS = {"seeds, Blinn 1": 1.0, "seeds, Blinn 0.5": 0.5}


def _inlined(material) -> int:
    """The nodes of *material*'s Cycles output, its groups inlined."""
    with be.inlined_cycles_tree(material) as tree:
        return len(tree.nodes)


def _count(bpy, model, kind, lights=1, blinn=None) -> int:
    """Inlined nodes of a Phong material lit by *lights* lights of *kind* in *model*, its
    Blinn control set to *blinn* (None: the default) as a user sets it."""
    be.reset_empty_file()
    scene = be.new_scene(f"{model} {kind}", 8, 8)
    bpy.context.window.scene = scene
    scene["phong_model"] = model
    be.add_ortho_camera(scene, (0.0, 0.0), 2.0, 2.0)
    ball = be.add_uv_sphere(scene, "Ball", (0.0, 0.0, 0.0), 1.0,
                            bpy.data.materials.new("Clay"), segments=8, rings=4)
    for index in range(lights if kind is not None else 0):
        data = bpy.data.lights.new(f"Light {index}", kind)
        data.use_shadow = True
        light = bpy.data.objects.new(f"Light {index}", data)
        light.location = (0.5 + index, 0.3, 3.0)
        scene.collection.objects.link(light)
    be.apply_phong(scene, [ball])
    if blinn is not None:
        ball.active_material.node_tree.nodes["phong_blinn"].outputs[0].default_value = blinn
        bpy.context.view_layer.update()  # what Blender's UI does after each change
    return _inlined(ball.active_material)


def _measured(bpy) -> dict:
    """{model: {"no light": nodes, kind: nodes one more light of it adds (the second)}}, and
    the same per light for the seeds' model at each Blinn of ``BLINNS``."""
    out = {}
    for model in MODELS:
        out[model] = {"no light": _count(bpy, model, None)}
        out[model].update({kind.lower(): _count(bpy, model, kind, 2) - _count(bpy, model, kind, 1)
                           for kind in KINDS})
    for name, blinn in BLINNS.items():
        out[name] = {kind.lower(): _count(bpy, "seeds", kind, 2, blinn)
                     - _count(bpy, "seeds", kind, 1, blinn) for kind in KINDS}
    return out


def test_a_light_costs_cycles_no_more_nodes_than_measured(bpy_clean):
    bpy = bpy_clean
    if not hasattr(bpy.types.Material, "inline_shader_nodes"):
        pytest.skip("Material.inline_shader_nodes: Blender 5 and later")
    release = be.bpy_release()
    got = _measured(bpy)
    be.report(f"[node counts] {release}: " + "; ".join(
        f"{model}: " + ", ".join(f"{k} {v}" for k, v in counts.items())
        for model, counts in got.items()))
    snapshot = json.load(open(DATA, encoding="utf-8")) if os.path.exists(DATA) else {}
    if os.environ.get("PHONG_UPDATE_SNAPSHOTS"):
        snapshot[release] = got
        with open(DATA, "w", encoding="utf-8") as handle:
            json.dump(snapshot, handle, indent=1, sort_keys=True)
            handle.write("\n")
    if release not in snapshot:
        pytest.skip(f"no node counts measured on bpy {release} (PHONG_UPDATE_SNAPSHOTS=1)")
    want = snapshot[release]
    grown = [f"{model} {key}: {got[model][key]} > {value}"
             for model, counts in want.items() for key, value in counts.items()
             if got[model][key] > value]
    assert not grown, "inlined nodes grew: " + "; ".join(grown)
    assert got["seeds"]["point"] > 0 and got["seeds"]["sun"] > 0, "a light costs nodes"
    # a Blinn of exactly 0 or 1 leaves a light one highlight: 5.3's Switch, or before 5.3 the
    # lights group of that highlight (lighting/rig.py, highlight_for)
    blend = got["seeds, Blinn 0.5"]
    for name in ("seeds", "seeds, Blinn 1"):
        more = [kind for kind in blend if got[name][kind] >= blend[kind]]
        assert not more, f"{name}: as many nodes as the blend for {more}"
