"""Runs inside a real Blender window (xvfb-run blender --enable-event-simulate,
not -b), driven by tests/gui/test_pick_pins_gui.py:

    xvfb-run -a blender --enable-event-simulate --python tests/gui/pick_pins_gui.py -- OUT_DIR

Pick Pins as users run it, with simulated events: a blob (source) and an
octopus (target) side by side, seen from the front; the tool is invoked over
the 3D View, the mouse moved onto a vertex of the blob (the overlay
highlights it: screenshot), clicked, moved onto a vertex of the octopus (the
half-picked pin and the line to the hovered vertex: screenshot), clicked, and
Enter pressed: one pin, the two vertices under the clicks (drawn white:
screenshot). A second session
picks another pair and is cancelled with Esc: the pins are as before. Then
Ctrl+Z takes the first session back in one step. Writes OUT_DIR/pick_pins.json
(the test asserts on it), then quits."""
import os
import sys

import bpy
import numpy as np
from bpy_extras import view3d_utils

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from gui_session import run_steps, screenshot_rgb, stats, view3d  # noqa: E402

import addon_utils  # noqa: E402
import make_samples  # noqa: E402

HOVER = np.array([1.0, 0.85, 0.1])
PENDING = np.array([1.0, 0.45, 0.05])


def pins():
    return [[p.vertex_a, p.vertex_b] for p in bpy.context.scene.paramorph_matches.pairs if p.pin]


def setup():
    for obj in list(bpy.data.objects):
        bpy.data.objects.remove(obj, do_unlink=True)
    addon_utils.enable("paramorph", default_set=True)
    source = make_samples.build_blob(subdivisions=3)
    target = make_samples.build_octopus(subdivisions=3, limbs=4)
    source.location, target.location = (-2.0, 0.0, 0.0), (2.2, 0.0, 0.0)
    for obj in bpy.context.view_layer.objects:
        obj.select_set(True)
    bpy.context.view_layer.objects.active = target
    window, area, region = view3d()
    with bpy.context.temp_override(window=window, area=area, region=region):
        space = area.spaces.active
        space.shading.type = "SOLID"
        space.shading.color_type = "SINGLE"
        space.shading.single_color = (0.8, 0.8, 0.8)
        space.overlay.show_floor = False
        space.overlay.show_axis_x = space.overlay.show_axis_y = False
        space.overlay.show_outline_selected = False  # the selection outline is orange/yellow too
        space.show_gizmo = False
        bpy.ops.view3d.view_axis(type="FRONT")
        bpy.ops.view3d.view_all()
        bpy.ops.ed.undo_push(message="Pick Pins inputs")


def _hit_vertex(region, rv3d, xy):
    """(object name, vertex) where the view ray through region pixel xy meets the
    scene (Blender's own ray cast): the hit polygon's vertex nearest the hit."""
    origin = view3d_utils.region_2d_to_origin_3d(region, rv3d, xy)
    direction = view3d_utils.region_2d_to_vector_3d(region, rv3d, xy)
    hit, location, _, polygon, obj, _ = bpy.context.scene.ray_cast(
        bpy.context.evaluated_depsgraph_get(), origin, direction)
    if not hit:
        return None
    corners = list(obj.data.polygons[polygon].vertices)
    world = [obj.matrix_world @ obj.data.vertices[v].co for v in corners]
    return obj.name, corners[min(range(len(corners)), key=lambda i: (world[i] - location).length)]


def front_vertices(name, count):
    """`count` vertices of the object that face the viewer, spread out, each with
    the window pixel it projects to; a vertex is used only where Blender's ray
    cast at that pixel and 2 pixels around it lands on the object, and the
    vertex recorded is the one nearest the hit (what a click there means)."""
    window, area, region = view3d()
    obj = bpy.data.objects[name]
    rv3d = area.spaces.active.region_3d
    world = np.array([tuple(obj.matrix_world @ v.co) for v in obj.data.vertices])
    normals = np.array([tuple(obj.matrix_world.to_3x3() @ v.normal) for v in obj.data.vertices])
    facing = np.argsort(normals[:, 1])[:20]  # the front view looks along +y
    out = []
    for vertex in sorted(facing, key=lambda v: -min((np.linalg.norm(world[v] - world[c]) for c, _ in out),
                                                    default=0.0)):
        x, y = (int(round(c)) for c in view3d_utils.location_3d_to_region_2d(region, rv3d, world[vertex]))
        hits = [_hit_vertex(region, rv3d, (x + dx, y + dy)) for dx, dy in ((0, 0), (2, 0), (-2, 0), (0, 2), (0, -2))]
        if any(h is None or h[0] != name for h in hits):
            continue
        out.append((hits[0][1], (region.x + x, region.y + y)))
        if len(out) == count:
            return out
    raise AssertionError(f"no {count} clickable front vertices on {name}")


def simulate(kind, value="PRESS", xy=None, **keys):
    window = view3d()[0]
    if xy is None:
        xy = stats["last_xy"]
    stats["last_xy"] = xy
    window.event_simulate(type=kind, value=value, x=xy[0], y=xy[1], **keys)


def click(xy):
    simulate("MOUSEMOVE", "NOTHING", xy=xy)
    simulate("LEFTMOUSE", "PRESS", xy=xy)
    simulate("LEFTMOUSE", "RELEASE", xy=xy)


def choose_targets():
    stats["source_points"] = front_vertices("Blob", 2)
    stats["target_points"] = front_vertices("Octopus", 2)


def picture(name):
    def take():
        rgb = screenshot_rgb(name)
        stats[name] = {"hover": int((np.abs(rgb - HOVER).max(axis=1) < 0.12).sum()),
                       "pending": int((np.abs(rgb - PENDING).max(axis=1) < 0.12).sum()),
                       "white": int((rgb.min(axis=1) > 0.97).sum())}
    return take


def invoke(label):
    def run():
        xy = stats["source_points"][0][1]
        simulate("MOUSEMOVE", "NOTHING", xy=xy)
        window, area, region = view3d()
        with bpy.context.temp_override(window=window, area=area, region=region):
            stats[label] = {"invoke": sorted(bpy.ops.paramorph.pick_pins("INVOKE_DEFAULT"))}
    return run


def hover_source(index):
    def run():
        simulate("MOUSEMOVE", "NOTHING", xy=stats["source_points"][index][1])
    return run


def record_hover(label):
    def run():
        from paramorph.morph import pin_store
        picker = pin_store.active_picker
        stats[label]["hover"] = list(picker.hover) if picker is not None and picker.hover else None
        stats[label]["pending"] = list(picker.pending) if picker is not None and picker.pending else None
    return run


def click_source(index):
    def run():
        click(stats["source_points"][index][1])
    return run


def hover_target(index):
    def run():
        simulate("MOUSEMOVE", "NOTHING", xy=stats["target_points"][index][1])
    return run


def click_target(index):
    def run():
        click(stats["target_points"][index][1])
    return run


def key(kind, **modifiers):
    def run():
        simulate(kind, "PRESS", **modifiers)
        simulate(kind, "RELEASE", **modifiers)
    return run


def record(label):
    def run():
        from paramorph.morph import pin_store
        stats.setdefault(label, {})
        stats[label].update({"pins": pins(), "active": pin_store.active_picker is not None})
    return run


steps = [setup, None, choose_targets, picture("before"),
         # First session: blob vertex, then octopus vertex, Enter.
         invoke("first"), None, hover_source(0), None, record_hover("first"), picture("hovering"),
         click_source(0), None, hover_target(0), None, picture("pending"), record("while_pending"),
         click_target(0), None, record("after_pair"), key("RET"), None, record("first_done"),
         picture("pinned"),
         # Second session: another pair, taken back with Backspace, picked again, then Esc.
         invoke("second"), None, click_source(1), None, click_target(1), None, record("second_picked"),
         key("BACK_SPACE"), None, record("second_backspace"), click_target(1), None, click_source(1), None,
         record("second_again"), key("ESC"), None, record("second_cancelled"),
         # Ctrl+Z: the first session goes in one step.
         key("Z", ctrl=True), None, None, record("undone")]


run_steps(steps, "pick_pins.json")
