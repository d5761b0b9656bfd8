# SPDX-License-Identifier: GPL-3.0-or-later
"""The comparison: a scene rendered by Eevee and Cycles (and optional peers) and checked against
the numpy reference of the formulas, into a report folder (``engine``)."""
