# SPDX-License-Identifier: GPL-3.0-or-later
"""Where outputs may go, and how they appear there: whole or not at all.

Pure python (no ``bpy``): the bake, the report and the headless command use it.

* :func:`output_problem` says why a folder cannot take outputs: it lies inside the
  extension's own folder, or it cannot be created or written.
* Unfinished work lives in hidden entries named ``.<kind>-<name>.<host>.<pid>.<random>``
  beside the destination; :func:`replace_dir` renames a finished folder into place with
  SIGINT / SIGTERM held back, so no signal leaves the destination missing.
* :func:`clean_stale` removes the hidden entries of killed runs (this host, process gone),
  so the next run starts clean; entries of live runs (other shards) are left alone.
* :func:`clean_name`, :func:`distinct` (a run's scene folders), :func:`safe_name` /
  :func:`safe_names` (files that pile up in one folder): Blender names as file names that
  no other name shares.
"""

from __future__ import annotations

import hashlib
import os
import platform
import re
import shutil
import signal
import tempfile

#: The extension's own folder (installed package or source tree): never an output.
PACKAGE_DIR = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
KINDS = ("partial", "old", "index")
_STALE = re.compile(r"^\.(%s)-[^.]*\.([A-Za-z0-9_-]+)\.(\d+)\." % "|".join(KINDS))


_UNSAFE = re.compile(r"[^A-Za-z0-9_.-]+")


def clean_name(name: str, default: str) -> str:
    """*name* as a file or folder name: characters other than letters, digits, ``_``, ``.``
    and ``-`` become ``_`` (*default* when nothing is left)."""
    return _UNSAFE.sub("_", name).strip("._") or default


def distinct(stems) -> list:
    """*stems* in order, a later one equal to an earlier one (but for case: one folder on
    Windows and macOS) followed by ``_`` until it is free: the scene folders of a run."""
    taken, out = set(), []
    for stem in stems:
        while stem.lower() in taken:
            stem += "_"
        taken.add(stem.lower())
        out.append(stem)
    return out


def safe_name(name: str, default: str = "object") -> str:
    """:func:`clean_name`, and a name so changed gets ``-`` and the first 6 hex digits of
    the SHA-1 of its exact UTF-8 text, so names never share a file across runs either
    ("Cube 1" and "Cube/1" both clean to "Cube_1")."""
    stem = clean_name(name, default)
    if stem != name:
        stem += "-" + hashlib.sha1(name.encode("utf-8")).hexdigest()[:6]
    return stem


def safe_names(names, default: str = "object") -> dict:
    """{name: :func:`safe_name`} for *names*, where names equal but for case also get the
    hash (files that pile up in one folder: the bake's images)."""
    names = list(names)
    stems = {name: safe_name(name, default) for name in names}
    folded = {}
    for stem in stems.values():
        folded[stem.lower()] = folded.get(stem.lower(), 0) + 1
    for name, stem in stems.items():
        if folded[stem.lower()] > 1 and stem == name:
            stems[name] = stem + "-" + hashlib.sha1(name.encode("utf-8")).hexdigest()[:6]
    return stems


def _host() -> str:
    return re.sub(r"[^A-Za-z0-9_-]", "_", platform.node().split(".")[0]) or "host"


def temp_prefix(kind: str, name: str) -> str:
    """Prefix of a hidden temporary entry owned by this process."""
    return f".{kind}-{name}.{_host()}.{os.getpid()}."


def inside_package(folder: str) -> bool:
    real, package = os.path.realpath(folder), os.path.realpath(PACKAGE_DIR)
    return os.path.commonpath([real, package]) == package


def output_problem(folder: str, refuse_package: bool = True) -> str | None:
    """None when *folder* can take outputs (it is created if missing), else why not."""
    if refuse_package and inside_package(folder):
        return (f"output folder {folder} is inside the extension's own folder "
                f"{os.path.realpath(PACKAGE_DIR)}; choose another folder")
    try:
        os.makedirs(folder, exist_ok=True)
        fd, probe = tempfile.mkstemp(prefix=temp_prefix("partial", "probe"), dir=folder)
        os.close(fd)
        os.remove(probe)
    except OSError as error:
        return f"cannot write to output folder {folder}: {error.strerror or error}"
    return None


def _alive(pid: int) -> bool:
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except OSError:
        return True
    return True


def clean_stale(folder: str) -> list:
    """Remove the hidden temporary entries of dead processes of this host; returns them."""
    removed = []
    if not os.path.isdir(folder):
        return removed
    host = _host()
    for name in sorted(os.listdir(folder)):
        match = _STALE.match(name)
        if not match or match.group(2) != host or _alive(int(match.group(3))):
            continue
        path = os.path.join(folder, name)
        if os.path.isdir(path) and not os.path.islink(path):
            shutil.rmtree(path, ignore_errors=True)
        else:
            try:
                os.remove(path)
            except OSError:
                continue
        removed.append(name)
    return removed


def write_file(path: str, data) -> str:
    """Write *data* (text, as UTF-8 with LF line ends, or bytes) to *path* atomically: a
    hidden temporary file beside it (``clean_stale`` knows its name) is renamed over *path*
    once complete; on an error it is removed and *path* is left as it was."""
    folder = os.path.dirname(os.path.abspath(path))
    name = os.path.basename(path).replace(".", "_")
    fd, tmp = tempfile.mkstemp(prefix=temp_prefix("partial", name), dir=folder)
    try:
        with os.fdopen(fd, "wb") as handle:
            handle.write(data.encode("utf-8") if isinstance(data, str) else data)
        os.chmod(tmp, 0o644)
        os.replace(tmp, path)
    except BaseException:
        if os.path.exists(tmp):
            os.remove(tmp)
        raise
    return path


def replace_dir(tmp: str, final: str) -> None:
    """Move the finished *tmp* folder to *final* (an older *final* is removed), with SIGINT
    and SIGTERM held back meanwhile: *final* is never missing nor half-written."""
    blocked = {signal.SIGINT, signal.SIGTERM}
    old_mask = signal.pthread_sigmask(signal.SIG_BLOCK, blocked)
    trash = None
    try:
        os.chmod(tmp, 0o755)
        if os.path.exists(final):
            trash = tempfile.mkdtemp(prefix=temp_prefix("old", os.path.basename(final)),
                                     dir=os.path.dirname(os.path.abspath(final)))
            os.rename(final, os.path.join(trash, "old"))
        os.rename(tmp, final)
    finally:
        signal.pthread_sigmask(signal.SIG_SETMASK, old_mask)
    if trash is not None:
        shutil.rmtree(trash, ignore_errors=True)
