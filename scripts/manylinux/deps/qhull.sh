#!/usr/bin/env bash
# Qhull 2020.2 (Debian source `qhull`): the reentrant C library only, static
# and PIC, with a QhullConfig.cmake giving Qhull::qhull_r as that archive.
set -euo pipefail
fetch_source qhull qhull-2020.2
src=$SRC/qhull-2020.2 b=$OBJ/qhull
cmake -S "$src" -B "$b" -DCMAKE_BUILD_TYPE=Release -DCMAKE_C_COMPILER="$CC" -DCMAKE_CXX_COMPILER="$CXX" \
  -DCMAKE_AR="$AR" -DCMAKE_RANLIB="$RANLIB" -DCMAKE_POSITION_INDEPENDENT_CODE=ON >/dev/null
cmake --build "$b" -j"$JOBS" --target qhullstatic_r
mkdir -p "$PREFIX/lib/cmake/Qhull" "$PREFIX/include/libqhull_r"
cp "$b/libqhullstatic_r.a" "$PREFIX/lib/"
cp "$src"/src/libqhull_r/*.h "$PREFIX/include/libqhull_r/"
cat > "$PREFIX/lib/cmake/Qhull/QhullConfig.cmake" <<'CM'
# Qhull::qhull_r: the static, PIC reentrant library (scripts/manylinux/deps/qhull.sh)
get_filename_component(_qhull_prefix "${CMAKE_CURRENT_LIST_DIR}/../../.." ABSOLUTE)
if(NOT TARGET Qhull::qhull_r)
  add_library(Qhull::qhull_r STATIC IMPORTED)
  set_target_properties(Qhull::qhull_r PROPERTIES
    IMPORTED_LOCATION "${_qhull_prefix}/lib/libqhullstatic_r.a"
    INTERFACE_INCLUDE_DIRECTORIES "${_qhull_prefix}/include")
endif()
set(Qhull_FOUND TRUE)
CM
