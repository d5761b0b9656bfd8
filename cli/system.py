# SPDX-License-Identifier: GPL-3.0-or-later
"""Check that bpy can load, and name the Debian/Ubuntu package that is missing if not.

bpy links against X11 and OpenGL/EGL libraries that a minimal machine lacks;
Eevee renders headless through Mesa's EGL.  Exit 0 when all is there, 1 with
an ``apt-get install`` line otherwise.  ``--packages`` prints every Debian package that bpy
needs (one per line) without importing it: what CI installs when it runs as root.

The three.js peer renderer (``core/threejs.py``, ``core/browser.py``) also needs a Chromium to
render its pages and npm to install three.js; it is optional, so the check above ignores it.
``--browser-packages`` prints the Debian packages it lacks (one per line, nothing when all are
there: CI installs them too), ``--browser`` says what is missing on stderr and exits 1 then.

The Slurm test and benchmark start a one-node cluster (``phong cluster``, ``cli/cluster.py``) from Debian's
Slurm and MUNGE packages; ``--cluster-packages`` prints those it lacks (CI installs them).
"""

from __future__ import annotations

import ctypes.util
import os
import shutil
import subprocess
import sys

# Shared library -> Debian/Ubuntu package providing it.
PACKAGES = {
    "libX11.so.6": "libx11-6", "libXrender.so.1": "libxrender1", "libXfixes.so.3": "libxfixes3",
    "libXi.so.6": "libxi6", "libxkbcommon.so.0": "libxkbcommon0", "libXext.so.6": "libxext6",
    "libxcb.so.1": "libxcb1", "libSM.so.6": "libsm6", "libICE.so.6": "libice6",
    "libXxf86vm.so.1": "libxxf86vm1", "libGL.so.1": "libgl1", "libEGL.so.1": "libegl1",
    "libEGL_mesa.so.0": "libegl-mesa0", "libgbm.so.1": "libgbm1",
}
# Not linked, but loaded at run time for Eevee's software OpenGL.
RUNTIME = ("libEGL.so.1", "libEGL_mesa.so.0", "libGL.so.1")


def missing_from_message(message: str) -> list:
    return [lib for lib in PACKAGES if lib in message]


def all_packages() -> list:
    return sorted(set(PACKAGES.values()) | {"libgl1-mesa-dri"})


# The browsers core/browser.py looks for (after $PHONG_CHROMIUM); keep the two lists alike.
BROWSERS = ("chromium", "chromium-browser", "google-chrome")


def browser_packages() -> list:
    """Debian packages the three.js peer renderer lacks, judged by the commands on PATH (npm
    may come from outside dpkg): chromium without a browser, nodejs and npm without npm."""
    wanted = os.environ.get("PHONG_CHROMIUM")
    names = (wanted,) if wanted else BROWSERS
    missing = [] if any(shutil.which(name) for name in names) else ["chromium"]
    if shutil.which("npm") is None:
        missing += ["nodejs", "npm"]
    return missing


def browser_hint() -> str | None:
    """One line naming what the three.js peer renderer lacks and how to install it; None when
    Chromium and npm are both there."""
    packages = browser_packages()
    if not packages:
        return None
    needs = " and ".join((["Chromium"] if "chromium" in packages else [])
                         + (["nodejs/npm (to install three.js)"] if "npm" in packages else []))
    return (f"The three.js peer renderer needs {needs}: "
            f"sudo apt-get install -y {' '.join(packages)} && bash tools/phong.sh setup")


# The commands a one-node Slurm cluster needs (cli/cluster.py) -> Debian package.
CLUSTER_COMMANDS = {"slurmctld": "slurmctld", "slurmd": "slurmd", "sbatch": "slurm-client",
                    "scontrol": "slurm-client", "squeue": "slurm-client", "munged": "munge"}


def cluster_packages() -> list:
    """Debian packages that cli/cluster.py lacks, judged by the commands on PATH (daemons
    live in /usr/sbin, which a user's PATH may lack)."""
    path = os.pathsep.join([os.environ.get("PATH", ""), "/usr/sbin", "/sbin"])
    return sorted({package for command, package in CLUSTER_COMMANDS.items()
                   if shutil.which(command, path=path) is None})


def main() -> int:
    if sys.argv[1:] == ["--packages"]:
        print("\n".join(all_packages()))
        return 0
    if sys.argv[1:] == ["--browser-packages"]:
        for package in browser_packages():
            print(package)
        return 0
    if sys.argv[1:] == ["--cluster-packages"]:
        for package in cluster_packages():
            print(package)
        return 0
    if sys.argv[1:] == ["--browser"]:
        hint = browser_hint()
        if hint:
            print(hint, file=sys.stderr)
        return 1 if hint else 0
    probe = subprocess.run([sys.executable, "-c", "import bpy"], capture_output=True, text=True)
    missing = missing_from_message(probe.stderr) if probe.returncode else []
    if probe.returncode and not missing:
        print("bpy failed to import:\n" + probe.stderr.strip()[-2000:], file=sys.stderr)
        return 1
    for lib in RUNTIME:
        name = lib.split(".so")[0].removeprefix("lib")
        if ctypes.util.find_library(name) is None and lib not in missing:
            missing.append(lib)
    if missing:
        packages = " ".join(sorted({PACKAGES[lib] for lib in missing}))
        print(f"Missing system libraries: {', '.join(missing)}.\n"
              f"Install them with: sudo apt-get install -y {packages}"
              + (" libgl1-mesa-dri" if "libEGL_mesa.so.0" in missing else ""), file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
