"""Add-on benchmark, inside Blender (issue 4's figures): sphere map and
segmentation of a ~100k-face mesh run through the operators, and the share
of the time spent moving mesh data between Blender and numpy.

    PARAMORPH_BUILD_DIR=build blender -b --factory-startup --python tests/bench/addon.py [-- --repeats 5]

Prints JSON lines: per operator the median wall time, and the time spent in
foreach_get/foreach_set (the Blender <-> numpy copies) with its share.
"sphere_map+segment_extremities" is the artist's sequence: Segment
Extremities reuses the conformal map Sphere Map just computed."""
import argparse
import cProfile
import json
import pstats
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
from paramorph import bridge, sphere_cache  # noqa: E402

def transfer_seconds(operator):
    """Seconds inside foreach_get / foreach_set (the Blender <-> numpy copies)
    during one run of `operator`, from a profiled run (the profiler times
    each built-in call; the operator makes few Python calls, so its overhead
    is small)."""
    profile = cProfile.Profile()
    profile.enable()
    assert operator() == {"FINISHED"}
    profile.disable()
    stats = pstats.Stats(profile).stats
    return sum(entry[2] for (_, _, name), entry in stats.items()
               if "foreach_get" in name or "foreach_set" in name)


def run(operator, repeats):
    times = []
    for _ in range(repeats):
        start = time.perf_counter()
        assert operator() == {"FINISHED"}
        times.append(time.perf_counter() - start)
    transfers = [transfer_seconds(operator) for _ in range(3)]
    return statistics.median(times), statistics.median(transfers), times


def main():
    argv = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
    parser = argparse.ArgumentParser()
    parser.add_argument("--repeats", type=int, default=5)
    parser.add_argument("--faces", type=int, default=100_000)
    args = parser.parse_args(argv)

    bpy.ops.wm.read_factory_settings(use_empty=True)
    addon_utils.enable("paramorph", default_set=True)
    obj = make_samples.build_octopus(subdivisions=8, faces=args.faces)
    mesh = obj.data
    pm = bridge.native
    V, F, _, _ = bridge.mesh_arrays(mesh)
    base = {"mesh": "octopus", "vertices": len(mesh.vertices), "faces": len(F),
            "blender": bpy.app.version_string, "threads": os.cpu_count()}
    for name, operator in (
            ("sphere_map", lambda: bpy.ops.paramorph.sphere_map()),
            ("segment_extremities (own sphere map)",
             lambda: sphere_cache.clear() or bpy.ops.paramorph.segment_extremities()),
            ("sphere_map+segment_extremities",
             lambda: bpy.ops.paramorph.sphere_map() | bpy.ops.paramorph.segment_extremities()),
            ("detect_feature_regions", lambda: bpy.ops.paramorph.detect_feature_regions())):
        median, transfer, times = run(operator, args.repeats)
        print(json.dumps({**base, "operator": name, "seconds_median": round(median, 3),
                          "transfer_seconds": round(transfer, 4),
                          "transfer_share": round(transfer / median, 4),
                          "seconds": [round(t, 3) for t in times]}), flush=True)
    # The native calls alone, for the ratio to the operator.
    for name, call in (("native sphere_map", lambda: pm.sphere_map(V, F)),
                       ("native segment_extremities", lambda: pm.segment_extremities(V, F))):
        times = []
        for _ in range(args.repeats):
            start = time.perf_counter()
            call()
            times.append(time.perf_counter() - start)
        print(json.dumps({**base, "operator": name, "seconds_median": round(statistics.median(times), 3),
                          "seconds": [round(t, 3) for t in times]}), flush=True)


main()
