"""Runs a Python script in a fresh Blender of the kind running the tests, as
`blender -b --python SCRIPT -- ARGS` would:

- inside `blender -b` (Debian's 3.4): `bpy.app.binary_path -b --factory-startup
  --python-exit-code 1 --python SCRIPT -- ARGS`;
- under the PyPI `bpy` module (4.5), which has no blender binary
  (`bpy.app.binary_path` is ""): the interpreter running the tests imports
  bpy, sets sys.argv to `[SCRIPT, "--", *ARGS]` and runs SCRIPT as __main__
  (runpy), the module's equivalent of --python. Exit status, stdout and
  stderr are the script's own in both cases.

Blender's user folders point to a temporary folder, so no user preferences
or add-ons leak in."""
import os
import subprocess
import sys

import bpy

RUN_AS_MAIN = ("import runpy, sys, bpy\n"
               "script = sys.argv[1]\n"
               "sys.argv = [script, '--', *sys.argv[2:]]\n"
               "runpy.run_path(script, run_name='__main__')\n")


def user_env(folder):
    env = dict(os.environ)
    for name in ("CONFIG", "SCRIPTS", "EXTENSIONS", "DATAFILES"):
        env[f"BLENDER_USER_{name}"] = os.path.join(str(folder), "user", name.lower())
    return env


def command(script, args):
    args = [str(a) for a in args]
    if bpy.app.binary_path:
        return [bpy.app.binary_path, "-b", "--factory-startup", "--python-exit-code", "1",
                "--python", str(script), "--", *args]
    return [sys.executable, "-c", RUN_AS_MAIN, str(script), *args]


def run(script, args, folder, timeout=120):
    """subprocess.CompletedProcess (text) of SCRIPT run with ARGS in a fresh Blender."""
    return subprocess.run(command(script, args), env=user_env(folder), capture_output=True,
                          text=True, timeout=timeout)
