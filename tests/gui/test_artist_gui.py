"""The add-on as an artist meets it, in a real window under Xvfb (issue 20;
tests/gui/artist_gui.py drives it with simulated input): the panel found
and telling what to do first, a long Morph To estimated before and while it
runs and stopped by Esc, a morph onto a scaled and turned target, a closed
mesh unwrapped without seams, a non-manifold edge named as Blender numbers
it, and a paste that does not fit at first and keeps running. With
PARAMORPH_SCREENSHOTS set (scripts/screenshots.sh) its pictures become the
README's."""
from window_run import needs_window, run_in_window


@needs_window
def test_the_add_on_as_an_artist_meets_it(tmp_path):
    stats = run_in_window(tmp_path, "artist_gui.py", "artist.json", simulate_events=True)
    # The Paramorph tab is found by clicking the sidebar's tabs and draws; with
    # nothing selected its greyed buttons say why.
    assert stats["tab_found"] and stats["panel_draws"] > 0, stats
    assert "Select a mesh object" in stats["greyed_reason"], stats
    assert (tmp_path / "panel.png").stat().st_size > 10_000
    # A long morph: said before it starts (the estimate from ~100k faces) and
    # in the status bar while it runs; Esc ends it and nothing is added.
    esc = stats["esc"]
    assert esc["invoke"] == ["RUNNING_MODAL"] and esc["running_before"] == 1, esc
    assert esc["faces"] == 102_400 and esc["line_before"].startswith("Morph To: "), esc
    assert any("left" in line for line in esc["lines"]), esc["lines"]
    assert esc["latency_s"] is not None and esc["running_after"] == 0, esc
    assert esc["objects_after"] == esc["objects_before"], esc
    print(f"Esc to the operator's end in the window: {esc['latency_s']} s (Esc handed to the operator "
          f"{esc.get('event_to_cancel_s')} s, the native call stopped {esc.get('cancel_to_end_s')} s later)")
    # The estimate, in the status bar from the start, until the progress can say more.
    assert esc["line_at_start"].startswith("Morph To: 102,400 faces: about "), esc
    assert "estimated from the face count" in esc["line_at_start"], esc
    assert esc["cancel_report"] and "left as it was" in esc["cancel_report"], esc
    # A modifier left out of the computation is named in the reports.
    modifier = stats["modifier"]
    assert modifier["invoke"] == ["RUNNING_MODAL"] and modifier["written"], modifier
    assert "Smoothed: computed on the mesh without its modifiers (Subdivision)" in modifier["warning"], modifier
    print(f"Waited for the operators to end: sphere map with a modifier {modifier['waited_s']} s, "
          f"kept-topology morph {stats['placed']['waited_s']} s")
    # Isometric Unwrap of a closed mesh without seams: refused at once, saying why; UVs untouched.
    unwrap = stats["unwrap"]
    assert unwrap["invoke"] == ["CANCELLED"] and unwrap["uv_unchanged"], unwrap
    assert "1 island is closed (no seam cuts it open)" in unwrap["error"] and "Mark Seam" in unwrap["error"], unwrap
    # A fin on a quad mesh: the report names the Blender edge, the one Select Non Manifold selects.
    fin = stats["fin"]
    assert fin["invoke"] == ["RUNNING_MODAL"] and fin["error"].count("not manifold") == 1, fin
    assert fin["blender_selects"] == [fin["named_edge"]], fin
    # Morph onto a target scaled x3 and turned 45 degrees: it ends at that size and turn.
    placed = stats["placed"]
    assert placed["invoke"] == ["RUNNING_MODAL"] and placed["keys"] >= 2, placed
    assert abs(placed["size_ratio"] - 1.0) < 0.05 and placed["mean_gap_share"] < 0.03, placed
    # A paste too large at first starts at a size that fits, says so, and keeps
    # running through refused S presses: Blender's own Resize never starts.
    paste = stats["paste"]
    assert paste["copy"] == ["FINISHED"] and paste["invoke"] == ["RUNNING_MODAL"], paste
    assert "shown at scale" in paste["first_header"], paste
    grow = paste["after_grow"]
    assert grow["phase"] == "placing" and grow["object_scale"] == [1.0, 1.0, 1.0], grow
    assert "does not fit there" in grow["header"], grow
    assert paste["after_cancel"] == {"phase": None, "polygons": paste["polygons_before"]}, paste
    assert (tmp_path / "paste.png").stat().st_size > 10_000
