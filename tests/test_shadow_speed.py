# SPDX-License-Identifier: GPL-3.0-or-later
"""Issue 43 item 8: the shadow speed benchmark (benchmarks/shadow_speed.py) runs at a tiny
size, and its scene is the artist scene with shadows on both sides and a floor."""

from __future__ import annotations

import json
import subprocess
import sys

import pytest

import blender_env as be


def _run(code, env=None, timeout=300):
    code = f"import json, os; {code}; os._exit(0)"
    run = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                         timeout=timeout, cwd=be.REPO_ROOT, env=env)
    assert run.returncode == 0, run.stdout[-2000:] + run.stderr[-2000:]
    return json.loads(run.stdout.split("RESULT ")[-1])


_SCENE = ("from phong_nodes.benchmarks import measure as m; bpy = m.worker_setup(); "
          "scene, objects, lights = m.artist_scene('s', 4, 3); "
          "print('RESULT ' + json.dumps({'shadows': [l.data.use_shadow for l in lights], "
          "'objects': [o.name for o in objects], 'materials': len({o.material_slots[0].material "
          "for o in objects}), 'floor_z': [max(v.co.z for v in o.data.vertices) "
          "for o in objects]}), flush=True)")


@pytest.mark.slow
def test_the_scene_has_shadows_and_a_floor_only_when_asked():
    import os  # noqa: PLC0415

    plain = _run(_SCENE, env={k: v for k, v in os.environ.items() if k != "PHONG_BENCH_SHADOWS"})
    assert plain["shadows"] == [False] * 3
    assert len(plain["objects"]) == 4
    shadowed = _run(_SCENE, env={**os.environ, "PHONG_BENCH_SHADOWS": "1"})
    assert shadowed["shadows"] == [True] * 3
    assert shadowed["objects"][-1] == "s floor" and len(shadowed["objects"]) == 5
    assert shadowed["materials"] == 5  # the floor has its own material
    assert shadowed["floor_z"][-1] < min(shadowed["floor_z"][:-1]) - 2.0  # below the cubes


@pytest.mark.slow
@pytest.mark.cycles
def test_the_shadow_speed_benchmark_runs():
    result = _run("from phong_nodes.benchmarks import shadow_speed as m; "
                  "print('RESULT ' + json.dumps(m.f12('cycles', 4, 2, 1, 32, 1, 1)), flush=True)")
    assert set(result["render_s"]) == {"principled", "phong"}
    assert all(t > 0 for times in result["render_s"].values() for t in times)
    assert all(0 < s <= t for s, t in zip(result["sync_s"]["phong"], result["render_s"]["phong"]))
    assert result["ratio_to_principled"]["principled"] == 1.0
    from phong_nodes.benchmarks import shadow_speed  # noqa: PLC0415  (no bpy)

    text = shadow_speed.table({"f12": [{**result, "goal": 1.6}]})
    assert "Cycles, 2 lights, 1 samples" in text and "1.6×" in text


_CHAIN = ("from phong_nodes.benchmarks import measure as m, shadow_speed as s; "
          "bpy = m.worker_setup(); out = {}\n"
          "for k in (0, 30):\n"
          "    scene, objects, lights = m.artist_scene(f's{k}', 3, 2)\n"
          "    materials = {o.material_slots[0].material for o in objects}\n"
          "    s._chain_materials(bpy, materials, k, len(lights))\n"
          "    inlined = [mat.inline_shader_nodes() for mat in materials]\n"
          "    out[k] = sorted({len(i.node_tree.nodes) for i in inlined})\n"
          "print('RESULT ' + json.dumps(out), flush=True)")


@pytest.mark.slow
def test_the_node_budget_materials_keep_every_node():
    """The node budget (benchmarks/README.md, ``--variant chain<K>``) holds only if neither
    Blender's inliner nor anything else folds the chain: each of K more Math nodes is one
    more inlined node, in every material."""
    if not hasattr(be.import_bpy().types.Material, "inline_shader_nodes"):
        pytest.skip("Material.inline_shader_nodes: Blender 5+")
    rays = 2 if hasattr(be.import_bpy().types, "ShaderNodeRaycast") else 0
    result = _run(_CHAIN)
    # Geometry, Separate XYZ, Scale, Emission, Material Output; a Raycast and a Multiply a ray
    assert result == {"0": [5 + 2 * rays], "30": [35 + 2 * rays]}
