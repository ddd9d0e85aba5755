#!/usr/bin/env bash
# Creates a venv with Blender as a Python module (PyPI `bpy`) and pytest, so
# tests/blender also runs against it:
#   scripts/bpy-venv.sh       .venv-bpy:   bpy 4.5 (cp311), numpy < 2
#     PARAMORPH_BUILD_DIR=build .venv-bpy/bin/python -m pytest tests/blender -q -p no:cacheprovider
#   scripts/bpy-venv.sh 5.2   .venv-bpy52: bpy 5.2 (cp313), numpy 2
#     PARAMORPH_PYTHON=3.13 scripts/build.sh   # the module for CPython 3.13, into build-cp313
#     PARAMORPH_BUILD_DIR=build-cp313 .venv-bpy52/bin/python -m pytest tests/blender -q -p no:cacheprovider
# bpy 4.5 wheels are cp311 and so is Debian's /usr/bin/python3, the Python the
# default build's module is built for: one paramorph_native*.so serves both.
# bpy 5.2 wheels are cp313 (Blender 5.1 and later embed CPython 3.13): that
# venv is made with a CPython 3.13 found as scripts/python-for.sh says, and
# takes the module built for it with a pybind11 that reads NumPy 2.
# Idempotent: a venv that already has the series' bpy is kept (the 5.2 wheel
# is about 400 MB). Installs the X11/GL client libraries bpy links against
# (even headless) with apt-get when they are missing. Exits 0 with
# "skipped: ..." when PyPI cannot be reached.   Usage: scripts/bpy-venv.sh [4.5|5.2]
set -euo pipefail
cd "$(dirname "$0")/.."
source scripts/python-for.sh

series=${1:-4.5}
case "$series" in
  # Debian 12's pybind11 (the default build's) reads NumPy 2 arrays wrongly.
  4.5) venv=.venv-bpy interpreter=/usr/bin/python3 numpy_major=1
       requirements=("bpy==4.5.*" "numpy<2" "pytest") ;;
  # Blender 5.x ships NumPy 2; the cp313 module is built with PyPI's pybind11.
  5.2) venv=.venv-bpy52 interpreter="" numpy_major=2
       requirements=("bpy==5.2.*" "numpy>=2,<3" "pytest") ;;
  *) echo "bpy-venv: unknown series '$series' (4.5 or 5.2)" >&2; exit 2 ;;
esac

# System libraries bpy 4.5 and 5.2 link against (`ldd` on bpy/__init__.so and
# bpy/lib/*.so, Debian 12), by Debian package; the rest ships in the wheel.
# libXxf86vm is no longer among them; EGL/Wayland are only dlopen'ed.
x11_packages=(
  libx11-6 libxext6 libxrender1 libxi6 libxfixes3 libxkbcommon0
  libsm6 libice6 libxt6 libgl1
)

missing=()
for p in "${x11_packages[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$p")
  fi
done
if [ ${#missing[@]} -gt 0 ]; then
  echo "bpy-venv: installing ${missing[*]}"
  sudo_cmd=()
  [ "$(id -u)" -eq 0 ] || sudo_cmd=(sudo)
  export DEBIAN_FRONTEND=noninteractive
  "${sudo_cmd[@]}" apt-get update -qq
  "${sudo_cmd[@]}" apt-get install -y -qq --no-install-recommends "${missing[@]}"
fi

installed() {
  [ -x "$venv/bin/python" ] && "$venv/bin/python" - "$series" "$numpy_major" <<'EOF' 2>/dev/null
import sys
from importlib.metadata import version
series, numpy_major = sys.argv[1], sys.argv[2]
ok = version("bpy").startswith(series + ".") and version("numpy").split(".")[0] == numpy_major
version("pytest")
sys.exit(0 if ok else 1)
EOF
}

if installed; then
  echo "bpy-venv: $venv already has bpy $("$venv/bin/python" -c 'from importlib.metadata import version; print(version("bpy"))')"
else
  index=${PIP_INDEX_URL:-https://pypi.org/simple}
  if ! /usr/bin/python3 - "$index" <<'EOF'
import sys, urllib.request
try:
    urllib.request.urlopen(sys.argv[1].rstrip("/") + "/bpy/", timeout=15).read(1)
except Exception as error:
    print(f"bpy-venv: {sys.argv[1]} unreachable ({error})")
    sys.exit(1)
EOF
  then
    echo "bpy-venv: skipped: PyPI is unreachable, $venv not created"
    exit 0
  fi
  [ -n "$interpreter" ] || interpreter=$(python_for 3.13)
  [ -x "$venv/bin/python" ] || "$interpreter" -m venv "$venv"
  "$venv/bin/python" -m pip install --quiet --upgrade pip
  "$venv/bin/python" -m pip install --quiet "${requirements[@]}"
fi

# bpy reads the user's extension folders at import: keep this check away from them.
scratch=$(mktemp -d)
trap 'rm -rf "$scratch"' EXIT
BLENDER_USER_EXTENSIONS="$scratch/extensions" BLENDER_USER_SCRIPTS="$scratch/scripts" \
BLENDER_USER_CONFIG="$scratch/config" \
  "$venv/bin/python" -c 'import bpy, numpy, pytest; print("bpy-venv: bpy", bpy.app.version_string, "numpy", numpy.__version__, "pytest", pytest.__version__)'
