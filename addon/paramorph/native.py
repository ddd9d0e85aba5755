"""Loads paramorph_native: from this package (the ABI-tagged .so that
scripts/install-addon.sh installs, imported relatively, so it works under any
package name) first, else the top-level module from sys.path: the wheel a
release extension carries (Blender installs it into the extension's
site-packages), or the build folder in development. `native` is None
when it cannot load, and `load_error` says why, so the add-on still loads
and can tell the user."""
import importlib

from .system_floor import explain_load_failure

native = None
load_error = ""

try:
    native = importlib.import_module(".paramorph_native", __package__)
except ImportError as error:
    if isinstance(error, ModuleNotFoundError) and error.name == f"{__package__}.paramorph_native":
        # No .so in this package (running from the source tree): the build folder.
        try:
            native = importlib.import_module("paramorph_native")
        except ImportError as fallback_error:
            load_error = str(fallback_error)
    else:  # a .so is here but does not load (wrong Python, missing library)
        load_error = str(error)
if native is None:  # shown in the panels and reports
    # A system or Blender too old for the released wheel, in plain words;
    # otherwise the loader's own message and what a source checkout does.
    load_error = explain_load_failure(load_error) or (
        f"paramorph_native could not be loaded ({load_error}); build it with "
        "scripts/build.sh and install the add-on again")
