# SPDX-License-Identifier: GPL-3.0-or-later
"""Everything of Phong Nodes without bpy apart from the group library: scene files
(``scenes``), the comparison of renders with the reference and its verdicts
(``compare``), the report (``report``) and output folders (``outputs``).

Never imports ``bpy``; the Blender layer (``addon``) imports this package, never the reverse.
"""
