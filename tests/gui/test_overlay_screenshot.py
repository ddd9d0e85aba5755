"""The one GUI test: a real Blender window under Xvfb draws the region
overlay; pixels prove the region colours appear (and do not without it)."""
import json
import os
import shutil
import subprocess

import pytest

REPO = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))


@pytest.mark.skipif(shutil.which("xvfb-run") is None or shutil.which("blender") is None,
                    reason="needs xvfb-run and blender (scripts/install-deps.sh installs both)")
def test_region_overlay_colours_the_viewport(tmp_path):
    command = ["xvfb-run", "-a", "-s", "-screen 0 1280x800x24", "blender", "--factory-startup",
               "--python", os.path.join(REPO, "tests", "gui", "overlay_screenshot.py"), "--", str(tmp_path)]
    run = subprocess.run(command, cwd=REPO, capture_output=True, text=True, timeout=300)
    report = tmp_path / "overlay.json"
    assert report.exists(), run.stdout[-3000:] + run.stderr[-3000:]
    stats = json.loads(report.read_text())
    assert "error" not in stats, stats["error"]
    off, on = stats["off"], stats["on"]
    # Solid grey shading on a grey background: next to no coloured pixels.
    assert off["colored"] < 0.002 * off["pixels"], stats
    # With the overlay the octopus shows its regions in several hues.
    assert on["colored"] > 0.02 * on["pixels"], stats
    assert on["hue_bins_used"] >= 3, stats
