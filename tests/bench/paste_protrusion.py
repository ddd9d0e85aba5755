"""Copy Feature on long protrusions (issue 32's figures), JSON lines:

    /usr/bin/python3 tests/bench/paste_protrusion.py [--anchors 10] [--updates 30]
        [--carry auto] [--only NAME[,NAME...]]

Features: generated tubes closed at their tip on a sphere (tentacle_sphere,
1, 2, 4 and 6.4 times as long as their base is wide; the 6.4x one bent 60
degrees like a horn and 150 degrees like a hanging trunk) and, where
../shared/models is present, the real animals' protrusions around their
landmarks (tail, muzzle, a front hoof's leg) and the horned cow's horn: the
connected faces within 6, 10 and 15 % of the model's diagonal around the tip,
as the issue's trial selected them.

Per feature: whether Copy Feature (extract_feature) succeeds, whether it is
carried as its own mesh, and its seconds; then Paste Feature onto the cartoon
cow (spot.obj; an icosphere without the models) at --anchors random vertices,
the feature's radius 6 % of the target's diagonal: how many pastes succeed
with a closed result (every edge in two faces, each way once); the median
interactive update (a drag of --updates small steps and turns at the first
anchor that took it); and on a flat grid the shape kept: the largest
distance from the feature placed as it was cut to the pasted result, over
the part's size (its diagonal). The same anchors for every feature. Last,
the hanging trunk dragged on a 100k-face sphere with ever larger roots.
"""
import argparse
import json
import statistics
import time

import numpy as np

from common import MODELS, emit, import_native, load_obj

pm = import_native()
import meshes  # noqa: E402


def tip_selection(V, F, tip, radius):
    """The faces wholly within `radius` of vertex `tip` that are edge-connected
    to a face at the tip."""
    near = np.linalg.norm(V - V[tip], axis=1) <= radius
    inside = np.flatnonzero(near[F].all(axis=1))
    if not len(inside):
        return inside
    position = {int(f): k for k, f in enumerate(inside)}
    edge_faces = {}
    for f in inside:
        for a, b in ((0, 1), (1, 2), (2, 0)):
            edge_faces.setdefault(tuple(sorted((int(F[f, a]), int(F[f, b])))), []).append(int(f))
    start = [int(f) for f in inside if tip in F[f]]
    if not start:
        return np.empty(0, np.int64)
    seen = {start[0]}
    stack = [start[0]]
    while stack:
        f = stack.pop()
        for a, b in ((0, 1), (1, 2), (2, 0)):
            for g in edge_faces[tuple(sorted((int(F[f, a]), int(F[f, b]))))]:
                if g not in seen and g in position:
                    seen.add(g)
                    stack.append(g)
    return np.array(sorted(seen), np.int64)


def closed(F):
    """Every edge in exactly two faces, once each way."""
    directed = np.concatenate([F[:, [0, 1]], F[:, [1, 2]], F[:, [2, 0]]]).astype(np.int64)
    n = int(directed.max()) + 1
    keys = directed[:, 0] * n + directed[:, 1]
    twins = directed[:, 1] * n + directed[:, 0]
    unique, counts = np.unique(keys, return_counts=True)
    return bool(counts.max() == 1 and np.isin(twins, unique).all())


def diagonal(V):
    return float(np.linalg.norm(V.max(axis=0) - V.min(axis=0)))


def generated_features():
    """(name, V, F, selection, length / width)."""
    out = []
    for length, bend in ((0.5, 0), (1.0, 0), (2.0, 0), (3.0, 0), (3.0, 60), (3.0, 150)):
        V, F, selection, ratio = meshes.protrusion(length, bend)
        kind = {0: "tube", 60: "horn", 150: "trunk"}[bend]
        out.append((f"{kind}-{ratio:.1f}x", V, F, selection, ratio))
    return out


def real_features():
    """(name, V, F, selection, None) around each real landmark tip."""
    if not (MODELS / "landmarks.json").exists():
        return []
    landmarks = json.loads((MODELS / "landmarks.json").read_text())
    out = []
    for model, tips in (("cat.obj", ("tail", "muzzle", "front_left_hoof")),
                        ("lion.obj", ("tail", "muzzle", "front_left_hoof")),
                        ("horned-cow.obj", ("tail", "muzzle", "horn"))):
        V, F = load_obj(MODELS / model)
        diag = diagonal(V)
        for tip_name in tips:
            tip = (int(np.argmax(V[:, 0])) if tip_name == "horn" else landmarks[model][tip_name])
            for share in (0.06, 0.10, 0.15):
                selection = tip_selection(V, F, tip, share * diag)
                out.append((f"{model[:-4]}-{tip_name}-{int(share * 100)}%", V, F, selection, None))
    return out


def paste_trials(feature, T, TF, anchors, updates):
    """(successes, closed results, median update ms, first error)."""
    scale = 0.06 * diagonal(T) / feature.radius
    picks = np.random.default_rng(7).choice(len(T), size=anchors, replace=False)
    ok = closed_ok = 0
    error = None
    drag_at = None
    for v in picks:
        try:
            s = pm.PasteSession(T, TF, feature, anchor=T[v], scale=scale)
        except pm.MeshError as e:
            error = error or f"{type(e).__name__}: {e}"
            continue
        ok += 1
        closed_ok += closed(np.asarray(s.result()[1]))
        drag_at = drag_at if drag_at is not None else (s, T[v])
    update_ms = None
    if drag_at is not None:
        s, anchor = drag_at
        step = 0.01 * s.stats["feature_radius"]
        times = []
        for k in range(updates):
            start = time.perf_counter()
            try:
                s.update(anchor=anchor + step * k * np.array([1.0, 0.3, 0.0]), rotation=0.02 * k, scale=scale)
            except pm.TargetTooSmallError:
                continue
            times.append(time.perf_counter() - start)
        update_ms = 1000 * statistics.median(times) if times else None
    return ok, closed_ok, update_ms, error


def shape_on_flat(feature):
    """How far the feature placed as cut lies from the pasted result on a flat
    grid (the feature 0.25 wide; the grid bends to meet its boundary), over
    the part's diagonal: the largest distance from the original's surface
    (vertices, edge midpoints, face centroids) to the result's. A carried
    feature's own faces are in the result: 0 up to round-off."""
    P, PF = meshes.plane_grid(n=120, half=1.0)
    scale = 0.25 / feature.radius
    s = pm.PasteSession(P, PF, feature, anchor=np.zeros(3), scale=scale)
    V2, F2, _ = s.result()
    placed = s.anchor_point + s.stats["lift"] * s.normal + scale * np.asarray(feature.vertices)  # rotation 0: frame = world axes
    d = pm.surface_distance(placed, np.asarray(feature.faces), np.asarray(V2), np.asarray(F2))
    return float(d.a_to_b) / diagonal(placed)


def dense_target_updates(updates):
    """The hanging trunk dragged on a 100k-face sphere, its root 0.05, 0.15 and
    0.4 of the sphere's radius: the target faces cut under it and the median
    update (the cut and the seam grow with the root)."""
    T, TF = meshes.sized_sphere_mesh(100000)
    V, F, selection, ratio = meshes.protrusion(3.0, 150)
    feature = pm.extract_feature(V, F, selection)
    for root in (0.05, 0.15, 0.4):
        scale = root / feature.radius
        s = pm.PasteSession(T, TF, feature, anchor=T[0], scale=scale)
        times = []
        for k in range(updates):
            start = time.perf_counter()
            s.update(anchor=T[0] + 0.002 * k, rotation=0.02 * k, scale=scale)
            times.append(time.perf_counter() - start)
        emit({"bench": "paste_protrusion", "feature": f"trunk-{ratio:.1f}x", "target": f"sphere {len(TF)} faces",
              "root_over_radius": root, "replaced_faces": int(s.stats["replaced_faces"]),
              "update_ms": round(1000 * statistics.median(times), 2)})


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--anchors", type=int, default=10)
    parser.add_argument("--updates", type=int, default=30)
    parser.add_argument("--carry", default="auto")
    parser.add_argument("--only", default="")
    args = parser.parse_args()
    if (MODELS / "spot.obj").exists():
        T, TF = load_obj(MODELS / "spot.obj")
        target = "spot"
    else:
        T, TF = meshes.icosphere(5)
        target = "icosphere(5)"
    only = [name for name in args.only.split(",") if name]
    for name, V, F, selection, ratio in generated_features() + real_features():
        if only and not any(name.startswith(o) for o in only):
            continue
        record = {"bench": "paste_protrusion", "feature": name, "selected_faces": int(len(selection)),
                  "carry": args.carry, "target": target}
        if ratio is not None:
            record["length_over_width"] = round(ratio, 2)
        start = time.perf_counter()
        try:
            feature = pm.extract_feature(V, F, selection, carry=args.carry)
        except pm.MeshError as e:
            record.update(copied=False, error=f"{type(e).__name__}: {e}")
            emit(record)
            continue
        record.update(copied=True, carried=bool(feature.carried), copy_seconds=round(time.perf_counter() - start, 3))
        ok, closed_ok, update_ms, error = paste_trials(feature, T, TF, args.anchors, args.updates)
        record.update(pasted=ok, closed=closed_ok, anchors=args.anchors,
                      update_ms=None if update_ms is None else round(update_ms, 2))
        if error:
            record["paste_error"] = error
        try:
            record["flat_shape_error"] = round(shape_on_flat(feature), 4)
        except pm.MeshError as e:
            record["flat_error"] = f"{type(e).__name__}: {e}"
        emit(record)
    if not only:
        dense_target_updates(args.updates)


if __name__ == "__main__":
    main()
