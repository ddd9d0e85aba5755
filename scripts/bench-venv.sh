#!/usr/bin/env bash
# Creates .venv-bench, the benchmarks' own virtual environment, with libigl from
# PyPI as the reference solver (SLIM, ARAP, LSCM) for tests/bench/planar.py.
# System site packages stay visible so the venv uses Debian's numpy, the one
# paramorph_native was built against; pip is told to keep it (a constraint
# pins numpy to the system version, so pip may not upgrade it inside the venv).
# Usage: scripts/bench-venv.sh        then: .venv-bench/bin/python tests/bench/planar.py
set -euo pipefail
cd "$(dirname "$0")/.."

venv=.venv-bench
if [ ! -x "$venv/bin/python" ]; then
  /usr/bin/python3 -m venv --system-site-packages "$venv"
fi

numpy_version=$(/usr/bin/python3 -c 'import numpy; print(numpy.__version__)')
constraints=$(mktemp)
trap 'rm -f "$constraints"' EXIT
echo "numpy==$numpy_version" > "$constraints"

"$venv/bin/python" -m pip install --quiet --upgrade pip
"$venv/bin/python" -m pip install --quiet -c "$constraints" libigl
"$venv/bin/python" -c 'from importlib.metadata import version; print("bench-venv: libigl", version("libigl"), "numpy", version("numpy"))'
