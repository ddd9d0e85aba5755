"""The add-on installed the way users install it, checked in a fresh Blender:
scripts/install-addon.sh (legacy add-on, Blender 3.4+) and, from 4.2 on,
the extension zip of scripts/build-extension.sh installed with Blender's own
"Install from Disk" operator. Each check starts a new Blender (the blender
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


@pytest.mark.skipif(bpy.app.version < (4, 2, 0), reason="extensions arrived in Blender 4.2")
def test_extension_zip_installs_enables_and_loads_its_module(tmp_path):
    env = user_env(tmp_path)
    out = run_script("build-extension.sh", env)
    m = manifest()
    zip_path = os.path.join(REPO, os.environ.get("PARAMORPH_BUILD_DIR", "build"),
                            f"paramorph-{m['version']}-linux-x64.zip")
    assert f"wrote {os.path.relpath(zip_path, REPO)}" in out
    with zipfile.ZipFile(zip_path) as z:
        names = sorted(z.namelist())
    assert "blender_manifest.toml" in names and "__init__.py" in names
    assert "paramorph_native" + MODULE_SUFFIX in names and "cli.py" in names
    assert not [n for n in names if "__pycache__" in n or n.endswith(".pyc")], names

    # Blender's own validator accepts the archive.
    import importlib.util
    cli = os.path.join(os.path.dirname(importlib.util.find_spec("bl_pkg").origin),
                       "cli", "blender_ext.py")
    proc = subprocess.run([sys.executable, cli, "validate", zip_path],
                          capture_output=True, text=True, timeout=60)
    assert proc.returncode == 0, proc.stdout + proc.stderr

    package = "bl_ext.user_default.paramorph"
    result = run_blender(CHECK.format(
        build=BUILD, mark=MARK, package=package, enable=EXTENSION_ENABLE.format(zip=zip_path),
        extra='{"repo_dir": repo.directory}'), env)
    folder = os.path.join(result["repo_dir"], "paramorph")
    assert result["repo_dir"] == str(tmp_path / "user" / "extensions" / "user_default")
    assert package in result["enabled"]
    assert result["package_file"] == os.path.join(folder, "__init__.py")
    assert result["native_file"] == os.path.join(folder, "paramorph_native" + MODULE_SUFFIX), result
    assert result["native_name"] == package + ".paramorph_native"
    assert not result["top_level_native"]
    assert result["closed_genus0"] is True


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
