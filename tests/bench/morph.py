"""Morph benchmarks (issue 5's figures), JSON lines:

    /usr/bin/python3 tests/bench/morph.py [--sizes 5600 50000] [--repeats 3]

optimize_sphere_map (thesis 4.3.3; Table 4.2: 934 s for Suzanne at 5,610
faces) on spot (shared models, when present) and on generated tentacle
meshes of about the given face counts, started from sphere_map."""
import argparse
import sys

from common import MODELS, emit, import_native, load_obj, median_run

pm = import_native()
import meshes  # noqa: E402  (tests/native, on sys.path after import_native)


def workloads(sizes):
    spot = MODELS / "spot.obj"
    if spot.exists():
        yield "spot", *load_obj(spot)
    for faces in sizes:
        # tentacle_sphere at the subdivision whose face count is nearest.
        best = min(range(1, 7), key=lambda s: abs(len(meshes.tentacle_sphere(s, tentacles=4)[1]) - faces))
        yield f"tentacles-{faces}", *meshes.tentacle_sphere(best, tentacles=4)


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--sizes", type=int, nargs="*", default=[5600, 50000])
    parser.add_argument("--repeats", type=int, default=3)
    args = parser.parse_args()
    for name, V, F in workloads(args.sizes):
        start = pm.sphere_map(V, F).positions
        seconds, r = median_run(lambda: pm.optimize_sphere_map(V, F, start), args.repeats)
        emit({"bench": "optimize_sphere_map", "mesh": name, "vertices": len(V), "faces": len(F),
              "seconds_median": round(seconds, 3), "iterations": r.iterations, "status": r.status,
              "flipped": r.flipped, "objective": round(r.objective, 2),
              "start_objective": round(r.start_objective, 2)})


if __name__ == "__main__":
    sys.exit(main())
