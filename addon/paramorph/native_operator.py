"""The shape every long paramorph operator shares: read the mesh on the main
thread, run the native call (in a thread with progress in the status bar and
Esc to cancel when Blender has a window; on the calling thread in `blender -b`,
from scripts and from the redo panel), then write the result on the main
thread. Nothing is written unless the call succeeded, so a cancelled or
failed run leaves the mesh exactly as it was."""
import time

import bpy
import numpy as np

from . import blender_numbers, bridge, messages, poll_reasons, run_time
from .jobs import NativeJob
from .native import load_error, native


# How long Esc waits for the native call to stop before going back to the
# event loop (it then ends on a later timer event).
CANCEL_WAIT_SECONDS = 0.5

# Above this many input faces an operator says before it starts that it may
# take minutes (a 97k-face horse morphed for 16 minutes with no warning).
LARGE_INPUT_FACES = 50_000


def remaining_words(elapsed, fraction):
    """'  about 2 min left' from the time so far and the fraction done, once
    there is enough of both to say something; '' before."""
    if fraction < 0.05 or elapsed < 2.0:
        return ""
    return f"  {run_time.duration_words(elapsed * (1.0 - fraction) / fraction)} left"


def numbering_for(error, object_name, F):
    """numbering_of for the mesh-problem errors that name elements; None for
    the others (a cancel or a failed solve reads no mesh again)."""
    if native is None or not isinstance(error, (native.NonManifoldError, native.DegenerateFaceError)):
        return None
    return numbering_of(object_name, F)


def numbering_of(object_name, F):
    """blender_numbers.MeshNumbering of the named object's mesh, whose loop
    triangles `F` were sent; None when it is gone or no longer has them."""
    obj = bpy.data.objects.get(object_name) if object_name else None
    if obj is None or obj.type != "MESH" or F is None:
        return None
    _, triangles, tri_poly, _ = bridge.mesh_arrays(obj.data, polygons=True)
    if triangles.shape != np.shape(F) or not np.array_equal(triangles, F):
        return None
    return blender_numbers.MeshNumbering(obj.data, tri_poly, triangles)


class NativeOperator:
    """Mixin for bpy.types.Operator. Subclasses define
    prepare(context) -> (function, args, kwargs, state)   (may raise UserError)
    finish(context, result, state) -> message for the INFO report.
    constraints: what a ConstraintError of the native call is about
    (messages.describe's keyword: "uv" for pinned UVs, None otherwise)."""

    constraints = None
    _job = None
    _timer = None
    _state = None
    _started = 0.0
    _faces = 0
    _notice = ""

    @classmethod
    def poll(cls, context):
        return poll_reasons.one_mesh(cls, context)

    def _prepare_or_report(self, context):
        if native is None:
            self.report({"ERROR"}, load_error)
            return None
        try:
            return self.prepare(context)
        except UserError as error:
            self.report({"ERROR"}, str(error))
            return None

    def _finish(self, context, job, state):
        if job.error is not None:
            level = {"WARNING"} if isinstance(job.error, native.Cancelled) else {"ERROR"}
            self.report(level, self.describe_error(job.error, state))
            return {"CANCELLED"}
        self.report({"INFO"}, self.finish(context, job.result, state))
        for name in state.get("objects", ()) if isinstance(state, dict) else ():
            obj = bpy.data.objects.get(name)
            note = bridge.modifier_note(obj) if obj is not None else ""
            if note:
                self.report({"WARNING"}, note)
        return {"FINISHED"}

    def describe_error(self, error, state):
        """The report for a failed native call (state["arrays"]: the mesh sent)."""
        arrays = state.get("arrays", (None, None)) if isinstance(state, dict) else (None, None)
        name = state.get("object") if isinstance(state, dict) else None
        return messages.describe(error, *arrays, repair=getattr(self, "repair", None),
                                 numbering=numbering_for(error, name, arrays[1]),
                                 constraints=self.constraints)

    def execute(self, context):
        prepared = self._prepare_or_report(context)
        if prepared is None:
            return {"CANCELLED"}
        function, args, kwargs, state = prepared
        return self._finish(context, NativeJob(function, *args, **kwargs).run(), state)

    def invoke(self, context, event):
        if bpy.app.background or context.window_manager is None or context.window is None:
            return self.execute(context)
        prepared = self._prepare_or_report(context)
        if prepared is None:
            return {"CANCELLED"}
        function, args, kwargs, self._state = prepared
        self._started = time.monotonic()
        # The input's faces: state["faces"] where prepare() counted them (inputs
        # passed as lists), else the (m, 3) integer arrays among the arguments.
        counted = self._state.get("faces") if isinstance(self._state, dict) else None
        self._faces = faces = counted if counted is not None else sum(
            len(a) for a in args if getattr(a, "ndim", 0) == 2 and a.shape[1:] == (3,) and a.dtype.kind == "i")
        # Said in the status bar at once (a modal operator's reports show only
        # when it ends; a cancelled one's INFO reports never do).
        self._notice = run_time.notice(self.bl_label, faces, LARGE_INPUT_FACES)
        if self._notice:
            self.report({"INFO"}, f"{self._notice}; the status bar shows the time left, Esc cancels")
            _set_status(context, f"{self._notice}  (Esc to cancel)")
        self._job = NativeJob(function, *args, **kwargs).start()
        wm = context.window_manager
        self._timer = wm.event_timer_add(0.1, window=context.window)
        wm.progress_begin(0, 100)
        wm.modal_handler_add(self)
        return {"RUNNING_MODAL"}

    def modal(self, context, event):
        job = self._job
        if event.type == "ESC" and event.value == "PRESS":
            job.cancel()
            # Wait for the native call to stop (it checks at its next progress
            # report, within a few tenths of a second; join lets it take the
            # GIL) rather than for the next timer event: Esc ends the operator
            # at once (issue 20: within 0.5 s).
            job.wait(CANCEL_WAIT_SECONDS)
        if event.type != "TIMER" and not job.cancelled:
            return {"PASS_THROUGH"}
        if not job.done():
            context.window_manager.progress_update(int(100 * job.fraction))
            for area in context.screen.areas if context.screen else ():
                if area.type == "VIEW_3D":  # the sidebar's progress line; not the viewport, whose
                    for region in area.regions:  # redraw of a large mesh ten times a second
                        if region.type == "UI":  # slowed the run and Esc
                            region.tag_redraw()
            if context.workspace is not None:
                elapsed = time.monotonic() - self._started
                left = remaining_words(elapsed, job.fraction)
                expected = run_time.estimate(self.bl_label, self._faces)
                if not left and self._notice and expected is not None:  # too early to tell from the progress
                    left = (f"  {run_time.duration_words(expected - elapsed)} left (estimated from "
                            f"{self._faces:,} faces)" if expected > elapsed else "  longer than estimated")
                text = f"{self.bl_label}: {job.stage} {100 * job.fraction:.0f}%{left}  (Esc to cancel)"
                _set_status(context, text)
            return {"RUNNING_MODAL"}
        self._end_modal(context)
        if job.error is None:
            run_time.learn(self.bl_label, self._faces, time.monotonic() - self._started)
        return self._finish(context, job, self._state)

    def _end_modal(self, context):
        wm = context.window_manager
        wm.event_timer_remove(self._timer)
        wm.progress_end()
        _set_status(context, None)

    def cancel(self, context):  # Blender closes the window or aborts the operator
        if self._job is not None:
            self._job.cancel()
            self._job.wait()
            self._end_modal(context)


# The status-bar line of the long operator running now (None when none is):
# what the artist reads there; window tests read it here (Blender has no
# getter for the status text).
status_line = None


def _set_status(context, text):
    global status_line
    status_line = text
    if context.workspace is not None:
        context.workspace.status_text_set(text)


class UserError(Exception):
    """A problem with what the user selected, reported as is."""
