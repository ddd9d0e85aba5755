"""RBF solver benchmark (issue 6: the paste session factors once, updates by
back-substitution), JSON lines:

    /usr/bin/python3 tests/bench/paste_rbf.py [--centres 400] [--points 20000] [--repeats 20]

N centres in 2D (random in the unit square), values with 3 columns: a
smooth 3D displacement (what a paste moves; random values would give r^3
coefficients near 1e7 whose evaluation loses 1e-8 to round-off). Reports the median seconds of: building + LU-factoring the
system (factor_s), one back-substitution (solve_s), building the evaluation
matrix of M points (evaluation_matrix_s, once per session), and evaluating
the M points through it (evaluate_s: one matrix product, what an update pays),
per basis."""
import argparse

import numpy as np

from common import emit, import_native, median_run

pm = import_native()


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--centres", type=int, default=400)
    parser.add_argument("--points", type=int, default=20000)
    parser.add_argument("--repeats", type=int, default=20)
    args = parser.parse_args()
    rng = np.random.default_rng(0)
    X = rng.uniform(0, 1, size=(args.centres, 2))
    Y = rng.uniform(0, 1, size=(args.points, 2))
    f = np.column_stack([np.sin(3 * X[:, 0]) * np.cos(2 * X[:, 1]), X[:, 0] * X[:, 1] - 0.5,
                         np.exp(-4 * ((X - 0.5) ** 2).sum(axis=1))])
    for basis, kwargs in [("polyharmonic", {}), ("wendland", {"support_radius": 0.3})]:
        factor_s, rbf = median_run(lambda: pm.RbfInterpolator(X, basis=basis, **kwargs), args.repeats)
        solve_s, c = median_run(lambda: rbf.solve(f), args.repeats)
        matrix_s, E = median_run(lambda: rbf.evaluation_matrix(Y), max(3, args.repeats // 4))
        evaluate_s, s = median_run(lambda: E @ c, args.repeats)
        residual = float(np.abs(rbf.evaluate(X, c) - f).max())
        emit({"bench": "paste_rbf", "basis": basis, "centres": args.centres, "points": args.points,
              "repeats": args.repeats, "factor_s": factor_s, "solve_s": solve_s,
              "evaluation_matrix_s": matrix_s, "evaluate_s": evaluate_s,
              "rcond": rbf.rcond, "max_residual_at_centres": residual})


if __name__ == "__main__":
    main()
