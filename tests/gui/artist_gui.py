"""Runs inside a real Blender window (xvfb-run blender --enable-event-simulate,
not -b), driven by tests/gui/test_artist_gui.py:

    xvfb-run -a blender --enable-event-simulate --python tests/gui/artist_gui.py -- OUT_DIR

The add-on as an artist meets it (issue 20), with simulated input:
- the sidebar's Paramorph tab found as a user finds it (clicking down the
  sidebar's tabs), with nothing selected: the panel says what to do
  first and a greyed button says why (its poll message); screenshot "panel";
- Morph To on two large meshes, modal: the estimate said before the run and
  in the status bar while it runs, then Esc pressed: how long until the
  operator has ended, and nothing written;
- Morph To between a source and a target scaled x3 and turned 45 degrees, in
  the window: the morph ends at the target's size and turn;
- Sphere Map on an object with a Subdivision modifier: the reports say the
  modifier was left out; Isometric Unwrap of a closed mesh without seams:
  refused in words; a fin on a quad mesh: named by the Blender edge that
  Select Non Manifold selects;
- Paste Feature asked for a size that does not fit: the tool starts at a
  size that fits, keeps running through refused S presses (the object is not
  scaled by Blender's own S), says why in the header; screenshot "paste";
  Esc leaves the mesh as it was.
Writes OUT_DIR/artist.json (the test asserts on it), then quits."""
import math
import os
import sys
import time

import bpy
import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from gui_session import (centre_of_region, keep_for_readme, run_steps, screenshot_rgb, simulate, stats,  # noqa: E402
                         view3d, wait_while)

import addon_utils  # noqa: E402
import make_samples  # noqa: E402

drawn = {"main": 0}


def clear_scene():
    for obj in list(bpy.data.objects):
        bpy.data.objects.remove(obj, do_unlink=True)


def in_view(function, *args, **kwargs):
    window, area, region = view3d()
    with bpy.context.temp_override(window=window, area=area, region=region):
        return function(*args, **kwargs)


def refused_in_view(operator, *args, **kwargs):
    """Runs an operator expected to refuse: (its result, its error report).
    Called from Python, an ERROR report comes as RuntimeError; in the window
    the artist reads the same line in the status bar."""
    try:
        return sorted(in_view(operator, *args, **kwargs)), ""
    except RuntimeError as error:
        return ["CANCELLED"], str(error)


def reports():
    """The reports the artist has seen, from an Info editor (the timeline at
    the bottom turned into one): Blender has no Python getter for them."""
    window = bpy.context.window_manager.windows[0]
    info = next((a for a in window.screen.areas if a.type == "INFO"), None)
    if info is None:
        info = min((a for a in window.screen.areas if a.type != "VIEW_3D"), key=lambda a: a.y)
        info.type = "INFO"
    region = next(r for r in info.regions if r.type == "WINDOW")
    with bpy.context.temp_override(window=window, area=info, region=region):
        bpy.ops.info.select_all(action="SELECT")
        bpy.ops.info.report_copy()
    return bpy.context.window_manager.clipboard.splitlines()


# --- the panel -----------------------------------------------------------------------

def setup():
    clear_scene()
    addon_utils.enable("paramorph", default_set=True)
    from paramorph import panels
    draw = panels.PARAMORPH_PT_main.draw

    def counted(self, context):  # Blender looks draw up at each redraw: this counts them
        drawn["main"] += 1
        draw(self, context)
    panels.PARAMORPH_PT_main.draw = counted
    window, area, region = view3d()
    space = area.spaces.active
    space.show_region_ui = True
    space.shading.type = "SOLID"
    space.overlay.show_floor = False
    area.tag_redraw()
    stats["tab_tries"] = 0


def find_tab():
    """Clicks down the sidebar's tab strip (its right edge), as a user picks a
    tab, until the Paramorph panel draws (re-inserts itself, at most 40 clicks)."""
    if drawn["main"]:
        stats["tab_found"] = True
        return
    window, area, _ = view3d()
    sidebar = next(r for r in area.regions if r.type == "UI")
    tries = stats["tab_tries"] = stats["tab_tries"] + 1
    y = sidebar.y + sidebar.height - 10 - 12 * tries
    if y < sidebar.y:
        stats["tab_found"] = False
        return
    xy = (sidebar.x + sidebar.width - 9, y)
    simulate("MOUSEMOVE", "NOTHING", xy=xy)
    simulate("LEFTMOUSE", "PRESS", xy=xy)
    simulate("LEFTMOUSE", "RELEASE", xy=xy)
    area.tag_redraw()
    steps.insert(0, find_tab)
    steps.insert(0, None)


def panel_picture():
    screenshot_rgb("panel")
    keep_for_readme("panel")
    stats["panel_draws"] = drawn["main"]
    # A greyed button says why: its poll message, in the window's own context.
    try:
        in_view(bpy.ops.paramorph.sphere_map, "INVOKE_DEFAULT")
        stats["greyed_reason"] = ""
    except RuntimeError as error:
        stats["greyed_reason"] = str(error)


# --- a long Morph To, its estimate and Esc ---------------------------------------------

def big_pair():
    clear_scene()
    source = make_samples.build_octopus(name="BigSource", subdivisions=7)
    target = make_samples.build_octopus(name="BigTarget", subdivisions=6, limbs=4)
    source.location, target.location = (-2.0, 0.0, 0.0), (2.0, 0.0, 0.0)
    for obj in (source, target):
        obj.select_set(True)
    bpy.context.view_layer.objects.active = target
    stats["esc"] = {"faces": len(source.data.polygons) + len(target.data.polygons),
                    "objects_before": sorted(o.name for o in bpy.data.objects)}


def morph_invoke():
    from paramorph import native_operator
    stats["esc"]["invoke"] = sorted(in_view(bpy.ops.paramorph.morph_to, "INVOKE_DEFAULT", topology="MERGED"))
    stats["esc"]["line_at_start"] = native_operator.status_line  # before the first progress report
    stats["esc"]["started"] = time.monotonic()
    stats["esc"]["lines"] = []

    def watch():  # the status bar while it runs, every 0.2 s until Esc
        line = native_operator.status_line
        if line is not None:
            stats["esc"]["lines"].append(line)
        return None if "pressed" in stats["esc"] else 0.2
    bpy.app.timers.register(watch, first_interval=0.2)


def wait_running(seconds):
    def wait():
        if time.monotonic() - stats["esc"]["started"] < seconds:
            steps.insert(0, wait)
    return wait


def press_escape():
    from paramorph import jobs, native_operator
    stats["esc"]["running_before"] = len(jobs.running())
    job = jobs.running()[0] if jobs.running() else None  # the one Esc cancels
    stats["esc"]["line_before"] = native_operator.status_line
    pressed = stats["esc"]["pressed"] = time.monotonic()
    simulate("ESC")
    simulate("ESC", "RELEASE")

    def ended():  # polled every 10 ms: the operator has ended when its status line is gone
        if native_operator.status_line is None:
            stats["esc"]["latency_s"] = round(time.monotonic() - pressed, 3)
            if job is not None and job.cancelled_at is not None and job.ended_at is not None:
                # Where the time went: Blender handing the Esc to the operator, the native call stopping.
                stats["esc"]["event_to_cancel_s"] = round(job.cancelled_at - pressed, 3)
                stats["esc"]["cancel_to_end_s"] = round(job.ended_at - job.cancelled_at, 3)
            return None
        if time.monotonic() - pressed > 30:
            stats["esc"]["latency_s"] = None
            return None
        return 0.01
    bpy.app.timers.register(ended, first_interval=0.01)


def wait_ended():
    if "latency_s" not in stats["esc"]:
        steps.insert(0, wait_ended)


def after_escape():
    from paramorph import jobs
    seen = reports()
    stats["esc"]["cancel_report"] = next((line for line in seen if "cancelled" in line), None)
    stats["esc"]["running_after"] = len(jobs.running())
    stats["esc"]["objects_after"] = sorted(o.name for o in bpy.data.objects)
    stats["esc"].pop("started"), stats["esc"].pop("pressed")


# --- Morph To with transforms, in the window ----------------------------------------------

def placed_pair():
    clear_scene()
    source = make_samples.build_octopus(name="Small", subdivisions=3, limbs=4)
    target = make_samples.build_octopus(name="Turned", subdivisions=4, limbs=4)
    source.location, target.location = (-3.0, 0.0, 0.0), (4.0, 0.0, 0.0)
    target.scale = (3.0, 3.0, 3.0)
    target.rotation_euler = (0.0, 0.0, math.radians(45.0))
    for obj in (source, target):
        obj.select_set(True)
    bpy.context.view_layer.objects.active = target
    bpy.context.view_layer.update()
    stats["placed"] = {"invoke": sorted(in_view(bpy.ops.paramorph.morph_to, "INVOKE_DEFAULT", topology="KEEP"))}


def keys_written():
    """Waits (up to 240 s) for Morph To to write its shape keys."""
    wait_while(steps, lambda: bpy.data.objects["Small"].data.shape_keys is None, stats["placed"], 240.0)()


def placed_check():
    source, target = bpy.data.objects["Small"], bpy.data.objects["Turned"]
    keys = source.data.shape_keys
    last = keys.key_blocks[-1]
    co = np.empty(3 * len(last.data))
    last.data.foreach_get("co", co)
    world = co.reshape(-1, 3) @ np.array(source.matrix_world)[:3, :3].T
    target_world = np.array([target.matrix_world @ v.co for v in target.data.vertices])
    extent = lambda P: np.linalg.norm(P.max(axis=0) - P.min(axis=0))
    stats["placed"]["size_ratio"] = float(extent(world) / extent(target_world))
    # Turned like the target: centred, each point of the last key lies on the
    # target (its four tentacles 45 degrees off would not).
    from mathutils.kdtree import KDTree
    tree = KDTree(len(target_world))
    for i, p in enumerate(target_world - target_world.mean(axis=0)):
        tree.insert(p, i)
    tree.balance()
    gaps = [tree.find(p)[2] for p in world - world.mean(axis=0)]
    stats["placed"]["mean_gap_share"] = float(np.mean(gaps) / extent(target_world))
    stats["placed"]["keys"] = len(keys.key_blocks)


# --- a modifier the computation leaves out, said in the reports ------------------------------

def modified_invoke():
    clear_scene()
    obj = make_samples.build_octopus(name="Smoothed", subdivisions=3)
    obj.modifiers.new("Subdivision", "SUBSURF")
    stats["modifier"] = {"invoke": sorted(in_view(bpy.ops.paramorph.sphere_map, "INVOKE_DEFAULT"))}


def modified_ended():
    """Waits (up to 120 s) for the sphere map's operator to end (its status line goes)."""
    from paramorph import native_operator
    wait_while(steps, lambda: native_operator.status_line is not None, stats["modifier"])()


def modified_check():
    seen = reports()
    stats["modifier"]["warning"] = next((line for line in seen if "without its modifiers" in line), None)
    stats["modifier"]["written"] = "Sphere" in bpy.data.objects["Smoothed"].data.uv_layers


# --- Isometric Unwrap of a closed mesh without seams ---------------------------------------

def unwrap_closed():
    """A closed sphere without seams, all selected, unwrapped from the window:
    refused before any work, in words that say what to do; UVs untouched."""
    clear_scene()
    bpy.ops.mesh.primitive_uv_sphere_add(segments=24, ring_count=12)
    mesh = bpy.context.active_object.data
    before = np.empty(2 * len(mesh.loops))
    mesh.uv_layers.active.data.foreach_get("uv", before)
    in_view(bpy.ops.object.mode_set, mode="EDIT")
    in_view(bpy.ops.mesh.select_all, action="SELECT")
    result, error = refused_in_view(bpy.ops.paramorph.isometric_unwrap, "INVOKE_DEFAULT")
    stats["unwrap"] = {"invoke": result, "error": error}
    in_view(bpy.ops.object.mode_set, mode="OBJECT")
    after = np.empty(2 * len(mesh.loops))
    mesh.uv_layers.active.data.foreach_get("uv", after)
    stats["unwrap"]["uv_unchanged"] = bool(np.array_equal(before, after))


# --- a non-manifold mesh, named in Blender's numbers, shown by Select Non Manifold ---------

def fin_mesh():
    import bmesh
    clear_scene()
    bpy.ops.mesh.primitive_cube_add()
    obj = bpy.context.active_object
    bm = bmesh.new()
    bm.from_mesh(obj.data)
    bmesh.ops.subdivide_edges(bm, edges=bm.edges[:], cuts=2, use_grid_fill=True)
    bm.edges.ensure_lookup_table()
    edge = next(e for e in bm.edges if len(e.link_faces) == 2)
    tips = [bm.verts.new((3.0, 3.0, 3.0)), bm.verts.new((3.0, 4.0, 3.0))]
    bm.faces.new((edge.verts[0], edge.verts[1], tips[1], tips[0]))  # a quad fin on a quad edge
    bm.to_mesh(obj.data)
    bm.free()
    obj.data.update()
    result, error = refused_in_view(bpy.ops.paramorph.sphere_map, "INVOKE_DEFAULT", repair=False)
    stats["fin"] = {"invoke": result, "error": error}


def fin_ended():
    """The sphere map runs in its thread and reports when it ends (waits up to 120 s)."""
    from paramorph import native_operator
    wait_while(steps, lambda: native_operator.status_line is not None, stats["fin"])()


def fin_check():
    import re
    obj = bpy.context.active_object
    error = stats["fin"]["error"] or next((line for line in reports() if "not manifold" in line), "")
    stats["fin"]["error"] = error
    match = re.search(r"\bedge (\d+)", error)
    named = int(match.group(1)) if match else -1
    # What Select All by Trait > Non Manifold selects (no boundary: only the fin's own edge has three faces).
    in_view(bpy.ops.object.mode_set, mode="EDIT")
    bpy.context.tool_settings.mesh_select_mode = (False, True, False)
    in_view(bpy.ops.mesh.select_all, action="DESELECT")
    in_view(bpy.ops.mesh.select_non_manifold, extend=False, use_wire=False, use_boundary=False,
            use_multi_face=True, use_non_contiguous=False, use_verts=False)
    in_view(bpy.ops.object.mode_set, mode="OBJECT")
    selected = [e.index for e in obj.data.edges if e.select]
    stats["fin"]["named_edge"], stats["fin"]["blender_selects"] = named, selected


# --- Paste Feature that does not fit at first --------------------------------------------

def paste_setup():
    clear_scene()
    source, target = make_samples.build_paste_pair()
    from paramorph import regions
    centres = np.empty(3 * len(source.data.polygons), dtype=np.float32)
    source.data.polygons.foreach_get("center", centres)
    ball = np.array(make_samples.BOSS_BALL)
    regions.select_polygons(source.data, np.linalg.norm(centres.reshape(-1, 3) - ball[:3], axis=1) <= ball[3])
    bpy.context.view_layer.objects.active = source
    in_view(bpy.ops.object.mode_set, mode="EDIT")
    bpy.context.tool_settings.mesh_select_mode = (False, False, True)
    stats["paste"] = {"copy": sorted(in_view(bpy.ops.paramorph.copy_feature, "EXEC_DEFAULT"))}
    in_view(bpy.ops.object.mode_set, mode="OBJECT")
    for obj in bpy.context.view_layer.objects:
        obj.select_set(obj == target)
    bpy.context.view_layer.objects.active = target
    in_view(bpy.ops.view3d.view_selected)
    target.select_set(False)
    stats["paste"]["polygons_before"] = len(target.data.polygons)


def paste_invoke():
    simulate("MOUSEMOVE", "NOTHING")  # the mouse over the target's middle
    # Six times the feature's size: far too large for this body.
    stats["paste"]["invoke"] = sorted(in_view(bpy.ops.paramorph.paste_feature, "INVOKE_DEFAULT", scale=6.0))


def wait_placing():
    """Waits (up to 120 s) until the tool follows the mouse."""
    from paramorph import ops_paste
    wait_while(steps, lambda: ops_paste.phase != "placing", stats["paste"])()


def paste_first_header():
    from paramorph import ops_paste
    stats["paste"]["first_header"] = ops_paste.header_line


def paste_grow():
    """S six times (x1.1 each): past the size that fits, refused, and the tool stays."""
    for _ in range(6):
        simulate("S")
        simulate("S", "RELEASE")


def paste_after_grow():
    from paramorph import ops_paste
    target = bpy.data.objects["CurvedTarget"]
    stats["paste"]["after_grow"] = {"phase": ops_paste.phase, "header": ops_paste.header_line,
                                    "object_scale": list(target.scale)}
    x, y = centre_of_region()
    simulate("MOUSEMOVE", "NOTHING", xy=(x + 25, y + 20))


def paste_to_a_sensible_size():
    """Shift+S back down to about the feature's own size, the mouse a little
    aside: the picture the README shows."""
    for _ in range(15):
        simulate("S", shift=True)
        simulate("S", "RELEASE", shift=True)
    x, y = centre_of_region()
    simulate("MOUSEMOVE", "NOTHING", xy=(x - 30, y + 40))


def paste_picture():
    from paramorph import ops_paste
    stats["paste"]["pictured_header"] = ops_paste.header_line
    screenshot_rgb("paste")
    keep_for_readme("paste")


def paste_cancel():
    simulate("ESC")
    simulate("ESC", "RELEASE")


def paste_after_cancel():
    from paramorph import ops_paste
    stats["paste"]["after_cancel"] = {"phase": ops_paste.phase,
                                      "polygons": len(bpy.data.objects["CurvedTarget"].data.polygons)}


steps = [setup, None, find_tab, None, panel_picture,
         big_pair, None, morph_invoke, wait_running(2.0), press_escape, wait_ended, None, after_escape,
         placed_pair, keys_written, None, placed_check, modified_invoke, modified_ended, None, modified_check,
         unwrap_closed, None, fin_mesh, fin_ended, None, fin_check,
         paste_setup, None, paste_invoke, wait_placing, None, paste_first_header, paste_grow, None,
         paste_after_grow, None, paste_to_a_sensible_size, None, paste_picture, paste_cancel, None, paste_after_cancel]


run_steps(steps, "artist.json")
