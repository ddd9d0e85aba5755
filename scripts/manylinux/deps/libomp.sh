#!/usr/bin/env bash
# LLVM's OpenMP runtime 19.1.7 (Debian source `llvm-toolchain-19`; only
# openmp/ and cmake/ are unpacked from its 164 MB tarball), standalone, static
# and PIC, no offload, OMPT or hwloc. zig ships no OpenMP runtime; libomp 16
# lacks __kmpc_dispatch_deinit, which zig 0.17's clang emits.
set -euo pipefail
version=19.1.7 top=$SRC/llvm-toolchain-19_19.1.7
if [ ! -d "$top/openmp" ]; then
  (cd "$SRC" && { ls llvm-toolchain-19_$version.orig.tar.xz >/dev/null 2>&1 ||
                  debian_source llvm-toolchain-19 --download-only; } &&
   tar xJf "llvm-toolchain-19_$version.orig.tar.xz" --wildcards "llvm-toolchain-19_$version/openmp/*" \
     "llvm-toolchain-19_$version/cmake/*")
fi
b=$OBJ/libomp
cmake -S "$top/openmp" -B "$b" -DCMAKE_BUILD_TYPE=Release -DCMAKE_C_COMPILER="$CC" -DCMAKE_CXX_COMPILER="$CXX" \
  -DCMAKE_AR="$AR" -DCMAKE_RANLIB="$RANLIB" -DCMAKE_POSITION_INDEPENDENT_CODE=ON \
  -DOPENMP_STANDALONE_BUILD=ON -DLIBOMP_ENABLE_SHARED=OFF -DLIBOMP_USE_HWLOC=OFF -DLIBOMP_OMPT_SUPPORT=OFF \
  -DOPENMP_ENABLE_LIBOMPTARGET=OFF -DOPENMP_ENABLE_OMPT_TOOLS=OFF -DLIBOMP_INSTALL_ALIASES=OFF \
  -DOPENMP_ENABLE_TESTING=OFF -DLIBOMP_ARCH=x86_64 >/dev/null
cmake --build "$b" -j"$JOBS" --target omp
install -D -m644 "$b/runtime/src/libomp.a" "$PREFIX/lib/libomp.a"
install -D -m644 "$b/runtime/src/omp.h" "$PREFIX/include/omp.h"
