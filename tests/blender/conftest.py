"""Inside blender -b: the built module, the add-on and the sample builders on sys.path."""
import os
import sys

REPO = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
BUILD = os.path.join(REPO, os.environ.get("PARAMORPH_BUILD_DIR", "build"), "python")
for path in (BUILD, os.path.join(REPO, "addon"), os.path.join(REPO, "blend_samples")):
    if path not in sys.path:
        sys.path.insert(0, path)
