"""Pick Pins (issue 16): a viewport tool that pins vertices of the morph's
source (the selected mesh) to vertices of its target (the active mesh). The
vertex under the mouse (the nearest corner of the face the view ray hits,
on either object) is highlighted; a click on a vertex of one object, then on
one of the other, adds the pin pair (either order); Backspace or Ctrl+Z takes
back the last pin of the session; Enter or the right button finishes, Esc
puts the pins back as they were. The session is one undo step.

The pins go to the scene's list (`scene.paramorph_matches`, saved with the
.blend) as they are picked, so the panel and the overlay show them at once.
The picking state lives in PinPicker, apart from the operator, so scripts and
tests can drive it (the modal tool only forwards events)."""
import bpy
import numpy as np
from mathutils import Vector
from mathutils.bvhtree import BVHTree

from .. import bridge, overlay, poll_reasons, view_ray
from ..native_operator import UserError
from . import pin_store
from .pin_store import add_pin, claim, restore, snapshot, two_objects

SIDES = ("source", "target")


class PickSurface:
    """One object's mesh for picking: a BVH of its loop triangles (object
    space) and each polygon's vertices, so a hit names a vertex of the mesh."""

    def __init__(self, obj):
        mesh = obj.data
        V, F, tri_poly, _ = bridge.mesh_arrays(mesh, polygons=True)
        self.obj = obj
        self.V = V
        self.tri_poly = tri_poly
        self.bvh = BVHTree.FromPolygons(V.tolist(), F.tolist(), all_triangles=True)
        self.loop_vertex = np.empty(len(mesh.loops), dtype=np.int32)
        mesh.loops.foreach_get("vertex_index", self.loop_vertex)
        self.loop_start = np.empty(len(mesh.polygons), dtype=np.int32)
        self.loop_total = np.empty(len(mesh.polygons), dtype=np.int32)
        mesh.polygons.foreach_get("loop_start", self.loop_start)
        mesh.polygons.foreach_get("loop_total", self.loop_total)

    def hit(self, origin, direction):
        """(world distance, vertex) for the view ray (object space), or None: the
        polygon's vertex nearest the point where the ray meets the mesh."""
        location, _, triangle, _ = self.bvh.ray_cast(origin, direction)
        if location is None:
            return None
        polygon = self.tri_poly[triangle]
        start = self.loop_start[polygon]
        corners = self.loop_vertex[start:start + self.loop_total[polygon]]
        vertex = int(corners[np.argmin(np.linalg.norm(self.V[corners] - np.array(location), axis=1))])
        matrix = self.obj.matrix_world
        return ((matrix @ location) - (matrix @ origin)).length, vertex

    def world(self, vertex):
        return self.obj.matrix_world @ Vector(self.V[vertex])


class PinPicker:
    """A Pick Pins session on (source, target). `hover` and `pending` are
    (side, vertex) with side 0 for the source and 1 for the target, or None."""

    def __init__(self, source, target):
        self.surfaces = (PickSurface(source), PickSurface(target))
        self.hover = None
        self.pending = None
        self.history = []  # the list's pairs before each pin of this session
        self.message = ""

    @property
    def objects(self):
        return tuple(s.obj for s in self.surfaces)

    def under(self, ray_for):
        """(side, vertex) under the mouse: the nearer of the two objects' hits.
        ray_for(obj) is the view ray in obj's coordinates, or None."""
        best = None
        for side, surface in enumerate(self.surfaces):
            ray = ray_for(surface.obj)
            hit = surface.hit(*ray) if ray is not None else None
            if hit is not None and (best is None or hit[0] < best[0]):
                best = (hit[0], side, hit[1])
        return None if best is None else (best[1], best[2])

    def click(self, matches, picked):
        """A click on `picked` ((side, vertex) or None): the first half of a pin,
        or the pin itself when the pending half is on the other object.
        Returns the pin (vertex of source, vertex of target) when one was added."""
        self.message = ""
        if picked is None:
            self.message = "no vertex there: click on one of the two objects"
            return None
        if self.pending is None or self.pending[0] == picked[0]:
            self.pending = picked  # first half, or a new first half on the same object
            return None
        a = picked[1] if picked[0] == 0 else self.pending[1]
        b = picked[1] if picked[0] == 1 else self.pending[1]
        self.history.append(snapshot(matches))
        replaced = add_pin(matches, a, b)
        self.pending = None
        source, target = self.objects
        self.message = (f"pinned {source.name} {a} → {target.name} {b}"
                        + (f" (replaced {replaced} pair{'' if replaced == 1 else 's'})" if replaced else ""))
        return a, b

    def undo(self, matches):
        """Drops the pending half, else takes back the last pin of this session."""
        if self.pending is not None:
            self.pending = None
            self.message = "dropped the half-picked pin"
        elif self.history:
            restore(matches, self.history.pop())
            self.message = "took back the last pin"
        else:
            self.message = "no pin of this session to take back"

    def marks(self):
        """What the overlay draws: world positions of the hovered and pending vertices (or None)."""
        def world(mark):
            return None if mark is None else tuple(self.surfaces[mark[0]].world(mark[1]))
        return {"hover": world(self.hover), "pending": world(self.pending),
                "hover_side": None if self.hover is None else self.hover[0],
                "pending_side": None if self.pending is None else self.pending[0]}

    def header(self, pins):
        names = [o.name for o in self.objects]
        if self.pending is None:
            text = f"Pick Pins: click a vertex of {names[0]} (source) or {names[1]} (target)"
        else:
            side, vertex = self.pending
            text = f"Pick Pins: {names[side]} vertex {vertex} — now click its partner on {names[1 - side]}"
        if self.hover is not None:
            text += f"   [under the mouse: {names[self.hover[0]]} {self.hover[1]}]"
        text += (f"   {pins} pin{'' if pins == 1 else 's'}   Backspace/Ctrl+Z: take back   "
                 "Enter/Right-click: done   Esc: cancel")
        return f"{text}   ({self.message})" if self.message else text


_NAVIGATION = {"MIDDLEMOUSE", "WHEELUPMOUSE", "WHEELDOWNMOUSE", "WHEELINMOUSE", "WHEELOUTMOUSE",
               "TRACKPADPAN", "TRACKPADZOOM", "NDOF_MOTION", "NUMPAD_0", "NUMPAD_1", "NUMPAD_2", "NUMPAD_3",
               "NUMPAD_4", "NUMPAD_5", "NUMPAD_6", "NUMPAD_7", "NUMPAD_8", "NUMPAD_9", "NUMPAD_PERIOD",
               "NUMPAD_PLUS", "NUMPAD_MINUS", "NUMPAD_SLASH", "NUMPAD_ASTERIX", "TIMER", "TIMER_REPORT",
               "WINDOW_DEACTIVATE"}


_WHERE = ("Pick Pins works in the 3D Viewport with the mouse (from scripts: "
          "paramorph.add_pin with vertex_a and vertex_b)")


class PARAMORPH_OT_pick_pins(bpy.types.Operator):
    """Pin vertices of the source (selected) to vertices of the target (active) in the
    viewport: click a vertex on one, then its partner on the other; Backspace takes the
    last back, Enter finishes, Esc cancels"""
    bl_idname = "paramorph.pick_pins"
    bl_label = "Pick Pins"
    bl_options = {"REGISTER", "UNDO"}

    _picker = None
    _before = None

    @classmethod
    def poll(cls, context):
        if not poll_reasons.two_meshes(cls, context):
            return False
        return context.mode == "OBJECT" or poll_reasons.refuse(cls, "Works in Object Mode: press Tab to switch")

    def execute(self, context):  # scripts, -b, repeat last: there is no mouse to pick with
        self.report({"ERROR"}, _WHERE)
        return {"CANCELLED"}

    def invoke(self, context, event):
        if (bpy.app.background or context.window is None or context.area is None
                or context.area.type != "VIEW_3D" or context.region_data is None):
            self.report({"ERROR"}, _WHERE)
            return {"CANCELLED"}
        try:
            source, target = two_objects(context)
        except UserError as error:
            self.report({"ERROR"}, str(error))
            return {"CANCELLED"}
        matches = context.scene.paramorph_matches
        self._before = snapshot(matches)
        claim(matches, source, target)
        self._picker = PinPicker(source, target)
        self._picker.hover = self._under(context, event)
        pin_store.set_active_picker(self._picker)
        context.window_manager.modal_handler_add(self)
        self._refresh(context)
        return {"RUNNING_MODAL"}

    def _under(self, context, event):
        return self._picker.under(lambda obj: view_ray.mouse_ray(context, obj, event))

    def _refresh(self, context):
        matches = context.scene.paramorph_matches
        pins = sum(p.pin for p in matches.pairs)
        context.area.header_text_set(self._picker.header(pins))
        overlay.tag_redraw(context)

    def modal(self, context, event):
        matches = context.scene.paramorph_matches
        picker = self._picker
        region = context.region
        kind, value = event.type, event.value
        inside = (region is not None and 0 <= event.mouse_region_x < region.width
                  and 0 <= event.mouse_region_y < region.height)
        if kind == "ESC" and value == "PRESS":
            restore(matches, self._before)
            self._end(context)
            return {"CANCELLED"}
        if value == "PRESS" and (kind in {"RET", "NUMPAD_ENTER"} or (kind == "RIGHTMOUSE" and inside)):
            self._end(context)
            changed = snapshot(matches) != self._before
            if changed:
                pins = sum(p.pin for p in matches.pairs)
                self.report({"INFO"}, f"Pick Pins: {pins} pin{'' if pins == 1 else 's'} on "
                                      f"{picker.objects[0].name} → {picker.objects[1].name}")
            return {"FINISHED"} if changed else {"CANCELLED"}
        if value == "PRESS" and (kind == "BACK_SPACE" or (kind == "Z" and (event.ctrl or event.oskey))):
            picker.undo(matches)
            self._refresh(context)
            return {"RUNNING_MODAL"}
        if kind == "MOUSEMOVE":
            picker.hover = self._under(context, event) if inside else None
            self._refresh(context)
            return {"RUNNING_MODAL"} if inside else {"PASS_THROUGH"}
        if kind == "LEFTMOUSE" and value == "PRESS" and inside:
            picker.hover = self._under(context, event)
            picker.click(matches, picker.hover)
            self._refresh(context)
            return {"RUNNING_MODAL"}
        if kind in _NAVIGATION or not inside:
            return {"PASS_THROUGH"}
        return {"RUNNING_MODAL"}

    def _end(self, context):
        pin_store.set_active_picker(None)
        if context.area is not None:
            context.area.header_text_set(None)
        overlay.tag_redraw(context)

    def cancel(self, context):  # Blender closes the window or aborts the tool
        if self._before is not None:
            try:
                restore(context.scene.paramorph_matches, self._before)
            except ReferenceError:  # a new file was loaded: its list is its own
                pass
        self._end(context)


classes = (PARAMORPH_OT_pick_pins,)
