"""Puts the built paramorph_native (PARAMORPH_BUILD_DIR, default "build") and the
shared test-mesh factory on sys.path."""
import os
import sys
from pathlib import Path

REPO = Path(__file__).resolve().parents[2]
BUILD = REPO / os.environ.get("PARAMORPH_BUILD_DIR", "build") / "python"
sys.path.insert(0, str(BUILD))
sys.path.insert(0, str(Path(__file__).resolve().parent))

try:
    import paramorph_native  # noqa: F401
except ImportError as error:  # pragma: no cover - the message is the point
    raise ImportError(
        f"paramorph_native not found in {BUILD}: build first (scripts/build.sh) or set "
        f"PARAMORPH_BUILD_DIR ({error})"
    ) from error
