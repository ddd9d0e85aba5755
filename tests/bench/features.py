"""Benchmark of the feature measures: prints one JSON line per (mesh, measure).

concavity: generated blobs (sized_sphere_mesh: smooth, about half of their
vertices on the hull, so the hull has about as many facets as vertices),
noisy spheres (1% radial noise pushes all but ~1% of the vertices inside: a
few thousand facets) and the models of ../shared/models when that folder
exists. shape_signature: the blobs (the time is mostly the sphere map's).
Times are medians of --repeats runs of the whole call, validation included.

    /usr/bin/python3 tests/bench/features.py [--sizes 10000 100000 200000]
        [--repeats 5] [--no-signature]
"""
import argparse

import numpy as np

from common import MODELS, emit, import_native, load_obj, median_run

pm = import_native()
import meshes  # noqa: E402  (tests/native, put on sys.path by import_native)


def workloads(sizes):
    for target in sizes:
        V, F = meshes.sized_sphere_mesh(target)
        yield f"blob-{target // 1000}k", V, F
    for name, (V, F) in {"noisy-sphere-100k": meshes.geodesic_sphere(100),
                         "noisy-icosphere-7": meshes.icosphere(7)}.items():
        noise = np.random.default_rng(len(V)).normal(size=(len(V), 1))
        yield name, V * (1.0 + 0.01 * noise), F
    for name in ("spot.obj", "stanford-bunny.obj"):
        if (MODELS / name).exists():
            V, F = load_obj(MODELS / name)
            yield name[:-4], V, F


def main():
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--sizes", type=int, nargs="*", default=[10000, 100000, 200000])
    parser.add_argument("--repeats", type=int, default=5)
    parser.add_argument("--no-signature", action="store_true")
    args = parser.parse_args()

    for name, V, F in workloads(args.sizes):
        seconds, I = median_run(lambda: pm.concavity(V, F), args.repeats)
        emit(dict(measure="concavity", mesh=name, V=int(V.shape[0]), F=int(F.shape[0]),
                  seconds=round(seconds, 4), hull_vertex_share=round(float(np.mean(I == 0)), 3),
                  max=round(float(I.max()), 5)))
        if not args.no_signature and name.startswith("blob"):
            seconds, h = median_run(lambda: pm.shape_signature(V, F), min(args.repeats, 3))
            emit(dict(measure="shape_signature", mesh=name, V=int(V.shape[0]),
                      F=int(F.shape[0]), seconds=round(seconds, 4), bins=int(h.size)))


if __name__ == "__main__":
    main()
