# Sourced by scripts/manylinux/*: the zig toolchain that targets glibc 2.28
# and the prefix the static dependencies go to.
#   PARAMORPH_MANYLINUX_CACHE  where the toolchain, sources and prefixes live
#                              (default ~/.cache/paramorph/manylinux; kept
#                              between clones, like pip's cache)
# The prefix is named by a stamp of the scripts that build it, the compiler
# wrapper and the zig version, so a change to any of them builds a fresh one
# beside the old.
manylinux_dir=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
ZIG_VERSION=0.17.1
cache=${PARAMORPH_MANYLINUX_CACHE:-$HOME/.cache/paramorph/manylinux}
mkdir -p "$cache/src" "$cache/logs"
stamp=$( (echo "zig $ZIG_VERSION"; cat "$manylinux_dir"/deps/*.sh "$manylinux_dir"/opencl_stub.py \
          "$manylinux_dir"/toolchain/zig) | sha256sum | cut -c1-12)
export PREFIX=$cache/prefix-$stamp
export SRC=$cache/src
export OBJ=$cache/obj-$stamp
export JOBS=${PARAMORPH_BUILD_JOBS:-$(nproc)}
zig_venv=$cache/zig-$ZIG_VERSION
if [ ! -x "$zig_venv/bin/python" ] || ! "$zig_venv/bin/python" -c 'import ziglang' 2>/dev/null; then
  echo "manylinux: installing ziglang $ZIG_VERSION (PyPI) into $zig_venv"
  /usr/bin/python3 -m venv "$zig_venv"
  "$zig_venv/bin/python" -m pip install -q "ziglang==$ZIG_VERSION"
fi
PARAMORPH_ZIG=$("$zig_venv/bin/python" -c 'import os, ziglang; print(os.path.join(os.path.dirname(ziglang.__file__), "zig"))')
export PARAMORPH_ZIG
export PARAMORPH_ZIG_SYSINC=$PREFIX/sysinc
export ZIG_GLOBAL_CACHE_DIR=$cache/zig-cache ZIG_LOCAL_CACHE_DIR=$cache/zig-cache
# ccache (the module's build) would key the wrapper by its mtime, new in
# every clone, and never hit: key it by what decides the code instead.
export CCACHE_COMPILERCHECK="string:zig-$ZIG_VERSION-$(sha256sum < "$manylinux_dir/toolchain/zig" | cut -c1-12)"
export CC=$manylinux_dir/toolchain/cc CXX=$manylinux_dir/toolchain/c++
export AR=$manylinux_dir/toolchain/ar RANLIB=$manylinux_dir/toolchain/ranlib

source "$manylinux_dir/../debian-source.sh"

# `fetch_source PACKAGE DIRNAME`: Debian 12's source package, unpacked in $SRC.
fetch_source() {
  [ -d "$SRC/$2" ] && return 0
  (cd "$SRC" && debian_source "$1")
  [ -d "$SRC/$2" ] || { echo "manylinux: apt-get source $1 did not give $SRC/$2" >&2; return 1; }
}
