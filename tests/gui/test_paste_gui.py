"""Paste Feature in a real Blender window under Xvfb (tests/gui/paste_gui.py):
undo (which needs a window) takes a paste back in one step, and the modal
tool, driven by simulated events (--enable-event-simulate), draws its
preview, leaves the mesh untouched when cancelled and writes it on Enter."""
import json
import os
import shutil
import subprocess

import pytest

REPO = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))


def has_paste_session():
    """Whether the build's module has PasteSession (asked in a plain Python: no bpy here)."""
    build = os.path.join(REPO, os.environ.get("PARAMORPH_BUILD_DIR", "build"), "python")
    probe = subprocess.run(["/usr/bin/python3", "-c", "import sys; sys.path.insert(0, sys.argv[1]); "
                            "import paramorph_native as pm; print(hasattr(pm, 'PasteSession'))", build],
                           capture_output=True, text=True, timeout=60)
    return probe.stdout.strip() == "True"


@pytest.mark.skipif(shutil.which("xvfb-run") is None or shutil.which("blender") is None,
                    reason="needs xvfb-run and blender (scripts/install-deps.sh installs both)")
def test_paste_feature_modal_tool_preview_cancel_confirm_and_undo(tmp_path):
    if not has_paste_session():
        pytest.skip("this build has no PasteSession")
    env = dict(os.environ, BLENDER_USER_CONFIG=str(tmp_path / "config"),
               BLENDER_USER_SCRIPTS=str(tmp_path / "scripts"))
    subprocess.run(["blender", "-b", "--factory-startup", "--python-exit-code", "1", "--python-expr",
                    "import bpy; bpy.context.preferences.view.show_splash = False; "
                    "bpy.ops.wm.save_userpref()"], env=env, check=True, capture_output=True, timeout=120)
    command = ["xvfb-run", "-a", "-s", "-screen 0 1280x800x24", "blender", "--enable-event-simulate",
               "--python", os.path.join(REPO, "tests", "gui", "paste_gui.py"), "--", str(tmp_path)]
    run = subprocess.run(command, cwd=REPO, env=env, capture_output=True, text=True, timeout=300)
    report = tmp_path / "paste.json"
    assert report.exists(), run.stdout[-3000:] + run.stderr[-3000:]
    stats = json.loads(report.read_text())
    assert "error" not in stats, stats["error"]
    start = stats["start"]
    assert stats["copy"] == ["FINISHED"] and stats["exec"] == ["FINISHED"], stats
    # A paste changes the mesh; one undo brings it back exactly.
    assert stats["exec_done"]["polygons"] > start["polygons"], stats
    assert stats["exec_undone"] == start, stats
    # The modal tool: its preview is drawn (the orange faces), Esc leaves the mesh as it was.
    assert stats["first"]["invoke"] == ["RUNNING_MODAL"], stats
    assert stats["preview"]["orange_share"] > stats["before"]["orange_share"] + 0.01, stats
    assert stats["cancelled"] == start, stats
    # Enter writes it; one undo takes it back.
    assert stats["second"]["invoke"] == ["RUNNING_MODAL"], stats
    assert stats["confirmed"]["polygons"] > start["polygons"], stats
    assert stats["modal_undone"] == start, stats
