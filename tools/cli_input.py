#!/usr/bin/env python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""What the headless commands (``tools/phong.py``: demo, compare; ``tools/phong_bake.py``: bake)
read alike: ``--shard``, ``--peers``, a .blend file and its ``--scenes``; ``BadInput`` is a
one-line reason for exit 2 with nothing written."""

from __future__ import annotations

import os

from phong_nodes.core import scenes


class BadInput(Exception):
    """Exit 2 with this one-line reason; nothing has been written."""


def parse_shard(parser, args) -> None:
    """args.shard as i/n (``auto`` resolved from the scheduler's variables) and
    args.shard_source; a bad value is a usage error (exit 2)."""
    try:
        args.shard, args.shard_source = scenes.resolve_shard(args.shard)
    except scenes.SceneError as error:
        parser.error(str(error))


def parse_peers(parser, text: str) -> list:
    """The --peers list ("threejs"); an unknown peer is a usage error (exit 2)."""
    peers = [p.strip().lower() for p in text.split(",") if p.strip()]
    unknown = sorted(set(peers) - {"threejs"})
    if unknown:
        parser.error(f"--peers: unknown peer(s) {', '.join(unknown)}; expected threejs")
    return peers


def peer_problem(peers) -> str | None:
    """Why a peer cannot run on this machine (what to install), or None."""
    if "threejs" not in peers:
        return None
    from phong_nodes.core import threejs  # noqa: PLC0415

    problem = threejs.unavailable()
    return None if problem is None else f"--peers threejs: {problem}"


def open_blend(file: str, scenes_arg) -> tuple:
    """Open the .blend *file*: (its scene names, the names *scenes_arg* ("a,b") gives, or
    None without it); BadInput (exit 2) for a missing or unreadable file or an unknown
    scene."""
    import bpy  # noqa: PLC0415

    path = os.path.abspath(file)
    if not os.path.isfile(path):
        raise BadInput(f"{file}: no such file")
    try:
        bpy.ops.wm.open_mainfile(filepath=path, load_ui=False)
    except RuntimeError as error:
        reason = str(error).strip().splitlines()[-1] if str(error).strip() else "unreadable"
        raise BadInput(f"{file}: cannot open as a .blend file ({reason})") from None
    names = [scene.name for scene in bpy.data.scenes]
    if not scenes_arg:
        return names, None
    wanted = [n.strip() for n in scenes_arg.split(",") if n.strip()]
    unknown = [n for n in wanted if n not in names]
    if unknown or not wanted:
        raise BadInput(f"--scenes: no scene {', '.join(map(repr, unknown)) or '(none given)'} "
                       f"in {file}; it has {', '.join(map(repr, names))}")
    return names, wanted
