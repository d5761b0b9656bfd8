# SPDX-License-Identifier: GPL-3.0-or-later
"""The one wording of a cut-short list of names in reports and messages (core/wording.py)."""

from phong_nodes.core.wording import name_list


def test_a_short_list_is_given_whole():
    assert name_list(["Cube", "Ball"]) == "'Cube', 'Ball'"
    assert name_list(["a", "b", "c"], quote=False) == "a, b, c"
    assert name_list([]) == ""


def test_a_long_list_says_how_many_it_leaves_out():
    assert name_list((f"M{i}" for i in range(7)), limit=5) == "'M0', 'M1', 'M2', 'M3', 'M4' and 2 more"
    assert name_list(["line 3", "line 9", "line 12", "line 40"], quote=False) == (
        "line 3, line 9, line 12 and 1 more")


def test_a_name_with_a_quote_stays_readable():
    assert name_list(["Bob's chair"]) == '"Bob\'s chair"'
