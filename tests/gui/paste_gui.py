"""Runs inside a real Blender window (xvfb-run blender --enable-event-simulate,
not -b), driven by tests/gui/test_paste_gui.py:

    xvfb-run -a blender --enable-event-simulate --python tests/gui/paste_gui.py -- OUT_DIR

Paste Feature as users run it: the boss of the paste sample copied, then
pasted from the redo-panel path with an undo step and undone (undo needs a
window); then the modal tool invoked over the 3D View and driven with
simulated events (mouse moves, R, Ctrl+wheel), its preview checked in a
viewport screenshot, cancelled with Esc (mesh untouched, no undo step),
invoked again and confirmed with Enter (mesh changed), and undone in one
step. Writes OUT_DIR/paste.json (the test asserts on it), then quits."""
import colorsys
import hashlib
import os
import sys

import bpy
import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from gui_session import centre_of_region, run_steps, screenshot_rgb, simulate, stats, view3d, wait_while  # noqa: E402

import addon_utils  # noqa: E402
import make_samples  # noqa: E402


def mesh_digest():
    mesh = bpy.data.objects["CurvedTarget"].data
    co = np.empty(3 * len(mesh.vertices), dtype=np.float32)
    mesh.vertices.foreach_get("co", co)
    return {"polygons": len(mesh.polygons), "vertices": len(mesh.vertices),
            "hash": hashlib.sha1(co.tobytes()).hexdigest()}


def setup():
    for obj in list(bpy.data.objects):
        bpy.data.objects.remove(obj, do_unlink=True)
    addon_utils.enable("paramorph", default_set=True)
    source, target = make_samples.build_paste_pair()
    bpy.context.view_layer.objects.active = source
    from paramorph import regions
    centres = np.empty(3 * len(source.data.polygons), dtype=np.float32)
    source.data.polygons.foreach_get("center", centres)
    ball = np.array(make_samples.BOSS_BALL)
    regions.select_polygons(source.data, np.linalg.norm(centres.reshape(-1, 3) - ball[:3], axis=1) <= ball[3])
    window, area, region = view3d()
    with bpy.context.temp_override(window=window, area=area, region=region):
        bpy.ops.object.mode_set(mode="EDIT")
        bpy.context.tool_settings.mesh_select_mode = (False, False, True)
        stats["copy"] = sorted(bpy.ops.paramorph.copy_feature("EXEC_DEFAULT", True))
        bpy.ops.object.mode_set(mode="OBJECT")
        for obj in bpy.context.view_layer.objects:
            obj.select_set(obj == target)
        bpy.context.view_layer.objects.active = target
        space = area.spaces.active
        space.shading.type = "SOLID"
        space.shading.color_type = "SINGLE"
        space.shading.single_color = (0.8, 0.8, 0.8)
        space.overlay.show_floor = False
        space.show_gizmo = False
        space.overlay.show_axis_x = space.overlay.show_axis_y = False
        bpy.ops.view3d.view_selected()
        bpy.ops.ed.undo_push(message="Paste target")
    target.select_set(False)  # no outline in the pictures
    stats["start"] = mesh_digest()


def paste_exec_and_undo():
    window, area, region = view3d()
    with bpy.context.temp_override(window=window, area=area, region=region):
        stats["exec"] = sorted(bpy.ops.paramorph.paste_feature("EXEC_DEFAULT", True, location=(0.0, 0.0, 1.3)))
        stats["exec_done"] = mesh_digest()
        bpy.ops.ed.undo()
    stats["exec_undone"] = mesh_digest()


def modal_invoke(label):
    def invoke():
        x, y = centre_of_region()
        simulate("MOUSEMOVE", "NOTHING", xy=(x, y))  # the mouse over the target's middle
        window, area, region = view3d()
        with bpy.context.temp_override(window=window, area=area, region=region):
            stats[label] = {"invoke": sorted(bpy.ops.paramorph.paste_feature("INVOKE_DEFAULT", True))}
    return invoke


def wait_placing():
    """Waits until the tool follows the mouse (at most 120 s)."""
    from paramorph import ops_paste
    wait_while(steps, lambda: ops_paste.phase != "placing", stats)()


def modal_drive():
    x, y = centre_of_region()
    simulate("MOUSEMOVE", "NOTHING", xy=(x + 20, y + 30))
    simulate("R")
    simulate("R", "RELEASE")
    simulate("WHEELUPMOUSE", ctrl=True)


def picture(name):
    def take():
        rgb = screenshot_rgb(name)
        hsv = np.array([colorsys.rgb_to_hsv(*c) for c in rgb[::7]])
        orange = (hsv[:, 1] > 0.35) & (hsv[:, 0] > 0.03) & (hsv[:, 0] < 0.15) & (hsv[:, 2] > 0.2)
        stats[name] = {"orange_share": float(orange.mean())}
    return take


def modal_cancel():
    simulate("ESC")
    simulate("ESC", "RELEASE")


def modal_confirm():
    simulate("RET")
    simulate("RET", "RELEASE")


def record(name):
    def take():
        stats[name] = mesh_digest()
    return take


def undo_last():
    window, area, region = view3d()
    with bpy.context.temp_override(window=window, area=area, region=region):
        bpy.ops.ed.undo()
    stats["modal_undone"] = mesh_digest()


steps = [setup, None, paste_exec_and_undo, None,
         picture("before"), modal_invoke("first"), wait_placing, None, modal_drive, None, picture("preview"),
         modal_cancel, None, record("cancelled"),
         modal_invoke("second"), wait_placing, None, modal_drive, None, modal_confirm, None, record("confirmed"),
         undo_last, None]


run_steps(steps, "paste.json")
