# SPDX-License-Identifier: GPL-3.0-or-later
"""How messages name things: the one wording of a list of names cut short ("'a', 'b' and 3
more") that reports, notes and errors share.  No bpy."""

from __future__ import annotations

from collections.abc import Iterable


def name_list(names: Iterable[str], limit: int = 3, quote: bool = True) -> str:
    """The first *limit* of *names*, comma-separated (each in quotes when *quote*), then
    " and N more" for the rest; an empty string for no names."""
    names = [repr(n) if quote else str(n) for n in names]
    shown = ", ".join(names[:limit])
    return shown + (f" and {len(names) - limit} more" if len(names) > limit else "")
