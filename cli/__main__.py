# SPDX-License-Identifier: GPL-3.0-or-later
"""``python -m phong_nodes.cli``: the ``phong`` command."""

import sys

sys.dont_write_bytecode = True  # write nothing outside --out (no __pycache__ beside the sources)

from . import console  # noqa: E402

console()
