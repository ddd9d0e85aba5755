#!/usr/bin/env bash
# Installs what is missing, builds, and runs every test: C++ (CTest), the
# module (pytest), a bounded fuzz run of the module (tests/fuzz), the
# Blender-side tests (pytest inside blender -b; the one GUI test, a real
# Blender window under Xvfb) and, when PyPI is reachable, the release and
# every Blender it is for: the manylinux_2_28 wheels for CPython 3.11 and 3.13
# and the extension (scripts/release.sh; its static dependencies build
# beside the tests, at the lowest priority), tests/blender in PyPI bpy 4.5
# (CPython 3.11) and bpy 5.2 (3.13) with the release installed from the zip,
# and the wheels in fresh Debian 11, 12 and 13 roots (scripts/prove-portable.sh).
set -euo pipefail
cd "$(dirname "$0")/.."
export PARAMORPH_BUILD_DIR=${PARAMORPH_BUILD_DIR:-build}
stage() { echo "== $* [$(date -u +%T), $((SECONDS / 60)) min in]"; }
scripts/install-deps.sh
scripts/build.sh

# The release's static dependencies (scripts/manylinux/build.sh --deps-only:
# about 20 minutes of two cores the first time on a machine, then kept under
# ~/.cache/paramorph/manylinux) build while the tests run, at nice 19.
mkdir -p out
deps_log=$PWD/out/manylinux-deps.log
nice -n 19 scripts/manylinux/build.sh --deps-only > "$deps_log" 2>&1 &
deps_pid=$!
trap 'kill "$deps_pid" 2>/dev/null || true' EXIT

stage "C++ unit tests (ctest)"
ctest --test-dir "$PARAMORPH_BUILD_DIR" --output-on-failure -j2

stage "native module tests (pytest)"
/usr/bin/python3 -m pytest tests/native -q -p no:cacheprovider

stage "fuzz: the driver's own tests, then a bounded run (tests/fuzz; README, Fuzzing)"
/usr/bin/python3 -m pytest tests/fuzz -q -p no:cacheprovider
# The gate gives the same verdict for the same commit on any day: every past
# finding's case file (tests/fuzz/findings) replayed, then fixed seeds with a
# fixed number of cases each (about 1.5 minutes; --seconds is only a cap that
# a sane run never reaches). New cases from the day's seed are
# scripts/fuzz-daily.sh's job, outside the gate. Each run prints its seed,
# and a finding its case file and replay command.
fuzz_status=0
/usr/bin/python3 tests/fuzz/fuzz.py --replay tests/fuzz/findings --call-timeout 20 --out out/fuzz/replay || fuzz_status=1
for seed in 0 1 2 3 4 5; do
  /usr/bin/python3 tests/fuzz/fuzz.py --cases 4000 --seconds 900 --call-timeout 20 --seed "$seed" \
    --out "out/fuzz/seed-$seed" || fuzz_status=1
done
[ "$fuzz_status" -eq 0 ] || { echo "fuzz: findings above (case files under out/fuzz)"; exit 1; }

stage "Blender tests (pytest inside blender -b)"
blender -b --factory-startup --python-exit-code 1 \
  --python tests/blender/run_pytest.py -- tests/blender -q

stage "GUI test (blender in a window under xvfb-run)"
/usr/bin/python3 -m pytest tests/gui -q -p no:cacheprovider

stage "PyPI bpy 4.5 and 5.2 (scripts/bpy-venv.sh)"
scripts/bpy-venv.sh
scripts/bpy-venv.sh 5.2
if [ -x .venv-bpy/bin/python ] && [ -x .venv-bpy52/bin/python ]; then
  stage "release: waiting for the static dependencies"
  wait "$deps_pid" || { tail -n 40 "$deps_log"; echo "the release's dependencies failed: $deps_log"; exit 1; }
  tail -n 12 "$deps_log"
  stage "release: manylinux_2_28 wheels for CPython 3.11 and 3.13 and the extension (scripts/release.sh)"
  PARAMORPH_RELEASE_PYTHONS="3.11 3.13" scripts/release.sh
  # tests/blender in Blender 4.5 (CPython 3.11, the development build) and in
  # Blender 5.2 (3.13, the release's own cp313 module): the release
  # extension's install test must run, not skip, in both.
  stage "Blender 4.5 tests (pytest with PyPI bpy 4.5)"
  PARAMORPH_REQUIRE_RELEASE=1 .venv-bpy/bin/python -m pytest tests/blender -q -p no:cacheprovider
  stage "Blender 5.2 tests (pytest with PyPI bpy 5.2)"
  rm -rf build-release-cp313 && mkdir -p build-release-cp313/python
  /usr/bin/python3 -m zipfile -e "$(ls dist/paramorph-*-cp313-cp313-manylinux_2_28_x86_64.whl)" build-release-cp313/python
  PARAMORPH_BUILD_DIR=build-release-cp313 PARAMORPH_REQUIRE_RELEASE=1 \
    .venv-bpy52/bin/python -m pytest tests/blender -q -p no:cacheprovider
  if [ "$(id -u)" -eq 0 ]; then
    stage "the wheels in fresh minimal Debian 11, 12 and 13 roots (scripts/prove-portable.sh --tests quick)"
    scripts/prove-portable.sh --tests quick --no-blender  # the install tests ran above
  else
    echo "skipped: scripts/prove-portable.sh needs root (debootstrap, chroot)"
  fi
else
  echo "skipped: no .venv-bpy or .venv-bpy52 (scripts/bpy-venv.sh creates them; it needs PyPI)"
fi
stage "done"
