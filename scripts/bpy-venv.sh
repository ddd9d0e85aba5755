#!/usr/bin/env bash
# Creates .venv-bpy: Blender 4.5 as a Python module (PyPI `bpy`), numpy < 2 and
# pytest, so tests/blender also runs against 4.5:
#   PARAMORPH_BUILD_DIR=build .venv-bpy/bin/python -m pytest tests/blender -q -p no:cacheprovider
# bpy 4.5 wheels are cp311 and so is Debian's /usr/bin/python3, the Python the
# native module is built for: one paramorph_native*.so serves both.
# Idempotent. Installs the X11/GL client libraries bpy links against (even
# headless) with apt-get when they are missing. Exits 0 with "skipped: ..."
# when PyPI cannot be reached.   Usage: scripts/bpy-venv.sh
set -euo pipefail
cd "$(dirname "$0")/.."

venv=.venv-bpy
requirements=("bpy==4.5.*" "numpy<2" "pytest")

# System libraries bpy 4.5 links against (`ldd` on bpy/__init__.so and
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
  [ -x "$venv/bin/python" ] && "$venv/bin/python" - <<'EOF' 2>/dev/null
import sys
from importlib.metadata import version
ok = version("bpy").startswith("4.5.") and int(version("numpy").split(".")[0]) < 2
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
  [ -x "$venv/bin/python" ] || /usr/bin/python3 -m venv "$venv"
  "$venv/bin/python" -m pip install --quiet --upgrade pip
  "$venv/bin/python" -m pip install --quiet "${requirements[@]}"
fi

# bpy reads the user's extension folders at import: keep this check away from them.
scratch=$(mktemp -d)
trap 'rm -rf "$scratch"' EXIT
BLENDER_USER_EXTENSIONS="$scratch/extensions" BLENDER_USER_SCRIPTS="$scratch/scripts" \
BLENDER_USER_CONFIG="$scratch/config" \
  "$venv/bin/python" -c 'import bpy, numpy, pytest; print("bpy-venv: bpy", bpy.app.version_string, "numpy", numpy.__version__, "pytest", pytest.__version__)'
