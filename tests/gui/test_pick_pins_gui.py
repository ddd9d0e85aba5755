"""Pick Pins in a real Blender window under Xvfb (tests/gui/pick_pins_gui.py),
driven by simulated events (--enable-event-simulate): the vertex under the
mouse and the half-picked pin are drawn, a click on each object adds one pin
with the vertices under the clicks, Backspace takes a pick back, Esc leaves
the pins as they were, and Ctrl+Z takes a finished session back in one step."""
from window_run import needs_window, run_in_window


@needs_window
def test_pick_pins_modal_tool_pins_cancels_and_undoes(tmp_path):
    stats = run_in_window(tmp_path, "pick_pins_gui.py", "pick_pins.json", simulate_events=True)
    (a0, _), (a1, _) = stats["source_points"]
    (b0, _), (b1, _) = stats["target_points"]
    first = stats["first"]
    assert first["invoke"] == ["RUNNING_MODAL"], stats
    # The vertex under the mouse is the one the mouse is on; the overlay draws it (yellow).
    assert first["hover"] == [0, a0], stats
    assert stats["hovering"]["hover"] > stats["before"]["hover"] + 20, stats
    # After the first click the half pin is drawn (orange) and nothing is pinned yet.
    assert stats["pending"]["pending"] > stats["before"]["pending"] + 20, stats
    assert stats["while_pending"]["pins"] == [], stats
    # The second click pins; Enter ends the session and keeps the pin.
    assert stats["after_pair"]["pins"] == [[a0, b0]], stats
    assert stats["first_done"] == {"pins": [[a0, b0]], "active": False}, stats
    # The pin is drawn (white dots joined by a line), the picking marks are gone.
    assert stats["pinned"]["white"] > stats["before"]["white"] + 40, stats
    assert stats["pinned"]["hover"] <= stats["before"]["hover"] + 5, stats
    # Second session: target-first order works too; Backspace takes the last pin back.
    assert stats["second"]["invoke"] == ["RUNNING_MODAL"], stats
    assert stats["second_picked"]["pins"] == [[a0, b0], [a1, b1]], stats
    assert stats["second_backspace"]["pins"] == [[a0, b0]], stats
    assert stats["second_again"]["pins"] == [[a0, b0], [a1, b1]], stats
    # Esc: the pins as they were before the session.
    assert stats["second_cancelled"] == {"pins": [[a0, b0]], "active": False}, stats
    # Ctrl+Z takes the first (finished) session back.
    assert stats["undone"]["pins"] == [], stats
