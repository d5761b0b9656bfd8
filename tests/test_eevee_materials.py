# SPDX-License-Identifier: GPL-3.0-or-later
"""Issue 30 items 4 and 5: the benchmarks of a full Eevee render of many materials
(benchmarks/eevee_materials.py) and of the Cycles cost of a light against a hand-minimal
chain (benchmarks/light_floor.py) run at tiny sizes, and their variants show the picture
of the Phong materials they stand beside."""

from __future__ import annotations

import json
import subprocess
import sys

import pytest

import blender_env as be


def _run(code, timeout=300):
    code = f"import json, os; {code}; os._exit(0)"
    run = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                         timeout=timeout, cwd=be.REPO_ROOT)
    assert run.returncode == 0, run.stdout[-2000:] + run.stderr[-2000:]
    return json.loads(run.stdout.split("RESULT ")[-1])


@pytest.mark.cycles
def test_the_0_3_lights_group_shows_the_picture_of_the_lights_group():
    """The lights group as version 0.3 built it (a Phong Shading per light; point, sun,
    spot, point, the fourth light's transform driven) renders what this version's renders."""
    difference = _run("from phong_nodes.benchmarks import eevee_materials as m; "
                      "print('RESULT ' + json.dumps(m.largest_difference(9, 4)), flush=True)")
    assert difference < 1e-4


@pytest.mark.eevee
@pytest.mark.slow
def test_the_eevee_materials_benchmark_runs():
    result = _run("from phong_nodes.benchmarks import eevee_materials as m; "
                  "print('RESULT ' + json.dumps(m.run(4, 4, 1, ['principled', 'phong', "
                  "'phong_0_3'])), flush=True)", timeout=600)
    assert set(result["render_s"]) == {"principled", "phong", "phong_0_3"}
    assert all(t > 0 for times in result["render_s"].values() for t in times)
    assert result["ratio_to_principled"]["principled"] == 1.0
    nodes = result["expanded_nodes"]
    assert nodes["phong"] < nodes["phong_0_3"]


@pytest.mark.slow
@pytest.mark.cycles
def test_the_minimal_chain_shows_the_phong_picture():
    """benchmarks/light_floor.py at a tiny size: the hand-minimal chain renders the Phong
    materials' picture with 1 and 2 point lights."""
    result = _run("from phong_nodes.benchmarks import light_floor as m; "
                  "print('RESULT ' + json.dumps(m.run([1, 2], 1, 32, 1)), flush=True)")
    assert set(result["render_s"]) == {"emission:1", "phong:1", "minimal:1", "phong:2",
                                       "minimal:2"}
    assert max(result["largest_difference"].values()) < 1e-4
    assert result["nodes_per_material"] == {"minimal:1": 20, "minimal:2": 36}
    assert set(result["extra_light_fraction"]) == {"phong", "minimal"}
