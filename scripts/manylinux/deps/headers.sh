#!/usr/bin/env bash
# Headers for the module's build:
#  sysinc/: the header-only packages Debian installs in /usr/include (CGAL,
#    Boost, the OpenCL headers), searched after zig's glibc 2.28 headers
#    (toolchain/zig drops /usr/include itself).
#  shim/ (searched first):
#    sys/single_threaded.h: glibc 2.28 has no __libc_single_threaded (2.32);
#      CGAL 5.5 uses it when the header exists. 0 is CGAL's cautious answer.
#    CGAL/boost/graph/iterator.h: CGAL 5.5.1 calls a base() that does not
#      exist in three operators, which clang >= 19 rejects (fixed in CGAL
#      5.6.2); Debian's header with this->g instead.
set -euo pipefail
mkdir -p "$PREFIX/sysinc" "$PREFIX/shim/sys" "$PREFIX/shim/CGAL/boost/graph"
for d in CGAL CL boost; do ln -sfn "/usr/include/$d" "$PREFIX/sysinc/$d"; done
# Debian's Python headers include x86_64-linux-gnu/pythonX.Y/pyconfig.h.
mkdir -p "$PREFIX/sysinc/x86_64-linux-gnu"
for d in /usr/include/x86_64-linux-gnu/python3*; do [ -d "$d" ] && ln -sfn "$d" "$PREFIX/sysinc/x86_64-linux-gnu/"; done
printf '#pragma once\nstatic const char __libc_single_threaded = 0;\n' > "$PREFIX/shim/sys/single_threaded.h"
sed 's/(! (this->base() == nullptr))/(! (this->g == nullptr))/' /usr/include/CGAL/boost/graph/iterator.h \
  > "$PREFIX/shim/CGAL/boost/graph/iterator.h"
grep -q 'this->g == nullptr' "$PREFIX/shim/CGAL/boost/graph/iterator.h"
