#!/usr/bin/env bash
# MPFR 4.2.0 (Debian source `mpfr4`) on our GMP, static and PIC: CGAL 5.5's
# CMake wants MPFR whenever it uses GMP. --disable-float128: clang has no C
# _Float128, and MPFR's fallback define collides with glibc's typedef.
set -euo pipefail
fetch_source mpfr4 mpfr4-4.2.0
src=$SRC/mpfr4-4.2.0 b=$OBJ/mpfr
rm -rf "$b" && mkdir -p "$b" && cd "$b"
"$src/configure" --prefix="$PREFIX" --enable-static --disable-shared --with-pic --with-gmp="$PREFIX" \
  --disable-float128 --build=x86_64-pc-linux-gnu --host=x86_64-pc-linux-gnu CC="$CC" AR="$AR" RANLIB="$RANLIB" \
  CFLAGS=-O2 > configure.log 2>&1 || { tail -20 configure.log; exit 1; }
make -j"$JOBS" -C src
make -C src install >/dev/null
