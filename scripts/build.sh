#!/usr/bin/env bash
# Configures and builds paramorph (Release) into ${PARAMORPH_BUILD_DIR:-build}.
# Usage: scripts/build.sh [TARGET...]   (default: every target; e.g. paramorph_native)
# PARAMORPH_BUILD_JOBS sets the parallel jobs (default: nproc).
#
# By default the module is built for Debian's /usr/bin/python3 (3.11, the
# Python Debian's Blender and bpy 4.5 embed) with Debian's pybind11.
# PARAMORPH_PYTHON=3.13 (a version, found on PATH, in pyenv or /usr/bin; or an
# interpreter's path) builds it for that Python instead, with PyPI's pybind11
# (>= 2.13, which reads NumPy 2 arrays; Debian 12's 2.10 does not) from
# .venv-cp313, which this creates with pybind11, NumPy 2 and pytest (so it
# also runs tests/native), into build-cp313 unless PARAMORPH_BUILD_DIR says
# otherwise; rebuilding that folder later keeps its Python (PARAMORPH_BUILD_DIR
# alone is enough). The C++ tests do not depend on Python: that build leaves them to
# the default one. E.g. for Blender 5.x / bpy 5.2:
#   PARAMORPH_PYTHON=3.13 scripts/build.sh
#   PARAMORPH_BUILD_DIR=build-cp313 .venv-cp313/bin/python -m pytest tests/native -q -p no:cacheprovider
set -euo pipefail
cd "$(dirname "$0")/.."
source scripts/python-for.sh

# ccache (when installed) shares objects with the release's wheel build and
# between build directories.
launcher=()
command -v ccache >/dev/null && launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache)
# Paths inside the checkout hashed relative to it: another clone (CI's) hits.
export CCACHE_BASEDIR=${CCACHE_BASEDIR:-$PWD}

# A build folder made for another Python keeps it: rebuilding build-cp313
# (PARAMORPH_BUILD_DIR=build-cp313 scripts/build.sh, as the scripts that
# build before they run do) must not turn it into a Debian-Python build.
cached_python() {
  sed -n 's/^Python3_EXECUTABLE:[A-Z]*=//p' "$1/CMakeCache.txt" 2>/dev/null || true
}
if [ -z "${PARAMORPH_PYTHON:-}" ] && [ -n "${PARAMORPH_BUILD_DIR:-}" ]; then
  cached=$(cached_python "$PARAMORPH_BUILD_DIR")
  [ -z "$cached" ] || [ "$cached" = /usr/bin/python3 ] || PARAMORPH_PYTHON=$cached
fi

if [ -z "${PARAMORPH_PYTHON:-}" ]; then
  build_dir=${PARAMORPH_BUILD_DIR:-build}
  # Debian's Python is the one Debian's Blender embeds; a pyenv/venv python3 on
  # PATH would build a module Blender cannot load.
  python_args=(-DPython3_EXECUTABLE=/usr/bin/python3)
else
  interpreter=$(python_for "$PARAMORPH_PYTHON")
  tag=$("$interpreter" -c 'import sys; print(f"cp{sys.version_info[0]}{sys.version_info[1]}")')
  build_dir=${PARAMORPH_BUILD_DIR:-build-$tag}
  venv=.venv-$tag
  if ! "$venv/bin/python" -c 'import pybind11, numpy, pytest, sys; sys.exit(pybind11.version_info < (2, 13))' 2>/dev/null; then
    echo "build: creating $venv (PyPI pybind11 >= 2.13, numpy 2, pytest) with $interpreter"
    [ -x "$venv/bin/python" ] || "$interpreter" -m venv "$venv"
    "$venv/bin/python" -m pip install --quiet --upgrade pip
    "$venv/bin/python" -m pip install --quiet "pybind11>=2.13" "numpy>=2" pytest
  fi
  cached=$(cached_python "$build_dir")
  if [ -n "$cached" ] && [ "$cached" != "$PWD/$venv/bin/python" ]; then
    echo "build: $build_dir is configured for $cached, not $venv: choose another PARAMORPH_BUILD_DIR or remove it" >&2
    exit 1
  fi
  python_args=(-DPython3_EXECUTABLE="$PWD/$venv/bin/python"
               -Dpybind11_DIR="$("$venv/bin/python" -m pybind11 --cmakedir)"
               -DPARAMORPH_BUILD_TESTS=OFF)
fi

cmake -S . -B "$build_dir" -DCMAKE_BUILD_TYPE=Release "${python_args[@]}" "${launcher[@]}" >/dev/null
targets=()
[ $# -eq 0 ] || targets=(--target "$@")
cmake --build "$build_dir" -j"${PARAMORPH_BUILD_JOBS:-$(nproc)}" "${targets[@]}"
echo "paramorph: built $(ls "$build_dir"/python/paramorph_native*.so)"
