#!/usr/bin/env bash
# Builds paramorph_native and packs the Blender 4.2+ extension:
#   ${PARAMORPH_BUILD_DIR:-build}/paramorph-<version>-linux-x64.zip
# with blender_manifest.toml, the add-on's Python files and the ABI-tagged
# module at the archive root (the layout `blender --command extension build`
# writes; Blender 3.4 has no such command, so Python's zipfile packs it).
# When .venv-bpy exists (scripts/bpy-venv.sh) the archive is checked with
# Blender 4.5's own validator.
# Install: Preferences > Get Extensions > Install from Disk, or
#   blender --command extension install-file -r user_default -e FILE.zip
# Usage: scripts/build-extension.sh
set -euo pipefail
cd "$(dirname "$0")/.."
build_dir=${PARAMORPH_BUILD_DIR:-build}

scripts/build.sh paramorph_native

# The manifest allows Blender 4.2 to 5.0, whose Python is 3.11, on linux-x64.
suffix=$(/usr/bin/python3 -c 'import importlib.machinery as m; print(m.EXTENSION_SUFFIXES[0])')
if [ "$suffix" != ".cpython-311-x86_64-linux-gnu.so" ]; then
  echo "build-extension: /usr/bin/python3 builds '$suffix' modules; the extension needs CPython 3.11 on x86_64" >&2
  exit 1
fi

zip=$(/usr/bin/python3 - "$build_dir" "$build_dir/python/paramorph_native$suffix" <<'EOF'
import os, sys, tomllib, zipfile

build_dir, module = sys.argv[1:]
source = "addon/paramorph"
with open(os.path.join(source, "blender_manifest.toml"), "rb") as f:
    manifest = tomllib.load(f)
(platform,) = manifest["platforms"]
out = os.path.join(build_dir, f"{manifest['id']}-{manifest['version']}-{platform}.zip")

members = []  # (path on disk, name in the archive)
for root, dirs, files in os.walk(source):
    dirs[:] = sorted(d for d in dirs if d != "__pycache__" and not d.startswith("."))
    for name in sorted(files):
        if name.endswith((".pyc", ".so")) or name.startswith("."):
            continue
        path = os.path.join(root, name)
        members.append((path, os.path.relpath(path, source)))
members.append((module, os.path.basename(module)))

tmp = out + ".tmp"
with zipfile.ZipFile(tmp, "w", zipfile.ZIP_DEFLATED) as z:
    for path, name in members:
        z.write(path, name)
os.replace(tmp, out)
print(out)
EOF
)

bpy_cli=""
if [ -x .venv-bpy/bin/python ]; then
  bpy_cli=$(.venv-bpy/bin/python - <<'EOF'
import glob, importlib.util, os
spec = importlib.util.find_spec("bpy")
if spec and spec.origin:
    found = glob.glob(os.path.join(os.path.dirname(spec.origin), "*", "scripts",
                                   "addons_core", "bl_pkg", "cli", "blender_ext.py"))
    print(found[0] if found else "")
EOF
)
fi
if [ -n "$bpy_cli" ]; then
  .venv-bpy/bin/python "$bpy_cli" validate "$zip" | sed 's/^/build-extension: /'
else
  echo "build-extension: not validated (no .venv-bpy; scripts/bpy-venv.sh makes one)"
fi
echo "build-extension: wrote $zip"
