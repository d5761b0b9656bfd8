# SPDX-License-Identifier: GPL-3.0-or-later
"""Phong Nodes: the textbook Phong lighting model as shader node groups.

The extension root only forwards to the Blender layer in ``addon/``.
"""

from .addon import register, unregister  # noqa: F401
