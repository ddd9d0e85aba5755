#!/usr/bin/env bash
# Installs the Debian packages paramorph needs, skipping those already present.
# Usage: scripts/install-deps.sh   (as root, or with sudo available)
# libopenblas0-serial becomes the system BLAS (update-alternatives): Ipopt's
# MUMPS spends most of its time in dgemm, 2-3x slower with the reference BLAS;
# the serial build, because threads only contend on small fronts.
# ccache lets the release's wheel build (scripts/release.sh) reuse build/'s
# objects; debootstrap makes the clean roots of scripts/prove-portable.sh.
set -euo pipefail

packages=(
  build-essential cmake pkg-config
  python3-dev python3-numpy python3-pytest pybind11-dev
  libeigen3-dev libmetis-dev libsuitesparse-dev
  ocl-icd-opencl-dev opencl-headers opencl-clhpp-headers pocl-opencl-icd
  coinor-libipopt-dev libosd-dev libqhull-dev libcgal-dev
  libopenblas0-serial
  libgtest-dev
  blender xvfb xauth
  ccache debootstrap
)

missing=()
for p in "${packages[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$p")
  fi
done

if [ ${#missing[@]} -eq 0 ]; then
  echo "install-deps: all ${#packages[@]} packages already installed"
  exit 0
fi

echo "install-deps: installing ${missing[*]}"
sudo_cmd=()
[ "$(id -u)" -eq 0 ] || sudo_cmd=(sudo)
export DEBIAN_FRONTEND=noninteractive
"${sudo_cmd[@]}" apt-get update -qq
"${sudo_cmd[@]}" apt-get install -y -qq --no-install-recommends "${missing[@]}"
