"""How close a kept topology comes to the target (issue 31), JSON lines:

    /usr/bin/python3 tests/bench/keep_topology.py [--pairs spot>cat,...]

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
possible in-betweens), and the seconds each step took.
Targets (issue 31): <= 3 % for a >= 2.5k-vertex source onto a >= 50k-face
target of another animal, <= 4 % for a ~500-vertex head; turned at
t = 1/2 <= 0.1 %."""
import argparse
import time

import numpy as np

from common import MODELS, emit, import_native, load_obj

pm = import_native()
from in_betweens import inverted_share_turning  # noqa: E402  (tests/native)

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


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--pairs", help="comma-separated a>b (default: " + ",".join(PAIRS) + ")")
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
        start = time.perf_counter()
        morph = pm.morph(VA, FA, VB, FB)
        record["morph_seconds"] = round(time.perf_counter() - start, 1)
        sampled = np.asarray(morph.target)[np.asarray(morph.vertex_of_a)]
        held = np.unique(np.asarray(morph.pairs, dtype=np.int64).reshape(-1, 2)[:, 0])
        start = time.perf_counter()
        fit = pm.fit_to_surface(sampled, FA, VB, FB, held=held)
        record["fit_seconds"] = round(time.perf_counter() - start, 1)
        end = np.asarray(fit.positions)
        record["hausdorff_before"] = share(pm.surface_distance(sampled, FA, VB, FB), VB)
        record["hausdorff_after"] = share(pm.surface_distance(end, FA, VB, FB), VB)
        record["turned_half_way_before"] = turned_half_way(VA, FA, sampled)
        record["turned_half_way_after"] = turned_half_way(VA, FA, end)
        emit(record)


if __name__ == "__main__":
    main()
