"""The README's cut-and-paste demo (scripts/demo_paste.py) in a fresh
Blender, as scripts/demo.sh runs it: paste.blend holds the plate, the curved
body with the boss pasted twice (more faces, still closed, relief where it
was pasted) and the stored feature; paste.png shows both objects."""
import os

import bpy
import numpy as np
import pytest

import blender_subprocess
from image_pixels import image_rgb
from paramorph import bridge, feature_store

REPO = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
DEMO = os.path.join(REPO, "scripts", "demo_paste.py")

pytestmark = pytest.mark.usefixtures("empty_scene")


def test_paste_demo_writes_the_pasted_body_and_a_render(tmp_path):
    if not hasattr(bridge.require_native(), "PasteSession"):
        pytest.skip("this build has no PasteSession")
    out = tmp_path / "paste out"
    proc = blender_subprocess.run(DEMO, ["--out", out, "--resolution", "480", "360"], tmp_path, timeout=300)
    log = f"exit {proc.returncode}\n{proc.stdout[-3000:]}\n{proc.stderr[-3000:]}"
    assert proc.returncode == 0, log
    blend, png = out / "paste.blend", out / "paste.png"
    assert f"demo: wrote {blend}" in proc.stdout and f"demo: wrote {png}" in proc.stdout, log
    rgb = image_rgb(str(png))
    assert rgb.shape[:2] == (360, 480)
    differs = np.abs(rgb - rgb[0, 0]).max(axis=2) > 0.05
    assert 0.05 < differs.mean() < 0.9  # both objects in the picture

    bpy.ops.wm.open_mainfile(filepath=str(blend))
    target = bpy.data.objects["CurvedTarget"].data
    assert len(target.polygons) > 5120  # the icosphere's 5120 faces, and the pasted ones
    loop_edge = np.empty(len(target.loops), dtype=np.int32)
    target.loops.foreach_get("edge_index", loop_edge)
    assert np.all(np.bincount(loop_edge, minlength=len(target.edges)) == 2)  # closed
    co = np.empty(3 * len(target.vertices), dtype=np.float32)
    target.vertices.foreach_get("co", co)
    co = co.reshape(-1, 3)
    # The boss (0.3 high) stands out of the top (z 1.3) and of the side (x 1.6, scaled 0.7).
    assert co[:, 2].max() > 1.3 + 0.2 and co[:, 0].max() > 1.6 + 0.14
    assert [f.name for f in feature_store.features()] == ["Feature BossPlate"]
