# SPDX-License-Identifier: GPL-3.0-or-later
"""Interchange with other programs: Phong materials as Wavefront MTL."""
