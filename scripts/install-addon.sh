#!/usr/bin/env bash
# Builds paramorph_native and installs the add-on as users install it: a legacy
# add-on (bl_info) in the user add-on folder of Debian's Blender, with the
# ABI-tagged module (paramorph_native.cpython-311-x86_64-linux-gnu.so) inside.
#
# Usage: scripts/install-addon.sh [ADDONS_DIR]
#   ADDONS_DIR           default: what Blender reports for
#                        bpy.utils.user_resource("SCRIPTS", path="addons"), so
#                        BLENDER_USER_SCRIPTS=DIR installs into DIR/addons
#   BLENDER              the Blender binary (default: blender)
#   PARAMORPH_BUILD_DIR  build folder (default: build)
# Then turn it on in Preferences > Add-ons, or:
#   blender -b --python-expr "import addon_utils, bpy; addon_utils.enable('paramorph', default_set=True); bpy.ops.wm.save_userpref()"
set -euo pipefail
cd "$(dirname "$0")/.."
build_dir=${PARAMORPH_BUILD_DIR:-build}
blender=${BLENDER:-blender}

scripts/build.sh paramorph_native

# One Blender start for the user add-on folder and its Python's module suffix.
info=$("$blender" -b --factory-startup --python-exit-code 1 --python-expr '
import importlib.machinery, sys, bpy
print("paramorph-info addons=" + bpy.utils.user_resource("SCRIPTS", path="addons"))
print("paramorph-info suffix=" + importlib.machinery.EXTENSION_SUFFIXES[0])
print("paramorph-info python=%d.%d" % sys.version_info[:2])
')
field() { sed -n "s/^paramorph-info $1=//p" <<<"$info"; }
addons=${1:-$(field addons)}
suffix=$(field suffix)
python=$(field python)
if [ -z "$addons" ] || [ -z "$suffix" ]; then
  echo "install-addon: could not ask $blender for its add-on folder:" >&2
  echo "$info" >&2
  exit 1
fi
addons=$(realpath -m "$addons")

module="$build_dir/python/paramorph_native$suffix"
if [ ! -f "$module" ]; then
  echo "install-addon: $module is missing: Blender runs Python $python, the build has:" >&2
  ls "$build_dir"/python/paramorph_native*.so >&2 || true
  exit 1
fi

dest="$addons/paramorph"
rm -rf "$dest"
mkdir -p "$dest"
# The add-on's Python files and subfolders; the manifest is for the extension only.
tar -C addon/paramorph --exclude=__pycache__ --exclude='*.pyc' \
  --exclude=blender_manifest.toml --exclude='paramorph_native*.so' -cf - . | tar -C "$dest" -xf -
install -m 755 "$module" "$dest/"

# Check the installed copy: it enables and loads its own module.
PARAMORPH_ADDONS=$addons "$blender" -b --factory-startup --python-exit-code 1 --python-expr "
import os, sys, addon_utils
sys.path.insert(0, os.environ['PARAMORPH_ADDONS'])
mod = addon_utils.enable('paramorph')
from paramorph import native
if mod is None or native.native is None:
    raise SystemExit('install-addon: the installed add-on does not load: ' + native.load_error)
print('paramorph-info loaded=' + native.native.__file__)
" | sed -n 's/^paramorph-info loaded=/install-addon: paramorph_native loads from /p'
echo "install-addon: installed $dest"
