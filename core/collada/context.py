# SPDX-License-Identifier: GPL-3.0-or-later
"""One reading's context (:class:`_Reading`), the one object that every function of the
reading is handed: the document being filled (and its warnings), the file's root element and
its elements by id (every reference is looked up there), and the places where decimal commas
were read (one warning at the end); and the look-ups of an element that every part shares
(its name, the id a URL names, an integer attribute).
"""

from __future__ import annotations

from .model import PROFILE


class _Reading:
    """The state of one reading (see the module's docstring); it holds data, no behaviour."""

    def __init__(self, doc, root):
        self.doc = doc
        self.root = root
        self.ids = {}
        for element in root.iter():
            ident = element.get("id")
            if ident is not None:
                self.ids.setdefault(ident, element)
        self.commas = []   # where decimal commas were read (one warning at the end)


def _name(element, default=""):
    """An element's exact name (our ``<extra>``), else its ``name``, else *default*."""
    exact = element.find(f"extra/technique[@profile='{PROFILE}']/name")
    if exact is not None and exact.text:
        return exact.text
    return element.get("name") or default


def _ref(url) -> str:
    """The id a URL (``#id``) or an IDREF names."""
    url = (url or "").strip()
    return url[1:] if url.startswith("#") else url


def _int_attr(element, name):
    if element is None or element.get(name) is None:
        return None
    try:
        return int(element.get(name).strip())
    except ValueError:
        return None
