"""Runs inside a real Blender window (xvfb-run blender, not -b), driven by
tests/gui/test_overlay_screenshot.py:

    xvfb-run -a blender --python tests/gui/overlay_screenshot.py -- OUT_DIR

(with BLENDER_USER_CONFIG holding preferences that turn the splash off).

Segments the octopus sample, takes a viewport screenshot with the region
overlay off and one with it on, and writes pixel statistics of both to
OUT_DIR/overlay.json (the test asserts on them); then undoes the
segmentation (as Ctrl+Z does, in the window) and records what is left; then runs
Sphere Map as users do (INVOKE: a modal operator, the native call in a
thread), cancels it as Esc or the panel's Cancel button would, checks the
mesh is untouched, runs it again to the end; then Preview Matches (its
candidates are stored) and Morph To as a modal operator, undone; then Morph To
keeping the source's topology (keys on the source itself), undone; then quits.
(Pick Pins' overlay has its own window test: pick_pins_gui.py.)"""
import colorsys
import os
import sys

import bpy
import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from gui_session import keep_for_readme, run_steps, screenshot_rgb, stats, view3d, wait_while  # noqa: E402

import addon_utils  # noqa: E402
import make_samples  # noqa: E402
from paramorph import jobs  # noqa: E402


def setup():
    for obj in list(bpy.data.objects):
        bpy.data.objects.remove(obj, do_unlink=True)
    addon_utils.enable("paramorph", default_set=True)
    obj = make_samples.build_octopus(subdivisions=4)
    window, area, region = view3d()
    with bpy.context.temp_override(window=window, area=area, region=region):
        bpy.ops.ed.undo_push(message="Octopus")
        # As the UI calls it: with an undo step (bpy.ops from Python pushes none by default).
        assert bpy.ops.paramorph.segment_extremities("EXEC_DEFAULT", True) == {"FINISHED"}
        space = area.spaces.active
        space.shading.type = "SOLID"
        space.shading.color_type = "SINGLE"
        space.shading.single_color = (0.8, 0.8, 0.8)
        space.overlay.show_floor = False
        space.show_gizmo = False  # the navigation gizmo is coloured too
        space.overlay.show_axis_x = space.overlay.show_axis_y = False
        bpy.ops.view3d.view_all()
    obj.select_set(False)  # no selection outline in the picture
    bpy.context.scene.paramorph.show_overlay = False
    labels = np.empty(len(obj.data.polygons), dtype=np.int32)
    obj.data.attributes["paramorph_region"].data.foreach_get("value", labels)
    stats["regions"] = int(labels.max()) + 1


def picture(name):
    def take():
        rgb = screenshot_rgb(name)
        saturation = rgb.max(axis=1) - rgb.min(axis=1)
        colored = rgb[saturation > 0.25]
        hues = np.array([colorsys.rgb_to_hsv(*c)[0] for c in colored[:: max(1, len(colored) // 4000)]])
        hue_bins = np.histogram(hues, bins=12, range=(0, 1))[0] if len(hues) else np.zeros(12)
        stats[name] = {"pixels": int(len(rgb)), "colored": int(len(colored)),
                       "hue_bins_used": int((hue_bins > 0.02 * max(1, len(hues))).sum())}
    return take


def overlay_on():
    bpy.context.scene.paramorph.show_overlay = True
    view3d()[1].tag_redraw()


def turn_inside_out():
    """Every face wound the other way (as some exporters write files): the
    normals point inwards; the overlay must show all the same."""
    import bmesh
    obj = bpy.data.objects["Octopus"]
    bm = bmesh.new()
    bm.from_mesh(obj.data)
    bmesh.ops.reverse_faces(bm, faces=list(bm.faces))
    bm.to_mesh(obj.data)
    bm.free()
    obj.data.update()
    view3d()[1].tag_redraw()


def undo_in_window():
    """Ctrl+Z in the 3D View; old references to data are gone after it."""
    window, area, region = view3d()
    with bpy.context.temp_override(window=window, area=area, region=region):
        bpy.ops.ed.undo()


def undo():
    """Undo in a real window: the segmentation goes."""
    obj = bpy.data.objects["Octopus"]
    before = obj.data.attributes.get("paramorph_region") is not None
    undo_in_window()
    obj = bpy.data.objects["Octopus"]
    stats["undo"] = {"regions_before": before,
                     "regions_after": obj.data.attributes.get("paramorph_region") is not None,
                     "vertices_after": len(obj.data.vertices)}


def modal_setup():
    """A mesh big enough that the sphere map runs for a while in its thread."""
    bpy.data.objects.remove(bpy.data.objects["Octopus"], do_unlink=True)
    obj = make_samples.build_octopus(name="Big", subdivisions=7)
    bpy.context.view_layer.objects.active = obj
    stats["modal"] = {"faces": len(obj.data.polygons)}


def modal_invoke(label):
    def invoke():
        window, area, region = view3d()
        with bpy.context.temp_override(window=window, area=area, region=region):
            stats["modal"][label + "_invoke"] = sorted(bpy.ops.paramorph.sphere_map("INVOKE_DEFAULT"))
        stats["modal"][label + "_running"] = len(jobs.running())
    return invoke


def modal_cancel():
    stats["modal"]["running_at_cancel"] = len(jobs.running())
    jobs.cancel_all()


def wait_for_jobs(written=lambda: True, key="modal"):
    """A step that waits while a job's thread runs or what it writes is not
    there yet, for at most 120 s: the operator writes on its first timer event
    after the thread ends, not when the thread ends."""
    def wait():
        wait_while(steps, lambda: jobs.running() or not written(), stats[key])()
    return wait


def sphere_written():
    return "Sphere" in bpy.data.objects["Big"].data.uv_layers


def modal_check(label):
    def check():
        mesh = bpy.data.objects["Big"].data
        stats["modal"][label] = {"sphere_uv": "Sphere" in mesh.uv_layers,
                                 "shape_keys": mesh.shape_keys is not None}
    return check


def morph_setup():
    bpy.data.objects.remove(bpy.data.objects["Big"], do_unlink=True)
    # One shape on two tessellations: its tentacles match.
    source = make_samples.build_octopus(name="Octopus", subdivisions=3, limbs=4)
    target = make_samples.build_octopus(name="OctopusB", subdivisions=4, limbs=4)
    source.location, target.location = (-1.8, 0.0, 0.0), (1.8, 0.0, 0.0)
    for obj in (source, target):
        obj.select_set(True)
    bpy.context.view_layer.objects.active = target
    window, area, region = view3d()
    with bpy.context.temp_override(window=window, area=area, region=region):
        bpy.ops.view3d.view_all()
        bpy.ops.ed.undo_push(message="Morph inputs")
        stats["morph"] = {"preview": sorted(bpy.ops.paramorph.preview_matches("EXEC_DEFAULT", True))}
    for obj in (source, target):
        obj.select_set(False)  # no selection outline in the picture
    matches = bpy.context.scene.paramorph_matches
    stats["morph"]["pairs"] = len(matches.pairs)
    stats["morph"]["candidates"] = len(matches.candidates)
    stats["morph"]["chosen"] = sum(c.chosen for c in matches.candidates)
    stats["morph"]["objects_before"] = sorted(o.name for o in bpy.data.objects)


def invoke_morph_to(topology):
    """Morph To from the 3D View (INVOKE, modal) on Octopus and OctopusB; its result."""
    source, target = bpy.data.objects["Octopus"], bpy.data.objects["OctopusB"]
    for obj in (source, target):
        obj.select_set(True)
    bpy.context.view_layer.objects.active = target
    window, area, region = view3d()
    with bpy.context.temp_override(window=window, area=area, region=region):
        return sorted(bpy.ops.paramorph.morph_to("INVOKE_DEFAULT", topology=topology))


def morph_invoke():
    stats["morph"]["invoke"] = invoke_morph_to("MERGED")
    stats["morph"]["running"] = len(jobs.running())


def morph_written():
    return "Octopus to OctopusB" in bpy.data.objects


def morph_check_and_undo():
    morph = bpy.data.objects.get("Octopus to OctopusB")
    keys = [] if morph is None or morph.data.shape_keys is None else \
        [k.name for k in morph.data.shape_keys.key_blocks]
    # Basis, eight in-betweens (as rigid as possible) and the target, driven by one property.
    stats["morph"]["made"] = len(keys) == 10 and keys[0] == "Basis" and keys[-1] == "OctopusB" and \
        "paramorph_morph" in morph and len(morph.data.shape_keys.animation_data.drivers) == 9
    stats["morph"]["objects_done"] = sorted(o.name for o in bpy.data.objects)
    undo_in_window()
    stats["morph"]["objects_undone"] = sorted(o.name for o in bpy.data.objects)


def keep_invoke():
    """Morph To again, keeping the source's topology: keys on Octopus itself."""
    stats["keep"] = {"keys_before": bpy.data.objects["Octopus"].data.shape_keys is not None}
    stats["keep"]["invoke"] = invoke_morph_to("KEEP")


def keep_written():
    return bpy.data.objects["Octopus"].data.shape_keys is not None


def keep_check_and_undo():
    source = bpy.data.objects["Octopus"]
    keys = [] if source.data.shape_keys is None else [k.name for k in source.data.shape_keys.key_blocks]
    stats["keep"]["keys"] = keys
    stats["keep"]["property"] = "paramorph_morph" in source
    undo_in_window()
    source = bpy.data.objects["Octopus"]
    stats["keep"]["keys_undone"] = source.data.shape_keys is not None
    stats["keep"]["property_undone"] = "paramorph_morph" in source
    stats["keep"]["objects_undone"] = sorted(o.name for o in bpy.data.objects)


steps = [setup, None, picture("off"), overlay_on, None, picture("on"), lambda: keep_for_readme("on", "overlay"),
         turn_inside_out, None,
         picture("inside_out"), undo,
         modal_setup, modal_invoke("first"), modal_cancel, wait_for_jobs(), None, modal_check("cancelled"),
         modal_invoke("second"), wait_for_jobs(sphere_written), None, modal_check("finished"),
         morph_setup, None, morph_invoke, wait_for_jobs(morph_written, "morph"), None, morph_check_and_undo,
         keep_invoke, wait_for_jobs(keep_written, "keep"), None, keep_check_and_undo]


run_steps(steps, "overlay.json")
