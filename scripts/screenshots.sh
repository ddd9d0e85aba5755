#!/bin/sh
# Regenerates the README's pictures (docs/screenshots/*.png) from the window
# tests (tests/gui, a real Blender window under Xvfb): the sidebar panel, a
# segmentation overlay and a paste in progress are what those tests see.
# Usage: scripts/screenshots.sh [pytest options]
set -e
cd "$(dirname "$0")/.."
PARAMORPH_SCREENSHOTS="$PWD/docs/screenshots" /usr/bin/python3 -m pytest tests/gui -q "$@"
ls -l docs/screenshots
