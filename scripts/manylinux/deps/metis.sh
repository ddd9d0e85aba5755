#!/usr/bin/env bash
# METIS 5.1.0 with GKlib (Debian source `metis`): static and PIC, 32-bit
# idx_t/real_t as Debian's.
set -euo pipefail
fetch_source metis metis-5.1.0.dfsg
src=$SRC/metis-5.1.0.dfsg b=$OBJ/metis
sed -i 's/^set(METIS_LIBRARY_TYPE SHARED)/set(METIS_LIBRARY_TYPE STATIC)/' "$src/CMakeLists.txt"  # hard-coded shared
cmake -S "$src" -B "$b" -DCMAKE_BUILD_TYPE=Release -DCMAKE_C_COMPILER="$CC" -DCMAKE_AR="$AR" -DCMAKE_RANLIB="$RANLIB" \
  -DCMAKE_POSITION_INDEPENDENT_CODE=ON -DGKLIB_PATH="$src/GKlib" >/dev/null
cmake --build "$b" -j"$JOBS" --target metis
install -D -m644 "$b/libmetis/libmetis.a" "$PREFIX/lib/libmetis.a"
install -D -m644 "$src/include/metis.h" "$PREFIX/include/metis.h"
