"""Whole morph from the operator, inside Blender (issue 5's figure: two
20k-face meshes <= 30 s), as an artist runs it (Morph To with its defaults:
automatic correspondence, no preview, no pins; then once more with one pin),
on two pairs:
  suzanne-octopus  a closed Suzanne (voxel remesh) into the octopus sample
                   decimated to the same size: unlike shapes;
  octopus-octopus  the octopus decimated from two icosphere levels (one shape,
                   two tessellations).

    PARAMORPH_BUILD_DIR=build blender -b --factory-startup --python tests/bench/morph_operator.py \
        [-- --faces 20000 --repeats 3]

Prints one JSON line per pair: the operator's median wall time and, from
the native result, the per-stage seconds of the last run, the merged face
count, the candidate chosen (kind, detail, score, and what "none" scored),
the pins and pairs held exactly and the distortion; then the time of one run
with a pin (the vertices farthest along +x on each object). The target of
--faces sets the octopus's size exactly and Suzanne's voxel size from a
fitted rule (faces ~ 33.4 / voxel^2)."""
import argparse
import json
import os
import statistics
import sys
import time

import bpy
import numpy as np

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
    from paramorph.morph import operators as ops_morph

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


def run_morph(source, target):
    select_pair(source, target)
    start = time.perf_counter()
    assert bpy.ops.paramorph.morph_to(topology="MERGED") == {"FINISHED"}
    seconds = time.perf_counter() - start
    bpy.data.objects.remove(bpy.context.view_layer.objects.active)
    return seconds


def farthest_along_x(obj):
    co = np.empty(3 * len(obj.data.vertices), dtype=np.float32)
    obj.data.vertices.foreach_get("co", co)
    return int(np.argmax(co.reshape(-1, 3)[:, 0]))


def run_pair(name, source, target, recorder, repeats):
    bpy.ops.paramorph.clear_matches()
    times = [run_morph(source, target) for _ in range(repeats)]
    result = recorder.last
    candidates = result.candidates
    chosen = candidates[result.chosen]
    none = next((c for c in candidates if c.kind == "none"), None)
    pins = int(np.count_nonzero(np.asarray(result.pair_is_pin)))
    record = {
        "benchmark": "morph_to operator", "pair": name, "source": source.name,
        "source_faces": len(source.data.polygons), "target": target.name,
        "target_faces": len(target.data.polygons), "merged_faces": len(result.faces),
        "chosen": {"kind": chosen.kind, "detail": chosen.detail, "score": round(chosen.score, 4)},
        "none_score": None if none is None else round(none.score, 4), "candidates": len(candidates),
        "pins": pins, "pairs": len(result.pairs) - pins, "distortion": round(result.distortion, 4),
        "inside_out": [result.inside_out_a, result.inside_out_b],
        "seconds_median": round(statistics.median(times), 2), "seconds": [round(t, 2) for t in times],
        "stages": {stage: round(seconds, 2) for stage, seconds in result.timings}}
    select_pair(source, target)
    assert bpy.ops.paramorph.add_pin(vertex_a=farthest_along_x(source),
                                     vertex_b=farthest_along_x(target)) == {"FINISHED"}
    record["seconds_with_a_pin"] = round(run_morph(source, target), 2)
    record["blender"] = bpy.app.version_string
    print(json.dumps(record), flush=True)


main()
