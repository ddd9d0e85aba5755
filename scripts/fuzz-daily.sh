#!/usr/bin/env bash
# New fuzz cases every day, outside the CI gate (scripts/test.sh runs fixed
# seeds only, so a commit's verdict does not depend on the date). Run it by
# hand or from a scheduled job; a finding is a bug to fix: copy its case file
# into tests/fuzz/findings/ (named DATE-TARGET-WHAT.pkl) with the fix, so the
# gate replays it from then on.
# Usage: scripts/fuzz-daily.sh [SEED] [SECONDS]   (defaults: today's date, UTC; 300)
set -euo pipefail
cd "$(dirname "$0")/.."
seed=${1:-$(date -u +%Y%m%d)}
seconds=${2:-300}
export PARAMORPH_BUILD_DIR=${PARAMORPH_BUILD_DIR:-build}
[ -d "$PARAMORPH_BUILD_DIR/python" ] || scripts/build.sh paramorph_native
exec /usr/bin/python3 tests/fuzz/fuzz.py --seconds "$seconds" --call-timeout 20 --seed "$seed" --out "out/fuzz/daily-$seed"
