"""Loads paramorph_native: from this folder (an ABI-tagged .so installed with
the add-on) first, else from sys.path. `native` is None when it cannot load,
and `load_error` says why, so the add-on still loads and can tell the user."""
import importlib
import os
import sys

native = None
load_error = ""

_here = os.path.dirname(os.path.abspath(__file__))
if _here not in sys.path:
    sys.path.insert(0, _here)
try:
    native = importlib.import_module("paramorph_native")
except ImportError as error:  # shown in the panels and reports
    load_error = (f"paramorph_native could not be loaded ({error}); build it with "
                  "scripts/build.sh and install the add-on again")
