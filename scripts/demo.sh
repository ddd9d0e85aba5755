#!/usr/bin/env bash
# Installs what is missing, builds the module, and runs the demo in blender -b
# on the sample objects (blend_samples/make_samples.py), through the add-on's
# operators: Sphere Map (closed Suzanne), Isometric Unwrap (pinned disc; skipped
# with a message while the operator is not in this build), Segment Extremities
# (octopus), Detect Feature Regions (CAD part). Writes OUT_DIR/demo.blend and
# OUT_DIR/demo.png (Workbench render, regions coloured from their attribute),
# then runs the batch CLI once: OUT_DIR/octopus_sphere.obj, the octopus with
# its "Sphere" UVs; then the morph demo (scripts/demo_morph.py) and a batch
# morph; then the cut-and-paste demo (scripts/demo_paste.py: a boss copied
# from a CAD-like plate and pasted twice onto a curved body, OUT_DIR/paste.blend
# and OUT_DIR/paste.png) and a batch paste.   Usage: scripts/demo.sh [OUT_DIR]   (default: out)
set -euo pipefail
cd "$(dirname "$0")/.."
export PARAMORPH_BUILD_DIR=${PARAMORPH_BUILD_DIR:-build}
out=$(realpath -m "${1:-out}")
scripts/install-deps.sh
scripts/build.sh paramorph_native
blender -b --factory-startup --python-exit-code 1 --python scripts/demo_blender.py -- --out "$out"

# The batch CLI from the source tree: the module comes from the build folder
# (an installed add-on has it inside, see README "Batch CLI").
blender -b --factory-startup --python-exit-code 1 \
  --python-expr "import sys; sys.path.insert(0, '$(realpath "$PARAMORPH_BUILD_DIR")/python')" \
  --python addon/paramorph/cli.py -- sphere "$out/demo.blend" "$out/octopus_sphere.obj" --object Octopus

# The morph demo: Suzanne into a blob (Preview Matches, Morph To), saved to
# $out/morph.blend with frames rendered to $out/morph_####.png; then the same
# through the batch CLI, from the demo's objects: $out/octopus_to_blob.blend.
blender -b --factory-startup --python-exit-code 1 --python scripts/demo_morph.py -- --out "$out"
blender -b --factory-startup --python-exit-code 1 \
  --python-expr "import sys; sys.path.insert(0, '$(realpath "$PARAMORPH_BUILD_DIR")/python')" \
  --python addon/paramorph/cli.py -- morph "$out/demo.blend" "$out/morph.blend" \
  --source-object Octopus --target-object Blob --frames 24 -o "$out/octopus_to_blob.blend"

# The cut-and-paste demo: the boss of a CAD-like plate copied (Copy Feature)
# and pasted twice onto a curved body (Paste Feature): $out/paste.blend and
# $out/paste.png; then the same through the batch CLI onto the morph demo's blob:
# $out/boss_on_blob.blend.
blender -b --factory-startup --python-exit-code 1 --python scripts/demo_paste.py -- --out "$out"
blender -b --factory-startup --python-exit-code 1 \
  --python-expr "import sys; sys.path.insert(0, '$(realpath "$PARAMORPH_BUILD_DIR")/python')" \
  --python addon/paramorph/cli.py -- paste "$out/paste.blend" "$out/morph.blend" "$out/boss_on_blob.blend" \
  --source-object BossPlate --target-object Blob --select-ball -0.6,0,0.6,0.7 --at 0,0,2
