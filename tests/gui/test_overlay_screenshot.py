"""The one GUI test: a real Blender window under Xvfb draws the region
overlay; pixels prove the region colours appear (and do not without it).
Undo, which needs a window, is checked in the same run, and so are the
modal operators (Sphere Map, Morph To) and the Preview Matches overlay."""
import json
import os
import shutil
import subprocess

import pytest

REPO = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))


@pytest.mark.skipif(shutil.which("xvfb-run") is None or shutil.which("blender") is None,
                    reason="needs xvfb-run and blender (scripts/install-deps.sh installs both)")
def test_region_overlay_colours_the_viewport(tmp_path):
    # Factory settings in a window open the first-run splash over the
    # viewport: start from saved preferences (in a temp folder) without it.
    env = dict(os.environ, BLENDER_USER_CONFIG=str(tmp_path / "config"),
               BLENDER_USER_SCRIPTS=str(tmp_path / "scripts"))
    subprocess.run(["blender", "-b", "--factory-startup", "--python-exit-code", "1", "--python-expr",
                    "import bpy; bpy.context.preferences.view.show_splash = False; "
                    "bpy.ops.wm.save_userpref()"], env=env, check=True, capture_output=True, timeout=120)
    command = ["xvfb-run", "-a", "-s", "-screen 0 1280x800x24", "blender",
               "--python", os.path.join(REPO, "tests", "gui", "overlay_screenshot.py"), "--", str(tmp_path)]
    run = subprocess.run(command, cwd=REPO, env=env, capture_output=True, text=True, timeout=300)
    report = tmp_path / "overlay.json"
    assert report.exists(), run.stdout[-3000:] + run.stderr[-3000:]
    stats = json.loads(report.read_text())
    assert "error" not in stats, stats["error"]
    off, on = stats["off"], stats["on"]
    # Grey shading on a grey background: only the UI's few coloured icons.
    assert off["colored"] < 0.005 * off["pixels"], stats
    # With the overlay the octopus shows its regions in several hues.
    assert on["colored"] > off["colored"] + 0.03 * on["pixels"], stats
    assert on["hue_bins_used"] >= 4, stats
    # Undo takes the segmentation back and keeps the mesh.
    assert stats["undo"]["regions_before"] and not stats["undo"]["regions_after"], stats
    assert stats["undo"]["vertices_after"] > 0, stats
    # The modal operator: running in a thread, cancelled -> nothing written,
    # run again -> finished and written.
    modal = stats["modal"]
    assert modal["first_invoke"] == ["RUNNING_MODAL"] and modal["running_at_cancel"] == 1, modal
    assert modal["cancelled"] == {"sphere_uv": False, "shape_keys": False}, modal
    assert modal["second_invoke"] == ["RUNNING_MODAL"], modal
    assert modal["finished"] == {"sphere_uv": True, "shape_keys": True}, modal
    # Preview Matches colours the matched regions of both objects; Morph To
    # runs in its thread to the end; undo takes the morph object away again.
    morph = stats["morph"]
    assert morph["preview"] == ["FINISHED"] and morph["pairs"] > 0, morph
    assert stats["preview"]["colored"] > 0.03 * stats["preview"]["pixels"], stats
    assert stats["preview"]["hue_bins_used"] >= 2, stats
    assert morph["invoke"] == ["RUNNING_MODAL"] and morph["running"] == 1, morph
    assert morph["made"], morph
    assert morph["objects_done"] == sorted(morph["objects_before"] + ["Octopus to OctopusB"]), morph
    assert morph["objects_undone"] == morph["objects_before"], morph
