"""The add-on installed the way users install it, checked in a fresh Blender:
scripts/install-addon.sh (legacy add-on, Blender 3.4+) and, from 4.2 on,
the release extension of scripts/release.sh (the wheel under wheels/)
installed with Blender's own "Install from Disk" operator. Each check starts a new Blender (the blender
binary under blender -b, the PyPI module under the bpy venv) whose user
folders are temporary, with the build folder first on sys.path, and asserts
that paramorph_native comes from the installed folder."""
import json
import os
import re
import shutil
import subprocess
import sys
import tomllib
import zipfile

import bpy
import pytest

REPO = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
BUILD = os.path.join(REPO, os.environ.get("PARAMORPH_BUILD_DIR", "build"), "python")

MODULE_SUFFIX = ".cpython-311-x86_64-linux-gnu.so"
MARK = "paramorph-test-result "

# Run inside the fresh Blender: enable, report where everything came from,
# and call the native module on a tetrahedron.
CHECK = r"""
import json, sys
sys.path.insert(0, {build!r})
import addon_utils, bpy
{enable}
import numpy as np
native = sys.modules[{package!r} + ".native"]
pm = native.native
V = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]], dtype=np.float64)
F = np.array([[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]], dtype=np.int32)
print({mark!r} + json.dumps({{
    "version": list(bpy.app.version),
    "enabled": sorted(a.module for a in bpy.context.preferences.addons),
    "package_file": sys.modules[{package!r}].__file__,
    "native_file": getattr(pm, "__file__", None),
    "native_name": getattr(pm, "__name__", None),
    "load_error": native.load_error,
    "top_level_native": "paramorph_native" in sys.modules,
    "closed_genus0": bool(pm.validate(V, F).is_closed_genus0) if pm else None,
    **{extra},
}}))
"""


def user_env(tmp_path):
    """Blender's user folders in tmp_path (empty: factory settings)."""
    env = dict(os.environ)
    for name in ("CONFIG", "SCRIPTS", "EXTENSIONS", "DATAFILES"):
        env[f"BLENDER_USER_{name}"] = str(tmp_path / "user" / name.lower())
    return env


def run_blender(code, env, timeout=120):
    """Runs `code` in a new Blender of the kind running these tests, returns
    the dict it printed after MARK."""
    if bpy.app.binary_path:  # blender -b
        cmd = [bpy.app.binary_path, "-b", "--factory-startup", "--python-exit-code", "1",
               "--python-expr", code]
    else:  # PyPI bpy: the interpreter running pytest
        cmd = [sys.executable, "-c", "import bpy\n" + code]
    proc = subprocess.run(cmd, env=env, capture_output=True, text=True, timeout=timeout)
    output = proc.stdout + proc.stderr
    assert proc.returncode == 0, output[-4000:]
    lines = [line for line in proc.stdout.splitlines() if line.startswith(MARK)]
    assert lines, output[-4000:]
    return json.loads(lines[-1][len(MARK):])


def run_script(name, env):
    proc = subprocess.run([os.path.join(REPO, "scripts", name)], cwd=REPO, env=env,
                          capture_output=True, text=True, timeout=300)
    assert proc.returncode == 0, (proc.stdout + proc.stderr)[-4000:]
    return proc.stdout


def bl_info_version():
    source = open(os.path.join(REPO, "addon", "paramorph", "__init__.py")).read()
    match = re.search(r'"version":\s*\((\d+),\s*(\d+),\s*(\d+)\)', source)
    return ".".join(match.groups())


def manifest():
    with open(os.path.join(REPO, "addon", "paramorph", "blender_manifest.toml"), "rb") as f:
        return tomllib.load(f)


def load_system_floor():
    """addon/paramorph/system_floor.py on its own (it needs no bpy)."""
    import importlib.util
    spec = importlib.util.spec_from_file_location(
        "paramorph_system_floor", os.path.join(REPO, "addon", "paramorph", "system_floor.py"))
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def test_a_system_below_the_wheels_floor_is_told_so_in_plain_words():
    floor = load_system_floor()
    # The wheels' floor is Blender's own: glibc 2.28 (manylinux_2_28).
    assert floor.GLIBC_FLOOR == (2, 28) and floor.WHEEL_POLICY == "manylinux_2_28_x86_64"
    loader = ("/lib/x86_64-linux-gnu/libc.so.6: version `GLIBC_2.28' not found (required by "
              "/home/a/.config/blender/4.5/extensions/.local/lib/python3.11/site-packages/"
              "paramorph_native.cpython-311-x86_64-linux-gnu.so)")
    text = floor.explain_load_failure(loader, glibc=(2, 27), python=(3, 11))
    assert "too old" in text and "glibc) 2.28 or newer" in text and "glibc 2.27" in text
    assert "Traceback" not in text and "not found" not in text
    # Below the floor even when the loader names another symbol first.
    assert "too old" in floor.explain_load_failure("undefined symbol: foo", glibc=(2, 27), python=(3, 11))
    # Debian 11 (glibc 2.31) is above it: no system advice for another fault.
    assert floor.explain_load_failure("undefined symbol: foo", glibc=(2, 31), python=(3, 11)) == ""
    cxx = floor.explain_load_failure("version `GLIBCXX_3.4.30' not found", glibc=(2, 36), python=(3, 11))
    assert "libstdc++" in cxx and "too old" not in cxx
    python = floor.explain_load_failure("No module named 'paramorph_native'", glibc=(2, 36), python=(3, 10))
    assert "Python 3.11 and 3.13" in python and "runs Python 3.10" in python
    # A Python the module is built for: a missing module is no Python mismatch (native.py says how to build).
    assert floor.explain_load_failure("No module named 'paramorph_native'", glibc=(2, 36), python=(3, 13)) == ""
    # Not the system's fault: no advice from here (native.py then says how to build).
    assert floor.explain_load_failure("libfoo.so.1: cannot open shared object file", glibc=(2, 36),
                                      python=(3, 11)) == ""
    # This machine (Debian 12, glibc 2.36) is above the floor.
    assert floor.system_glibc() >= floor.GLIBC_FLOOR


def test_one_version_everywhere():
    cmake = open(os.path.join(REPO, "CMakeLists.txt")).read()
    cmake_version = re.search(r"project\(paramorph VERSION ([0-9.]+)", cmake).group(1)
    m = manifest()
    assert m["version"] == bl_info_version() == cmake_version
    assert (m["schema_version"], m["id"], m["type"]) == ("1.0.0", "paramorph", "add-on")
    assert m["platforms"] == ["linux-x64"] and m["license"] == ["SPDX:GPL-3.0-or-later"]
    assert m["blender_version_min"] == "4.2.0" and "files" in m["permissions"]


def test_install_addon_script_installs_a_legacy_addon(tmp_path):
    blender = bpy.app.binary_path or shutil.which("blender")
    if not blender:
        pytest.skip("install-addon.sh needs a blender binary")
    if not bpy.app.binary_path:
        # PyPI bpy: the script installs into the blender binary on PATH, and
        # the check below loads that install here, with this Python.
        binary_python = subprocess.run(
            [blender, "-b", "--factory-startup", "--python-expr", "import sys; print('python=%d.%d' % sys.version_info[:2])"],
            capture_output=True, text=True, timeout=120).stdout
        here = "python=%d.%d" % sys.version_info[:2]
        if here not in binary_python:
            pytest.skip(f"{blender} runs another Python than this bpy ({here}): its install cannot load here")
    env = user_env(tmp_path)
    env["BLENDER"] = blender
    out = run_script("install-addon.sh", env)

    installed = tmp_path / "user" / "scripts" / "addons" / "paramorph"
    assert f"installed {installed}" in out
    names = sorted(os.listdir(installed))
    sources = [n for n in os.listdir(os.path.join(REPO, "addon", "paramorph"))
               if n not in ("__pycache__", "blender_manifest.toml") and not n.endswith(".pyc")]
    assert names == sorted(sources + ["paramorph_native" + MODULE_SUFFIX]), names
    assert "cli.py" in names  # the batch entry point ships with the add-on

    # A fresh Blender enables it from the user add-on folder as a user does,
    # even with the build folder first on sys.path.
    result = run_blender(CHECK.format(
        build=BUILD, mark=MARK, package="paramorph", extra="{}",
        enable="assert addon_utils.enable('paramorph', default_set=True) is not None"), env)
    assert "paramorph" in result["enabled"]
    assert result["package_file"] == str(installed / "__init__.py")
    assert result["native_file"] == str(installed / ("paramorph_native" + MODULE_SUFFIX)), result
    assert result["native_name"] == "paramorph.paramorph_native"
    assert not result["top_level_native"]
    assert result["closed_genus0"] is True


EXTENSION_ENABLE = r"""
repo = next(r for r in bpy.context.preferences.extensions.repos if r.module == "user_default")
status = bpy.ops.extensions.package_install_files(
    filepath={zip!r}, repo="user_default", enable_on_install=True)
assert status == {{"FINISHED"}}, status
"""


RELEASE_DIR = os.path.join(REPO, os.environ.get("PARAMORPH_RELEASE_DIR", "dist"))

# Run inside a fresh Blender with the release extension installed and no
# build folder on sys.path: the four tools an artist reaches first, each on a
# small scene, through the add-on's operators.
RELEASE_CHECK = r"""
import json, sys
sys.path.insert(0, {samples!r})
import bpy
{enable}
import numpy as np
import make_samples
package = "bl_ext.user_default.paramorph"
native = sys.modules[package + ".native"]
regions = sys.modules[package + ".regions"]
pm = native.native
out = {{"load_error": native.load_error, "native_file": getattr(pm, "__file__", None),
        "build_info": pm.build_info() if pm else None, "repo_dir": repo.directory}}

def activate(*objects):
    if bpy.context.object and bpy.context.object.mode != "OBJECT":
        bpy.ops.object.mode_set(mode="OBJECT")
    for other in bpy.context.view_layer.objects:
        other.select_set(other in objects)
    bpy.context.view_layer.objects.active = objects[-1]

bpy.ops.mesh.primitive_ico_sphere_add(subdivisions=3)
out["sphere_map"] = sorted(bpy.ops.paramorph.sphere_map())
out["sphere_uv"] = "Sphere" in bpy.context.active_object.data.uv_layers

bpy.ops.mesh.primitive_grid_add(x_subdivisions=10, y_subdivisions=10, size=2.0)
bpy.ops.object.mode_set(mode="EDIT")
bpy.ops.mesh.select_all(action="SELECT")
out["unwrap"] = sorted(bpy.ops.paramorph.isometric_unwrap())
bpy.ops.object.mode_set(mode="OBJECT")

source = make_samples.build_blob(subdivisions=3)
target = make_samples.build_octopus(subdivisions=3, limbs=4)
target.location = (4.0, 0.0, 0.0)
activate(source, target)
before = set(bpy.data.objects)
out["morph_to"] = sorted(bpy.ops.paramorph.morph_to(topology="MERGED"))
made = list(set(bpy.data.objects) - before)
out["morph_keys"] = len(made[0].data.shape_keys.key_blocks) if made and made[0].data.shape_keys else 0

plate = make_samples.build_boss_plate()
centres = np.empty(3 * len(plate.data.polygons), dtype=np.float32)
plate.data.polygons.foreach_get("center", centres)
ball = np.array(make_samples.BOSS_BALL)
regions.select_polygons(plate.data, np.linalg.norm(centres.reshape(-1, 3) - ball[:3], axis=1) <= ball[3])
activate(plate)
bpy.ops.object.mode_set(mode="EDIT")
bpy.context.tool_settings.mesh_select_mode = (False, False, True)
out["copy_feature"] = sorted(bpy.ops.paramorph.copy_feature())
bpy.ops.object.mode_set(mode="OBJECT")
bpy.ops.mesh.primitive_uv_sphere_add(segments=64, ring_count=32, radius=1.6)
sphere = bpy.context.active_object
activate(sphere)
faces_before = len(sphere.data.polygons)
out["paste_feature"] = sorted(bpy.ops.paramorph.paste_feature(location=(0.0, 0.0, 1.6)))
out["pasted_faces"] = len(sphere.data.polygons) - faces_before
print({mark!r} + json.dumps(out))
"""


def release_zip():
    """The extension scripts/release.sh made; CI (scripts/test.sh) makes it
    first and sets PARAMORPH_REQUIRE_RELEASE=1, so a missing one fails there."""
    m = manifest()
    path = os.path.join(RELEASE_DIR, f"paramorph-{m['version']}-linux-x64.zip")
    if not os.path.exists(path):
        if os.environ.get("PARAMORPH_REQUIRE_RELEASE") == "1":
            pytest.fail(f"{path} is missing: scripts/release.sh did not make it")
        pytest.skip("no release extension: run scripts/release.sh")
    return path


@pytest.mark.skipif(bpy.app.version < (4, 2, 0), reason="extensions arrived in Blender 4.2")
def test_the_release_zip_carries_the_wheel_licences_and_no_loose_module():
    zip_path = release_zip()
    with zipfile.ZipFile(zip_path) as z:
        names = sorted(z.namelist())
        manifest_text = z.read("blender_manifest.toml").decode()
        wheels = sorted(n for n in names if n.startswith("wheels/"))
        # One wheel for Blender 4.2-5.0 (CPython 3.11), one for 5.1 and later (3.13).
        assert [re.fullmatch(r"wheels/paramorph-[0-9.]+-(cp3\d+)-\1-manylinux_2_28_x86_64\.whl", n).group(1)
                for n in wheels] == ["cp311", "cp313"], wheels
        wheel_bytes = {n: z.read(n) for n in wheels}
    assert tomllib.loads(manifest_text)["wheels"] == ["./" + n for n in wheels]
    assert not [n for n in names if n.endswith(".so") or ".so." in n], names  # the module only in the wheels
    assert "LICENSE" in names and "__init__.py" in names and "system_floor.py" in names
    assert "licenses/third_party/README" in names and any(n.endswith(".copyright") for n in names), names
    assert not [n for n in names if "__pycache__" in n or n.endswith(".pyc")], names
    import io
    for name, data in wheel_bytes.items():
        with zipfile.ZipFile(io.BytesIO(data)) as w:
            inside = w.namelist()
            readme = w.read(next(n for n in inside if n.endswith("licenses/third_party/README"))).decode()
        assert any(n.endswith("/licenses/LICENSE") for n in inside), name
        # Everything is linked into the module (manylinux_2_28 by zig): nothing vendored beside it,
        # and a licence text for each library linked in, none for Ipopt/MUMPS (not linked).
        assert not [n for n in inside if n.startswith("paramorph.libs/")], inside
        texts = {os.path.basename(n) for n in inside if "/licenses/third_party/" in n} - {"README"}
        for library in ("suitesparse", "openblas", "metis", "qhull", "opensubdiv", "gmp", "mpfr4",
                        "llvm-toolchain-19", "libcxx", "libcgal-dev"):
            assert any(t.startswith(library + ".") for t in texts), (library, texts)
            assert any(line.strip().startswith(library + ".") for line in readme.splitlines()), library
        assert not [n for n in inside if re.search(r"ipopt|mumps|coinmumps", n, re.I)], inside

    # Blender's own validator accepts the archive.
    import importlib.util
    cli = os.path.join(os.path.dirname(importlib.util.find_spec("bl_pkg").origin), "cli", "blender_ext.py")
    proc = subprocess.run([sys.executable, cli, "validate", zip_path], capture_output=True, text=True, timeout=60)
    assert proc.returncode == 0, proc.stdout + proc.stderr


@pytest.mark.skipif(bpy.app.version < (4, 2, 0), reason="extensions arrived in Blender 4.2")
def test_the_release_extension_installs_and_its_tools_run(tmp_path):
    zip_path = release_zip()
    env = user_env(tmp_path)
    result = run_blender(RELEASE_CHECK.format(
        samples=os.path.join(REPO, "blend_samples"), mark=MARK, enable=EXTENSION_ENABLE.format(zip=zip_path)),
        env, timeout=600)
    assert result["load_error"] == "", result["load_error"]
    # The module is the wheel's, installed into the extensions' site-packages.
    extensions = str(tmp_path / "user" / "extensions")
    assert result["native_file"].startswith(extensions) and "site-packages" in result["native_file"], result
    assert result["build_info"]["ipopt"] is False  # what is distributed carries no Ipopt
    assert result["sphere_map"] == ["FINISHED"] and result["sphere_uv"]
    assert result["unwrap"] == ["FINISHED"]
    assert result["morph_to"] == ["FINISHED"] and result["morph_keys"] >= 3
    assert result["copy_feature"] == ["FINISHED"]
    assert result["paste_feature"] == ["FINISHED"] and result["pasted_faces"] > 0


MISSING_NATIVE = r"""
import json, sys
import addon_utils, bpy
assert addon_utils.enable('paramorph', default_set=True) is not None
native = sys.modules['paramorph.native']
bpy.ops.mesh.primitive_ico_sphere_add()
try:
    bpy.ops.paramorph.sphere_map()
    report = ""
except RuntimeError as error:
    report = str(error)
print({mark!r} + json.dumps({{
    "enabled": sorted(a.module for a in bpy.context.preferences.addons),
    "native_missing": native.native is None,
    "load_error": native.load_error,
    "panel": hasattr(bpy.types, "PARAMORPH_PT_main"),
    "report": report,
}}))
"""


def test_without_its_native_module_the_addon_loads_and_says_how_to_build_it(tmp_path):
    env = user_env(tmp_path)
    installed = tmp_path / "user" / "scripts" / "addons" / "paramorph"
    shutil.copytree(os.path.join(REPO, "addon", "paramorph"), installed,
                    ignore=shutil.ignore_patterns("*.so", "__pycache__"))
    result = run_blender(MISSING_NATIVE.format(mark=MARK), env)  # no build folder on sys.path
    assert "paramorph" in result["enabled"] and result["panel"]
    assert result["native_missing"]
    assert "scripts/build.sh" in result["load_error"]
    assert "could not be loaded" in result["report"] and "scripts/build.sh" in result["report"]
