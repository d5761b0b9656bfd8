#!/usr/bin/env bash
# Phong Nodes developer entry point.
#   bash tools/phong.sh demo [options]   build the demo scenes and compare them (see: demo --help)
#   bash tools/phong.sh compare FILE.blend [options]   compare the scenes of a .blend (compare --help)
#   bash tools/phong.sh test [pytest options]
#   bash tools/phong.sh build [DIR]      DIR/<id>-<version>.zip (DIR: dist), validated by Blender's own tool
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

# The source tree is the package `phong_nodes` in the environment (a link in site-packages),
# so the CLI, the tests, the benchmarks and tools import it by name.
link_package() {
  local site
  site=$("$venv/bin/python" -c 'import sysconfig; print(sysconfig.get_paths()["purelib"])')
  if [ "$(readlink "$site/phong_nodes" 2>/dev/null)" != "$root" ]; then
    ln -sfn "$root" "$site/phong_nodes"
  fi
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

# three.js for the three.js peer renderer (core/threejs.py), the version pinned by
# tools/threejs/package-lock.json, installed with npm into a cache folder outside the repository
# ($PHONG_THREE_DIR, else ~/.cache/phong-nodes/three-<version>).  Optional: without npm it says
# so on one line and the rest of Phong Nodes works as before.
ensure_three() {
  local version=0.181.0
  local dir=${PHONG_THREE_DIR:-${XDG_CACHE_HOME:-$HOME/.cache}/phong-nodes/three-$version}
  if [ -n "${PHONG_THREE_DIR:-}" ]; then
    export PHONG_THREE_DIR
  fi
  if [ -f "$dir/node_modules/three/build/three.cjs" ]; then
    return 0
  fi
  if ! command -v npm >/dev/null 2>&1; then
    echo "three.js peer renderer unavailable: it needs nodejs/npm (sudo apt-get install -y nodejs npm)" >&2
    return 0
  fi
  echo "Installing three.js $version into $dir (npm ci)..." >&2
  mkdir -p "$dir"
  cp "$root/tools/threejs/package.json" "$root/tools/threejs/package-lock.json" "$dir/"
  if ! (cd "$dir" && npm ci --no-audit --no-fund --silent >&2); then
    echo "npm could not install three.js into $dir: the three.js peer renderer is unavailable" >&2
  fi
}

setup
link_package
ensure_three
"$venv/bin/python" "$root/tools/check_system.py"

case "$command" in
  setup) ;;
  demo) exec "$venv/bin/python" "$root/tools/phong.py" "$@" ;;
  compare) exec "$venv/bin/python" "$root/tools/phong.py" compare "$@" ;;
  test) cd "$root" && exec "$venv/bin/python" -m pytest "$@" ;;
  build) build "$@" ;;
  *) echo "unknown command '$command' (expected demo, compare, test, build or setup)" >&2; exit 2 ;;
esac
