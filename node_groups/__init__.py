# SPDX-License-Identifier: GPL-3.0-or-later
"""Phong node groups: definitions (``library``), the expression builder
(``expr``), the numpy reference (``reference``) and, for Blender only, the
loader (``loader``).  Importing this package does not import ``bpy``.
"""
