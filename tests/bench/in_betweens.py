"""In-betweens of morphs (issue 17): as-rigid-as-possible (ShapeInterpolation)
against the thesis' straight lines, at t = 1/4, 1/2, 3/4.

    /usr/bin/python3 tests/bench/in_betweens.py [--quick]

JSON lines, one per pair: faces turned over against both ends (share of the
merged faces, ours and straight), faces passing through other faces (ours and
straight), how far the volume leaves the monotone path between the ends
(share of the larger end's), the setup (factor) and per-frame seconds; for
the known-truth re-pose also the distance to the true half pose (share of
the diagonal). Pairs: generated quadrupeds (a horse re-posed on one mesh; a
horse onto a re-tessellated galloping copy; cow onto horse and back; a coarse
cow onto a horse; scan-like noisy, irregular meshes; CAD-like parts onto
animals; a horse onto a cow turned 150 degrees as a whole) and, when ../shared/models is there, spot onto a horse.
Targets (issue 17): turned over <= 0.1 %, self-intersecting <= a fifth of
straight's, volume within 5 %. turned_between_ends_pct: faces whose normals
at the two ends point apart (they pass a right angle on the way, where
"against both ends" is a toss-up).
"""
import argparse
import time

import numpy as np

from common import MODELS, emit, import_native, load_obj

pm = import_native()
import meshes  # noqa: E402  (tests/native, on sys.path after import_native)
import quadrupeds as Q  # noqa: E402
from in_betweens import face_normals, inverted_share, inverted_share_turning, rotation, volume_excursion  # noqa: E402

TIMES = (0.25, 0.5, 0.75)
FOLDED = {"leg_fl": (40.0, 60.0), "leg_fr": (-40.0, 60.0), "leg_hl": (40.0, 60.0), "leg_hr": (-40.0, 60.0),
          "neck": 30.0, "head": -30.0, "tail": 60.0}


def turned_between_ends(source, target, F):
    """Share of faces whose normals at the two ends point apart: they must
    turn past a right angle on the way, where "against both ends" is a toss-up."""
    return float((np.einsum("ij,ij->i", face_normals(source, F), face_normals(target, F)) < 0).mean())


def measure(name, source, target, F, extra=None):
    start = time.perf_counter()
    interp = pm.ShapeInterpolation(source, target, F)
    setup = time.perf_counter() - start
    start = time.perf_counter()
    ours = [interp.at(t) for t in TIMES]
    per_frame = (time.perf_counter() - start) / len(TIMES)
    straight = [(1 - t) * source + t * target for t in TIMES]
    record = {"bench": "in_betweens", "pair": name, "faces": len(F),
              "inverted_pct": [round(100 * inverted_share(source, target, P, F), 3) for P in ours],
              "inverted_pct_turning": [round(100 * inverted_share_turning(source, target, P, F, t), 3)
                                       for P, t in zip(ours, TIMES)],
              "inverted_pct_straight": [round(100 * inverted_share(source, target, P, F), 3) for P in straight],
              "self_intersecting": [pm.self_intersections(P, F).intersecting_faces for P in ours],
              "self_intersecting_straight": [pm.self_intersections(P, F).intersecting_faces for P in straight],
              "volume_excursion": round(volume_excursion(source, target, ours, F), 4),
              "volume_excursion_straight": round(volume_excursion(source, target, straight, F), 4),
              "turned_between_ends_pct": round(100 * turned_between_ends(source, target, F), 3),
              "setup_seconds": round(setup, 2), "frame_seconds": round(per_frame, 3)}
    if extra:
        record.update(extra(ours[1], straight[1]))
    emit(record)


def reposed_on_one_mesh():
    V0, F, _ = Q.quadruped("horse", 6000, seed=2)
    V1 = Q.quadruped("horse", 6000, pose=FOLDED, seed=2)[0]
    half = {k: tuple(0.5 * a for a in v) if isinstance(v, tuple) else 0.5 * v for k, v in FOLDED.items()}
    truth = Q.quadruped("horse", 6000, pose=half, seed=2)[0]
    diagonal = np.linalg.norm(np.ptp(V0, axis=0))

    def to_truth(ours, straight):
        return {"half_pose_error_max": round(float(np.linalg.norm(ours - truth, axis=1).max() / diagonal), 5),
                "half_pose_error_max_straight": round(float(np.linalg.norm(straight - truth, axis=1).max() / diagonal), 5)}
    measure("horse 6k rest -> legs folded (one mesh)", V0, V1, F, to_truth)


def scan_like(mesh, seed, noise=0.0005):
    """The mesh with every vertex moved at random by `noise` of its diagonal (a scan's noise)."""
    V, F = mesh[0], mesh[1]
    scale = noise * np.linalg.norm(np.ptp(V, axis=0))
    return V + np.random.default_rng(seed).normal(scale=scale, size=V.shape), F


def morphed(name, A, B):
    m = pm.morph(A[0], A[1], B[0], B[1])
    measure(name, np.asarray(m.source), np.asarray(m.target), np.asarray(m.faces))


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--quick", action="store_true", help="the re-pose and one morph")
    args = parser.parse_args()
    reposed_on_one_mesh()
    morphed("cow 6k -> horse walk 20k", Q.quadruped("cow", 6000, seed=0),
            Q.quadruped("horse", 20000, pose=Q.WALK, seed=3))
    if args.quick:
        return 0
    morphed("horse 6k -> horse gallop 12k (re-tessellated)", Q.quadruped("horse", 6000, seed=1),
            Q.quadruped("horse", 12000, pose=Q.GALLOP, seed=5))
    morphed("horse 20k -> cow gallop 6k", Q.quadruped("horse", 20000, seed=1),
            Q.quadruped("cow", 6000, pose=Q.GALLOP, seed=5))
    morphed("cow 3k -> horse walk 6k (coarse)", Q.quadruped("cow", 3000, seed=0),
            Q.quadruped("horse", 6000, pose=Q.WALK, seed=3))
    morphed("scan-like cow 6k -> scan-like horse walk 20k (jitter 0.4, noise 0.05 % of the diagonal)",
            scan_like(Q.quadruped("cow", 6000, seed=0, jitter=0.4), seed=1),
            scan_like(Q.quadruped("horse", 20000, pose=Q.WALK, seed=3, jitter=0.4), seed=2))
    morphed("two-boss CAD part -> horse walk 6k", meshes.two_boss_part(8)[:2],
            Q.quadruped("horse", 6000, pose=Q.WALK, seed=3))
    morphed("CAD box with a boss -> cow 6k", meshes.cad_box(8)[:2], Q.quadruped("cow", 6000, seed=0))
    horse, cow = Q.quadruped("horse", 6000, seed=1), Q.quadruped("cow", 6000, pose=Q.GALLOP, seed=5)
    morphed("horse 6k -> cow gallop 6k turned 150 degrees", horse,
            (cow[0] @ rotation([0.2, 1.0, 0.4], 150.0).T, cow[1]))
    if (MODELS / "spot.obj").exists():
        V, F = load_obj(MODELS / "spot.obj")
        morphed("spot 5.9k -> horse walk 20k", (V, F), Q.quadruped("horse", 20000, pose=Q.WALK, seed=3))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
