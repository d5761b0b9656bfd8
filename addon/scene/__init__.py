# SPDX-License-Identifier: GPL-3.0-or-later
"""What the comparison, Bake Phong Lighting and the exporters share about a scene: exact render
settings (``render``), the scene as plain data for the reference (``describe``) and the meshes
the demo scenes and tests build (``meshes``).  Nothing here imports the rooms above it."""
