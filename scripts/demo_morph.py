"""The README's morph demo, run inside `blender -b` by scripts/demo.sh:

    blender -b --factory-startup --python-exit-code 1 --python scripts/demo_morph.py -- [--out DIR] [--frames N]

Builds the morph sample of blend_samples/make_samples.py (a closed Suzanne
and a blob of unrelated triangulations) and runs the add-on's operators on it
as an artist would: Segment Extremities on Suzanne (its regions' colours are
what the renders show), Preview Matches (the correspondence Morph To will
choose, printed with its score and what "no pairs" scored), then Morph To
over N frames (eased). The morph object carries Suzanne's region colours; the
two inputs are hidden. Saves DIR/morph.blend and renders the first, middle and
last frames with Workbench to DIR/morph_####.png."""
import os
import sys

import bpy
import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import demo_blender  # noqa: E402  (puts the build, the add-on and the samples on sys.path)
import make_samples  # noqa: E402


def morph_corners(obj, frames):
    """World-space bounding-box corners of the morph at the given frames."""
    corners = []
    for frame in frames:
        bpy.context.scene.frame_set(frame)
        evaluated = obj.evaluated_get(bpy.context.evaluated_depsgraph_get())
        corners.append(demo_blender.world_corners(evaluated))
    return np.vstack(corners)


def main():
    args, out_dir = demo_blender.start("demo_morph.py", (960, 720), lambda parser: parser.add_argument(
        "--frames", type=int, default=48, help="length of the morph"))
    source, target = make_samples.build_morph_pair()
    view_layer = bpy.context.view_layer
    view_layer.objects.active = source
    bpy.ops.paramorph.segment_extremities()
    print(f"demo: {source.name}: {source.paramorph_regions} regions (their colours ride along)", flush=True)
    view_layer.objects.active = target  # the pair again: Suzanne selected, the blob active
    bpy.ops.paramorph.preview_matches()
    matches = bpy.context.scene.paramorph_matches
    chosen = next(c for c in matches.candidates if c.chosen)
    none = next((c for c in matches.candidates if c.kind == "none"), None)
    print(f"demo: preview matches: chosen {chosen.kind} ({chosen.detail}), score {chosen.score:.3g}"
          + (f", no pairs {none.score:.3g}" if none is not None else "")
          + f"; {len(matches.pairs)} pairs of {len(matches.candidates)} candidates", flush=True)
    scene = bpy.context.scene
    scene.frame_start, scene.frame_end = 1, args.frames
    bpy.ops.paramorph.morph_to(topology="MERGED", frame_start=1, frame_end=args.frames, easing="EASE")
    morph = bpy.context.view_layer.objects.active
    print(f"demo: {morph.name}: {len(morph.data.vertices)} vertices, {len(morph.data.polygons)} faces, "
          f"shape keys {[k.name for k in morph.data.shape_keys.key_blocks]}", flush=True)
    for obj in (source, target):
        obj.hide_render = True
        obj.hide_set(True)

    frames = (1, (1 + args.frames) // 2, args.frames)
    demo_blender.add_camera([morph], args.resolution[0] / args.resolution[1],
                            corners=morph_corners(morph, frames))
    demo_blender.set_up_render(scene, os.path.join(out_dir, "morph_"), args.resolution)
    blend = os.path.join(out_dir, "morph.blend")
    scene.frame_set(1)
    bpy.ops.wm.save_as_mainfile(filepath=blend, check_existing=False)
    print(f"demo: wrote {blend}", flush=True)
    for frame in frames:
        scene.frame_set(frame)
        png = os.path.join(out_dir, f"morph_{frame:04d}.png")
        demo_blender.render_still(scene, png)
        print(f"demo: wrote {png} (frame {frame})", flush=True)


if __name__ == "__main__":
    main()
