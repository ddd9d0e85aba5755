#!/usr/bin/env bash
# Installs what is missing, builds, and runs every test: C++ (CTest), the
# module (pytest), a bounded fuzz run of the module (tests/fuzz), the
# Blender-side tests (pytest inside blender -b; the one GUI test, a real
# Blender window under Xvfb) and, when PyPI is reachable, the release and
# every Blender it is for: the manylinux_2_28 wheels for CPython 3.11 and 3.13
# and the extension (scripts/release.sh; the modules and their static
# dependencies build beside the tests, at the lowest priority), then at once
# tests/blender in PyPI bpy 4.5 (CPython 3.11) and bpy 5.2 (3.13) with the
# release installed from the zip, and the wheels in fresh Debian 11, 12 and
# 13 roots (scripts/prove-portable.sh).
set -euo pipefail
cd "$(dirname "$0")/.."
export PARAMORPH_BUILD_DIR=${PARAMORPH_BUILD_DIR:-build}
stage() { echo "== $* [$(date -u +%T), $((SECONDS / 60)) min in]"; }
scripts/install-deps.sh
mkdir -p out
# The Debian 11, 12 and 13 roots the wheels are proven in, with their
# Pythons (debootstrap, and CPython 3.11 built for Debian 11; cached under
# /var/tmp/paramorph-roots): mostly downloads, so from the start, beside all
# the rest, at the lowest priority.
background=()  # process groups an early exit stops
trap 'for pid in "${background[@]}"; do kill -- -"$pid" 2>/dev/null || true; done' EXIT
roots_pid=
if [ "$(id -u)" -eq 0 ]; then
  setsid nice -n 19 scripts/prove-portable.sh --prepare > out/portable-prepare.log 2>&1 &
  roots_pid=$!
  background+=("$roots_pid")
fi
scripts/build.sh

# Beside the tests, at nice 19 and each in its own process group (so an
# early exit stops them whole): the release's manylinux_2_28 modules for
# CPython 3.11 and 3.13 (scripts/manylinux/build.sh: its static
# dependencies, about 15 minutes of two cores the first time on a machine and
# then kept under ~/.cache/paramorph/manylinux, then the modules, which
# ccache shares with earlier builds), and the PyPI bpy 4.5 and 5.2 venvs.
rm -rf out/manylinux-wheels
setsid nice -n 19 scripts/manylinux/build.sh out/manylinux-wheels 3.11 3.13 > out/manylinux-build.log 2>&1 &
modules_pid=$!
setsid bash -c 'scripts/bpy-venv.sh && scripts/bpy-venv.sh 5.2' > out/bpy-venv.log 2>&1 &
bpy_pid=$!
background+=("$modules_pid" "$bpy_pid")

# `together NAME CMD... -- NAME CMD...`: the commands at once, each into
# out/NAME.log; each log's last lines (a failing one whole) once all end.
together() {
  local names=() pids=() name status=0 i
  while [ $# -gt 0 ]; do
    name=$1; shift
    local cmd=()
    while [ $# -gt 0 ] && [ "$1" != -- ]; do cmd+=("$1"); shift; done
    [ $# -eq 0 ] || shift
    "${cmd[@]}" > "out/$name.log" 2>&1 &
    names+=("$name"); pids+=($!)
  done
  for i in "${!pids[@]}"; do
    if wait "${pids[$i]}"; then
      echo "-- ${names[$i]}:"; tail -n 4 "out/${names[$i]}.log"
    else
      echo "-- ${names[$i]} FAILED:"; cat "out/${names[$i]}.log"; status=1
    fi
  done
  return $status
}

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

stage "PyPI bpy 4.5 and 5.2 (scripts/bpy-venv.sh, beside the tests)"
wait "$bpy_pid" || { cat out/bpy-venv.log; exit 1; }
tail -n 4 out/bpy-venv.log
if [ -x .venv-bpy/bin/python ] && [ -x .venv-bpy52/bin/python ]; then
  stage "release: waiting for the modules (out/manylinux-build.log)"
  wait "$modules_pid" || { tail -n 40 out/manylinux-build.log; echo "the release's modules failed"; exit 1; }
  tail -n 14 out/manylinux-build.log
  stage "release: the wheels checked and tagged manylinux_2_28, and the extension (scripts/release.sh)"
  scripts/release.sh --built out/manylinux-wheels
  rm -rf build-release-cp313 && mkdir -p build-release-cp313/python
  /usr/bin/python3 -m zipfile -e "$(ls dist/paramorph-*-cp313-cp313-manylinux_2_28_x86_64.whl)" build-release-cp313/python
  # tests/blender in Blender 4.5 (CPython 3.11, the development build) and in
  # Blender 5.2 (3.13, the release's own cp313 module), the release
  # extension's install test run (not skipped) in both; and the wheels in
  # fresh minimal Debian 11, 12 and 13 roots: all three at once.
  stage "Blender 4.5 and 5.2 tests (pytest with PyPI bpy), the wheels in Debian 11, 12 and 13 roots"
  portable=(echo "skipped: scripts/prove-portable.sh needs root (debootstrap, chroot)")
  # --no-blender: the install tests run in the suites beside it.
  if [ -n "$roots_pid" ]; then
    wait "$roots_pid" || { cat out/portable-prepare.log; echo "preparing the Debian roots failed"; exit 1; }
    portable=(scripts/prove-portable.sh --tests quick --no-blender)
  fi
  together \
    blender-4.5 env PARAMORPH_REQUIRE_RELEASE=1 .venv-bpy/bin/python -m pytest tests/blender -q -p no:cacheprovider -- \
    blender-5.2 env PARAMORPH_BUILD_DIR=build-release-cp313 PARAMORPH_REQUIRE_RELEASE=1 \
      .venv-bpy52/bin/python -m pytest tests/blender -q -p no:cacheprovider -- \
    portable "${portable[@]}"
else
  echo "skipped: no .venv-bpy or .venv-bpy52 (scripts/bpy-venv.sh creates them; it needs PyPI)"
fi
stage "done"
