# SPDX-License-Identifier: GPL-3.0-or-later
"""One reading's context (:class:`_Reading`): everything a reading of a file and the files it
inlines shares, in one explicit object that the parsers, the field access, PROTO expansion,
the geometry nodes and the reader are handed (no reader object whose parts share ``self``):
its option (the resolver of URLs), its notes (the warnings collected, counted by kind), its
memo and caches (each node built once, PROTO instances expanded once, files parsed once,
arrays and tessellations shared) and its budgets (nodes copied by PROTO expansion, Inline
files being read), and the document being built.
"""

from __future__ import annotations

from .model import _Notes


class _Reading:
    """The state of one reading (see the module's docstring); it holds data, no behaviour."""

    def __init__(self, resolver):
        # option: (url, base folder) → local path or None
        self.resolver = resolver
        # notes: the warnings, and the counts that become warnings at the end
        self.notes = _Notes()
        self.ignored = {}           # node type → count (behaviour, sound, shaders, ROUTE)
        self.unknown = {}           # unknown node types → count
        self.too_deep = 0           # nodes nested deeper than MAX_DEPTH
        # memo and caches
        self.memo = {}              # id(_N) → (_N, built object); the _N is kept alive
        self.busy = set()           # ids of the nodes being built (a node inside itself)
        self.expanded = {}          # id(instance) → (instance, copied body root)
        self.files = {}             # real path → _Source (None: failed or being read)
        self.canon = {}             # type as written → canonical type (or None)
        self.arrays = {}            # (id(data node), field) → (node, values)
        self.tessellated = {}       # a primitive's type and fields → its shared arrays
        # budgets
        self.copies = 0             # nodes copied by PROTO expansion (MAX_NODES)
        self.loading = []           # real paths of the Inline files being built (recursion)
        # the document being built: its main file and the bindable nodes already bound
        self.doc = None
        self.main = None
        self.bound = set()
