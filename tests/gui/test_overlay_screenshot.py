"""The overlay GUI test: a real Blender window under Xvfb draws the region
overlay; pixels prove the region colours appear (and do not without it).
Undo, which needs a window, is checked in the same run, and so are the
modal operators (Sphere Map, Morph To) and Preview Matches."""
from window_run import needs_window, run_in_window



@needs_window
def test_region_overlay_colours_the_viewport(tmp_path):
    stats = run_in_window(tmp_path, "overlay_screenshot.py", "overlay.json")
    off, on = stats["off"], stats["on"]
    # Grey shading on a grey background: only the UI's few coloured icons.
    assert off["colored"] < 0.005 * off["pixels"], stats
    # With the overlay the octopus shows its regions in several hues.
    assert on["colored"] > off["colored"] + 0.03 * on["pixels"], stats
    assert on["hue_bins_used"] >= 4, stats
    # Inside out (normals inwards), the regions show as much as before.
    inside_out = stats["inside_out"]
    assert inside_out["colored"] > 0.8 * on["colored"] and inside_out["hue_bins_used"] >= 4, stats
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
    # Preview Matches stores the candidates it weighed, one chosen; Morph To
    # runs in its thread to the end; undo takes the morph object away again.
    morph = stats["morph"]
    assert morph["preview"] == ["FINISHED"] and morph["candidates"] >= 1 and morph["chosen"] == 1, morph
    assert morph["invoke"] == ["RUNNING_MODAL"] and morph["running"] == 1, morph
    assert morph["made"], morph
    assert morph["objects_done"] == sorted(morph["objects_before"] + ["Octopus to OctopusB"]), morph
    assert morph["objects_undone"] == morph["objects_before"], morph
    # Keeping the source's topology: keys on the source itself, and undo takes
    # them (and the driving property) away, no object added or lost.
    keep = stats["keep"]
    assert keep["invoke"] == ["RUNNING_MODAL"] and not keep["keys_before"], keep
    assert keep["keys"][0] == "Basis" and keep["keys"][-1] == "OctopusB" and len(keep["keys"]) == 10, keep
    assert keep["property"], keep
    assert not keep["keys_undone"] and not keep["property_undone"], keep
    assert keep["objects_undone"] == morph["objects_before"], keep
