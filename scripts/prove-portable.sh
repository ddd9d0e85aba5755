#!/usr/bin/env bash
# Proves the released wheel portable (issue 18): in fresh minimal Debian 12
# (bookworm) and Debian 13 (trixie) roots, debootstrapped from the Debian
# archive, with CPython 3.11 and no -dev package, the wheel from
# scripts/release.sh
#   - installs with pip (numpy and pytest from PyPI),
#   - resolves, under ldd, nothing outside the wheel but libc, libm,
#     libstdc++, libgcc_s, libz (and the dynamic loader),
#   - imports with no OpenCL driver installed, runs on the CPU, and says why
#     there is no device,
#   - passes tests/native (--tests quick: validation, sphere and planar
#     maps, optimize (no Ipopt), paste, devices and the README quickstart).
# Debian 13's own Python is 3.13; Blender 4.2-5.0 embed 3.11, so its root
# gets Debian 12's python3.11 package (pinned from bookworm): the interpreter
# is the same, the C library (2.41), libstdc++ (GCC 14) and everything else
# are Debian 13's.
# Pristine roots are cached under $PARAMORPH_ROOTS (default
# /var/tmp/paramorph-roots) and each check runs in a throwaway copy.
# Then (unless --no-blender) the extension zip beside the wheel is installed
# into Blender 4.5 (PyPI bpy, temporary user folders) and Sphere Map,
# Isometric Unwrap, Morph To, Copy and Paste Feature run from it
# (tests/blender/test_install.py -k release).
# Usage: scripts/prove-portable.sh [--wheel FILE] [--suites "bookworm trixie"] [--tests full|quick] [--no-blender]
# Needs root (debootstrap, chroot, mount) and the Debian archive and PyPI.
set -euo pipefail
cd "$(dirname "$0")/.."
repo=$PWD

wheel=""
suites="bookworm trixie"
tests=full
blender=yes
while [ $# -gt 0 ]; do
  case "$1" in
    --no-blender) blender=no; shift ;;
    --wheel) wheel=$2; shift 2 ;;
    --suites) suites=$2; shift 2 ;;
    --tests) tests=$2; shift 2 ;;
    *) echo "prove-portable: unknown argument $1" >&2; exit 2 ;;
  esac
done
if [ -z "$wheel" ]; then
  wheel=$(ls "${PARAMORPH_RELEASE_DIR:-dist}"/paramorph-*manylinux*.whl 2>/dev/null | head -n 1 || true)
fi
if [ -z "$wheel" ] || [ ! -f "$wheel" ]; then
  echo "prove-portable: no wheel (run scripts/release.sh first, or pass --wheel)" >&2
  exit 1
fi
wheel=$(readlink -f "$wheel")
[ "$(id -u)" -eq 0 ] || { echo "prove-portable: needs root (debootstrap, chroot)" >&2; exit 1; }
command -v debootstrap >/dev/null || {
  DEBIAN_FRONTEND=noninteractive apt-get install -y -qq --no-install-recommends debootstrap >/dev/null
}
# What pip installs in the roots is fetched here (the host's PyPI access and
# certificates) and installed there offline: pip itself, numpy, pytest.
wheels_dir=$(mktemp -d /var/tmp/paramorph-wheels.XXXXXX)
/usr/bin/python3 -m pip download -q --dest "$wheels_dir" --only-binary :all: --python-version 3.11 \
  --implementation cp --platform manylinux2014_x86_64 --platform manylinux_2_17_x86_64 pip "numpy<2" pytest
pip_wheel=$(ls "$wheels_dir"/pip-*.whl)
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

for suite in $suites; do
  pristine="$roots/$suite"
  if [ ! -x "$pristine/usr/bin/apt-get" ] || [ ! -f "$pristine/.paramorph-ready" ]; then
    say "debootstrap --variant=minbase from $mirror"
    rm -rf "$pristine"
    debootstrap --variant=minbase "$suite" "$pristine" "$mirror" > "$roots/$suite.log" 2>&1 ||
      { tail -n 20 "$roots/$suite.log" >&2; exit 1; }
    touch "$pristine/.paramorph-ready"
  fi
  scratch=$(mktemp -d /var/tmp/paramorph-root.XXXXXX)
  cp -a "$pristine/." "$scratch/"
  mount -t proc proc "$scratch/proc" && mounted+=("$scratch/proc")
  mount --bind /dev "$scratch/dev" && mounted+=("$scratch/dev")
  cp /etc/resolv.conf "$scratch/etc/resolv.conf"
  in_root() { chroot "$scratch" /usr/bin/env -i PATH=/usr/local/bin:/usr/bin:/bin HOME=/root LANG=C.UTF-8 \
                /bin/bash -c "$1"; }

  say "CPython 3.11, no -dev packages"
  if [ "$suite" != "bookworm" ]; then
    echo "deb $mirror bookworm main" > "$scratch/etc/apt/sources.list.d/bookworm.list"
    printf 'Package: *\nPin: release n=bookworm\nPin-Priority: 100\n' > "$scratch/etc/apt/preferences.d/bookworm"
  fi
  in_root "apt-get update -qq && DEBIAN_FRONTEND=noninteractive apt-get install -y -qq --no-install-recommends \
           python3.11 >/dev/null" || { say "could not install python3.11"; exit 1; }
  dev=$(in_root "dpkg-query -W -f='\${Package}\n' | grep -- '-dev\$' || true")
  [ -z "$dev" ] || { say "the root has -dev packages: $dev"; exit 1; }

  mkdir -p "$scratch/opt/in"
  cp "$wheel" "$wheels_dir"/*.whl "$scratch/opt/in/"
  git -C "$repo" archive HEAD tests README.md | tar -x -C "$scratch/opt/in"
  pip_name=$(basename "$pip_wheel")
  in_root "python3.11 -m venv --without-pip /opt/venv && /opt/venv/bin/python /opt/in/$pip_name/pip install -q \
           --no-warn-script-location /opt/in/$pip_name && /opt/venv/bin/python -m pip install -q \
           --no-index --find-links /opt/in /opt/in/$(basename "$wheel") pytest" || { say "pip install failed"; exit 1; }
  say "installed $(basename "$wheel") into $(in_root 'cat /etc/debian_version'), glibc \
$(in_root 'ldd --version | head -n 1 | grep -o "[0-9.]*$"')"

  # Nothing resolved outside the wheel but the system's base libraries.
  site=$(in_root "/opt/venv/bin/python -c 'import sysconfig; print(sysconfig.get_paths()[\"platlib\"])'")
  outside=$(in_root "for f in $site/paramorph_native*.so $site/paramorph.libs/*; do ldd \"\$f\"; done" |
    awk -v libs="$site/paramorph.libs/" '
      /=>/ { name = $1; path = $3
             if (path == "not") { print "not found: " name; next }
             if (index(path, libs) == 1) next
             if (name ~ /^(libc|libm|libstdc\+\+|libgcc_s|libz|libpthread|libdl|librt)\.so/) next
             print name " => " path }
      /ld-linux/ && !/=>/ { next }' | sort -u)
  if [ -n "$outside" ]; then
    say "resolved outside the wheel:"
    echo "$outside" >&2
    exit 1
  fi
  say "ldd: only the wheel's libraries and libc/libm/libstdc++/libgcc_s/libz"

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
echo "prove-portable: the wheel is portable to: $suites"

if [ "$blender" = yes ]; then
  [ -x .venv-bpy/bin/python ] || scripts/bpy-venv.sh
  echo "prove-portable: the extension in Blender 4.5 (tests/blender/test_install.py -k release)"
  PARAMORPH_RELEASE_DIR=$(dirname "$wheel") PARAMORPH_REQUIRE_RELEASE=1 \
    .venv-bpy/bin/python -m pytest tests/blender/test_install.py -k release -q -p no:cacheprovider
fi
