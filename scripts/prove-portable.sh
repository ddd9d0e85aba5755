#!/usr/bin/env bash
# Proves the released wheels portable (issues 18, 30): in fresh minimal
# Debian roots, debootstrapped from the Debian archive, with no -dev package,
# the wheel for the root's CPython from scripts/release.sh
#   - installs with pip (numpy and pytest from PyPI),
#   - resolves, under ldd, nothing but the C library's own parts (libc, libm,
#     libpthread, libdl and the dynamic loader): everything else is linked in,
#   - imports with no OpenCL driver installed, runs on the CPU, and says why
#     there is no device,
#   - passes tests/native (--tests quick: validation, sphere and planar
#     maps, optimize (no Ipopt), paste, devices and the README quickstart).
# The roots and their Pythons:
#   bullseye  Debian 11, glibc 2.31 (the oldest Debian in the archive; the
#             wheels' floor is 2.28): CPython 3.11 built from Debian 12's
#             python3.11 source in a throwaway copy of the root with its
#             compilers, then copied into the clean root (Debian 11's own
#             Python is 3.9, which no Blender embeds)
#   bookworm  Debian 12, glibc 2.36: its python3.11 (Blender 4.2-5.0's)
#   trixie    Debian 13, glibc 2.41: its python3.13 (Blender 5.1 and later)
# Pristine roots (and the built CPython) are cached under $PARAMORPH_ROOTS
# (default /var/tmp/paramorph-roots) and each check runs in a throwaway copy.
# Then (unless --no-blender) the extension zip beside the wheels is installed
# into Blender 4.5 (PyPI bpy, temporary user folders) and Sphere Map,
# Isometric Unwrap, Morph To, Copy and Paste Feature run from it
# (tests/blender/test_install.py -k release).
# Each suite's root with its Python installed is cached too (SUITE-python),
# so a check copies it and installs only the wheel; --prepare builds the
# cached roots and Pythons alone, needing no wheels (scripts/test.sh runs it
# beside the build: it is mostly downloads).
# Usage: scripts/prove-portable.sh [--wheels DIR] [--suites "bullseye bookworm trixie"] [--tests full|quick] [--no-blender]
#        scripts/prove-portable.sh --prepare [--suites ...]
# Needs root (debootstrap, chroot, mount) and the Debian archive and PyPI.
set -euo pipefail
cd "$(dirname "$0")/.."
repo=$PWD

wheels=${PARAMORPH_RELEASE_DIR:-dist}
suites="bullseye bookworm trixie"
tests=full
blender=yes
prepare_only=no
while [ $# -gt 0 ]; do
  case "$1" in
    --prepare) prepare_only=yes; shift ;;
    --no-blender) blender=no; shift ;;
    --wheels) wheels=$2; shift 2 ;;
    --suites) suites=$2; shift 2 ;;
    --tests) tests=$2; shift 2 ;;
    *) echo "prove-portable: unknown argument $1" >&2; exit 2 ;;
  esac
done
if [ $prepare_only = no ]; then
  wheels=$(readlink -f "$wheels")
  ls "$wheels"/paramorph-*manylinux*.whl >/dev/null 2>&1 ||
    { echo "prove-portable: no wheels in $wheels (run scripts/release.sh first, or pass --wheels)" >&2; exit 1; }
fi
[ "$(id -u)" -eq 0 ] || { echo "prove-portable: needs root (debootstrap, chroot)" >&2; exit 1; }
command -v debootstrap >/dev/null || {
  DEBIAN_FRONTEND=noninteractive apt-get install -y -qq --no-install-recommends debootstrap >/dev/null
}
# What pip installs in the roots is fetched here (the host's PyPI access and
# certificates) and installed there offline: pip itself, numpy, pytest.
wheels_dir=$(mktemp -d /var/tmp/paramorph-wheels.XXXXXX)
if [ $prepare_only = no ]; then
  for python in 3.11 3.13; do
    /usr/bin/python3 -m pip download -q --dest "$wheels_dir" --only-binary :all: --python-version "$python" \
      --implementation cp --platform manylinux2014_x86_64 --platform manylinux_2_17_x86_64 pip numpy pytest
  done
  pip_wheel=$(ls "$wheels_dir"/pip-*.whl)
fi
roots=${PARAMORPH_ROOTS:-/var/tmp/paramorph-roots}
mirror=${PARAMORPH_DEBIAN_MIRROR:-http://deb.debian.org/debian}
mkdir -p "$roots"

say() { echo "prove-portable [$suite]: $*"; }

mounted=()
cleanup() {
  for m in "${mounted[@]}"; do umount -l "$m" 2>/dev/null || true; done
  [ -z "${scratch:-}" ] || rm -rf "$scratch"
  rm -rf "$wheels_dir"
}
trap cleanup EXIT

# `built_python SUITE VERSION`: a tarball of /opt/cpython-VERSION built from
# Debian 12's pythonVERSION source inside a throwaway copy of SUITE's pristine
# root with its own compiler and -dev packages (they never reach the root the
# wheel is tested in), cached beside the roots.
source scripts/debian-source.sh
built_python() {
  local suite=$1 version=$2 tarball=$roots/$1-cpython-$2.tar.gz builder source
  if [ ! -f "$tarball" ]; then
    source=$(ls "$roots"/python"$version"_*.orig.tar.* 2>/dev/null | head -n 1)
    [ -n "$source" ] || { (cd "$roots" && debian_source "python$version" --download-only) >&2
                          source=$(ls "$roots"/python"$version"_*.orig.tar.* | head -n 1); }
    builder=$(mktemp -d /var/tmp/paramorph-builder.XXXXXX)
    cp -a "$roots/$suite/." "$builder/"
    cp /etc/resolv.conf "$builder/etc/resolv.conf"
    mkdir -p "$builder/opt/src" && tar xf "$source" -C "$builder/opt/src" --strip-components=1
    mount -t proc proc "$builder/proc"
    chroot "$builder" /usr/bin/env -i PATH=/usr/bin:/bin HOME=/root LANG=C.UTF-8 /bin/bash -c "
      apt-get update -qq && DEBIAN_FRONTEND=noninteractive apt-get install -y -qq --no-install-recommends \
        gcc make libc6-dev zlib1g-dev libffi-dev libbz2-dev liblzma-dev >/dev/null &&
      cd /opt/src && ./configure -q --prefix=/opt/cpython-$version --without-ensurepip >/dev/null &&
      make -s -j$(nproc) >/dev/null 2>&1 && make -s install >/dev/null 2>&1" >&2 ||
      { umount -l "$builder/proc"; echo "prove-portable: building CPython $version for $suite failed" >&2; return 1; }
    umount -l "$builder/proc"
    tar czf "$tarball.tmp" -C "$builder" "opt/cpython-$version" && mv "$tarball.tmp" "$tarball"
    rm -rf "$builder"
  fi
  echo "$tarball"
}

suite_python() {
  case $1 in
    bullseye) echo 3.11 ;;  # built from source (built_python)
    bookworm) echo 3.11 ;;
    *) echo 3.13 ;;
  esac
}

# `python_root SUITE`: $roots/SUITE-python, SUITE's pristine minimal root
# (debootstrap, cached) with the Python the check uses installed and no -dev
# package, built once and cached.
python_root() {
  local suite=$1 python pristine=$roots/$1 ready=$roots/$1-python builder
  python=$(suite_python "$suite")
  [ -f "$ready/.paramorph-ready" ] && return 0
  if [ ! -x "$pristine/usr/bin/apt-get" ] || [ ! -f "$pristine/.paramorph-ready" ]; then
    say "debootstrap --variant=minbase from $mirror"
    rm -rf "$pristine"
    debootstrap --variant=minbase "$suite" "$pristine" "$mirror" > "$roots/$suite.log" 2>&1 ||
      { tail -n 20 "$roots/$suite.log" >&2; return 1; }
    touch "$pristine/.paramorph-ready"
  fi
  builder=$(mktemp -d /var/tmp/paramorph-root.XXXXXX)
  cp -a "$pristine/." "$builder/"
  cp /etc/resolv.conf "$builder/etc/resolv.conf"
  local install
  if [ "$suite" = bullseye ]; then
    say "CPython $python built from source for Debian 11 (cached), no -dev packages in the root"
    local python_tarball
    python_tarball=$(built_python "$suite" "$python") || return 1
    tar xzf "$python_tarball" -C "$builder"
    install="apt-get install -y -qq --no-install-recommends libffi7 >/dev/null &&
             ln -s /opt/cpython-$python/bin/python$python /usr/local/bin/python$python"
  else
    say "CPython $python from Debian, no -dev packages"
    install="apt-get install -y -qq --no-install-recommends python$python python$python-venv >/dev/null"
  fi
  mount -t proc proc "$builder/proc"
  chroot "$builder" /usr/bin/env -i PATH=/usr/local/bin:/usr/bin:/bin HOME=/root LANG=C.UTF-8 DEBIAN_FRONTEND=noninteractive \
    /bin/bash -c "apt-get update -qq && $install && apt-get clean" ||
    { umount -l "$builder/proc"; rm -rf "$builder"; say "could not set up CPython $python"; return 1; }
  umount -l "$builder/proc"
  touch "$builder/.paramorph-ready"
  rm -rf "$ready" && mv "$builder" "$ready"
}

for suite in $suites; do
  python_root "$suite" || exit 1
  [ $prepare_only = no ] || continue
  python=$(suite_python "$suite")
  scratch=$(mktemp -d /var/tmp/paramorph-root.XXXXXX)
  cp -a "$roots/$suite-python/." "$scratch/"
  mount -t proc proc "$scratch/proc" && mounted+=("$scratch/proc")
  mount --bind /dev "$scratch/dev" && mounted+=("$scratch/dev")
  cp /etc/resolv.conf "$scratch/etc/resolv.conf"
  in_root() { chroot "$scratch" /usr/bin/env -i PATH=/usr/local/bin:/usr/bin:/bin HOME=/root LANG=C.UTF-8 \
                /bin/bash -c "$1"; }

  tag=cp${python/./}
  wheel=$(ls "$wheels"/paramorph-*-"$tag"-"$tag"-manylinux*.whl 2>/dev/null | head -n 1)
  [ -n "$wheel" ] || { say "no $tag wheel in $wheels"; exit 1; }
  dev=$(in_root "dpkg-query -W -f='\${Package}\n' | grep -- '-dev\$' || true")
  [ -z "$dev" ] || { say "the root has -dev packages: $dev"; exit 1; }

  mkdir -p "$scratch/opt/in"
  cp "$wheel" "$wheels_dir"/*.whl "$scratch/opt/in/"
  git -C "$repo" archive HEAD tests README.md | tar -x -C "$scratch/opt/in"
  pip_name=$(basename "$pip_wheel")
  in_root "python$python -m venv --without-pip /opt/venv && /opt/venv/bin/python /opt/in/$pip_name/pip install -q \
           --no-warn-script-location /opt/in/$pip_name && /opt/venv/bin/python -m pip install -q \
           --no-index --find-links /opt/in /opt/in/$(basename "$wheel") pytest" || { say "pip install failed"; exit 1; }
  say "installed $(basename "$wheel") into $(in_root 'cat /etc/debian_version'), glibc \
$(in_root 'ldd --version | head -n 1 | grep -o "[0-9.]*$"')"

  # Nothing resolved outside the wheel but the system's base libraries.
  site=$(in_root "/opt/venv/bin/python -c 'import sysconfig; print(sysconfig.get_paths()[\"platlib\"])'")
  outside=$(in_root "for f in $site/paramorph_native*.so $site/paramorph.libs/*; do [ -e \"\$f\" ] || continue; ldd \"\$f\"; done" |
    awk -v libs="$site/paramorph.libs/" '
      /=>/ { name = $1; path = $3
             if (path == "not") { print "not found: " name; next }
             if (index(path, libs) == 1) next
             if (name ~ /^(libc|libm|libpthread|libdl|librt)\.so/) next
             print name " => " path }
      /ld-linux/ && !/=>/ { next }' | sort -u)
  if [ -n "$outside" ]; then
    say "resolved outside the wheel:"
    echo "$outside" >&2
    exit 1
  fi
  say "ldd: nothing but libc, libm, libpthread, libdl (and the loader)"

  # No OpenCL driver (ICD) in a minimal root: import, CPU path, and why.
  in_root "cd /tmp && /opt/venv/bin/python - <<'EOF'
import sys
import numpy as np
import paramorph_native as pm
sys.path.insert(0, '/opt/in/tests/native')
import meshes
assert pm.devices() == [], pm.devices()
assert not pm.opencl_available()
reason = pm.opencl_error()
assert 'no OpenCL driver' in reason, reason
V, F = meshes.noisy_blob(3)
r = pm.sphere_map(V, F)  # backend 'auto': the CPU path
assert r.flipped == 0 and np.allclose(np.linalg.norm(r.positions, axis=1), 1.0)
print('prove-portable: no OpenCL driver: devices() == [], opencl_error():', reason)
print('prove-portable: build_info():', pm.build_info())
EOF" || { say "the module failed without OpenCL"; exit 1; }

  selection="tests/native"
  [ "$tests" = quick ] && selection="tests/native/test_validate.py tests/native/test_sphere.py tests/native/test_planar.py tests/native/test_morph.py tests/native/test_paste_session.py tests/native/test_devices.py tests/native/test_readme_quickstart.py"
  say "pytest $selection (against the installed wheel)"
  in_root "cd /opt/in && PARAMORPH_BUILD_DIR=no-build /opt/venv/bin/python -m pytest -q -p no:cacheprovider \
           $selection 2>&1 | tail -n 3" | tee "$scratch/pytest.log"
  grep -q " passed" "$scratch/pytest.log" && ! grep -Eq "[0-9]+ (failed|error)" "$scratch/pytest.log" ||
    { say "tests failed"; exit 1; }

  for m in "${mounted[@]}"; do umount -l "$m"; done
  mounted=()
  rm -rf "$scratch"
  scratch=""
done
[ $prepare_only = no ] || { echo "prove-portable: roots with their Pythons ready in $roots: $suites"; exit 0; }
echo "prove-portable: the wheels are portable to: $suites"

if [ "$blender" = yes ]; then
  [ -x .venv-bpy/bin/python ] || scripts/bpy-venv.sh
  echo "prove-portable: the extension in Blender 4.5 (tests/blender/test_install.py -k release)"
  PARAMORPH_RELEASE_DIR=$wheels PARAMORPH_REQUIRE_RELEASE=1 \
    .venv-bpy/bin/python -m pytest tests/blender/test_install.py -k release -q -p no:cacheprovider
fi
