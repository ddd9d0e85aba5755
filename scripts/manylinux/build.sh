#!/usr/bin/env bash
# Builds paramorph_native wheels that load on glibc 2.28 and later
# (manylinux_2_28: Blender's own floor, Rocky/Alma/RHEL 8, Ubuntu 20.04,
# Debian 11) for each CPython asked for, into OUT (not yet tagged: release.sh
# checks and tags them):
#   scripts/manylinux/build.sh OUT [3.11 3.12 3.13]
#   scripts/manylinux/build.sh --deps-only     (the static prefix alone)
# How: zig's clang targeting glibc 2.28 with libc++ linked in
# (toolchain/zig), and every library the module uses built from Debian 12's
# source packages as static, PIC archives (deps/*.sh, in order below) into a
# prefix under PARAMORPH_MANYLINUX_CACHE, named by a stamp of those scripts
# and kept: a cold build is about 20 minutes on 2 cores (OpenBLAS's kernel
# sets half of it), then only the module compiles (about 6 minutes for the
# first Python; ccache shares the core's objects with the others).
# Each Python's build tools (PyPI pybind11 >= 2.13, which reads NumPy 2
# arrays, and scikit-build-core) live in a venv in the cache.
# Needs: Debian 12 with the build's packages (scripts/install-deps.sh: CGAL,
# Boost and the OpenCL headers are used from /usr/include), the Debian source
# archive and PyPI, and each CPython (scripts/python-for.sh finds them).
set -euo pipefail
cd "$(dirname "$0")/../.."
[ $# -ge 1 ] || { echo "usage: scripts/manylinux/build.sh OUT [PYTHON...] | --deps-only" >&2; exit 2; }
deps_only=no
[ "$1" != --deps-only ] || deps_only=yes
out=$1; shift
pythons=("$@")
[ ${#pythons[@]} -gt 0 ] || pythons=(3.11 3.12 3.13)
if [ $deps_only = no ]; then
  mkdir -p "$out"
  out=$(cd "$out" && pwd)
fi
source scripts/python-for.sh
source scripts/manylinux/env.sh

if [ ! -f "$PREFIX/.complete" ]; then
  echo "manylinux: building the static dependencies into $PREFIX (logs in $cache/logs)"
  mkdir -p "$PREFIX/lib" "$PREFIX/include" "$OBJ"
  export -f fetch_source debian_source
  for step in headers qhull metis suitesparse opensubdiv libomp gmp mpfr openblas opencl; do
    [ -f "$PREFIX/.done-$step" ] && continue  # an interrupted build goes on where it stopped
    started=$SECONDS
    if ! bash "scripts/manylinux/deps/$step.sh" > "$cache/logs/$step.log" 2>&1; then
      tail -n 30 "$cache/logs/$step.log" >&2
      echo "manylinux: $step failed (the whole log: $cache/logs/$step.log)" >&2
      exit 1
    fi
    touch "$PREFIX/.done-$step"
    echo "manylinux: $step $((SECONDS - started)) s"
  done
  touch "$PREFIX/.complete"
fi
echo "manylinux: static dependencies in $PREFIX"
[ $deps_only = no ] || exit 0
export PARAMORPH_MANYLINUX_PREFIX=$PREFIX

# The licence of everything linked into the module, for the wheel's
# .dist-info/licenses/third_party (release.sh): each source package's
# debian/copyright, the header-only libraries' Debian copyright files, and
# zig's libc++, libc++abi, libunwind and compiler-rt.
licences=$PREFIX/licenses
rm -rf "$licences" && mkdir -p "$licences"
for source in qhull:qhull-2020.2 metis:metis-5.1.0.dfsg suitesparse:suitesparse-5.12.0+dfsg \
              opensubdiv:opensubdiv-3.5.0 gmp:gmp-6.2.1+dfsg1 mpfr4:mpfr4-4.2.0 openblas:openblas-0.3.21+ds; do
  cp "$SRC/${source#*:}/debian/copyright" "$licences/${source%%:*}.copyright"
done
tar xJf "$(ls "$SRC"/llvm-toolchain-19_*.debian.tar.xz | head -n 1)" -O debian/copyright \
  > "$licences/llvm-toolchain-19.copyright"  # libomp
for package in libcgal-dev libboost1.74-dev libeigen3-dev; do
  cp "/usr/share/doc/$package/copyright" "$licences/$package.copyright"
done
zig_lib=$(dirname "$PARAMORPH_ZIG")/lib
for part in libcxx libcxxabi libunwind; do cp "$zig_lib/$part/LICENSE.TXT" "$licences/$part.LICENSE.txt"; done
cp "$(dirname "$PARAMORPH_ZIG")/LICENSE" "$licences/zig.LICENSE.txt"  # compiler-rt and the glibc stubs

launcher=()
command -v ccache >/dev/null && launcher=(-C cmake.define.CMAKE_CXX_COMPILER_LAUNCHER=ccache)
export CCACHE_BASEDIR=${CCACHE_BASEDIR:-$PWD}  # another clone (CI's) hits
for version in "${pythons[@]}"; do
  interpreter=$(python_for "$version")
  tag=$("$interpreter" -c 'import sys; print(f"cp{sys.version_info[0]}{sys.version_info[1]}")')
  venv=$cache/venv-$tag
  if ! "$venv/bin/python" -c 'import pybind11, scikit_build_core, build, sys; sys.exit(pybind11.version_info < (2, 13))' 2>/dev/null; then
    rm -rf "$venv"
    "$interpreter" -m venv "$venv"
    "$venv/bin/python" -m pip install -q --upgrade pip
    "$venv/bin/python" -m pip install -q "pybind11>=2.13" "scikit-build-core>=0.10" build
  fi
  "$venv/bin/python" - "$licences/pybind11.LICENSE.txt" <<'PY'
import importlib.metadata, shutil, sys
licence = next(f for f in importlib.metadata.distribution("pybind11").files if f.name == "LICENSE")
shutil.copy(licence.locate(), sys.argv[1])
PY
  started=$SECONDS
  # Not isolated: the venv's pybind11. The Python's own headers come from
  # its prefix (pyenv or /usr/local), never /usr/include's glibc.
  PARAMORPH_WITH_IPOPT=OFF CMAKE_GENERATOR="Unix Makefiles" CMAKE_BUILD_PARALLEL_LEVEL=$JOBS \
    "$venv/bin/python" -m build --wheel --no-isolation --skip-dependency-check --outdir "$out" \
    -C cmake.define.CMAKE_TOOLCHAIN_FILE="$PWD/scripts/manylinux/toolchain.cmake" \
    -C build-dir="build-manylinux/$tag" "${launcher[@]}" . > "$cache/logs/module-$tag.log" 2>&1 ||
    { tail -n 40 "$cache/logs/module-$tag.log" >&2; echo "manylinux: the $tag module failed" >&2; exit 1; }
  echo "manylinux: $tag wheel in $((SECONDS - started)) s: $(ls "$out"/paramorph-*-"$tag"-*.whl)"
done
