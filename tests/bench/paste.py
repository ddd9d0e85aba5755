"""Feature paste benchmark (issue 6's figures: first paste of a 10k-face feature
onto a 100k-face target <= 1 s; interactive update <= 30 ms median; issue 19:
the same budget on curved targets, where the disc map stands in for the
exponential map), JSON lines:

    /usr/bin/python3 tests/bench/paste.py [--target sphere|scan|head|noisy-head]
        [--faces 100000] [--feature-n 90] [--scale 0.3] [--updates 40]
        [--repeats 3] [--anchors 8] [--radius 0.04] [--target-map auto]

Feature: the Gaussian bump of meshes.bump_plane(n=--feature-n) (about 10k faces
at 90), extracted once (not timed here: tests/bench/extract_feature.py).

--target sphere (default): meshes.sized_sphere_mesh(--faces), the unit
sphere. First paste: the median seconds of PasteSession(...) (topology,
OpenSubdiv refiner, closest-point tree, the feature's lookup grid, RBF
factorization, one placement). Update: the median of --updates
session.update() calls that slide the anchor along an arc in small steps and
turn the feature, as a drag does.

--target scan | head | noisy-head: meshes.scan_like(--faces) (noisy, bumpy),
meshes.cartoon_head(6) (82k faces) or the same with scan noise (0.6 edge):
the feature at --radius times the target's diagonal, as issue 19 measured.
At --anchors random vertices where it fits, a drag of --updates steps (each
1% of the feature's radius along the surface, turning 0.02 rad), repeated
--repeats times: the median update and the median of its parameterization
part (stats map_seconds), overall and split by the map used (exponential or
disc), the 90th percentile, and the median CPU time of the process per
update (all threads; with OMP_NUM_THREADS=1 the figure least disturbed by
other work on a shared machine). --target-map exponential times the paste as
it was before the disc map (it refuses where that folds)."""
import argparse
import statistics
import time

import numpy as np

from common import emit, import_native, median_run

pm = import_native()
import meshes  # noqa: E402  (tests/native, on sys.path after import_native)


def curved_target(name, faces):
    if name == "scan":
        return meshes.scan_like(faces)
    if name == "head":
        return meshes.cartoon_head(6)
    return meshes.cartoon_head(6, noise=0.6)


def drag_on_curved_target(args, feature):
    T, TF = curved_target(args.target, args.faces)
    scale = args.radius * np.linalg.norm(T.max(0) - T.min(0)) / feature.radius
    rng = np.random.default_rng(0)
    N = np.zeros_like(T)  # vertex normals, to step along the tangent plane
    n = np.cross(T[TF[:, 1]] - T[TF[:, 0]], T[TF[:, 2]] - T[TF[:, 0]])
    for k in range(3):
        np.add.at(N, TF[:, k], n)
    N /= np.linalg.norm(N, axis=1, keepdims=True)
    session, starts = None, []
    for v in rng.choice(len(T), 20 * args.anchors, replace=False):
        try:
            if session is None:
                session = pm.PasteSession(T, TF, feature, anchor=T[v], scale=scale, target_map=args.target_map)
            else:
                session.update(anchor=T[v], rotation=0.0)
            starts.append(v)
        except pm.TargetTooSmallError:
            pass
        if len(starts) == args.anchors:
            break
    step = 0.01 * session.stats["feature_radius"]
    runs, cpu_runs, records = [], [], []
    for _ in range(args.repeats):
        times, cpu = [], []
        for v in starts:
            direction = np.cross(N[v], [0.0, 0.0, 1.0] if abs(N[v][2]) < 0.9 else [1.0, 0.0, 0.0])
            direction /= np.linalg.norm(direction)
            for k in range(args.updates):
                t0, c0 = time.perf_counter(), time.process_time()
                try:
                    session.update(anchor=T[v] + (k * step) * direction, rotation=0.02 * k)
                except pm.TargetTooSmallError:
                    records.append(None)
                    continue
                times.append(time.perf_counter() - t0)
                cpu.append(time.process_time() - c0)
                st = session.stats
                records.append((times[-1], st["map_seconds"], st["target_map"], st["disc_faces"]))
        runs.append(statistics.median(times))
        cpu_runs.append(statistics.median(cpu))
    done = [r for r in records if r is not None]

    def median_of(rows, k):
        return statistics.median(r[k] for r in rows) if rows else None

    disc = [r for r in done if r[2] == "disc"]
    exp = [r for r in done if r[2] == "exponential"]
    emit({"bench": "paste_curved", "target": args.target, "target_faces": int(len(TF)),
          "feature_faces": int(len(feature.faces)), "radius_fraction": args.radius, "scale": scale,
          "target_map": args.target_map, "anchors": len(starts), "updates": len(records),
          "refused_updates": len(records) - len(done), "repeats": args.repeats,
          "update_median_seconds": statistics.median(runs), "update_median_per_run": runs,
          "update_cpu_median_seconds": statistics.median(cpu_runs),
          "update_p90_seconds": float(np.percentile([r[0] for r in done], 90)),
          "map_median_seconds": median_of(done, 1),
          "disc_updates": len(disc), "disc_update_median_seconds": median_of(disc, 0),
          "disc_map_median_seconds": median_of(disc, 1), "disc_faces_median": median_of(disc, 3),
          "exponential_updates": len(exp), "exponential_update_median_seconds": median_of(exp, 0)})


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--target", choices=["sphere", "scan", "head", "noisy-head"], default="sphere")
    parser.add_argument("--faces", type=int, default=100000)
    parser.add_argument("--feature-n", type=int, default=90)
    parser.add_argument("--scale", type=float, default=0.3)
    parser.add_argument("--updates", type=int, default=40)
    parser.add_argument("--repeats", type=int, default=3)
    parser.add_argument("--anchors", type=int, default=8)
    parser.add_argument("--radius", type=float, default=0.04)
    parser.add_argument("--target-map", default="auto", choices=["auto", "exponential", "disc"])
    args = parser.parse_args()
    V, F, faces = meshes.bump_plane(n=args.feature_n, height=0.1, sigma=0.3, radius=0.9)
    feature = pm.extract_feature(V, F, faces, resolution=64, backend="cpu")
    if args.target != "sphere":
        drag_on_curved_target(args, feature)
        return
    T, TF = meshes.sized_sphere_mesh(args.faces)
    start = np.array([0.0, 0.0, 1.0])
    first, session = median_run(lambda: pm.PasteSession(T, TF, feature, anchor=start, scale=args.scale,
                                                        target_map=args.target_map), args.repeats)
    setup = session.stats
    times = []
    for k in range(args.updates):
        angle = 0.005 * (k + 1)  # radians along a great circle: ~1/100 of the feature's radius
        anchor = np.array([np.sin(angle), 0.0, np.cos(angle)])
        t0 = time.perf_counter()
        session.update(anchor=anchor, rotation=0.02 * k)
        times.append(time.perf_counter() - t0)
    V2, F2, new = session.result()
    emit({"bench": "paste", "target_faces": int(len(TF)), "feature_faces": int(len(feature.faces)),
          "scale": args.scale, "repeats": args.repeats, "first_paste_seconds": first,
          "update_median_seconds": statistics.median(times), "update_max_seconds": max(times),
          "updates": args.updates, "level": setup["level"], "refined_faces": setup["refined_faces"],
          "moved_vertices": setup["moved_vertices"], "control_points": setup["control_points"],
          "out_vertices": int(len(V2)), "out_faces": int(len(F2)), "new_faces": int(len(new)),
          "target_map": setup["target_map"]})


if __name__ == "__main__":
    main()
