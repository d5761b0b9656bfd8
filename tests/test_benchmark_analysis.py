# SPDX-License-Identifier: GPL-3.0-or-later
"""The benchmarks' analysis and table without Blender: synthetic worker results with values
worked out by hand, so a wrong ratio, goal or verdict fails here and not in a 10-minute run."""

import json
import subprocess
import sys

import pytest

from phong_nodes.benchmarks import analyse, table


def artist_run(objects, lights, *, phong_move, principled_move, drivers, apply=0.5,
               relink=0.3, add=0.4):
    return {"objects": objects, "lights": lights, "phong_materials": objects,
            "principled_drivers": 0, "drivers": drivers, "drivers_after_add": drivers + 12,
            "principled_move": principled_move, "phong_move": phong_move,
            "apply_operator": apply, "apply_update": 0.0, "add_light_update": add,
            "relink_operator": relink, "relink_update": 0.0}


def test_move_ratio_is_the_ratio_of_each_repeats_medians():
    runs = [artist_run(1000, 4, phong_move=[0.008, 0.010, 0.030],
                       principled_move=[0.001, 0.002, 0.004], drivers=54),
            artist_run(1000, 4, phong_move=[0.006, 0.006, 0.1],
                       principled_move=[0.003, 0.003, 0.0001], drivers=54)]
    case = analyse.artist_figure(runs)["cases"]["1000x4"]
    # repeat 1: 0.010 / 0.002 = 5; repeat 2: 0.006 / 0.003 = 2
    assert case["move_ratio"]["values"] == pytest.approx([5.0, 2.0])
    assert case["move_ratio"]["median"] == pytest.approx(3.5)
    assert (case["move_ratio"]["min"], case["move_ratio"]["max"]) == pytest.approx((2.0, 5.0))
    assert case["phong_move_ms"]["values"] == pytest.approx([10.0, 6.0])
    assert case["drivers"] == [54]


def test_drivers_independent_of_objects_only_when_equal_for_each_light_count():
    same = [artist_run(n, k, phong_move=[0.01], principled_move=[0.005], drivers=d)
            for n in (1000, 10000) for k, d in ((4, 54), (16, 204))]
    figure = analyse.artist_figure(same)
    assert figure["drivers_independent_of_objects"] is True
    assert figure["drivers_by_lights"] == {"4": [54], "16": [204]}
    grown = same[:-1] + [artist_run(10000, 16, phong_move=[0.01], principled_move=[0.005],
                                    drivers=205)]
    figure = analyse.artist_figure(grown)
    assert figure["drivers_independent_of_objects"] is False
    assert table.artist_rows(figure)[-1][3] == "missed"


def test_artist_rows_apply_the_seconds_goals_at_1000_objects_only():
    runs = [artist_run(1000, 4, phong_move=[0.012], principled_move=[0.002], drivers=54,
                       apply=3.0, relink=0.3),
            artist_run(10000, 4, phong_move=[0.1], principled_move=[0.05], drivers=54,
                       apply=12.0, relink=6.0)]
    rows = {row[0]: row for row in table.artist_rows(analyse.artist_figure(runs))}
    move = rows["6. 1,000 objects, 4 lights: one update after moving a light, Phong / Principled"]
    assert move[1].startswith("6.0 ") and move[2] == "≤ 3×" and move[3] == "missed by 2.0×"
    apply = rows["6. 1,000 objects, 4 lights: Apply Phong Material"]
    assert apply[2] == "< 2 s" and apply[3] == "missed by 1.5×"
    relink = rows["6. 1,000 objects, 4 lights: Relink Phong Lights after adding a light"]
    assert relink[3] == "met"
    big = rows["6. 10,000 objects, 4 lights: Apply Phong Material"]
    assert big[2] == "report" and big[3] == ""
    assert rows["6. 10,000 objects, 4 lights: one update after moving a light, "
                "Phong / Principled"][3] == "met"


@pytest.mark.parametrize("value, goal, kind, expected", [
    (1.2, 1.2, "max", "met"), (1.2, 1.2, "max_strict", "missed by 1.0×"),
    (0.9, 1.0, "max_strict", "met"), (3.0, 1.2, "max", "missed by 2.5×"),
    (5.0, 1.0, "info", "")])
def test_verdict(value, goal, kind, expected):
    assert table.verdict(value, goal, kind) == expected


def test_summary_and_format():
    s = analyse.summary([3, 1, 2])
    assert (s["median"], s["min"], s["max"], s["values"]) == (2.0, 1.0, 3.0, [3.0, 1.0, 2.0])
    assert table.fmt(s) == "2.00 (1.00–3.00)"
    assert analyse.ratio_summary([2, 9], [1, 3])["values"] == [2.0, 3.0]


def test_analysis_modules_import_where_bpy_cannot():
    code = ("import sys; sys.modules['bpy'] = None\n"
            "import phong_nodes.benchmarks.analyse, phong_nodes.benchmarks.table\n"
            "import phong_nodes.benchmarks.run, phong_nodes.benchmarks.measure\n"
            "print(sorted(m for m in sys.modules if m.startswith('phong_nodes.addon')))")
    result = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                            timeout=120)
    assert result.returncode == 0, result.stderr[-2000:]
    assert result.stdout.strip() == "[]"


def test_demo_figure_sums_each_repeat_and_states_the_verdict():
    cfg = {"demo_scenes": ["a", "b"]}

    def run(a_shared, a_distinct, b_shared, b_distinct):
        return {"a:shared": {"first": a_shared, "second": 0.1, "materials": None},
                "a:distinct": {"first": a_distinct, "second": 0.1, "materials": 3},
                "b:shared": {"first": b_shared, "second": 0.1, "materials": None},
                "b:distinct": {"first": b_distinct, "second": 0.1, "materials": 8}}

    figure = analyse.demo_figure([run(1.0, 2.0, 1.0, 6.0), run(2.0, 2.0, 2.0, 4.0)], cfg)
    assert figure["ratio"]["values"] == [2.0 / 8.0, 4.0 / 6.0]
    assert figure["scenes"]["b"]["materials"] == 8
    (row,) = table.demo_rows(figure)
    assert row[3] == "met"
    slower = analyse.demo_figure([run(3.0, 1.0, 3.0, 1.0)], cfg)
    assert table.demo_rows(slower)[0][3].startswith("missed")
    assert table.demo_rows(None) == []


def test_two_releases_side_by_side(tmp_path):
    """benchmarks/releases.py puts each figure of two runs in one row, labelled by release."""
    import copy  # noqa: PLC0415
    import json  # noqa: PLC0415
    import os  # noqa: PLC0415

    root = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
    with open(os.path.join(root, "benchmarks", "results.json")) as handle:
        old = json.load(handle)
    new = copy.deepcopy(old)
    new["meta"]["bpy"] = "9.9.9"
    new["figures"]["node_cost_cycles"]["ratio"] = {"median": 1.5, "min": 1.25, "max": 1.75}
    paths = []
    for name, data in (("old.json", old), ("new.json", new)):
        paths.append(str(tmp_path / name))
        with open(paths[-1], "w") as handle:
            json.dump(data, handle)
    result = subprocess.run([sys.executable, os.path.join(root, "benchmarks", "releases.py"),
                             *paths], capture_output=True, text=True, timeout=60)
    assert result.returncode == 0, result.stderr
    lines = result.stdout.splitlines()
    assert lines[0] == f"| figure | bpy {old['meta']['bpy']} | bpy 9.9.9 |"
    (row,) = [line for line in lines if line.startswith("| 1. Node cost")]
    ratio = old["figures"]["node_cost_cycles"]["ratio"]
    assert f"{ratio['median']:.2f} ({ratio['min']:.2f}–{ratio['max']:.2f})×" in row
    assert "| 1.50 (1.25–1.75)× (missed by 1.2×) |" in row
    missing = subprocess.run([sys.executable, os.path.join(root, "benchmarks", "releases.py"),
                              str(tmp_path / "nope.json")], capture_output=True, text=True)
    assert missing.returncode == 2 and "nope.json" in missing.stderr


def test_the_committed_table_is_the_one_its_figures_give():
    """One owner for the benchmark figures: ``results.json``; ``results.md`` is generated from
    it (by run.py), so the two never disagree."""
    import json  # noqa: PLC0415
    import os  # noqa: PLC0415

    folder = os.path.dirname(table.__file__)
    with open(os.path.join(folder, "results.json"), encoding="utf-8") as handle:
        data = json.load(handle)
    with open(os.path.join(folder, "results.md"), encoding="utf-8") as handle:
        committed = handle.read()
    assert committed == table.markdown(data["figures"], data["meta"]) + "\n"


def test_finished_picture_ratio_and_samples_are_each_case_s_medians():
    """The time-to-a-finished-picture table: the ratio of the two cases' median seconds and
    each case's median samples per pixel (worked out by hand: Principled 10 and 30 s -> 20,
    Phong 12, 14 and 40 s -> 14; 14 / 20 = 0.70)."""
    from phong_nodes.benchmarks import finished_picture

    run = {"principled": [{"render_s": 10.0, "mean_samples": 900.0, "max_samples": 4096.0},
                          {"render_s": 30.0, "mean_samples": 1100.0, "max_samples": 4096.0}],
           "phong": [{"render_s": 12.0, "mean_samples": 100.0, "max_samples": 512.0},
                     {"render_s": 14.0, "mean_samples": 300.0, "max_samples": 1024.0},
                     {"render_s": 40.0, "mean_samples": 200.0, "max_samples": 2048.0}]}
    median = {"principled": 20.0, "phong": 14.0}
    result = {"figures": [{"lights": 4, "runs": run, "median_s": median,
                           "ratio_to_principled": 14.0 / 20.0}]}
    text = finished_picture.table(result)
    row = text.splitlines()[-1]
    assert "**0.70×**" in row
    assert "| 1000 (4096) | 200 (1024) |" in row


def test_publish_writes_the_json_it_is_given_and_prints_the_text(tmp_path, capsys):
    from phong_nodes.benchmarks import table  # noqa: PLC0415

    out = tmp_path / "run.json"
    table.publish({"ratio": 1.5, "runs": [1, 2]}, str(out), "| table |")
    assert json.loads(out.read_text(encoding="utf-8")) == {"ratio": 1.5, "runs": [1, 2]}
    assert capsys.readouterr().out == "| table |\n"
    table.publish({"ratio": 2.0}, None, "printed only")
    assert capsys.readouterr().out == "printed only\n"
