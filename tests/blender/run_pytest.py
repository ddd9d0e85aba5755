"""Runs pytest inside Blender:
    blender -b --factory-startup --python-exit-code 1 --python tests/blender/run_pytest.py -- ARGS"""
import os
import sys

import pytest

REPO = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
args = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else ["tests/blender"]
code = pytest.main(["-p", "no:cacheprovider", *args])
sys.exit(int(code))
