#!/usr/bin/env bash
# Phong Nodes developer entry point.
#   bash tools/phong.sh demo [options]   render the demo (see: demo --help)
#   bash tools/phong.sh test [pytest options]
#   bash tools/phong.sh setup            only create/refresh the virtual environment
# The virtual environment lives in .venv (or $PHONG_VENV) and is rebuilt when
# requirements.txt changes.  PHONG_BPY=4.2.23 (or 4.5.15, ...) uses that bpy release
# instead, in its own .venv-bpy<version>: how CI checks the older LTS releases.
set -euo pipefail

root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
requirements=$root/requirements.txt
venv=${PHONG_VENV:-$root/.venv}
if [ -n "${PHONG_BPY:-}" ]; then
  venv=${PHONG_VENV:-$root/.venv-bpy$PHONG_BPY}
  mkdir -p "$venv"
  requirements=$venv/requirements.txt
  sed "s/^bpy==.*/bpy==$PHONG_BPY/" "$root/requirements.txt" > "$requirements"
fi
command=${1:-demo}
[ $# -gt 0 ] && shift

find_python() {
  for candidate in python3.11 python3; do
    if command -v "$candidate" >/dev/null 2>&1 &&
       "$candidate" -c 'import sys; sys.exit(sys.version_info[:2] != (3, 11))' 2>/dev/null; then
      echo "$candidate"; return 0
    fi
  done
  echo "Phong Nodes needs Python 3.11 (the bpy 5.0.1 wheel is built for it)." >&2
  echo "On Debian/Ubuntu: install python3.11 and python3.11-venv." >&2
  return 1
}

setup() {
  local stamp="$venv/.requirements.sha256"
  local want
  want=$(sha256sum "$requirements" | cut -d' ' -f1)
  if [ -x "$venv/bin/python" ] && [ "$(cat "$stamp" 2>/dev/null)" = "$want" ]; then
    return 0
  fi
  local python
  python=$(find_python)
  echo "Setting up $venv (Python packages from requirements.txt)..." >&2
  if ! "$python" -m venv "$venv"; then
    echo "Could not create a virtual environment: on Debian/Ubuntu install python3.11-venv." >&2
    exit 1
  fi
  "$venv/bin/python" -m pip install --quiet --upgrade pip >&2
  "$venv/bin/python" -m pip install --quiet -r "$requirements" >&2
  echo "$want" > "$stamp"
}

setup
"$venv/bin/python" "$root/tools/check_system.py"

case "$command" in
  setup) ;;
  demo) exec "$venv/bin/python" "$root/tools/phong.py" "$@" ;;
  test) cd "$root" && exec "$venv/bin/python" -m pytest "$@" ;;
  *) echo "unknown command '$command' (expected demo, test or setup)" >&2; exit 2 ;;
esac
