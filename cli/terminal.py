# SPDX-License-Identifier: GPL-3.0-or-later
"""The terminal side of the headless commands: Ctrl+C and SIGTERM noted and raised at the next
step (``check_interrupt``), a stream for our own lines while Blender's log goes elsewhere
(``terminal``), and leaving without bpy's clean-up where it crashes (``exit_process``)."""

from __future__ import annotations

import os
import signal
import sys


class Interrupted(KeyboardInterrupt):
    """Ctrl+C (SIGINT) or SIGTERM: stop at the next step, keep only finished scene folders."""

    def __init__(self, signum: int):
        super().__init__(signum)
        self.signum = signum


_PENDING = []


def _on_signal(signum, _frame):
    # Only note it: raising here could land inside a Blender callback, which would print a
    # traceback and swallow it.  check_interrupt() raises at the next step.
    _PENDING.append(signum)


def check_interrupt() -> None:
    if _PENDING:
        raise Interrupted(_PENDING[0])


def run_interruptible(work, state) -> int:
    """*work()* with Ctrl+C / SIGTERM ending it with 130 / 143 and one line on stderr;
    *state* counts the done / total scenes the line names."""
    previous = {sig: signal.signal(sig, _on_signal) for sig in (signal.SIGINT, signal.SIGTERM)}
    try:
        return work()
    except KeyboardInterrupt as stop:
        signum = getattr(stop, "signum", signal.SIGINT)
        print(f"phong: interrupted by {signal.Signals(signum).name} after {state['done']} of "
              f"{state['total']} scene(s); finished scene folders are complete, nothing "
              "half-written was kept", file=sys.stderr)
        return 128 + signum
    finally:
        for sig, handler in previous.items():
            signal.signal(sig, handler)


def terminal():
    """A stream to the terminal for our own lines: Blender's render log goes to fd 1, which
    is sent to /dev/null unless PHONG_VERBOSE=1."""
    say = os.fdopen(os.dup(1), "w", buffering=1)
    if os.environ.get("PHONG_VERBOSE") != "1":
        devnull = os.open(os.devnull, os.O_WRONLY)
        sys.stdout.flush()
        os.dup2(devnull, 1)
        os.close(devnull)
    return say


def exit_process(code: int) -> None:
    """Exit with *code*, without bpy's clean-up where it would crash (compat)."""
    if "bpy" in sys.modules:
        from ..addon import compat  # noqa: PLC0415

        compat.leave_if_exit_crashes(code)
    sys.exit(code)
