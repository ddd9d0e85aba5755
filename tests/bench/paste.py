"""Feature paste benchmark (issue 6's figures: first paste of a 10k-face feature
onto a 100k-face target <= 1 s; interactive update <= 30 ms median), JSON lines:

    /usr/bin/python3 tests/bench/paste.py [--faces 100000] [--feature-n 90]
        [--scale 0.3] [--updates 40] [--repeats 3]

Feature: the Gaussian bump of meshes.bump_plane(n=--feature-n) (about 10k faces
at 90), extracted once (not timed here: tests/bench/extract_feature.py).
Target: meshes.sized_sphere_mesh(--faces), the unit sphere. First paste: the
median seconds of PasteSession(...) (topology, OpenSubdiv refiner,
closest-point tree, the feature's lookup grid, RBF factorization, one
placement). Update: the median of --updates session.update() calls that slide
the anchor along an arc in small steps and turn the feature, as a drag does."""
import argparse
import statistics
import time

import numpy as np

from common import emit, import_native, median_run

pm = import_native()
import meshes  # noqa: E402  (tests/native, on sys.path after import_native)


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--faces", type=int, default=100000)
    parser.add_argument("--feature-n", type=int, default=90)
    parser.add_argument("--scale", type=float, default=0.3)
    parser.add_argument("--updates", type=int, default=40)
    parser.add_argument("--repeats", type=int, default=3)
    args = parser.parse_args()
    V, F, faces = meshes.bump_plane(n=args.feature_n, height=0.1, sigma=0.3, radius=0.9)
    feature = pm.extract_feature(V, F, faces, resolution=64, backend="cpu")
    T, TF = meshes.sized_sphere_mesh(args.faces)
    start = np.array([0.0, 0.0, 1.0])
    first, session = median_run(lambda: pm.PasteSession(T, TF, feature, anchor=start, scale=args.scale),
                                args.repeats)
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
          "out_vertices": int(len(V2)), "out_faces": int(len(F2)), "new_faces": int(len(new))})


if __name__ == "__main__":
    main()
