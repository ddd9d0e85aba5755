#!/usr/bin/env bash
# OpenBLAS 0.3.21 (Debian source `openblas`): BLAS and OpenBLAS's own LAPACK
# subset (`make libs`; the +ds source has no netlib LAPACK), which has the
# dpotrf_/zpotrf_ CHOLMOD calls. Serial with locking (callers may be OpenMP
# threads), no Fortran, static and PIC, CPU dispatch at run time over three
# kernel sets: PRESCOTT (any x86-64), HASWELL (AVX2; OpenBLAS also gives it
# to Zen) and SKYLAKEX (AVX-512). Each set is a full BLAS build: three
# instead of six halves the dependencies' cold build, and CHOLMOD's
# supernodes are too small for the sets in between to show.
set -euo pipefail
fetch_source openblas openblas-0.3.21+ds
src=$SRC/openblas-0.3.21+ds
cd "$src"
make clean >/dev/null 2>&1 || true
make -j"$JOBS" MAKE_NB_JOBS="$JOBS" CC="$CC" HOSTCC=gcc AR="$AR" RANLIB="$RANLIB" NOFORTRAN=1 C_LAPACK=1 \
  USE_OPENMP=0 USE_THREAD=0 USE_LOCKING=1 NO_SHARED=1 NEED_PIC=1 NO_AFFINITY=1 DYNAMIC_ARCH=1 TARGET=PRESCOTT \
  DYNAMIC_LIST="HASWELL SKYLAKEX" COMMON_OPT=-O2 NUM_THREADS=64 libs > "$OBJ/openblas.log" 2>&1 ||
  { tail -30 "$OBJ/openblas.log"; exit 1; }
install -D -m644 "$(readlink -f libopenblas.a)" "$PREFIX/lib/libopenblas.a"
