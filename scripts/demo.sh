#!/usr/bin/env bash
# Installs what is missing, builds, and runs the demo in blender -b: sphere maps
# a generated mesh and a sample scene, writing .blend files with a "Sphere" UV
# layer and a "Sphere" shape key.   Usage: scripts/demo.sh [OUT_DIR]
set -euo pipefail
cd "$(dirname "$0")/.."
export PARAMORPH_BUILD_DIR=${PARAMORPH_BUILD_DIR:-build}
out=$(realpath -m "${1:-out}")
scripts/install-deps.sh
scripts/build.sh
blender -b --factory-startup --python-exit-code 1 --python scripts/demo_blender.py -- --out "$out"
