# SPDX-License-Identifier: GPL-3.0-or-later
"""Per Vertex (Gouraud) and Per Face (flat) shading of Phong materials: ``modes.py`` (the
setting's life), ``geometry.py`` (the Geometry Nodes group), ``groups.py`` (the shader
groups)."""
