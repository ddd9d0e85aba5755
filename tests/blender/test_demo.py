"""The README demo (scripts/demo_blender.py) in a fresh Blender, as
scripts/demo.sh runs it: it must write demo.blend with every sample processed
and a Workbench render whose pixels show the regions in distinct colours."""
import os

import bpy
import numpy as np
import pytest

import blender_subprocess
from image_pixels import image_rgb
import make_samples
from paramorph import uv_patch

REPO = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
DEMO = os.path.join(REPO, "scripts", "demo_blender.py")


pytestmark = pytest.mark.usefixtures("empty_scene")


def test_pinned_disc_sample_pins_the_active_uv_layer():
    mesh = make_samples.build_pinned_disc().data
    assert [layer.name for layer in mesh.uv_layers] == ["UVMap"]
    pins = uv_patch.uv_pins(mesh, mesh.uv_layers.active)
    loop_vertex = np.empty(len(mesh.loops), dtype=np.int32)
    mesh.loops.foreach_get("vertex_index", loop_vertex)
    assert len(np.unique(loop_vertex[pins])) == 4


def saturated_hues(path):
    """Image size, share of strongly coloured pixels, and their hue histogram
    (12 bins of 30 degrees)."""
    image = image_rgb(path)
    height, width = image.shape[:2]
    rgb = image.reshape(-1, 3)
    high, low = rgb.max(axis=1), rgb.min(axis=1)
    strong = (high > 0.25) & ((high - low) > 0.45 * high)
    r, g, b = rgb[strong].T
    chroma = (high - low)[strong]
    hue = np.degrees(np.arctan2(np.sqrt(3.0) * (g - b), 2.0 * r - g - b)) % 360.0
    counts = np.bincount((hue // 30).astype(int) % 12, minlength=12)
    assert np.all(chroma > 0)
    return (width, height), strong.mean(), counts


def test_demo_writes_blend_and_a_render_with_region_colours(tmp_path):
    out = tmp_path / "demo out"
    proc = blender_subprocess.run(DEMO, ["--out", out, "--resolution", "960", "540"], tmp_path,
                                  timeout=180)
    log = f"exit {proc.returncode}\n{proc.stdout[-3000:]}\n{proc.stderr[-3000:]}"
    assert proc.returncode == 0, log
    blend, png = out / "demo.blend", out / "demo.png"
    assert f"demo: wrote {blend}" in proc.stdout and f"demo: wrote {png}" in proc.stdout, log
    assert png.stat().st_size > 10_000

    size, coloured, hues = saturated_hues(str(png))
    assert size == (960, 540)
    # Octopus and CAD part regions: several distinct saturated hues, each on
    # a real patch of the picture (not a few anti-aliased pixels).
    assert (hues >= 300).sum() >= 5, (coloured, hues)
    assert 0.01 < coloured < 0.5, coloured

    bpy.ops.wm.open_mainfile(filepath=str(blend))
    objects = bpy.data.objects
    assert {"SuzanneClosed", "PinnedDisc", "Octopus", "CadPart", "DemoCamera"} <= set(objects.keys())
    suzanne = objects["SuzanneClosed"].data
    assert "Sphere" in suzanne.uv_layers and "Sphere" in suzanne.shape_keys.key_blocks
    for name, least in (("Octopus", 7), ("CadPart", 10)):
        mesh = objects[name].data
        labels = np.empty(len(mesh.polygons), dtype=np.int32)
        mesh.attributes["paramorph_region"].data.foreach_get("value", labels)
        assert labels.max() + 1 >= least, (name, labels.max() + 1)
        assert mesh.color_attributes.active_color.name == "paramorph_region_color"
    # Side by side along x: the objects' world bounding boxes do not overlap.
    boxes = []
    for obj in (o for o in objects if o.type == "MESH"):
        M = np.array(obj.matrix_world)
        corners = np.array([tuple(c) for c in obj.bound_box]) @ M[:3, :3].T + M[:3, 3]
        boxes.append((corners[:, 0].min(), corners[:, 0].max()))
    boxes.sort()
    assert len(boxes) == 4 and all(a[1] < b[0] for a, b in zip(boxes, boxes[1:])), boxes
    scene = bpy.context.scene
    assert scene.render.engine == "BLENDER_WORKBENCH" and scene.camera.name == "DemoCamera"
    assert scene.display.shading.color_type in ("VERTEX", "ATTRIBUTE")
