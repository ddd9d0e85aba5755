"""ZoomOut (functional maps, pyFM) on the real animals, scored like our morph:

    /tmp/fmvenv/bin/python tests/bench/zoomout.py [--no-self-check]

A reference to print beside paramorph's own landmark numbers. Needs the
PyPI package `pyfmaps` (import name `pyFM`, with scipy and numpy < 2) and
../shared/models; without either it prints one JSON line saying so and
exits 0. Not a test: the project does not depend on pyFM.

Method, following the pyFM README's quickstart: both meshes area-normalised
and centred, the Laplace-Beltrami spectrum on the intrinsic Delaunay
triangulation, WKS descriptors (optionally WKS of the hint vertices too,
pyFM's `landmarks`), a 30x30 functional map fitted with the descriptor,
Laplacian-commutativity, descriptor-commutativity and orientation terms,
ZoomOut from 30 to 110 in steps of 5, then the point-to-point map.

Direction: pyFM's FM_12 carries functions from mesh1 to mesh2 and its
point-to-point map p2p_21 goes the other way (for each vertex of mesh2 a
vertex of mesh1). We want, for each vertex of A, a vertex of B, so B is
pyFM's mesh1 and A its mesh2. The self-check (first JSON line) maps a mesh
onto a rotated copy of itself with its vertices shuffled: the answer is
known exactly, and the wrong direction would give the shuffle instead of its
inverse (and an array of the wrong length between meshes of different size).

For each ordered pair among cat, lion, horned-cow, with no hints and with
the four hooves as hints, one JSON line: per landmark (four hooves, muzzle,
tail) the distance from where A's landmark vertex lands on B to B's own, as
a share of B's bounding-box diagonal; the mean and largest; how many land
nearest their own counterpart among the six; the seconds (spectra of both
meshes included). Hints only add descriptors in pyFM: they are not
constraints, so hinted landmarks need not land exactly."""
import argparse
import json
import sys
import time

import numpy as np

from common import MODELS, emit, load_obj

try:
    from pyFM.functional import FunctionalMapping
    from pyFM.mesh import TriMesh
    _PYFM_ERROR = None
except Exception as exc:  # noqa: BLE001  (any failure to import means: skip)
    FunctionalMapping = TriMesh = None
    _PYFM_ERROR = f"{type(exc).__name__}: {exc}"

ANIMALS = ("cat", "lion", "horned-cow")
LANDMARKS = ("front_right_hoof", "front_left_hoof", "hind_right_hoof", "hind_left_hoof", "muzzle", "tail")
HOOVES = LANDMARKS[:4]

# pyFM settings (README quickstart; w_orient > 0 so left and right are told apart).
K_DESCR = 128          # eigenpairs behind the WKS (pyFM's default)
N_DESCR = 100          # WKS energies per descriptor (pyFM's default)
SUBSAMPLE_STEP = 2     # keep every second descriptor column (README)
FIT_WEIGHTS = dict(w_descr=1e0, w_lap=1e-1, w_dcomm=1e0, w_orient=1e0)
INTRINSIC = True       # Laplacian on the intrinsic Delaunay triangulation


def zoomout_correspondence(VA, FA, VB, FB, hints=None, k_init=30, k_final=110, step=5):
    """For every vertex of A (VA (n,3), FA (m,3)) the index of its vertex on B:
    an int array of length len(VA). hints: optional (index on A, index on B)
    pairs, given to pyFM as landmarks (extra WKS descriptors, not constraints).
    ZoomOut from a k_init x k_init functional map up to k_final in steps of
    `step` (k_final - k_init must be a multiple of it)."""
    if FunctionalMapping is None:
        raise ImportError(f"pyFM is not importable ({_PYFM_ERROR})")
    if k_final < k_init or (k_final - k_init) % step:
        raise ValueError(f"k_final - k_init = {k_final - k_init} is not a non-negative multiple of step = {step}")
    # B is pyFM's mesh1 and A its mesh2: pyFM's point-to-point map p2p_21 gives,
    # for each vertex of mesh2 (A), a vertex of mesh1 (B).
    mesh1 = TriMesh(np.asarray(VB, dtype=np.float64), np.asarray(FB), area_normalize=True, center=True)
    mesh2 = TriMesh(np.asarray(VA, dtype=np.float64), np.asarray(FA), area_normalize=True, center=True)
    k_process = max(k_final, K_DESCR)
    # Computed here so the intrinsic Laplacian is used: preprocess() below finds
    # k_process eigenpairs already there and keeps them (it would otherwise
    # compute a cotan spectrum).
    mesh1.process(k=k_process, intrinsic=INTRINSIC)
    mesh2.process(k=k_process, intrinsic=INTRINSIC)

    landmarks = None
    if hints is not None and len(hints):
        ab = np.asarray(hints, dtype=np.int64).reshape(-1, 2)
        landmarks = ab[:, ::-1].copy()      # pyFM: column 0 on mesh1 (B), column 1 on mesh2 (A)

    model = FunctionalMapping(mesh1, mesh2)
    model.preprocess(n_descr=N_DESCR, descr_type="WKS", landmarks=landmarks, subsample_step=SUBSAMPLE_STEP,
                     k_process=k_process, k_descr=K_DESCR)
    model.fit(K=k_init, **FIT_WEIGHTS)
    nit = (k_final - k_init) // step
    FM = model.zoomout_refine(nit=nit, step=step) if nit else model.FM_12
    p2p_21 = model.get_p2p(FM)              # for each vertex of mesh2 (A), its vertex on mesh1 (B)
    out = np.asarray(p2p_21, dtype=np.int64)
    assert out.shape == (len(VA),), (out.shape, len(VA))
    return out


def _rotation(seed):
    q, r = np.linalg.qr(np.random.default_rng(seed).normal(size=(3, 3)))
    q = q * np.sign(np.diag(r))
    return q if np.linalg.det(q) > 0 else -q


def self_check(V, F, name, seed=7):
    """Maps (V, F) onto a rotated, moved copy with its vertices shuffled; the
    right answer is the inverse shuffle. Returns the JSON record."""
    rng = np.random.default_rng(seed)
    perm = rng.permutation(len(V))           # B's vertex j is A's vertex perm[j]
    inverse = np.argsort(perm)               # A's vertex i is B's vertex inverse[i]
    VB = (V @ _rotation(seed).T + np.array([0.3, -2.0, 1.0]))[perm]
    FB = inverse[F]
    start = time.perf_counter()
    corr = zoomout_correspondence(V, F, VB, FB)
    seconds = time.perf_counter() - start
    diag = np.linalg.norm(np.ptp(VB, axis=0))
    err = np.linalg.norm(VB[corr] - VB[inverse], axis=1) / diag
    wrong_way = np.linalg.norm(VB[perm] - VB[inverse], axis=1).mean() / diag
    ok = bool(np.median(err) < 0.01 and err.mean() < 0.02)
    return {"bench": "zoomout_self_check", "mesh": name, "vertices": len(V),
            "exact": round(float((corr == inverse).mean()), 4),
            "error_mean": round(float(err.mean()), 5), "error_median": round(float(np.median(err)), 5),
            "error_p95": round(float(np.percentile(err, 95)), 5),
            "wrong_direction_would_give_mean": round(float(wrong_way), 4),
            "ok": ok, "seconds": round(seconds, 2)}


def landmark_scores(corr, LA, VB, LB):
    """Per landmark the distance from where A's lands on B to B's own (share of
    B's bounding-box diagonal), and whether it lands nearest its own of the six."""
    landed = VB[corr[LA]]
    distances = np.linalg.norm(landed[:, None, :] - VB[LB][None], axis=2)
    errors = np.diag(distances) / np.linalg.norm(np.ptp(VB, axis=0))
    return errors, np.argmin(distances, axis=1) == np.arange(len(LB))


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--no-self-check", action="store_true", help="skip the rotated-copy direction check")
    args = parser.parse_args()
    if FunctionalMapping is None:
        emit({"bench": "zoomout", "skipped": f"pyFM (pip package pyfmaps) not importable: {_PYFM_ERROR}"})
        return 0
    files = [MODELS / f"{a}.obj" for a in ANIMALS] + [MODELS / "landmarks.json"]
    missing = [str(p) for p in files if not p.is_file()]
    if missing:
        emit({"bench": "zoomout", "skipped": f"models missing: {', '.join(missing)}"})
        return 0
    table = json.loads((MODELS / "landmarks.json").read_text())
    meshes = {a: load_obj(MODELS / f"{a}.obj") for a in ANIMALS}
    lms = {a: np.array([table[f"{a}.obj"][n] for n in LANDMARKS]) for a in ANIMALS}

    if not args.no_self_check:
        record = self_check(*meshes["lion"], "lion")
        emit(record)
        if not record["ok"]:
            emit({"bench": "zoomout", "error": "self-check failed: the map is not ~identity on a rotated copy"})
            return 1

    for a in ANIMALS:
        for b in ANIMALS:
            if a == b:
                continue
            (VA, FA), (VB, FB) = meshes[a], meshes[b]
            for hinted in (False, True):
                hints = [(table[f"{a}.obj"][n], table[f"{b}.obj"][n]) for n in HOOVES] if hinted else None
                start = time.perf_counter()
                corr = zoomout_correspondence(VA, FA, VB, FB, hints=hints)
                seconds = time.perf_counter() - start
                errors, own = landmark_scores(corr, lms[a], VB, lms[b])
                emit({"bench": "zoomout", "pair": f"{a} -> {b}", "hints": "four hooves" if hinted else "none",
                      "vertices": [len(VA), len(VB)],
                      "landmark_error": {n: round(float(e), 4) for n, e in zip(LANDMARKS, errors)},
                      "landmark_error_mean": round(float(errors.mean()), 4),
                      "landmark_error_max": round(float(errors.max()), 4),
                      "nearest_own": int(own.sum()), "landmarks": len(own), "seconds": round(seconds, 1)})
    return 0


if __name__ == "__main__":
    sys.exit(main())
