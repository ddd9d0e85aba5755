"""Paste Feature in a real Blender window under Xvfb (tests/gui/paste_gui.py):
undo (which needs a window) takes a paste back in one step, and the modal
tool, driven by simulated events (--enable-event-simulate), draws its
preview, leaves the mesh untouched when cancelled and writes it on Enter."""
from window_run import needs_window, run_in_window


@needs_window
def test_paste_feature_modal_tool_preview_cancel_confirm_and_undo(tmp_path):
    stats = run_in_window(tmp_path, "paste_gui.py", "paste.json", simulate_events=True)
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
