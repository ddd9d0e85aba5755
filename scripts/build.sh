#!/usr/bin/env bash
# Configures and builds paramorph (Release) into ${PARAMORPH_BUILD_DIR:-build}.
set -euo pipefail
cd "$(dirname "$0")/.."
build_dir=${PARAMORPH_BUILD_DIR:-build}
# Debian's Python is the one Debian's Blender embeds; a pyenv/venv python3 on
# PATH would build a module Blender cannot load.
cmake -S . -B "$build_dir" -DCMAKE_BUILD_TYPE=Release -DPython3_EXECUTABLE=/usr/bin/python3 >/dev/null
cmake --build "$build_dir" -j"$(nproc)"
echo "paramorph: built $(ls "$build_dir"/python/paramorph_native*.so)"
