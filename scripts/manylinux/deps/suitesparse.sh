#!/usr/bin/env bash
# SuiteSparse 5.12 (Debian source `suitesparse`): SuiteSparse_config, AMD,
# CAMD, COLAMD, CCOLAMD and CHOLMOD (Partition on our METIS, Supernodal on
# OpenBLAS), static and PIC, without OpenMP or CUDA. BLAS and LAPACK are
# resolved at the module's link.
set -euo pipefail
fetch_source suitesparse suitesparse-5.12.0+dfsg
src=$SRC/suitesparse-5.12.0+dfsg
args=(CC="$CC" CXX="$CXX" AR="$AR" "ARCHIVE=$AR rcs" RANLIB="$RANLIB" CUDA=no CFOPENMP= AUTOCC=no
      "CFLAGS=-fPIC" OPTIMIZATION=-O3 MY_METIS_LIB=-lmetis MY_METIS_INC="$PREFIX/include")
mkdir -p "$PREFIX/include/suitesparse" "$PREFIX/lib"
# The tree builds in place: what a build for another prefix left is cleared.
for p in SuiteSparse_config AMD/Lib CAMD/Lib COLAMD/Lib CCOLAMD/Lib CHOLMOD/Lib; do
  make -C "$src/$p" clean >/dev/null 2>&1 || true
done
make -j"$JOBS" -C "$src/SuiteSparse_config" static "${args[@]}"
cp "$src/SuiteSparse_config/libsuitesparseconfig.a" "$PREFIX/lib/"
cp "$src/SuiteSparse_config/SuiteSparse_config.h" "$PREFIX/include/suitesparse/"
for p in AMD CAMD COLAMD CCOLAMD CHOLMOD; do
  make -j"$JOBS" -C "$src/$p/Lib" static "${args[@]}"
  cp "$src/$p"/Lib/lib*.a "$PREFIX/lib/"
  cp "$src/$p"/Include/*.h "$PREFIX/include/suitesparse/"
done
