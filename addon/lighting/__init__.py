# SPDX-License-Identifier: GPL-3.0-or-later
"""Phong materials driven by Blender lights: the material recipe, drivers, settings."""
