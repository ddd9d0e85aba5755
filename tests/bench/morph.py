"""Morph benchmarks (issue 5's figures), JSON lines:

    /usr/bin/python3 tests/bench/morph.py [--sizes 5600 50000] [--repeats 3]
        [--meshes spot blob bunny tentacles]

optimize_sphere_map (thesis 4.3.3; Table 4.2: 934 s for Suzanne at 5,610
faces), started as morph starts it (--start auto: the conformal sphere_map,
or the radial projection relaxed until fold-free, thesis 4.3.2, where the
conformal one squeezes faces), or from either one (--start relaxed,
--start conformal), on:
  spot       the shared model (2,930 vertices, 5,856 faces), when present;
  blob       sized_sphere_mesh of about each --sizes face count (a noisy
             sphere: its radial projection folds little, few bounds active);
  bunny      the shared Stanford bunny with its 5 holes closed by centroid
             fans (34,839 vertices, 69,674 faces; ears squeezed to 1e-12 by
             the conformal start), when present;
  tentacles  tentacle_sphere of about each --sizes face count (4 long
             fingers, squeezed to rounding by the conformal start).
Default: spot and blob. --solvers: "ipopt" (the barrier path's first 4
decades of mu, then Ipopt's polish; source builds with Ipopt) and "barrier"
(the path alone, 8 decades: what the released wheel, built without Ipopt,
runs); both where this build has Ipopt, for the side-by-side figures.
Reports Ipopt's iterations, the barrier's Newton steps, the median seconds,
folded faces, the smallest triple product over epsilon, the objective (n at
best) and, for "barrier", its relative gap to "ipopt"'s objective."""
import argparse
import sys

import numpy as np

from common import MODELS, emit, import_native, load_obj, median_run

pm = import_native()
import meshes  # noqa: E402  (tests/native, on sys.path after import_native)


def closed_bunny():
    """The shared bunny scan with each boundary loop closed by a fan around its centroid."""
    V, F = load_obj(MODELS / "stanford-bunny.obj")
    used = np.unique(F)
    remap = np.full(len(V), -1)
    remap[used] = np.arange(len(used))
    V, F = V[used], remap[F]
    directed = {(a, b) for a, b in np.concatenate([F[:, [0, 1]], F[:, [1, 2]], F[:, [2, 0]]]).tolist()}
    follow = {b: a for a, b in directed if (b, a) not in directed}  # boundary edges, reversed
    fans, extra, seen = [], [], set()
    for first in follow:
        if first in seen:
            continue
        loop, vertex = [], first
        while vertex not in seen:
            seen.add(vertex)
            loop.append(vertex)
            vertex = follow[vertex]
        centre = len(V) + len(extra)
        extra.append(V[loop].mean(axis=0))
        fans += [[loop[i], loop[(i + 1) % len(loop)], centre] for i in range(len(loop))]
    return np.vstack([V, extra]), np.vstack([F, fans]).astype(np.int32)


def workloads(sizes, names):
    if "spot" in names and (MODELS / "spot.obj").exists():
        yield "spot", *load_obj(MODELS / "spot.obj")
    for faces in sizes:
        if "blob" in names:
            yield f"blob-{faces}", *meshes.sized_sphere_mesh(faces)
        if "tentacles" in names:
            # tentacle_sphere at the subdivision whose face count is nearest.
            best = min(range(1, 7), key=lambda s: abs(len(meshes.tentacle_sphere(s, tentacles=4)[1]) - faces))
            yield f"tentacles-{faces}", *meshes.tentacle_sphere(best, tentacles=4)
    if "bunny" in names and (MODELS / "stanford-bunny.obj").exists():
        yield "bunny-closed", *closed_bunny()


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--sizes", type=int, nargs="*", default=[5600, 50000])
    parser.add_argument("--repeats", type=int, default=3)
    parser.add_argument("--meshes", nargs="*", default=["spot", "blob"],
                        choices=["spot", "blob", "bunny", "tentacles"])
    parser.add_argument("--start", choices=["auto", "relaxed", "conformal"], default="auto")
    parser.add_argument("--solvers", nargs="*", choices=["ipopt", "barrier"],
                        default=["ipopt", "barrier"] if pm.build_info()["ipopt"] else ["barrier"])
    args = parser.parse_args()
    for name, V, F in workloads(args.sizes, args.meshes):
        if args.start == "relaxed":
            start = pm.sphere_map(V, F, init="relaxation", max_outer_iterations=0).positions
        elif args.start == "conformal":
            start = pm.sphere_map(V, F).positions
        else:
            start = None  # optimize_sphere_map picks it, as morph does: its time is counted
        reference = None
        for solver in args.solvers:
            seconds, r = median_run(lambda: pm.optimize_sphere_map(V, F, start, solver=solver), args.repeats)
            record = {"bench": "optimize_sphere_map", "mesh": name, "start": args.start, "solver": solver,
                      "vertices": len(V), "faces": len(F),
                      "seconds_median": round(seconds, 3), "repeats": args.repeats, "iterations": r.iterations,
                      "barrier_steps": r.barrier_steps, "status": r.status, "flipped": r.flipped,
                      "min_triple_over_epsilon": round(r.min_triple / r.epsilon, 4),
                      "objective": round(r.objective, 3), "start_objective": round(r.start_objective, 3)}
            if reference is not None:
                record["objective_gap_to_" + args.solvers[0]] = float(f"{(reference - r.objective) / reference:.2e}")
            reference = r.objective if reference is None else reference
            emit(record)

if __name__ == "__main__":
    sys.exit(main())
