#!/usr/bin/env bash
# OpenSubdiv 3.5.0 (Debian source `opensubdiv`): libosdCPU only (Sdc, Vtr,
# Far, Bfr, Osd CPU), static and PIC, no GPU, OpenMP, TBB, examples or tests.
set -euo pipefail
fetch_source opensubdiv opensubdiv-3.5.0
src=$SRC/opensubdiv-3.5.0 b=$OBJ/opensubdiv
off=()
for o in EXAMPLES TUTORIALS REGRESSION PTEX DOC OMP TBB CUDA OPENCL CLEW OPENGL METAL DX TESTS GLTESTS GLEW GLFW; do
  off+=(-DNO_$o=ON)
done
cmake -S "$src" -B "$b" -DCMAKE_BUILD_TYPE=Release -DCMAKE_C_COMPILER="$CC" -DCMAKE_CXX_COMPILER="$CXX" \
  -DCMAKE_AR="$AR" -DCMAKE_RANLIB="$RANLIB" -DCMAKE_POSITION_INDEPENDENT_CODE=ON "${off[@]}" >/dev/null
cmake --build "$b" -j"$JOBS" --target osd_static_cpu
cp "$b/lib/libosdCPU.a" "$PREFIX/lib/"
(cd "$src" && find opensubdiv \( -path '*/far/*' -o -path '*/bfr/*' -o -path '*/sdc/*' -o -path '*/vtr/*' \
   -o -path '*/osd/*' -o -name version.h \) -name '*.h' | grep -v -E '/osd/(cuda|cl|gl|d3d|mtl|hlsl|glsl|tbb|omp)' |
 while read -r h; do install -D -m644 "$h" "$PREFIX/include/$h"; done)
