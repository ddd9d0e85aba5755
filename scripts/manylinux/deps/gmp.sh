#!/usr/bin/env bash
# GMP 6.2.1 (Debian source `gmp`): static and PIC, no C++, for the generic
# x86_64 host (baseline code that runs on every x86-64, not tuned to the
# build machine;'s per-CPU variants doubled the build for a
# library CGAL's filters reach only on near-degenerate predicates). CGAL needs it: its
# Boost.Multiprecision fallback throws on a denormal corner that our closest
# points must survive (tests/native/test_fuzz_findings.py).
set -euo pipefail
fetch_source gmp gmp-6.2.1+dfsg1
src=$SRC/gmp-6.2.1+dfsg1 b=$OBJ/gmp
# The +dfsg tarball has no doc/ (GFDL): a do-nothing doc/Makefile.in.
mkdir -p "$src/doc"
[ -f "$src/doc/Makefile.in" ] ||
  printf 'all install install-data install-exec check clean distclean uninstall installdirs install-strip:\n\t@:\n' \
    > "$src/doc/Makefile.in"
rm -rf "$b" && mkdir -p "$b" && cd "$b"
"$src/configure" --prefix="$PREFIX" --enable-static --disable-shared --with-pic \
  --build=x86_64-pc-linux-gnu --host=x86_64-pc-linux-gnu CC="$CC" CC_FOR_BUILD=gcc AR="$AR" RANLIB="$RANLIB" \
  CFLAGS=-O2 > configure.log 2>&1 || { tail -20 configure.log; exit 1; }
make -j"$JOBS"
make install >/dev/null
