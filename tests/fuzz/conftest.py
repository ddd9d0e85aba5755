"""pytest setup for tests/fuzz: the fuzz driver's modules (this folder) and the
built paramorph_native ($PARAMORPH_BUILD_DIR/python, default build/) on sys.path."""
import os
import sys
from pathlib import Path

HERE = Path(__file__).resolve().parent
REPO = HERE.parents[1]
sys.path.insert(0, str(HERE))
sys.path.insert(0, str(REPO / os.environ.get("PARAMORPH_BUILD_DIR", "build") / "python"))
