"""extract_feature benchmark (issue 6: a 10k-face feature), JSON lines:

    /usr/bin/python3 tests/bench/extract_feature.py [--n 224] [--feature-faces 10000]
        [--resolution 64] [--repeats 3] [--backend cpu]

A Gaussian bump (height 0.04, sigma = radius / 3) on a plane grid of 2 n**2
faces over [-1, 1]**2 (n = 224: 100,352 faces), the feature the faces within
the radius that holds about --feature-faces faces. Reports the median seconds
of extract_feature, the feature's size, and the grid's inside nodes."""
import argparse

import numpy as np

from common import emit, import_native, median_run

pm = import_native()
import meshes  # noqa: E402  (tests/native, on sys.path after import_native)


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--n", type=int, default=224)
    parser.add_argument("--feature-faces", type=int, default=10000)
    parser.add_argument("--resolution", type=int, default=64)
    parser.add_argument("--repeats", type=int, default=3)
    parser.add_argument("--backend", default="cpu")
    args = parser.parse_args()
    faces_per_area = 2 * args.n ** 2 / 4.0
    radius = np.sqrt(args.feature_faces / (np.pi * faces_per_area))
    V, F, faces = meshes.bump_plane(n=args.n, height=0.04, sigma=radius / 3, radius=radius)
    seconds, feature = median_run(
        lambda: pm.extract_feature(V, F, faces, resolution=args.resolution, backend=args.backend), args.repeats)
    emit({"bench": "extract_feature", "mesh_faces": int(len(F)), "feature_faces": int(len(faces)),
          "resolution": args.resolution, "backend": args.backend, "repeats": args.repeats,
          "median_seconds": round(seconds, 4), "inside_nodes": int(feature.mask.sum()),
          "radius": feature.radius})


if __name__ == "__main__":
    main()
