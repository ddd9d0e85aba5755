"""Region refinement benchmark (issue 6's paste: OpenSubdiv Loop refinement of
the target region + limit positions and normals), JSON lines:

    /usr/bin/python3 tests/bench/paste_refine.py [--faces 100000] [--region 2500]
        [--level 2] [--repeats 5]

Target: sized_sphere_mesh of about --faces faces (tests/native/meshes.py).
Region: the --region faces nearest one vertex (by centroid distance, a
roughly round patch). Reports the median seconds of refine_region (topology
checks, tessellation, stitching, Bfr limit evaluation of every vertex) and
the output's size."""
import argparse

import numpy as np

from common import emit, import_native, median_run

pm = import_native()
import meshes  # noqa: E402  (tests/native, on sys.path after import_native)


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--faces", type=int, default=100000)
    parser.add_argument("--region", type=int, default=2500)
    parser.add_argument("--level", type=int, default=2)
    parser.add_argument("--repeats", type=int, default=5)
    args = parser.parse_args()
    V, F = meshes.sized_sphere_mesh(args.faces)
    centroids = V[F].mean(axis=1)
    region = np.argsort(np.linalg.norm(centroids - V[0], axis=1))[: args.region].astype(np.int32)
    seconds, r = median_run(lambda: pm.refine_region(V, F, region, level=args.level), args.repeats)
    emit({"bench": "paste_refine", "faces": int(len(F)), "vertices": int(len(V)),
          "region_faces": int(len(region)), "level": args.level, "repeats": args.repeats,
          "seconds": seconds, "out_vertices": int(len(r.V)), "out_faces": int(len(r.F)),
          "new_faces": int(len(r.new_faces))})


if __name__ == "__main__":
    main()
