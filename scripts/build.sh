#!/usr/bin/env bash
# Configures and builds paramorph (Release) into ${PARAMORPH_BUILD_DIR:-build}.
# Usage: scripts/build.sh [TARGET...]   (default: every target; e.g. paramorph_native)
# PARAMORPH_BUILD_JOBS sets the parallel jobs (default: nproc).
set -euo pipefail
cd "$(dirname "$0")/.."
build_dir=${PARAMORPH_BUILD_DIR:-build}
# Debian's Python is the one Debian's Blender embeds; a pyenv/venv python3 on
# PATH would build a module Blender cannot load.
# ccache (when installed) shares objects with the release's wheel build.
launcher=()
command -v ccache >/dev/null && launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache)
cmake -S . -B "$build_dir" -DCMAKE_BUILD_TYPE=Release -DPython3_EXECUTABLE=/usr/bin/python3 "${launcher[@]}" >/dev/null
targets=()
[ $# -eq 0 ] || targets=(--target "$@")
cmake --build "$build_dir" -j"${PARAMORPH_BUILD_JOBS:-$(nproc)}" "${targets[@]}"
echo "paramorph: built $(ls "$build_dir"/python/paramorph_native*.so)"
