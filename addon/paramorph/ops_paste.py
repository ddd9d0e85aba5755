"""Feature cut-and-paste (thesis ch. 5). "Copy Feature" (Edit Mode) extracts
the selected faces' feature and stores it in the .blend (feature_store);
"Paste Feature" pastes the last copied feature (or a named one) onto the
active mesh: interactively at the face under the mouse (the mouse slides it
over the surface, the wheel and R / Shift+R turn it, Ctrl+wheel and S /
Shift+S scale it, a live preview shows the result, Enter or the left button
confirms, Esc or the right button leaves the mesh as it was), or from the
redo panel / scripts at an explicit location. The mesh is only written on
confirm, in one undo step (paste_mesh keeps untouched polygons and their
data as they were)."""
import math

import bpy
import numpy as np
from mathutils.bvhtree import BVHTree

from . import bridge, feature_store, messages, paste_mesh, paste_preview, poll_reasons, regions, view_ray
from .jobs import NativeJob
from .native import load_error, native
from .native_operator import NativeOperator, UserError, numbering_for
from .preferences import backend

ROTATE_STEP = math.radians(15.0)
SCALE_STEP = 1.1


# --- Copy Feature ------------------------------------------------------------------

class PARAMORPH_OT_copy_feature(NativeOperator, bpy.types.Operator):
    """Copy the feature made of the selected faces (a boss, an ear, a horn, a trunk)
    into this file, to paste it onto a surface with Paste Feature"""
    bl_idname = "paramorph.copy_feature"
    bl_label = "Copy Feature"
    bl_options = {"REGISTER", "UNDO"}

    resolution: bpy.props.IntProperty(
        name="Resolution", default=64, min=8, max=512,
        description="Samples per side of the feature's displacement grid (more keeps finer detail)")

    @classmethod
    def poll(cls, context):
        return poll_reasons.one_mesh(cls, context, {"EDIT"})

    def prepare(self, context):
        obj = context.active_object
        with bridge.object_mode(context, obj):
            V, F, tri_poly, _ = bridge.mesh_arrays(obj.data, polygons=True)
            selected = regions.selected_polygons(obj.data)
        faces = np.flatnonzero(selected[tri_poly]).astype(np.int32)
        state = {"arrays": (V, F), "object": obj.name, "polygons": int(selected.sum())}
        return (native.extract_feature, (V, F, faces),
                {"resolution": self.resolution, "backend": backend(context)}, state)

    def finish(self, context, result, state):
        datablock = feature_store.store(result.to_arrays(), state["object"], state["polygons"])
        # A long part (a trunk, a horn, a limb) is pasted as it is, sewn in at its root.
        whole = "; a long part: it pastes whole, attached at its root" if getattr(result, "carried", False) else ""
        return f"copied feature {datablock.name} ({state['polygons']} faces{whole})"


# --- Paste Feature -----------------------------------------------------------------

def target_arrays(context, obj):
    """V, F (loop triangles), tri_poly of the object's mesh (Edit Mode included)."""
    with bridge.object_mode(context, obj):
        V, F, tri_poly, _ = bridge.mesh_arrays(obj.data, polygons=True)
    return V, F, tri_poly


def load_feature(name):
    """The stored feature `name` ("" = the last copied) as a native Feature, and its datablock."""
    datablock = feature_store.find(name)
    if datablock is None:
        if name:
            raise UserError(f"no stored feature named {name!r}: copy one with Copy Feature")
        raise UserError("no feature copied yet: select a feature's faces in Edit Mode and run Copy Feature")
    try:
        return native.Feature.from_arrays(feature_store.load_arrays(datablock)), datablock
    except (ValueError, KeyError, TypeError) as error:
        raise UserError(f"{datablock.name} is not a usable feature ({error}): copy it again") from None


def cursor_in_object(context, obj):
    """The 3D cursor in the object's coordinates."""
    return np.array(obj.matrix_world.inverted() @ context.scene.cursor.location, dtype=np.float64)


# Smaller sizes a paste tries, in turn, where the feature does not fit.
SMALLER = (0.7, 0.5, 0.35, 0.25)
# Where the mouse's place does not fit, the way from the last place that
# fitted is halved down to CLOSE_ENOUGH of the target's bounding-box
# diagonal, at most BISECTIONS times (a long drag stops at 1/32 of its length).
BISECTIONS = 5
CLOSE_ENOUGH = 0.003


def _why_not(error):
    """A refusal in an artist's words: no face or vertex numbers (issue 20)."""
    text = str(error)
    if "boundary" in text or "does not extend" in text:
        return "it would hang over the edge of the surface"
    if "degenerate" in text:
        return "the surface under it has zero-area faces"
    if "not a single disc" in text:
        return "the surface under it wraps around a thin part or has a hole"
    if "folds over" in text or "curved" in text or "flattened" in text:
        return "the surface is too curved under it"
    if "root does not fit" in text:  # a long part's root (issue 32)
        return "its root does not fit on the surface there"
    return text.split(" (")[0].split(";")[0].split(". ")[0]


def build_fitting_session(V, F, feature, *, anchor, scale, progress, **options):
    """native.PasteSession at `anchor` and `scale`; where the feature does not
    fit, the same place at smaller sizes, then the nearest places around it
    (so the tool always has a paste to show and keeps running, issue 20).
    Returns (session, scale used, note: '' or what was changed)."""
    anchor = np.asarray(anchor, dtype=np.float64)
    first = None
    for factor in (1.0,) + SMALLER:
        try:
            session = native.PasteSession(V, F, feature, anchor=anchor, scale=scale * factor,
                                          progress=progress, **options)
        except native.TargetTooSmallError as error:
            first = first or error
            continue
        note = "" if factor == 1.0 else (f"does not fit at full size ({_why_not(first)}): shown at scale "
                                         f"{scale * factor:.2f}")
        return session, scale * factor, note
    # Other places, nearest first: vertices at growing distances from the anchor.
    distance = np.linalg.norm(np.asarray(V) - anchor, axis=1)
    order = np.argsort(distance)
    for k in np.unique(np.geomspace(8, max(len(order) - 1, 8), 10).astype(int)):
        place = np.asarray(V)[order[min(k, len(order) - 1)]]
        try:
            session = native.PasteSession(V, F, feature, anchor=place, scale=scale, progress=progress, **options)
        except native.TargetTooSmallError:
            continue
        return session, scale, f"does not fit at the mouse ({_why_not(first)}): shown at the nearest place it fits"
    raise first


class PasteController:
    """The interactive state of a paste: the session, its placement, and what
    each event does. Kept apart from the operator so scripts and tests drive
    it directly (the modal tool only forwards events)."""

    def __init__(self, session, V, F, tri_poly, rotation, scale):
        self.session = session
        self.V, self.F, self.tri_poly = V, F, tri_poly
        self.rotation, self.scale = float(rotation), float(scale)
        self.message = ""
        self._refusal = ("", "")  # (why, hint) of the last refusal
        self._anchor = np.asarray(session.anchor_point, dtype=np.float64)
        self._size = float(np.linalg.norm(np.ptp(np.asarray(V), axis=0))) if len(V) else 1.0

    def _update(self, **placement):
        try:
            self.session.update(**placement)
        except native.TargetTooSmallError as error:
            self._refusal = (_why_not(error), self._smaller_hint(placement))
            self.message = "does not fit there: {}{}".format(*self._refusal)
            return False
        except native.InvalidInputError as error:
            self.message = str(error)
            return False
        self.message = ""
        for key, value in placement.items():
            if key != "anchor":
                setattr(self, key, float(value))
        if "anchor" in placement:
            self._anchor = np.asarray(placement["anchor"], dtype=np.float64)
        return True

    def _smaller_hint(self, placement):
        """'; Shift+S makes it fit' only when a smaller size fits there
        (checked with the session, then put back as it was)."""
        if "anchor" not in placement:
            return ""
        wanted = float(placement.get("scale", self.scale))
        for factor in SMALLER[:2]:
            try:
                self.session.update(anchor=placement["anchor"], scale=wanted * factor)
            except (native.TargetTooSmallError, native.InvalidInputError):
                continue
            self.session.update(anchor=self._anchor, scale=self.scale)  # the last placement, which fitted
            return f"; at scale {wanted * factor:.2f} it fits (Shift+S makes it smaller)"
        return "; try a flatter place"

    def move(self, point):
        """Slides the feature to `point`; where it does not fit there, as far
        towards it as it fits (the nearest place along the way from the last
        place, halved BISECTIONS times), saying so: the tool follows the
        mouse up to the edge instead of stopping short (issue 20)."""
        point = np.asarray(point, dtype=np.float64)
        if self._update(anchor=point):
            return True
        why, hint = self._refusal if self.message.startswith("does not fit") else (self.message, "")
        start, reached, astray = self._anchor.copy(), 0.0, False
        low, high = 0.0, 1.0
        # Halve down to a step of CLOSE_ENOUGH of the mesh's size, at most
        # BISECTIONS times: a mouse move of a few pixels needs one or two.
        length = float(np.linalg.norm(point - start)) / max(self._size, 1e-300)
        for _ in range(min(BISECTIONS, max(1, int(np.ceil(np.log2(max(length / CLOSE_ENOUGH, 1.0))))))):
            middle = 0.5 * (low + high)
            wanted = start + middle * (point - start)
            try:
                self.session.update(anchor=wanted)
            except (native.TargetTooSmallError, native.InvalidInputError):
                high = middle
                continue
            # The straight line may pass through the inside (a thin part, a
            # concave side): a midpoint that snapped far from it landed on
            # another part of the surface, not on the way to the mouse.
            astray = np.linalg.norm(np.asarray(self.session.anchor_point) - wanted) > 0.25 * np.linalg.norm(
                point - start)
            if astray:
                high = middle
                continue
            low = reached = middle
        if astray:  # the session was left there: back to the last place on the way
            self.session.update(anchor=start + reached * (point - start))
        if reached == 0.0:
            return False
        self._anchor = start + reached * (point - start)
        self.message = f"does not fit at the mouse ({why}): shown as near as it fits{hint}"
        return True

    def rotate(self, angle):
        return self._update(rotation=self.rotation + angle)

    def rescale(self, factor):
        return self._update(scale=self.scale * factor)

    def handle(self, event, hit):
        """One event: "CONFIRM", "CANCEL", "UPDATED", "REFUSED" (kept the last
        placement) or "PASS" (not ours: navigation). `hit()` is the surface
        point under the mouse in object space, or None."""
        kind, value = event.type, event.value
        if kind in {"RET", "NUMPAD_ENTER", "LEFTMOUSE"} and value == "PRESS":
            return "CONFIRM"
        if kind in {"ESC", "RIGHTMOUSE"} and value == "PRESS":
            return "CANCEL"
        done = None
        if kind == "MOUSEMOVE":
            point = hit()
            if point is None:
                return "PASS"
            done = self.move(point)
        elif kind in {"WHEELUPMOUSE", "WHEELDOWNMOUSE"}:
            sign = 1 if kind == "WHEELUPMOUSE" else -1
            done = self.rescale(SCALE_STEP ** sign) if event.ctrl else self.rotate(sign * ROTATE_STEP)
        elif kind == "R" and value == "PRESS":
            done = self.rotate(-ROTATE_STEP if event.shift else ROTATE_STEP)
        elif kind == "S" and value == "PRESS":
            done = self.rescale(1.0 / SCALE_STEP if event.shift else SCALE_STEP)
        if done is None:
            return "PASS"
        return "UPDATED" if done else "REFUSED"

    def header(self):
        """The header line: the placement and, first, what went wrong (the
        keys are in the status bar, KEYS: after them the message ran off
        the header, issue 20)."""
        placement = f"rotation {math.degrees(self.rotation):.0f}°, scale {self.scale:.2f}"
        return f"Paste Feature: {self.message}   ({placement})" if self.message else f"Paste Feature: {placement}"


# The status bar while the paste follows the mouse, as Blender's own modal tools show their keys.
KEYS = ("Move: slide    Wheel, R, Shift+R: turn    Ctrl+Wheel, S, Shift+S: scale    "
        "Enter, Left Click: paste    Esc, Right Click: cancel")


class PARAMORPH_OT_paste_feature(bpy.types.Operator):
    """Paste the copied feature onto the active mesh at the face under the mouse: move
    the mouse to slide it, wheel or R to turn, Ctrl+wheel or S to scale, Enter to confirm"""
    bl_idname = "paramorph.paste_feature"
    bl_label = "Paste Feature"
    bl_options = {"REGISTER", "UNDO"}

    feature: bpy.props.StringProperty(
        name="Feature", default="",
        description="Stored feature to paste (a 'Feature ...' mesh datablock); empty: the last copied")
    location: bpy.props.FloatVectorProperty(
        name="Location", size=3, subtype="TRANSLATION",
        description="Where the feature goes, in the object's coordinates (snapped to the surface)")
    # SKIP_SAVE: a new paste starts at the feature's own size and turn; the
    # last run's scale, remembered by Blender, made the next paste fail
    # where it did not fit (issue 20). The redo panel still shows them.
    rotation: bpy.props.FloatProperty(
        name="Rotation", default=0.0, subtype="ANGLE", options={"SKIP_SAVE"},
        description="Turn about the surface normal (0: the feature's x along the object's x)")
    scale: bpy.props.FloatProperty(
        name="Scale", default=1.0, min=1e-3, soft_min=0.1, soft_max=10.0, options={"SKIP_SAVE"},
        description="Size of the feature relative to the copied one")
    blend_radius: bpy.props.FloatProperty(
        name="Blend Radius", default=2.0, min=1.11, soft_max=6.0,
        description="Radius of the surface around the feature that bends to meet it, in feature radii")
    subdivision_level: bpy.props.IntProperty(
        name="Subdivision Level", default=-1, min=-1, max=6,
        description="Loop subdivision of the target under the feature (-1: matched to the feature's detail)")
    basis: bpy.props.EnumProperty(
        name="Basis", default="polyharmonic",
        items=(("polyharmonic", "Smooth Blend", "The surface around the feature bends smoothly, like a thin "
                "plate (polyharmonic r^3 basis)"),
               ("wendland", "Local Blend", "The bend stays inside the blend radius; the rest of the surface "
                "does not move (Wendland compactly supported basis)")))
    fit: bpy.props.EnumProperty(
        name="Fit", default="keep_form",
        items=(("keep_form", "Keep Form", "The feature keeps its own shape; the surface around it blends in"),
               ("follow_surface", "Follow Surface", "The feature's base bends with the target surface")))

    _controller = None
    _state = None

    @classmethod
    def poll(cls, context):
        return poll_reasons.one_mesh(cls, context, {"OBJECT", "EDIT"})

    # -- shared -----------------------------------------------------------------------

    def _options(self):
        return {"rotation": self.rotation, "scale": self.scale, "blend_radius": self.blend_radius,
                "subdivision_level": self.subdivision_level, "basis": self.basis, "fit": self.fit}

    def _prepare(self, context):
        """(obj, feature datablock, native Feature, V, F, tri_poly) or a UserError."""
        if native is None:
            raise UserError(load_error)
        if not hasattr(native, "PasteSession"):
            raise UserError("this paramorph build has no PasteSession: rebuild the module")
        obj = context.active_object
        if obj.data.shape_keys is not None:
            raise UserError(f"{obj.name} has shape keys: Paste Feature changes its topology; "
                            "apply or remove them first")
        feature, datablock = load_feature(self.feature)
        V, F, tri_poly = target_arrays(context, obj)
        return obj, datablock, feature, V, F, tri_poly

    def _describe(self, error, V, F):
        obj = bpy.context.active_object
        return messages.describe(error, V, F, numbering=numbering_for(error, obj.name if obj else None, F))

    def _write(self, context, obj, datablock, V, F, tri_poly, session):
        V2, F2, new_faces = session.result()
        with bridge.object_mode(context, obj, face_select=True):
            summary = paste_mesh.write(obj.data, V, F, tri_poly, V2, F2, new_faces, session.replaced_faces,
                                       session.new_face_parents)
            mask = np.zeros(len(obj.data.polygons), dtype=bool)
            mask[summary["new_polygons"]] = True
            if "moved_vertices" in summary:  # no new faces: the faces the feature moved
                mask = _polygons_of_vertices(obj.data, summary["moved_vertices"])
            regions.select_polygons(obj.data, mask)  # the pasted faces selected
        self.location = tuple(float(x) for x in np.asarray(session.anchor_point))
        stats = dict(session.stats) if hasattr(session, "stats") else {}
        level = stats.get("level")
        self.report({"INFO"}, (
            f"Paste Feature: {datablock.name} on {obj.name}: {summary['added']} new faces, "
            f"{summary['removed']} faces replaced, {summary['kept']} kept"
            + (f", subdivision level {level}" if level is not None else "")))
        return {"FINISHED"}

    # -- redo panel / scripts -----------------------------------------------------------

    def execute(self, context):
        try:
            obj, datablock, feature, V, F, tri_poly = self._prepare(context)
        except UserError as error:
            self.report({"ERROR"}, str(error))
            return {"CANCELLED"}
        job = NativeJob(native.PasteSession, V, F, feature, anchor=np.array(self.location, dtype=np.float64),
                        **self._options()).run()
        if job.error is not None:
            level = {"WARNING"} if isinstance(job.error, native.Cancelled) else {"ERROR"}
            self.report(level, self._describe(job.error, V, F))
            return {"CANCELLED"}
        try:
            return self._write(context, obj, datablock, V, F, tri_poly, job.result)
        except paste_mesh.PasteWriteError as error:
            self.report({"ERROR"}, f"{error}: the mesh was left as it was")
            return {"CANCELLED"}

    # -- interactive ------------------------------------------------------------------

    def invoke(self, context, event):
        obj = context.active_object
        interactive = not (bpy.app.background or context.window is None or context.area is None
                           or context.area.type != "VIEW_3D" or context.region_data is None)
        if not interactive:
            if not self.properties.is_property_set("location"):
                self.location = tuple(cursor_in_object(context, obj))
            return self.execute(context)
        try:
            obj, datablock, feature, V, F, tri_poly = self._prepare(context)
        except UserError as error:
            self.report({"ERROR"}, str(error))
            return {"CANCELLED"}
        bvh = BVHTree.FromPolygons(V.tolist(), F.tolist(), all_triangles=True)
        start = _surface_under_mouse(context, obj, bvh, event)
        if start is None:
            start = cursor_in_object(context, obj)
        # The session is built in a thread (progress in the header, Esc cancels),
        # then the tool takes the mouse.
        options = self._options()
        scale = options.pop("scale")
        self._state = {"object": obj, "datablock": datablock, "bvh": bvh, "arrays": (V, F, tri_poly),
                       "job": NativeJob(build_fitting_session, V, F, feature, anchor=start, scale=scale,
                                        **options).start()}
        wm = context.window_manager
        self._state["timer"] = wm.event_timer_add(0.05, window=context.window)
        wm.modal_handler_add(self)
        _set_phase("building")
        return {"RUNNING_MODAL"}

    def _building(self, context, event):
        """The modal step while the session is being built."""
        job = self._state["job"]
        if event.type in {"ESC", "RIGHTMOUSE"} and event.value == "PRESS":
            job.cancel()
        if not job.done():
            if event.type == "TIMER":
                context.area.header_text_set(f"Paste Feature: {job.stage} {100 * job.fraction:.0f}%  (Esc to cancel)")
            return {"PASS_THROUGH"} if event.type in _NAVIGATION else {"RUNNING_MODAL"}
        context.window_manager.event_timer_remove(self._state.pop("timer"))
        V, F, tri_poly = self._state["arrays"]
        if job.error is not None:
            self._end(context)
            level = {"WARNING"} if isinstance(job.error, native.Cancelled) else {"ERROR"}
            self.report(level, self._describe(job.error, V, F))
            return {"CANCELLED"}
        session, scale, note = job.result
        self._controller = PasteController(session, V, F, tri_poly, self.rotation, scale)
        self._controller.message = note
        paste_preview.start()
        self._refresh(context)  # and the phase: placing
        return {"RUNNING_MODAL"}

    def _refresh(self, context):
        controller = self._controller
        V2, F2, new_faces = controller.session.result()
        num_untouched = len(controller.F) - len(controller.session.replaced_faces)
        paste_preview.build(self._state["object"].matrix_world, controller.V, V2, F2, new_faces, num_untouched)
        _set_phase("placing", controller.header())
        context.area.header_text_set(controller.header())
        if context.workspace is not None:
            context.workspace.status_text_set(KEYS)
        context.area.tag_redraw()

    def modal(self, context, event):
        if self._controller is None:
            return self._building(context, event)
        controller, state = self._controller, self._state
        action = controller.handle(event, lambda: _surface_under_mouse(context, state["object"], state["bvh"], event))
        if action == "PASS":
            return {"PASS_THROUGH"} if event.type in _NAVIGATION else {"RUNNING_MODAL"}
        if action in {"UPDATED", "REFUSED"}:
            self._refresh(context)
            return {"RUNNING_MODAL"}
        self._end(context)
        if action == "CANCEL":
            return {"CANCELLED"}
        self.rotation, self.scale = controller.rotation, controller.scale
        try:
            return self._write(context, state["object"], state["datablock"], controller.V, controller.F,
                               controller.tri_poly, controller.session)
        except paste_mesh.PasteWriteError as error:
            self.report({"ERROR"}, f"{error}: the mesh was left as it was")
            return {"CANCELLED"}

    def _end(self, context):
        _set_phase(None)
        timer = self._state.pop("timer", None) if self._state else None
        if timer is not None:
            context.window_manager.event_timer_remove(timer)
        paste_preview.stop()
        if context.workspace is not None:
            context.workspace.status_text_set(None)
        if context.area is not None:
            context.area.header_text_set(None)
            context.area.tag_redraw()

    def cancel(self, context):  # Blender closes the window or aborts the tool
        job = self._state.get("job") if self._state else None
        if job is not None and not job.done():
            job.cancel()
            job.wait()
        self._end(context)


# What the interactive tool is doing: None, "building" (the session, in a
# thread) or "placing" (following the mouse), and the header it shows then.
# Scripts and the GUI test read them (Blender has no getter for the header).
phase = None
header_line = None


def _set_phase(value, header=None):
    global phase, header_line
    phase, header_line = value, header


_NAVIGATION = {"MIDDLEMOUSE", "TRACKPADPAN", "TRACKPADZOOM", "NDOF_MOTION", "NUMPAD_1", "NUMPAD_2",
               "NUMPAD_3", "NUMPAD_4", "NUMPAD_5", "NUMPAD_6", "NUMPAD_7", "NUMPAD_8", "NUMPAD_9",
               "NUMPAD_PERIOD", "NUMPAD_PLUS", "NUMPAD_MINUS", "TIMER", "TIMER_REPORT", "WINDOW_DEACTIVATE"}


def _polygons_of_vertices(mesh, vertices):
    """Polygons with a corner among `vertices`."""
    chosen = np.zeros(len(mesh.vertices), dtype=bool)
    chosen[vertices] = True
    loop_vertex = np.empty(len(mesh.loops), dtype=np.int32)
    mesh.loops.foreach_get("vertex_index", loop_vertex)
    loop_total = np.empty(len(mesh.polygons), dtype=np.int32)
    mesh.polygons.foreach_get("loop_total", loop_total)
    poly_of_loop = np.repeat(np.arange(len(loop_total)), loop_total)
    mask = np.zeros(len(loop_total), dtype=bool)
    mask[poly_of_loop[chosen[loop_vertex]]] = True
    return mask


def _surface_under_mouse(context, obj, bvh, event):
    """The first hit of the view ray through the mouse on the mesh, object space, or None."""
    ray = view_ray.mouse_ray(context, obj, event)
    if ray is None:
        return None
    location, _, _, _ = bvh.ray_cast(*ray)
    return None if location is None else np.array(location, dtype=np.float64)


classes = (PARAMORPH_OT_copy_feature, PARAMORPH_OT_paste_feature)

