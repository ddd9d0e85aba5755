"""The pytest side of tests/gui: runs a window script (gui_session.py) in a
real Blender under Xvfb and returns the stats it wrote."""
import json
import os
import shutil
import subprocess

import pytest

REPO = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))

needs_window = pytest.mark.skipif(shutil.which("xvfb-run") is None or shutil.which("blender") is None,
                                  reason="needs xvfb-run and blender (scripts/install-deps.sh installs both)")


def run_in_window(tmp_path, script, report, simulate_events=False):
    """Runs tests/gui/<script> in a window (simulated input if asked) with
    OUT_DIR = tmp_path; returns the stats it wrote to tmp_path/<report>."""
    # Factory settings in a window open the first-run splash over the
    # viewport: start from saved preferences (in a temp folder) without it.
    env = dict(os.environ, BLENDER_USER_CONFIG=str(tmp_path / "config"),
               BLENDER_USER_SCRIPTS=str(tmp_path / "scripts"))
    subprocess.run(["blender", "-b", "--factory-startup", "--python-exit-code", "1", "--python-expr",
                    "import bpy; bpy.context.preferences.view.show_splash = False; "
                    "bpy.ops.wm.save_userpref()"], env=env, check=True, capture_output=True, timeout=120)
    command = ["xvfb-run", "-a", "-s", "-screen 0 1280x800x24", "blender"]
    command += ["--enable-event-simulate"] if simulate_events else []
    command += ["--python", os.path.join(REPO, "tests", "gui", script), "--", str(tmp_path)]
    run = subprocess.run(command, cwd=REPO, env=env, capture_output=True, text=True, timeout=600)
    path = tmp_path / report
    assert path.exists(), run.stdout[-3000:] + run.stderr[-3000:]
    stats = json.loads(path.read_text())
    stacks = tmp_path / "stacks.txt"
    if stacks.exists():  # a wait gave up (gui_session.wait_while): shown with the failure
        print("Python stacks where a wait gave up:\n" + stacks.read_text()[-6000:])
    assert "error" not in stats, stats["error"]
    return stats
