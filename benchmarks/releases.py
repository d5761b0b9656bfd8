#!/usr/bin/env python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""The figures of two or more benchmark runs side by side (for instance one per Blender release):

    .venv/bin/python benchmarks/releases.py benchmarks/results-bpy5.0.1.json benchmarks/results.json

prints a Markdown table with each figure's median (min–max) and verdict per run, labelled by the
run's bpy release.  Pure: reads the runs' ``results.json`` files, never imports ``bpy``."""

from __future__ import annotations

import argparse
import json
import sys

from phong_nodes.benchmarks.table import side_by_side


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("results", nargs="+", help="results.json files of benchmarks/run.py")
    args = parser.parse_args(argv)
    runs = {}
    for path in args.results:
        try:
            with open(path, encoding="utf-8") as handle:
                data = json.load(handle)
        except (OSError, ValueError) as error:
            print(f"releases: {path}: {error}", file=sys.stderr)
            return 2
        label = f"bpy {data['meta']['bpy']}"
        runs[label if label not in runs else f"{label} ({path})"] = (data["figures"], data["meta"])
    print(side_by_side(runs))
    return 0


if __name__ == "__main__":
    sys.exit(main())
