# SPDX-License-Identifier: GPL-3.0-or-later
"""The supported releases are one list, requirements/releases.txt: the tables of README.md and
docs/releases.md say the same releases, in the same order, with the same Python, LTS and
default; CI (.ci/run) tests the releases flagged `ci` through `tools/phong.sh releases ci`."""

import os
import re

import blender_env as be

_listed = be.supported_releases


def _table(path: str) -> list:
    """(Blender, bpy, Python, default note) of each row of the page's release table."""
    text = open(path, encoding="utf-8").read()
    rows = []
    for match in re.finditer(r"^\| ([0-9.]+(?: LTS)?) \| ([0-9.]+)( \(the default[^)]*\))? \| "
                             r"([0-9.]+) \| ([^|]+) \|$", text, re.M):
        rows.append((match[1], match[2], match[4], bool(match[3]), match[5]))
    return rows


def _expected() -> list:
    out = []
    for bpy, python, flags in _listed():
        major_minor = ".".join(bpy.split(".")[:2])
        out.append((major_minor + (" LTS" if "lts" in flags else ""), bpy, python,
                    "default" in flags))
    return out


def test_the_readme_and_the_releases_page_show_the_list():
    for page in ("README.md", os.path.join("docs", "releases.md")):
        rows = _table(os.path.join(be.REPO_ROOT, page))
        assert [row[:4] for row in rows] == _expected(), page
        tested = [row[1] for row in rows if row[4].startswith("whole suite in CI")]
        assert tested == [bpy for bpy, _py, flags in _listed() if "ci" in flags], page


def test_ci_reads_the_list():
    script = open(os.path.join(be.REPO_ROOT, ".ci", "run"), encoding="utf-8").read()
    assert "tools/phong.sh releases ci" in script
    assert not re.search(r"\b\d\.\d\.\d+\b", script), "a release is named in .ci/run"

