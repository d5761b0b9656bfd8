# SPDX-License-Identifier: GPL-3.0-or-later
"""Per Vertex (Gouraud) and Per Face (flat) shading of Phong materials (modes.py)."""
