# SPDX-License-Identifier: GPL-3.0-or-later
"""The extension registered for the length of a command's run (:class:`Registered`), shared by
``runs``, ``apply`` and ``bake``: a module of its own so that none of them imports another
for it."""

from __future__ import annotations


class Registered:
    """The extension registered (from the first ``ensure()``: importing bpy takes a second)
    until the block ends, on every path: bpy 4.2 crashes at interpreter exit while classes
    registered without an add-on (here: by hand) are still registered."""

    def __init__(self):
        self.done = False

    def ensure(self) -> None:
        if not self.done:
            from .. import register  # noqa: PLC0415

            register()
            self.done = True

    def __enter__(self):
        return self

    def __exit__(self, *_exc):
        if self.done:
            from .. import unregister  # noqa: PLC0415

            unregister()
