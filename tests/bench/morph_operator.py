"""Whole morph from the operator, inside Blender (issue 5's figure: two
20k-face meshes <= 30 s), as an artist runs it (no Sphere Map cached
beforehand, features on), on two pairs:
  suzanne-octopus  a closed Suzanne (voxel remesh) into the octopus sample
                   decimated to the same size: unlike shapes, so the 3D
                   registration is left out (see morph.h, max_fold_share);
  octopus-octopus  the octopus decimated from two icosphere levels (one shape,
                   two tessellations): the registration is used.

    PARAMORPH_BUILD_DIR=build blender -b --factory-startup --python tests/bench/morph_operator.py \
        [-- --faces 20000 --repeats 3]

Prints one JSON line per pair: the operator's median wall time and, from
the native result, the per-stage seconds of the last run, the merged face
count and the pairs used. The target of --faces sets the octopus's size
exactly and Suzanne's voxel size from a fitted rule (faces ~ 33.4 / voxel^2)."""
import argparse
import json
import os
import statistics
import sys
import time

import bpy

REPO = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
BUILD = os.path.join(REPO, os.environ.get("PARAMORPH_BUILD_DIR", "build"), "python")
for path in (BUILD, os.path.join(REPO, "addon"), os.path.join(REPO, "blend_samples")):
    sys.path.insert(0, path)

import addon_utils  # noqa: E402
import make_samples  # noqa: E402


class RecordingNative:
    """The native module with morph() wrapped to keep its last result, so the
    benchmark reads the stage timings of the run the operator made."""

    def __init__(self, native):
        self._native = native
        self.last = None

    def __getattr__(self, name):
        return getattr(self._native, name)

    def morph(self, *args, **kwargs):
        self.last = self._native.morph(*args, **kwargs)
        return self.last


def select_pair(source, target):
    for obj in bpy.context.view_layer.objects:
        obj.select_set(obj in (source, target))
    bpy.context.view_layer.objects.active = target


def main():
    argv = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
    parser = argparse.ArgumentParser()
    parser.add_argument("--faces", type=int, default=20_000)
    parser.add_argument("--repeats", type=int, default=3)
    args = parser.parse_args(argv)

    bpy.ops.wm.read_factory_settings(use_empty=True)
    addon_utils.enable("paramorph", default_set=True)
    from paramorph import ops_morph

    recorder = RecordingNative(ops_morph.native)
    ops_morph.native = recorder
    pairs = {
        "suzanne-octopus": lambda: (make_samples.build_suzanne_closed(voxel_size=(33.4 / args.faces) ** 0.5),
                                    make_samples.build_octopus(subdivisions=6, faces=args.faces)),
        "octopus-octopus": lambda: (make_samples.build_octopus(subdivisions=6, faces=args.faces),
                                    make_samples.build_octopus(name="OctopusB", subdivisions=7,
                                                               faces=args.faces)),
    }
    for name, build in pairs.items():
        for obj in list(bpy.data.objects):
            bpy.data.objects.remove(obj)
        source, target = build()
        target.location = (4.0, 0.0, 0.0)
        run_pair(name, source, target, recorder, args.repeats)


def run_pair(name, source, target, recorder, repeats):
    from paramorph import sphere_cache

    times = []
    for _ in range(repeats):
        sphere_cache.clear()  # an artist's first Morph To computes both sphere maps
        select_pair(source, target)
        start = time.perf_counter()
        assert bpy.ops.paramorph.morph_to() == {"FINISHED"}
        times.append(time.perf_counter() - start)
        bpy.data.objects.remove(bpy.context.view_layer.objects.active)
    result = recorder.last
    print(json.dumps({
        "benchmark": "morph_to operator", "pair": name, "source": source.name, "source_faces": len(source.data.polygons),
        "target": target.name, "target_faces": len(target.data.polygons),
        "merged_faces": len(result.faces), "pairs": len(result.pairs),
        "registered": result.registration_cost is not None,
        "registration_fold_share": round(result.registration_fold_share, 4),
        "seconds_median": round(statistics.median(times), 2), "seconds": [round(t, 2) for t in times],
        "stages": {name: round(seconds, 2) for name, seconds in result.timings},
        "blender": bpy.app.version_string}), flush=True)


main()
