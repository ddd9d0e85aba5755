"""pytest setup for tests/native: puts the built paramorph_native module and the
shared test-mesh factory (meshes.py, next to this file) on sys.path.

The module is looked for in <repo>/$PARAMORPH_BUILD_DIR/python
(PARAMORPH_BUILD_DIR is relative to the repository root, default "build").
"""
import os
import sys
from pathlib import Path

import pytest

HERE = Path(__file__).resolve().parent
REPO = HERE.parents[1]
BUILD = REPO / os.environ.get("PARAMORPH_BUILD_DIR", "build") / "python"

sys.path.insert(0, str(HERE))   # `import meshes`
sys.path.insert(0, str(BUILD))  # `import paramorph_native`

try:
    import paramorph_native  # noqa: F401
except ImportError as error:  # pragma: no cover - the message is the point
    pytest.exit(
        f"cannot import paramorph_native from {BUILD} ({error}).\n"
        f"Build it first (cmake -S . -B build && cmake --build build), or point "
        f"PARAMORPH_BUILD_DIR at your build directory (relative to {REPO}); the Python "
        f"running the tests ({sys.executable}, {sys.version.split()[0]}) must match the one "
        f"the module was built for.",
        returncode=4,
    )
