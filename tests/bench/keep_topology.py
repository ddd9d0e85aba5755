"""How close a kept topology comes to the target (issue 31), JSON lines:

    /usr/bin/python3 tests/bench/keep_topology.py [--pairs "spot>cat,..."] [--placements] [--smooth-pleats N]

Morph To with Keep Source's Topology puts the source's own vertices on the
target through the correspondence, then fits them to the target both ways
(fit_to_surface, the matched tips held); the end shape is the source's mesh
there. For each pair of real characters in ../shared/models (the target
subdivided, four faces for one, until it has 50k faces, so it is a fine mesh
of a different animal as the issue asks), and Blender's Suzanne head (its
largest part, from bpy when this Python has it) onto the cartoon cow as it
is: the Hausdorff distance (sampled both ways, surface_distance) of the end
shape to the target as a share of the target's bounding-box diagonal, before
and after the fit, the share of faces turned over at t = 1/2 (as rigid as
possible in-betweens), the share of faces whose normal points against the
target's under their centre (pleats and wrinkles the distance does not see)
before and after the fit (--smooth-pleats 0: without the fit's pleat
smoothing, to compare), and the seconds each step took.
With --placements, each pair again with the source placed as a user's scene
might have it (turned about the up axis beside the target, facing away and
twice the size, tilted), and the whole scene turned, scaled and moved (the
distance then a share of the target's own diagonal): the correspondence may
differ with the source's placement, never with the whole scene's. Where
landmarks.json has both models, how far each source landmark lands from the
target's (% of the diagonal, before the fit: the correspondence's own).
Targets (issue 31): <= 3 % for a >= 2.5k-vertex source onto a >= 50k-face
target of another animal, <= 4 % for a ~500-vertex head; turned at
t = 1/2 <= 0.1 %."""
import argparse
import json
import time

import numpy as np

from common import MODELS, emit, import_native, load_obj

pm = import_native()
from in_betweens import inverted_share_turning, rotation  # noqa: E402  (tests/native)

PAIRS = ["suzanne>spot", "spot>cat", "spot>lion", "spot>horned-cow", "lion>horned-cow", "cat>lion", "lion>cat",
         "horned-cow>lion", "cat>horned-cow"]


def subdivided(V, F):
    """Each triangle cut into four at its edge midpoints (the same surface, 4x the faces)."""
    edges = np.sort(np.concatenate([F[:, [0, 1]], F[:, [1, 2]], F[:, [2, 0]]]), axis=1)
    unique, inverse = np.unique(edges, axis=0, return_inverse=True)
    mid = len(V) + inverse.ravel().reshape(3, -1).T  # (m, 3): midpoints of edges 01, 12, 20
    V2 = np.concatenate([V, 0.5 * (V[unique[:, 0]] + V[unique[:, 1]])])
    a, b, c = F.T
    ab, bc, ca = mid.T
    F2 = np.concatenate([np.stack([a, ab, ca], 1), np.stack([ab, b, bc], 1), np.stack([ca, bc, c], 1),
                         np.stack([ab, bc, ca], 1)]).astype(np.int32)
    return V2, F2


def suzanne():
    """Blender's Suzanne, its largest part (the head; the eyes ride along in the add-on), or None without bpy."""
    try:
        import bpy
    except ImportError:
        return None
    bpy.ops.wm.read_factory_settings(use_empty=True)
    bpy.ops.mesh.primitive_monkey_add(size=2.0)
    mesh = bpy.context.active_object.data
    mesh.calc_loop_triangles()
    V = np.array([v.co[:] for v in mesh.vertices])
    F = np.array([t.vertices[:] for t in mesh.loop_triangles], dtype=np.int32)
    fixed = pm.repair(V, F, keep_largest_component=True)
    return np.asarray(fixed.V), np.asarray(fixed.F)


def share(distance, V):
    return round(float(distance.hausdorff / np.linalg.norm(np.ptp(V, axis=0))), 4)


def turned_half_way(VA, FA, end):
    return round(inverted_share_turning(VA, end, pm.ShapeInterpolation(VA, end, FA).at(0.5), FA, 0.5), 5)


def placements(size):
    """(name, source transform, whole scene transform): (R, scale, move) each."""
    same = (np.eye(3), 1.0, np.zeros(3))
    up = [0.0, 1.0, 0.0]  # the models in ../shared/models stand along +y
    return [("source turned 90 deg about up, beside", (rotation(up, 90), 1.0, np.array([size, 0, 0])), same),
            ("source facing away, twice the size", (rotation(up, 180), 2.0, np.array([0, 0, size])), same),
            ("source turned 20 deg and tilted 10",
             (rotation(up, 20) @ rotation([1, 0, 0], 10), 1.0, np.array([-size, 0, 0])), same),
            ("whole scene turned -120 deg, x7, moved", same, (rotation([0, 1, 1], -120), 7.0, np.array([-30.0, 4, 2])))]


def landmark_misses(a, b, sampled, VB, diagonal):
    """Where the source's landmarks land through the correspondence, as a
    share of the target's diagonal from the target's own (% each), when
    landmarks.json has both models; else None. B's own vertices keep their
    indices in its subdivided copy."""
    path = MODELS / "landmarks.json"
    if not path.exists():
        return None
    marks = json.loads(path.read_text())
    if f"{a}.obj" not in marks or f"{b}.obj" not in marks:
        return None
    of_a, of_b = marks[f"{a}.obj"], marks[f"{b}.obj"]
    return {name: round(float(100 * np.linalg.norm(sampled[of_a[name]] - VB[of_b[name]]) / diagonal), 1)
            for name in of_a if name in of_b}


def keep(VA, FA, VB, FB, record, smooth_pleats=20):
    """Morph, then the fit; adds seconds and figures to record."""
    start = time.perf_counter()
    morph = pm.morph(VA, FA, VB, FB)
    record["morph_seconds"] = round(time.perf_counter() - start, 1)
    sampled = np.asarray(morph.target)[np.asarray(morph.vertex_of_a)]
    held = np.unique(np.asarray(morph.pairs, dtype=np.int64).reshape(-1, 2)[:, 0])
    start = time.perf_counter()
    fit = pm.fit_to_surface(sampled, FA, VB, FB, held=held, smooth_pleats=smooth_pleats)
    record["fit_seconds"] = round(time.perf_counter() - start, 1)
    record["facing_away_before"] = round(fit.facing_away_before, 4)
    record["facing_away_after"] = round(fit.facing_away_after, 4)
    record["pleat_moves"] = fit.pleat_moves
    return sampled, np.asarray(fit.positions)


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--pairs", help="comma-separated a>b (default: " + ",".join(PAIRS) + ")")
    parser.add_argument("--placements", action="store_true", help="also with the source or the scene turned")
    parser.add_argument("--smooth-pleats", type=int, default=20,
                        help="passes of the fit's pleat smoothing (0: none)")
    args = parser.parse_args()
    if not MODELS.exists():
        emit({"bench": "keep_topology", "skipped": f"no models folder at {MODELS}"})
        return
    for pair in (args.pairs.split(",") if args.pairs else PAIRS):
        a, b = pair.split(">")
        source = suzanne() if a == "suzanne" else load_obj(MODELS / f"{a}.obj")
        if source is None:
            emit({"bench": "keep_topology", "pair": pair, "skipped": "Suzanne needs bpy (e.g. .venv-bpy/bin/python)"})
            continue
        VA, FA = source
        VB, FB = load_obj(MODELS / f"{b}.obj")
        while a != "suzanne" and len(FB) < 50000:
            VB, FB = subdivided(VB, FB)
        record = {"bench": "keep_topology", "pair": f"{a} -> {b}", "source_vertices": len(VA),
                  "target_faces": len(FB)}
        diagonal = np.linalg.norm(np.ptp(VB, axis=0))
        sampled, end = keep(VA, FA, VB, FB, record, args.smooth_pleats)
        record["hausdorff_before"] = share(pm.surface_distance(sampled, FA, VB, FB), VB)
        record["hausdorff_after"] = share(pm.surface_distance(end, FA, VB, FB), VB)
        record["turned_half_way_before"] = turned_half_way(VA, FA, sampled)
        record["turned_half_way_after"] = turned_half_way(VA, FA, end)
        record["landmark_miss_percent"] = landmark_misses(a, b, sampled, VB, diagonal)
        emit(record)
        if not args.placements:
            continue
        for name, (RA, sA, tA), (R, s, t) in placements(diagonal):
            placed = {"bench": "keep_topology", "pair": f"{a} -> {b}", "placement": name}
            A, B = s * (sA * VA @ RA.T + tA) @ R.T + t, s * VB @ R.T + t
            sampled, end = keep(A, FA, B, FB, placed, args.smooth_pleats)
            for when, X in (("before", sampled), ("after", end)):
                placed[f"hausdorff_{when}"] = round(float(pm.surface_distance(X, FA, B, FB).hausdorff / (s * diagonal)), 4)
                placed[f"turned_half_way_{when}"] = turned_half_way(A, FA, X)
            placed["landmark_miss_percent"] = landmark_misses(a, b, sampled, B, s * diagonal)
            emit(placed)


if __name__ == "__main__":
    main()
