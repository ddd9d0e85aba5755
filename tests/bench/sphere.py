"""Benchmark of sphere_map(): prints one JSON line per (mesh, weights, backend, solver).

Meshes: generated closed genus-0 blobs of about 10k, 100k and 400k faces, and
../shared/models/spot.obj when that folder exists. Times are medians of 3 runs
of the whole call (validation, start, outer loop). A last line compares the
inner iterations of PCG and of Algorithm 3 (Jacobi) to the same residual.

    /usr/bin/python3 tests/bench/sphere.py [--sizes 10000 100000 400000]
        [--backends cpu opencl] [--solvers auto] [--weights conformal barycentric]
"""
import argparse

import numpy as np

from common import MODELS, emit, import_native, load_obj, median_run

pm = import_native()
import meshes  # noqa: E402  (tests/native, put on sys.path by import_native)


def quasi_conformal(V, X, F):
    """Area-weighted ratio of the singular values of each triangle's linear map
    onto its chord triangle on the sphere (1 = conformal)."""
    def frames(P):
        a, b, c = P[F[:, 0]], P[F[:, 1]], P[F[:, 2]]
        e1, e2 = b - a, c - a
        n = np.cross(e1, e2)
        x = e1 / np.linalg.norm(e1, axis=1, keepdims=True)
        y = np.cross(n, e1)
        y /= np.linalg.norm(y, axis=1, keepdims=True)
        E = np.zeros((len(F), 2, 2))
        E[:, 0, 0] = np.linalg.norm(e1, axis=1)
        E[:, 0, 1] = np.einsum("ij,ij->i", e2, x)
        E[:, 1, 1] = np.einsum("ij,ij->i", e2, y)
        return E, 0.5 * np.linalg.norm(n, axis=1)

    S, area = frames(V)
    T, _ = frames(X)
    s = np.linalg.svd(T @ np.linalg.inv(S), compute_uv=False)
    return float(np.sum(area * s[:, 0] / s[:, 1]) / area.sum())


def workloads(sizes):
    for target in sizes:
        V, F = meshes.sized_sphere_mesh(target)
        yield f"blob-{target // 1000}k", V, F
    spot = MODELS / "spot.obj"
    if spot.exists():
        V, F = load_obj(spot)
        yield "spot", V, F


def main():
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--sizes", type=int, nargs="*", default=[10000, 100000, 400000])
    parser.add_argument("--backends", nargs="*", default=["cpu", "opencl"])
    parser.add_argument("--solvers", nargs="*", default=["auto"])
    parser.add_argument("--weights", nargs="*", default=["conformal", "barycentric"])
    parser.add_argument("--repeats", type=int, default=3)
    parser.add_argument("--no-jacobi", action="store_true", help="skip the iteration comparison")
    args = parser.parse_args()

    usable = any(d["usable"] for d in pm.devices())
    backends = [b for b in args.backends if b != "opencl" or usable]
    for name, V, F in workloads(args.sizes):
        for weights in args.weights:
            for backend in backends:
                for solver in args.solvers:
                    seconds, r = median_run(
                        lambda: pm.sphere_map(V, F, weights=weights, backend=backend,
                                              solver=solver), args.repeats)
                    emit(dict(mesh=name, V=int(V.shape[0]), F=int(F.shape[0]), weights=weights,
                              backend=r.backend, solver=r.solver, seconds=round(seconds, 4),
                              outer_iterations=r.outer_iterations,
                              inner_iterations=r.inner_iterations,
                              inner_per_outer=list(r.inner_per_outer), residual=r.residual,
                              flipped=int(r.flipped), stop=r.stop_reason,
                              quasi_conformal=round(quasi_conformal(V, r.positions, F), 3),
                              timings={k: round(v, 4) for k, v in r.timings.items()}))

    if not args.no_jacobi:
        # Same saddle point (one outer step) to the same residual, both solvers.
        V, F = meshes.sized_sphere_mesh(10000)
        runs = {s: pm.sphere_map(V, F, solver=s, backend="cpu", max_outer_iterations=1,
                                 check_every=10)
                for s in ("jacobi", "pcg")}
        emit(dict(comparison="inner_iterations_to_same_residual", mesh="blob-10k",
                  F=int(F.shape[0]), tol=1e-7,
                  jacobi=runs["jacobi"].inner_iterations, pcg=runs["pcg"].inner_iterations,
                  jacobi_residual=runs["jacobi"].residual, pcg_residual=runs["pcg"].residual,
                  ratio=round(runs["jacobi"].inner_iterations / max(1, runs["pcg"].inner_iterations), 1),
                  jacobi_seconds=round(runs["jacobi"].seconds, 3),
                  pcg_seconds=round(runs["pcg"].seconds, 3)))


if __name__ == "__main__":
    main()
