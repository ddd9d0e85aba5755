#!/usr/bin/env bash
# Installs what is missing, builds, and runs every test: C++ (CTest), the
# module (pytest), the Blender-side tests (pytest inside blender -b, and in
# the PyPI bpy 4.5 module when PyPI is reachable) and the one GUI test (a
# real Blender window under Xvfb).
set -euo pipefail
cd "$(dirname "$0")/.."
export PARAMORPH_BUILD_DIR=${PARAMORPH_BUILD_DIR:-build}
scripts/install-deps.sh
scripts/build.sh

echo "== C++ unit tests (ctest)"
ctest --test-dir "$PARAMORPH_BUILD_DIR" --output-on-failure -j2

echo "== native module tests (pytest)"
/usr/bin/python3 -m pytest tests/native -q -p no:cacheprovider

echo "== Blender tests (pytest inside blender -b)"
blender -b --factory-startup --python-exit-code 1 \
  --python tests/blender/run_pytest.py -- tests/blender -q

echo "== GUI test (blender in a window under xvfb-run)"
/usr/bin/python3 -m pytest tests/gui -q -p no:cacheprovider

echo "== Blender 4.5 tests (pytest with PyPI bpy)"
scripts/bpy-venv.sh
if [ -x .venv-bpy/bin/python ]; then
  .venv-bpy/bin/python -m pytest tests/blender -q -p no:cacheprovider
else
  echo "skipped: no .venv-bpy (scripts/bpy-venv.sh creates it)"
fi
