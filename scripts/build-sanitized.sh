#!/usr/bin/env bash
# Builds paramorph_native with AddressSanitizer and UndefinedBehaviorSanitizer
# into ${PARAMORPH_ASAN_BUILD_DIR:-build-asan} (only the Python module), for the
# fuzz driver (tests/fuzz/fuzz.py --build-dir build-asan; see README, "Fuzzing").
# -O1 -g without NDEBUG: Eigen's bounds assertions and libstdc++'s
# (_GLIBCXX_ASSERTIONS) are on too, so an index past an array's end aborts
# with a message even where ASan would not see it (inside one allocation).
# Not part of scripts/test.sh: a build from nothing takes most of an hour on
# two cores (ccache makes rebuilds quick).
# Usage: scripts/build-sanitized.sh     (PARAMORPH_BUILD_JOBS sets the parallel jobs)
set -euo pipefail
cd "$(dirname "$0")/.."
build_dir=${PARAMORPH_ASAN_BUILD_DIR:-build-asan}
sanitize="-fsanitize=address,undefined -fno-omit-frame-pointer -fno-sanitize-recover=undefined"
launcher=()
command -v ccache >/dev/null && launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache)
cmake -S . -B "$build_dir" -DCMAKE_BUILD_TYPE=RelWithDebInfo \
  -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O1 -g -D_GLIBCXX_ASSERTIONS" \
  -DCMAKE_CXX_FLAGS="$sanitize" \
  -DCMAKE_SHARED_LINKER_FLAGS="-fsanitize=address,undefined" \
  -DCMAKE_EXE_LINKER_FLAGS="-fsanitize=address,undefined" \
  -DPARAMORPH_BUILD_TESTS=OFF \
  -DPython3_EXECUTABLE=/usr/bin/python3 "${launcher[@]}" >/dev/null
cmake --build "$build_dir" -j"${PARAMORPH_BUILD_JOBS:-$(nproc)}" --target paramorph_native
module=$(ls "$build_dir"/python/paramorph_native*.so)
# The module must link the sanitizer runtimes; Python is not instrumented, so
# libasan has to be loaded first (LD_PRELOAD) in any process importing it.
ldd "$module" | grep -q libasan || { echo "build-sanitized: $module does not link libasan" >&2; exit 1; }
echo "paramorph: built $module (ASan/UBSan)"
echo "run:  tests/fuzz/fuzz.py --build-dir $build_dir --seconds 300 --call-timeout 120"
echo "      (its workers get LD_PRELOAD=$(gcc -print-file-name=libasan.so):$(gcc -print-file-name=libstdc++.so))"
