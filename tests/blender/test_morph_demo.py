"""The README's morph demo (scripts/demo_morph.py) in a fresh Blender, as
scripts/demo.sh runs it: it must write morph.blend, whose morph object is
keyed from Suzanne's shape to the blob's, and renders of the first, middle
and last frames that show the shape changing."""
import os

import bpy
import numpy as np
import pytest

import blender_subprocess
from image_pixels import image_rgb

REPO = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
DEMO = os.path.join(REPO, "scripts", "demo_morph.py")


pytestmark = pytest.mark.usefixtures("empty_scene")


def silhouette(path):
    """Boolean mask of the pixels that differ from the render's background
    (the corner pixel's colour)."""
    rgb = image_rgb(path)
    return np.abs(rgb - rgb[0, 0]).max(axis=2) > 0.05


def test_morph_demo_writes_an_animated_morph_and_renders_it_changing(tmp_path):
    out = tmp_path / "morph out"
    frames = 12
    proc = blender_subprocess.run(DEMO, ["--out", out, "--frames", frames, "--resolution", "320", "240"],
                                  tmp_path, timeout=300)
    log = f"exit {proc.returncode}\n{proc.stdout[-3000:]}\n{proc.stderr[-3000:]}"
    assert proc.returncode == 0, log
    blend = out / "morph.blend"
    middle = (1 + frames) // 2
    pngs = [out / f"morph_{frame:04d}.png" for frame in (1, middle, frames)]
    assert f"demo: wrote {blend}" in proc.stdout, log
    for png in pngs:
        assert f"demo: wrote {png}" in proc.stdout, log

    first, half, last = (silhouette(str(png)) for png in pngs)
    for mask in (first, half, last):
        assert 0.02 < mask.mean() < 0.9  # the object is in the picture, not filling it
    # Suzanne and the blob have different outlines: the renders must differ,
    # and the middle frame lies between the two.
    changed = (first != last).mean()
    assert changed > 0.01, changed
    assert (first != half).mean() > 0.1 * changed and (half != last).mean() > 0.1 * changed

    bpy.ops.wm.open_mainfile(filepath=str(blend))
    morph = bpy.data.objects["SuzanneClosed to Blob"]
    keys = morph.data.shape_keys
    names = [k.name for k in keys.key_blocks]
    assert names[0] == "Basis" and names[-1] == "Blob" and len(names) == 10  # eight in-betweens
    # One property, keyframed with easing, drives the keys.
    curve = morph.animation_data.action.fcurves.find('["paramorph_morph"]') \
        if hasattr(morph.animation_data.action, "fcurves") else None
    scene = bpy.context.scene
    values = []
    for frame in (1, middle, frames):
        scene.frame_set(frame)
        values.append((morph["paramorph_morph"], keys.key_blocks["Blob"].value))
    assert values[0] == pytest.approx((0.0, 0.0)) and values[2] == pytest.approx((1.0, 1.0))
    assert 0.0 < values[1][0] < 1.0
    if curve is not None:
        assert [k.interpolation for k in curve.keyframe_points] == ["BEZIER", "BEZIER"]
    assert bpy.data.objects["SuzanneClosed"].hide_render and bpy.data.objects["Blob"].hide_render
