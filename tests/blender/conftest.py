"""Inside blender -b, or in a Python with the PyPI `bpy` module
(scripts/bpy-venv.sh): the built module, the add-on and the sample builders
on sys.path."""
import os
import sys
import tempfile

REPO = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
BUILD = os.path.join(REPO, os.environ.get("PARAMORPH_BUILD_DIR", "build"), "python")

if "bpy" not in sys.modules:
    # The PyPI module: Blender starts at `import bpy` and reads the user's
    # preferences, scripts and extensions then (and puts the extensions'
    # site-packages on sys.path). Point it at empty folders first, as
    # --factory-startup does for the blender binary.
    _user = tempfile.TemporaryDirectory(prefix="paramorph-bpy-user-")
    for name, sub in (("CONFIG", "config"), ("SCRIPTS", "scripts"),
                      ("EXTENSIONS", "extensions"), ("DATAFILES", "datafiles")):
        os.environ.setdefault(f"BLENDER_USER_{name}", os.path.join(_user.name, sub))
    # Importing bpy is what puts Blender's scripts/modules (addon_utils,
    # bpy_extras) on sys.path; the blender binary has them from the start.
    import bpy  # noqa: F401,E402

for path in (BUILD, os.path.join(REPO, "addon"), os.path.join(REPO, "blend_samples")):
    if path not in sys.path:
        sys.path.insert(0, path)


import pytest  # noqa: E402


@pytest.fixture
def empty_scene():
    """Factory settings with no objects, before and after the test (the
    tests that run scripts in a fresh Blender start from and leave this)."""
    import bpy
    bpy.ops.wm.read_factory_settings(use_empty=True)
    yield
    bpy.ops.wm.read_factory_settings(use_empty=True)


@pytest.fixture
def addon_scene():
    """An empty scene with the add-on enabled as a user enables it."""
    import addon_utils
    import bpy
    bpy.ops.wm.read_factory_settings(use_empty=True)
    addon_utils.enable("paramorph", default_set=True)
    yield
    addon_utils.disable("paramorph", default_set=True)
