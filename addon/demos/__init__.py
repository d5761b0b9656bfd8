# SPDX-License-Identifier: GPL-3.0-or-later
"""Demo scenes from scene files, exact render settings, the comparison bake."""
