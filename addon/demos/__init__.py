# SPDX-License-Identifier: GPL-3.0-or-later
"""Demo scenes built from the scene files ``scenes/*.toml`` as ordinary live scenes (``builder``)."""
