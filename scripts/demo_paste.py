"""The README's cut-and-paste demo, run inside `blender -b` by scripts/demo.sh:

    blender -b --factory-startup --python-exit-code 1 --python scripts/demo_paste.py -- [--out DIR]

Builds the paste sample of blend_samples/make_samples.py (a CAD-like plate
with a cylindrical boss, and a smooth curved body) and runs the add-on's
operators on it as an artist would: in Edit Mode on the plate, the boss and
a ring of plate around it selected (the faces within BOSS_BALL), Copy
Feature; then on the curved body, Paste Feature at the top of the body and
again, turned and smaller, on its side. Saves DIR/paste.blend (both objects
and the stored feature) and a Workbench render DIR/paste.png."""
import math
import os
import sys

import bpy
import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import demo_blender  # noqa: E402  (puts the build, the add-on and the samples on sys.path)
import make_samples  # noqa: E402

# Where the feature goes on the curved target (its object coordinates), its turn and scale.
PLACEMENTS = (((0.0, 0.0, 1.3), 0.0, 1.0), ((1.6, 0.0, 0.0), math.radians(30.0), 0.7))


def select_ball(obj, ball):
    """Selects (face select) the faces of `obj` whose centre lies in the ball (x, y, z, r)."""
    from paramorph import regions
    mesh = obj.data
    centres = np.empty(3 * len(mesh.polygons), dtype=np.float32)
    mesh.polygons.foreach_get("center", centres)
    inside = np.linalg.norm(centres.reshape(-1, 3) - np.array(ball[:3]), axis=1) <= ball[3]
    regions.select_polygons(mesh, inside)
    return int(inside.sum())


def main():
    args, out_dir = demo_blender.start("demo_paste.py", (960, 720))
    source, target = make_samples.build_paste_pair()

    demo_blender.activate(source)
    count = select_ball(source, make_samples.BOSS_BALL)
    bpy.ops.object.mode_set(mode="EDIT")
    bpy.context.tool_settings.mesh_select_mode = (False, False, True)
    bpy.ops.paramorph.copy_feature()
    bpy.ops.object.mode_set(mode="OBJECT")
    print(f"demo: copy feature: {count} faces of {source.name}", flush=True)

    demo_blender.activate(target)
    faces = len(target.data.polygons)
    for location, rotation, scale in PLACEMENTS:
        bpy.ops.paramorph.paste_feature(location=location, rotation=rotation, scale=scale)
        print(f"demo: paste feature on {target.name} at {location}, rotation "
              f"{math.degrees(rotation):.0f} deg, scale {scale}: {faces} -> {len(target.data.polygons)} faces",
              flush=True)
        faces = len(target.data.polygons)
    # Deselect, so the render shows no selection.
    for obj in (source, target):
        obj.data.polygons.foreach_set("select", np.zeros(len(obj.data.polygons), dtype=bool))
    bpy.context.view_layer.update()

    scene = bpy.context.scene
    demo_blender.add_camera([source, target], args.resolution[0] / args.resolution[1],
                            direction=(0.35, -1.0, 0.8))
    png = os.path.join(out_dir, "paste.png")
    demo_blender.set_up_render(scene, png, args.resolution)
    scene.display.shading.color_type = "OBJECT"
    source.color = (0.55, 0.65, 0.85, 1.0)
    target.color = (0.9, 0.6, 0.35, 1.0)
    blend = os.path.join(out_dir, "paste.blend")
    bpy.ops.wm.save_as_mainfile(filepath=blend, check_existing=False)
    print(f"demo: wrote {blend}", flush=True)
    demo_blender.render_still(scene, png)
    print(f"demo: wrote {png} ({args.resolution[0]}x{args.resolution[1]}, Workbench)", flush=True)


if __name__ == "__main__":
    main()
