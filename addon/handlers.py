# SPDX-License-Identifier: GPL-3.0-or-later
"""Keep one copy of each Phong group when materials are appended from other files.

Appending a material brings its node groups along; where the file already has them,
Blender names the newcomers ``Phong Shading.001``.  After each depsgraph update in which
the number of node groups changed, the copies are merged into the groups already present
(the newest version wins, so nothing is downgraded).
"""

import bpy
from bpy.app.handlers import persistent

from ..node_groups import loader

_seen = {"count": -1}


@persistent
def merge_appended_copies(_scene, _depsgraph=None):
    count = len(bpy.data.node_groups)
    if count == _seen["count"]:
        return
    loader.merge_copies()
    _seen["count"] = len(bpy.data.node_groups)


def register():
    bpy.app.handlers.depsgraph_update_post.append(merge_appended_copies)


def unregister():
    bpy.app.handlers.depsgraph_update_post.remove(merge_appended_copies)
