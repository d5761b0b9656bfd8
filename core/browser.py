# SPDX-License-Identifier: GPL-3.0-or-later
"""Headless Chromium for the three.js peer renderer: open a page of ``core/threejs.py`` and
take its pixels and errors back.

Chromium renders WebGL on the CPU (ANGLE on SwiftShader, no GPU needed) and prints the page's
DOM after the load event (``--dump-dom``); the page has by then rendered synchronously and
written the picture as base64 RGBA into ``<pre id="phong-pixels">``.  One render of a small
page (256 x 128, a few triangles) takes 1.3 to 1.6 s of wall time, nearly all of it Chromium
starting up (measured with Chromium 150 on a 16-core machine; a fresh profile every time).

A page that draws after the load event (the glTF check's: GLTFLoader decodes textures off the
main thread) is read with ``until_done``: Chromium is driven over its DevTools pipe and the DOM
taken once the page's title says it has finished, in real time.  (A virtual time budget was
tried first: Chromium's virtual clock runs on while a decode is pending off the main thread,
and CI once caught the page still loading.)

Errors are the page's own capture (``window.onerror``, unhandled rejections, ``console.error``
and ``console.warn``) plus the ``CONSOLE`` lines of level ERROR in Chromium's log; the rest of
the log (D-Bus, EGL_BAD_MATCH and other GPU-process noise) is not the page's and is ignored.
"""

from __future__ import annotations

import base64
import fcntl
import html
import json
import os
import re
import select
import shutil
import signal
import subprocess
import tempfile
import time
from dataclasses import dataclass, field

import numpy as np

BROWSERS = ("chromium", "chromium-browser", "google-chrome")

FLAGS = (
    "--headless=new", "--use-angle=swiftshader", "--enable-unsafe-swiftshader",
    "--allow-file-access-from-files", "--no-first-run", "--disable-background-networking",
    "--disable-component-update", "--disable-sync", "--disable-quic", "--disable-extensions",
    "--enable-logging=stderr", "--v=0",
)


class BrowserError(RuntimeError):
    """Chromium could not render the page; ``errors`` holds what the page reported."""

    def __init__(self, message: str, errors: list | None = None, title: str = ""):
        super().__init__(message)
        self.errors = list(errors or [])
        self.title = title


@dataclass
class PageResult:
    rgba: np.ndarray            # uint8 (H, W, 4), row 0 = top of the picture
    errors: list = field(default_factory=list)
    seconds: float = 0.0        # wall time of the Chromium run
    title: str = ""             # "phong: done" when the page finished without an exception


def find_browser() -> str | None:
    """``$PHONG_CHROMIUM`` (a path or a command name), else the first of chromium,
    chromium-browser, google-chrome on PATH; None when there is none."""
    wanted = os.environ.get("PHONG_CHROMIUM")
    if wanted:
        return shutil.which(wanted)
    for name in BROWSERS:
        path = shutil.which(name)
        if path:
            return path
    return None


def missing_message(peer: str = "three.js") -> str:
    """One line: what the *peer* renderer ("three.js", "X_ITE": an npm package shown in
    Chromium) lacks and the command that installs it."""
    no_browser, no_npm = find_browser() is None, shutil.which("npm") is None
    if not (no_browser or no_npm):
        return "Chromium and npm are there (PHONG_CHROMIUM picks another Chromium or Chrome)"
    needs = (["Chromium"] if no_browser else []) + ([f"nodejs/npm (to install {peer})"]
                                                   if no_npm else [])
    packages = (["chromium"] if no_browser else []) + (["nodejs", "npm"] if no_npm else [])
    return (f"The {peer} peer renderer needs {' and '.join(needs)}: "
            f"sudo apt-get install -y {' '.join(packages)} && bash tools/phong.sh setup"
            + (" (or set PHONG_CHROMIUM to a Chromium or Chrome binary)" if no_browser else ""))


def package_dir(variable: str, name: str, version: str) -> str:
    """The folder holding ``node_modules/<name>`` of an npm package that a page loads:
    ``$<variable>`` if set, else ``${XDG_CACHE_HOME:-~/.cache}/phong-nodes/<name>-<version>``
    (where ``tools/phong.sh setup`` installs it)."""
    folder = os.environ.get(variable)
    if folder:
        return folder
    cache = os.environ.get("XDG_CACHE_HOME") or os.path.join(os.path.expanduser("~"), ".cache")
    return os.path.join(cache, "phong-nodes", f"{name}-{version}")


def package_file(folder: str, package: str, relative: str, label: str, version: str,
                 missing) -> str:
    """Path of *relative* in the npm *package* under *folder*; *missing* (an exception type)
    naming the setup command when it is absent."""
    path = os.path.join(folder, "node_modules", package, relative)
    if not os.path.isfile(path):
        raise missing(f"{label} {version} is not installed: run "
                      f"`bash tools/phong.sh setup` (needs npm); looked for {path}")
    return path


# Chromium's log line of a console message: "[pid:tid:date:LEVEL:CONSOLE:12] "text", source: ..."
# (older releases: "LEVEL:CONSOLE(12)]").  Chromium logs ordinary pages' messages at INFO,
# whatever their console level, so only the ERROR ones of other builds count here: the page
# captures its own console.error / console.warn itself.
_CONSOLE = re.compile(
    r"^\[[^\]]*?:(?P<level>[A-Za-z0-9]+):CONSOLE(?::\d+|\(\d+\))\]\s*(?P<text>.*)$")
_PRE = re.compile(r"<pre\b(?P<attrs>[^>]*)>(?P<text>.*?)</pre>", re.DOTALL)
_ATTR = re.compile(r'([\w:-]+)="([^"]*)"')
_TITLE = re.compile(r"<title>(.*?)</title>", re.DOTALL)


def console_errors(log: str) -> list:
    """The console messages of level ERROR in Chromium's log (stderr)."""
    found = []
    for line in log.splitlines():
        match = _CONSOLE.match(line.strip())
        if match and match.group("level").upper() == "ERROR":
            found.append("console: " + match.group("text"))
    return found


def parse_dom(dom: str) -> tuple:
    """(title, errors, rgba or None) from the DOM the page left."""
    pres = {}
    for match in _PRE.finditer(dom):
        attrs = dict(_ATTR.findall(match.group("attrs")))
        if "id" in attrs:
            pres[attrs["id"]] = (attrs, match.group("text"))
    title = _TITLE.search(dom)
    title = html.unescape(title.group(1)).strip() if title else ""
    errors = []
    if "phong-errors" in pres:
        errors = [line for line in html.unescape(pres["phong-errors"][1]).splitlines() if line]
    rgba = None
    if "phong-pixels" in pres:
        attrs, text = pres["phong-pixels"]
        width, height = int(attrs.get("data-width", 0)), int(attrs.get("data-height", 0))
        data = base64.b64decode("".join(text.split())) if width and height else b""
        if width and height and len(data) == width * height * 4:
            rgba = np.frombuffer(data, dtype=np.uint8).reshape(height, width, 4).copy()
    return title, errors, rgba


def _command(browser: str, html_path: str, profile: str, extra=(),
             mode: str = "--dump-dom") -> list:
    """Chromium's command line for the page; *mode*: ``--dump-dom`` (print the DOM after the
    load event) or ``--remote-debugging-pipe`` (:func:`_run_until_done`)."""
    command = [browser, *FLAGS, *extra, f"--user-data-dir={profile}"]
    if hasattr(os, "geteuid") and os.geteuid() == 0:
        command.append("--no-sandbox")  # Chromium refuses to run as root with its sandbox
    url = "file://" + os.path.abspath(html_path)
    return command + [mode, url]


def render_page(html_path: str, timeout: float = 180, extra_flags=(),
                until_done: bool = False) -> PageResult:
    """Render the page in headless Chromium (a fresh profile, removed afterwards) and return its
    pixels, errors and the wall time.  :class:`BrowserError` on a timeout, a Chromium that
    failed without printing a DOM, or a page that left no pixels (its errors in the message).

    By default the DOM is the one Chromium prints after the load event (``--dump-dom``), for
    pages that draw synchronously.  *until_done*: for a page that draws later (GLTFLoader
    decodes its textures off the main thread, after the load event), Chromium is driven over
    its DevTools pipe instead and the DOM is taken once the page's title says it has finished
    (``phong: done`` or ``phong: error``), in real time, up to *timeout*.  *extra_flags*: more
    Chromium flags."""
    browser = find_browser()
    if browser is None:
        raise BrowserError(missing_message())
    if not os.path.isfile(html_path):
        raise BrowserError(f"no page {html_path}")
    profile = tempfile.mkdtemp(prefix="phong-chromium-")
    start = time.monotonic()
    try:
        if until_done:
            dom, log, returncode = _run_until_done(browser, html_path, profile, extra_flags,
                                                   timeout)
        else:
            dom, log, returncode = _run_dump_dom(browser, html_path, profile, extra_flags,
                                                 timeout)
    finally:
        shutil.rmtree(profile, ignore_errors=True)
    seconds = time.monotonic() - start
    if "<html" not in dom:
        last = [line for line in log.splitlines() if line.strip()][-3:]
        raise BrowserError(f"Chromium ({browser}) exited with {returncode} and no page "
                           f"for {html_path}: " + " / ".join(last))
    title, errors, rgba = parse_dom(dom)
    errors += console_errors(log)
    if rgba is None:
        raise BrowserError(f"{html_path} left no pixels (title {title!r}): "
                           + ("; ".join(errors) or "no error reported"), errors, title)
    return PageResult(rgba=rgba, errors=errors, seconds=seconds, title=title)


def _run_dump_dom(browser, html_path, profile, extra_flags, timeout) -> tuple:
    """(DOM, log, exit code) of ``chromium --dump-dom``."""
    process = subprocess.Popen(_command(browser, html_path, profile, extra_flags),
                               stdin=subprocess.DEVNULL, stdout=subprocess.PIPE,
                               stderr=subprocess.PIPE, start_new_session=True)
    try:
        out, err = process.communicate(timeout=timeout)
    except subprocess.TimeoutExpired:
        _kill_group(process)
        process.communicate()
        raise BrowserError(f"Chromium did not finish {html_path} in {timeout:g} s") from None
    finally:
        _kill_group(process)  # helpers that outlived the browser process
    return out.decode("utf-8", "replace"), err.decode("utf-8", "replace"), process.returncode


#: The page's titles once it has finished (see ``threejs.capture_js``).
DONE_TITLES = ("phong: done", "phong: error")
OUTER_HTML = "document.documentElement.outerHTML"
_POLL_S = 0.05


def _run_until_done(browser, html_path, profile, extra_flags, timeout) -> tuple:
    """(DOM, log, exit code): Chromium opens the page under ``--remote-debugging-pipe`` (the
    DevTools protocol as NUL-ended JSON on its file descriptors 3 and 4) and the page's title
    is read until it is one of :data:`DONE_TITLES`; then the DOM is read and Chromium closed.
    Chromium's log goes to a temporary file, read afterwards."""
    to_child, from_parent = os.pipe()    # Chromium reads commands on its fd 3
    to_parent, from_child = os.pipe()    # and writes answers on its fd 4
    command = _command(browser, html_path, profile, extra_flags, "--remote-debugging-pipe")

    def child_fds():  # in the child: its pipe ends as fds 3 and 4 (dup2 makes them inheritable)
        read_end = fcntl.fcntl(to_child, fcntl.F_DUPFD, 10)
        write_end = fcntl.fcntl(from_child, fcntl.F_DUPFD, 10)
        os.dup2(read_end, 3)
        os.dup2(write_end, 4)

    with tempfile.TemporaryFile() as log_file:
        process = subprocess.Popen(command, stdin=subprocess.DEVNULL,
                                   stdout=subprocess.DEVNULL, stderr=log_file,
                                   start_new_session=True, close_fds=False,
                                   preexec_fn=child_fds)
        os.close(to_child)
        os.close(from_child)
        pipe = _DevTools(from_parent, to_parent, time.monotonic() + timeout, html_path)
        ending = False  # Chromium was asked to close, or has closed: give it time to exit
        try:
            dom = pipe.dom_when_done()
        except _Late:
            raise BrowserError(f"Chromium did not open {html_path} in {timeout:g} s") from None
        except _PipeClosed:
            dom, ending = "", True
        else:
            try:
                pipe.send("Browser.close")
            except _PipeClosed:
                pass  # it ended by itself: the DOM read before stands
            ending = True
        finally:
            pipe.close()
            if ending:
                try:
                    process.wait(timeout=10)
                except subprocess.TimeoutExpired:
                    pass
            _kill_group(process)
            process.wait()
        log_file.seek(0)
        log = log_file.read().decode("utf-8", "replace")
    return dom, log, process.returncode


class _PipeClosed(Exception):
    """Chromium closed its DevTools pipe (it ended)."""


class _Late(Exception):
    """The deadline passed."""


class _DevTools:
    """The few DevTools protocol calls :func:`_run_until_done` needs, over Chromium's pipe."""

    def __init__(self, write_fd: int, read_fd: int, deadline: float, html_path: str):
        self.write_fd, self.read_fd = write_fd, read_fd
        self.deadline, self.html_path = deadline, html_path
        self.buffer = b""
        self.next_id = 0

    def close(self) -> None:
        for fd in (self.write_fd, self.read_fd):
            try:
                os.close(fd)
            except OSError:
                pass

    def send(self, method: str, session: str | None = None, **params) -> int:
        self.next_id += 1
        message = {"id": self.next_id, "method": method, "params": params}
        if session:
            message["sessionId"] = session
        try:
            os.write(self.write_fd, json.dumps(message).encode("utf-8") + b"\0")
        except (BrokenPipeError, OSError):
            raise _PipeClosed() from None
        return self.next_id

    def call(self, method: str, session: str | None = None, **params) -> dict:
        """The result of one call (events read meanwhile are dropped)."""
        wanted = self.send(method, session, **params)
        while True:
            message = self._read()
            if message.get("id") == wanted:
                if "error" in message:
                    raise BrowserError(f"Chromium's DevTools refused {method}: "
                                       f"{message['error'].get('message', message['error'])}")
                return message.get("result", {})

    def _read(self) -> dict:
        while b"\0" not in self.buffer:
            left = self.deadline - time.monotonic()
            if left <= 0:
                raise _Late()
            ready, _, _ = select.select([self.read_fd], [], [], min(left, 1.0))
            if ready:
                chunk = os.read(self.read_fd, 1 << 16)
                if not chunk:
                    raise _PipeClosed()
                self.buffer += chunk
        message, self.buffer = self.buffer.split(b"\0", 1)
        return json.loads(message.decode("utf-8", "replace"))

    def dom_when_done(self) -> str:
        """The page's DOM once its title is one of :data:`DONE_TITLES`; BrowserError naming
        the page's title and the errors it reported when that has not happened by the
        deadline."""
        session = None
        while session is None:  # the one page Chromium opened, once it has its file:// URL
            for target in self.call("Target.getTargets").get("targetInfos", []):
                if target.get("type") == "page" and target.get("url", "").startswith("file:"):
                    session = self.call("Target.attachToTarget", targetId=target["targetId"],
                                        flatten=True)["sessionId"]
                    break
            else:
                self._sleep()
        try:
            while self._evaluate(session, "document.title") not in DONE_TITLES:
                self._sleep()
        except _Late:
            self.deadline = time.monotonic() + 10   # time to read what the page left
            title, errors, _ = parse_dom(self._evaluate(session, OUTER_HTML) or "")
            raise BrowserError(f"{self.html_path} did not finish in the time given (title "
                               f"{title!r}): " + ("; ".join(errors) or "no error reported"),
                               errors, title) from None
        return self._evaluate(session, OUTER_HTML) or ""

    def _evaluate(self, session: str, expression: str):
        """The value of *expression* in the page; None while the page has no context to
        evaluate it in (it is being navigated or replaced: the next poll asks again)."""
        try:
            result = self.call("Runtime.evaluate", session, expression=expression,
                               returnByValue=True)
        except BrowserError:
            return None
        return result.get("result", {}).get("value")

    def _sleep(self) -> None:
        if time.monotonic() + _POLL_S > self.deadline:
            raise _Late()
        time.sleep(_POLL_S)


def _kill_group(process: subprocess.Popen) -> None:
    """End what is left of the process group this module started for Chromium."""
    try:
        os.killpg(process.pid, signal.SIGKILL)
    except (ProcessLookupError, PermissionError, OSError):
        pass
