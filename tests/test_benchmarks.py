# SPDX-License-Identifier: GPL-3.0-or-later
"""Smoke test of benchmarks/run.py at tiny sizes, so the benchmark script cannot rot.

Runs the whole script (``--quick --repeats 1``: every worker, Cycles and Eevee, with warm
shader caches) into a temp folder and checks the JSON schema and that every ratio is finite
and positive.  The real figures come from ``.venv/bin/python benchmarks/run.py``.
"""

from __future__ import annotations

import json
import math
import os
import subprocess
import sys

import pytest

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
SCRIPT = os.path.join(ROOT, "benchmarks", "run.py")

FIGURES = ("node_cost_cycles", "light_scaling_cycles", "light_scaling_eevee", "eevee_compile",
           "quality_per_second", "scale", "scale_distinct", "artist_scale", "demo_eevee")


def _is_summary(value):
    return isinstance(value, dict) and {"median", "min", "max", "values"} <= set(value)


def _summaries(node, path=""):
    if _is_summary(node):
        yield path, node
    elif isinstance(node, dict):
        for key, value in node.items():
            yield from _summaries(value, f"{path}.{key}" if path else key)


@pytest.fixture(scope="module")
def quick_run(tmp_path_factory):
    out = tmp_path_factory.mktemp("bench")
    proc = subprocess.run([sys.executable, SCRIPT, "--quick", "--repeats", "1",
                           "--out", str(out / "results.json")],
                          capture_output=True, text=True, timeout=600, cwd=ROOT)
    assert proc.returncode == 0, proc.stdout[-3000:] + proc.stderr[-3000:]
    with open(out / "results.json") as fh:
        data = json.load(fh)
    return data, (out / "results.md").read_text(), proc.stdout


@pytest.mark.slow
@pytest.mark.cycles
@pytest.mark.eevee
def test_schema(quick_run):
    data, _md, _stdout = quick_run
    assert set(data) == {"meta", "figures", "raw"}
    meta = data["meta"]
    assert meta["schema"] == 1 and meta["quick"] is True and meta["repeats"] == 1
    for key in ("load_before", "load_after"):
        assert meta[key] is None or (len(meta[key]) == 3 and all(x >= 0 for x in meta[key]))
    assert set(FIGURES) <= set(data["figures"])
    for name in FIGURES:
        figure = data["figures"][name]
        assert isinstance(figure["what"], str) and figure["what"]
        assert "goal" in figure and "goal_kind" in figure
    lights = [str(n) for n in meta["config"]["lights"]]
    assert list(data["figures"]["light_scaling_cycles"]["ratios"]) == lights
    assert list(data["figures"]["light_scaling_eevee"]["ratios"]) == lights


@pytest.mark.slow
@pytest.mark.cycles
@pytest.mark.eevee
def test_ratios_finite_and_positive(quick_run):
    data, _md, _stdout = quick_run
    found = 0
    for path, summary in _summaries(data["figures"]):
        values = summary["values"] + [summary["median"], summary["min"], summary["max"]]
        assert all(math.isfinite(v) for v in values), path
        assert summary["min"] <= summary["median"] <= summary["max"], path
        if "ratio" in path.split(".")[-1] or ".ratios." in f".{path}.":
            assert all(v > 0 for v in values), path
            found += 1
    assert found >= 10


@pytest.mark.slow
@pytest.mark.cycles
@pytest.mark.eevee
def test_markdown_table_printed(quick_run):
    _data, md, stdout = quick_run
    assert md.startswith("| figure | median (min–max) | goal | verdict | detail |")
    assert md.strip() in stdout
    assert md.count("\n|") >= 9
