# SPDX-License-Identifier: GPL-3.0-or-later
"""Benchmarks of Phong Nodes: run.py (orchestrator), measure.py (bpy workers), analyse.py and
table.py (pure)."""
