"""Feature matching benchmarks (thesis 4.5), JSON lines:

    /usr/bin/python3 tests/bench/matching.py [--repeats 3]

match_features of each mesh against a copy of itself turned by a known
rotation, scaled and moved (the shared models spot and stanford-bunny when
present), and of meshes.bumps_and_pits / two_boss_part against the same
surface triangulated differently, turned, scaled and moved. Reports the
median time, the region and point pair counts, the rotation error
(max |R Q - I|) and the largest distance of a point pair's two vertices
under the known transform (share of A's bounding-box diagonal)."""
import argparse
import sys

import numpy as np

from common import MODELS, emit, import_native, load_obj, median_run

pm = import_native()
import meshes  # noqa: E402  (tests/native, on sys.path after import_native)


def workloads():
    for name in ("spot", "stanford-bunny"):
        path = MODELS / f"{name}.obj"
        if path.exists():
            V, F = load_obj(path)
            yield f"{name} (itself)", (V, F), (V, F)
    yield "bumps_and_pits (icosphere 4 / geodesic 19)", meshes.bumps_and_pits(), \
        meshes.bumps_and_pits(meshes.geodesic_sphere(19))
    yield "two_boss_part (8 / 12 alternate)", meshes.two_boss_part(8), \
        meshes.two_boss_part(12, alternate_diagonals=True)


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--repeats", type=int, default=3)
    args = parser.parse_args()
    q, _ = np.linalg.qr(np.random.default_rng(11).normal(size=(3, 3)))
    Q = q * np.sign(np.linalg.det(q))
    for name, (VA, FA), (V0, FB) in workloads():
        VB = 2.0 * V0 @ Q.T + [1.0, -2.0, 3.0]
        seconds, m = median_run(lambda: pm.match_features(VA, FA, VB, FB), args.repeats)
        diag = np.linalg.norm(VA.max(0) - VA.min(0))
        apart = np.linalg.norm(VA[m.point_pairs[:, 0]] - V0[m.point_pairs[:, 1]], axis=1) / diag
        emit({"bench": "match_features", "mesh": name, "faces_a": len(FA), "faces_b": len(FB),
              "seconds_median": round(seconds, 3), "regions": [len(m.centroids_a), len(m.centroids_b)],
              "region_pairs": len(m.region_pairs), "points": [len(m.points_a), len(m.points_b)],
              "point_pairs": len(m.point_pairs),
              "rotation_error": float(np.abs(m.rotation @ Q - np.eye(3)).max().round(4)),
              "worst_point_pair": float(apart.max().round(4)) if len(apart) else None})


if __name__ == "__main__":
    sys.exit(main())
