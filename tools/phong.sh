#!/usr/bin/env bash
# Phong Nodes: set up the project's environment, then run a command in it.
#   bash tools/phong.sh demo|compare|apply|bake|report|slurm|cluster ...   the `phong` command of the
#                                        environment (phong --help; phong demo --help ...)
#   bash tools/phong.sh test [pytest options]   the quick tests: those not marked slow, on
#                                        $PHONG_TEST_WORKERS processes (default 2; pytest-xdist,
#                                        a test file per process); given test paths
#                                        (tests/..., a ::node id) it runs just those, all of them
#   bash tools/phong.sh test --all [pytest options]   every test, in one process (CI runs the
#                                        quick command, then `test --all -m slow`)
#   bash tools/phong.sh build [DIR]      DIR/<id>-<version>.zip (DIR: dist), validated by Blender's own tool
#   bash tools/phong.sh setup            only create/refresh the virtual environment
#   bash tools/phong.sh which            print the bpy release and Python it would use, change nothing
#   bash tools/phong.sh releases [FLAG]  the supported bpy releases (with FLAG, e.g. ci: those flagged)
# Which Blender: the supported releases are requirements/releases.txt, one list; without
# PHONG_BPY the `default` release of Python 3.13 where a Python 3.13 exists (on PATH, or one of
# pyenv's interpreters), else the default of Python 3.11.  PHONG_BPY=4.2.23 (any bpy release,
# listed or not) uses that release instead, on the Python its wheels are built for, in its own
# .venv-bpy<version>; PHONG_PYTHON=/path/to/python picks the interpreter.  The pins beside bpy
# are requirements/python<a.b>.txt.  The default environment is .venv (or $PHONG_VENV), rebuilt
# when its pins or interpreter change.
set -euo pipefail

root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
releases_file=$root/requirements/releases.txt
command=${1:-demo}
[ $# -gt 0 ] && shift

# The supported releases: "bpy python flags..." lines of releases.txt, comments left out.
releases() {
  sed -e 's/#.*//' -e '/^[[:space:]]*$/d' "$releases_file"
}

# The bpy releases flagged $1 (all without $1), newest first.
releases_flagged() {
  releases | awk -v flag="${1:-}" '{ for (i = 3; i <= NF; i++) if ($i == flag) { print $1; next } } flag == "" { print $1 }'
}

# The default release of Python $1 (e.g. 3.13): the one flagged `default` on that Python.
default_for_python() {
  releases | awk -v py="$1" '$2 == py { for (i = 3; i <= NF; i++) if ($i == "default") { print $1; exit } }'
}

# The Python a.b that bpy release $1 is built for: its line in releases.txt; a release not
# listed by Blender's rule (5.1 and later need 3.13, 4.2 to 5.0 need 3.11).
python_for_bpy() {
  local listed
  listed=$(releases | awk -v bpy="$1" '$1 == bpy { print $2; exit }')
  if [ -n "$listed" ]; then
    echo "$listed"; return 0
  fi
  case "$1" in
    4.*|5.0|5.0.*) echo 3.11 ;;
    5.*|[6-9].*) echo 3.13 ;;
    *) echo "PHONG_BPY=$1: not a bpy release (expected one of: $(releases_flagged | tr '\n' ' ' | sed 's/ $//'))" >&2
       return 1 ;;
  esac
}

if [ "$command" = releases ]; then
  releases_flagged "${1:-}"
  exit 0
fi

# An interpreter of Python $1 (e.g. 3.13) that runs: python$1 on PATH, then pyenv's (its shims
# refuse a version that is not selected, so its versions folder is searched too), then python3.
find_python() {
  local want=$1 candidate
  local candidates=("python$want")
  candidates+=($(ls -d "${PYENV_ROOT:-$HOME/.pyenv}"/versions/"$want"*/bin/python"$want" 2>/dev/null | sort -V -r))
  candidates+=(python3)
  for candidate in "${candidates[@]}"; do
    if command -v "$candidate" >/dev/null 2>&1 &&
       "$candidate" -c "import sys; sys.exit(sys.version_info[:2] != tuple(map(int, '$want'.split('.'))))" \
         >/dev/null 2>&1; then
      command -v "$candidate"; return 0
    fi
  done
  return 1
}

# Choose the release, its Python and its environment.
if [ -n "${PHONG_BPY:-}" ]; then
  pyver=$(python_for_bpy "$PHONG_BPY") || exit 2
  venv=${PHONG_VENV:-$root/.venv-bpy$PHONG_BPY}
  python=${PHONG_PYTHON:-$(find_python "$pyver" || true)}
  if [ -z "$python" ]; then
    echo "bpy $PHONG_BPY needs Python $pyver, which this machine lacks: install python$pyver and python$pyver-venv (or pyenv install $pyver)" >&2
    exit 2
  fi
  bpy_pin=$PHONG_BPY
  reason="PHONG_BPY"
else
  newest=$(default_for_python 3.13)
  older=$(default_for_python 3.11)
  venv=${PHONG_VENV:-$root/.venv}
  if [ -n "${PHONG_PYTHON:-}" ]; then
    python=$PHONG_PYTHON
    pyver=$("$python" -c 'import sys; print("%d.%d" % sys.version_info[:2])') || exit 2
    reason="PHONG_PYTHON"
  elif python=$(find_python 3.13); then
    pyver=3.13; reason="Python 3.13 found"
  elif python=$(find_python 3.11); then
    pyver=3.11; reason="no Python 3.13 found"
  else
    echo "Phong Nodes needs Python 3.13 (bpy $newest) or Python 3.11 (bpy $older): install python3.13 and python3.13-venv (Debian 13; elsewhere pyenv install 3.13)" >&2
    exit 2
  fi
  bpy_pin=$(default_for_python "$pyver")
  if [ -z "$bpy_pin" ] || [ ! -f "$root/requirements/python$pyver.txt" ]; then
    echo "PHONG_PYTHON=$python is Python $pyver; Phong Nodes runs on Python 3.13 (bpy $newest) or 3.11 (bpy $older)" >&2
    exit 2
  fi
fi
pins=$(printf 'bpy==%s\n%s\n' "$bpy_pin" "$(cat "$root/requirements/python$pyver.txt")")
choice="bpy $bpy_pin on Python $pyver ($python; $reason)"
if [ "$command" = which ]; then
  echo "$choice"
  exit 0
fi
echo "Phong Nodes: $choice" >&2

# How the messages name a path: relative to the repository where it lies inside it.
shown() {
  case "$1" in
    "$root"/*) echo "${1#"$root"/}" ;;
    *) echo "$1" ;;
  esac
}

# pip's own output (its progress, and the build backend's notes on `pip install -e .`) goes to
# $venv/pip.log, read back to the terminal only when pip fails.
pip_logged() {
  local log="$venv/pip.log"
  if ! "$venv/bin/python" -m pip "$@" >>"$log" 2>&1; then
    echo "pip install failed ($(shown "$log"), its last lines):" >&2
    tail -n 40 "$log" >&2
    exit 1
  fi
}

setup() {
  local stamp="$venv/.requirements.sha256"
  local want
  want=$(printf '%s\n%s\n' "$pins" "$python" | sha256sum | cut -d' ' -f1)
  if [ -x "$venv/bin/python" ] && [ "$(cat "$stamp" 2>/dev/null)" = "$want" ]; then
    return 0
  fi
  echo "Setting up $(shown "$venv") (bpy $bpy_pin and the pins of requirements/python$pyver.txt): about a minute..." >&2
  if ! "$python" -m venv --clear "$venv" >&2; then
    echo "Could not create a virtual environment with $python: on Debian/Ubuntu install python$pyver-venv." >&2
    exit 1
  fi
  pip_logged install --upgrade pip
  printf '%s\n' "$pins" > "$venv/requirements.txt"
  pip_logged install -r "$venv/requirements.txt"
  echo "$want" > "$stamp"
}

# The source tree is the package `phong_nodes` in the environment (`pip install -e .`, which
# also installs the `phong` command), so the CLI, the tests, the benchmarks and tools import it
# by name.  Done again when the environment's package is another checkout's.
install_package() {
  if [ -x "$venv/bin/phong" ] && "$venv/bin/python" - "$root" <<'PY' 2>/dev/null
import os, sys
import phong_nodes
sys.exit(os.path.dirname(os.path.realpath(phong_nodes.__file__)) != os.path.realpath(sys.argv[1]))
PY
  then
    return 0
  fi
  # an environment made by an earlier version holds the tree as a link in site-packages
  local site
  site=$("$venv/bin/python" -c 'import sysconfig; print(sysconfig.get_paths()["purelib"])')
  [ -L "$site/phong_nodes" ] && rm -f "$site/phong_nodes"
  echo "Installing this tree into $(shown "$venv") as the package phong_nodes (pip install -e .)..." >&2
  pip_logged install --no-deps -e "$root"
}

build() {
  local tool out=${1:-$root/dist}
  tool=$("$venv/bin/python" -c 'import bpy, os; print(os.path.join(bpy.utils.resource_path("LOCAL"), "scripts/addons_core/bl_pkg/cli/blender_ext.py"))')
  mkdir -p "$out"
  "$venv/bin/python" "$tool" validate "$root"
  "$venv/bin/python" "$tool" build --source-dir "$root" --output-dir "$out"
  local zip
  zip=$(ls -t "$out"/*.zip | head -n 1)
  "$venv/bin/python" "$tool" validate "$zip"
  echo "$zip"
}

# An npm package a peer renderer loads in Chromium, the version pinned by tools/<tool>/
# package-lock.json, installed with npm into a cache folder outside the repository ($<variable>,
# else ~/.cache/phong-nodes/<package>-<version>; core/browser.py's package_dir).  Optional:
# without npm it says so on one line and the rest of Phong Nodes works as before.
#   ensure_npm_package LABEL TOOL PACKAGE VERSION VARIABLE FILE-IN-PACKAGE
ensure_npm_package() {
  local label=$1 tool=$2 package=$3 version=$4 variable=$5 file=$6
  local dir=${!variable:-${XDG_CACHE_HOME:-$HOME/.cache}/phong-nodes/$package-$version}
  if [ -n "${!variable:-}" ]; then
    export "${variable?}"
  fi
  if [ -f "$dir/node_modules/$package/$file" ]; then
    return 0
  fi
  if ! command -v npm >/dev/null 2>&1; then
    echo "$label peer renderer unavailable: it needs nodejs/npm (sudo apt-get install -y nodejs npm)" >&2
    return 0
  fi
  echo "Installing $label $version into $dir (npm ci)..." >&2
  mkdir -p "$dir"
  cp "$root/tools/$tool/package.json" "$root/tools/$tool/package-lock.json" "$dir/"
  if ! (cd "$dir" && npm ci --no-audit --no-fund --silent >&2); then
    echo "npm could not install $label into $dir: the $label peer renderer is unavailable" >&2
  fi
}

# three.js for the three.js peer renderer (core/threejs.py)
ensure_three() {
  ensure_npm_package three.js threejs three 0.181.0 PHONG_THREE_DIR build/three.cjs
}

# X_ITE for the X_ITE peer renderer (core/x_ite.py)
ensure_x_ite() {
  ensure_npm_package X_ITE x_ite x_ite 15.0.1 PHONG_X_ITE_DIR dist/x_ite.min.js
}

# The pytest arguments of `test ARGS`: --all: ARGS, every test, in one process; test paths in
# ARGS (tests/..., a ::node id, a .py file): ARGS, those tests whatever their marks; else the
# quick tests: -m "not slow" on $PHONG_TEST_WORKERS processes (default 2), each test file in one
# process (its module fixtures are made once), then ARGS (a later -m or -n of ARGS wins).
# README.md's "Tests" says what runs where.
test_arguments() {
  local arg
  if [ "${1:-}" = --all ]; then
    shift; test_args=("$@"); return 0
  fi
  for arg in "$@"; do
    case "$arg" in
      tests/*|*::*|*.py) test_args=("$@"); return 0 ;;
    esac
  done
  test_args=(-m "not slow" -n "${PHONG_TEST_WORKERS:-2}" --dist loadfile "$@")
}

setup
install_package
ensure_three
ensure_x_ite
"$venv/bin/python" "$root/cli/system.py"

case "$command" in
  setup) ;;
  demo|compare|apply|bake|report|slurm|cluster) exec "$venv/bin/phong" "$command" "$@" ;;
  test) test_arguments "$@"; cd "$root" && exec "$venv/bin/python" -m pytest "${test_args[@]}" ;;
  build) build "$@" ;;
  *) echo "unknown command '$command' (expected demo, compare, apply, bake, report, slurm, cluster, test, build, setup or which)" >&2; exit 2 ;;
esac
