# SPDX-License-Identifier: GPL-3.0-or-later
"""Interchange with other programs: the table of formats (``formats.py``), each format's
importer and exporter, what every import leaves behind (``native.py``) and the round-trip keys
(``keys.py``)."""
