"""How fast Esc acts on every long call the add-on's operators make (issue
20: "Esc acts within 0.5 s on every long operator, progress at least that
often"). Each call runs in a thread on a large generated mesh, as the
operators run it; the progress callback records when it is called and, at
each of the cancel times, answers False (what Esc does). Per call and cancel
time: the latency from the cancel request to the call returning
(Cancelled), and the longest gap between progress reports before it (a
run that finished first: over the whole run). In the add-on, Esc waits for
the call to return, so the operator ends with it.

    python3 tests/bench/esc_latency.py [--faces 80000] [--cancel-at 1 3 6] [--only sphere_map ...]

Prints one JSON line per call and cancel time, then a summary line."""
import argparse
import threading
import time

import numpy as np

from common import emit, import_native

pm = import_native()
import meshes  # noqa: E402  (tests/native, put on sys.path by import_native)


def large_blob(faces, seed=0):
    """A noisy closed blob with about `faces` triangles."""
    V, F = meshes.sized_sphere_mesh(faces)
    rng = np.random.default_rng(seed)
    direction = V / np.linalg.norm(V, axis=1, keepdims=True)
    bumps = 0.12 * np.sin(5 * direction[:, 0]) * np.cos(4 * direction[:, 1]) + 0.004 * rng.standard_normal(len(V))
    return V * (1.0 + bumps)[:, None], F


def cap(V, F, fraction=0.35):
    """About `fraction` of the faces, around the top (a disc: by direction from
    the centre, which the radial bumps do not break up)."""
    centres = V[F].mean(axis=1)
    up = centres[:, 2] / np.linalg.norm(centres, axis=1)
    return np.flatnonzero(up > np.quantile(up, 1.0 - fraction)).astype(np.int32)


def calls(faces):
    V, F = large_blob(faces)
    VB, FB = large_blob(faces // 2, seed=3)
    VB = VB * [1.3, 0.8, 1.0]
    disc = cap(V, F)
    used = np.unique(F[disc])
    remap = -np.ones(len(V), dtype=np.int64)
    remap[used] = np.arange(len(used))
    VD, FD = V[used], remap[F[disc]].astype(np.int32)
    feature_faces = cap(V, F, 0.05)
    feature = pm.extract_feature(V, F, feature_faces)
    side = V[np.argmax(V[:, 0])]  # a paste on the blob's side
    merged = pm.morph(V, F, VB, FB)  # the in-betweens work on the merged mesh (~3.7x the faces)
    S, T, FM = np.asarray(merged.source), np.asarray(merged.target), np.asarray(merged.faces)
    return {
        "repair": lambda progress: pm.repair(V, F, progress=progress),
        "sphere_map": lambda progress: pm.sphere_map(V, F, progress=progress),
        "segment_extremities": lambda progress: pm.segment_extremities(V, F, progress=progress),
        "feature_regions": lambda progress: pm.feature_regions(V, F, progress=progress),
        "shape_signature": lambda progress: pm.shape_signature(V, F, progress=progress),
        "isometric_map": lambda progress: pm.isometric_map(VD, FD, progress=progress),
        "extract_feature": lambda progress: pm.extract_feature(V, F, feature_faces, progress=progress),
        "paste_session": lambda progress: pm.PasteSession(V, F, feature, anchor=side, progress=progress),
        "morph_correspondence": lambda progress: pm.morph_correspondence(V, F, VB, FB, progress=progress),
        "morph": lambda progress: pm.morph(V, F, VB, FB, progress=progress),
        "shape_interpolation": lambda progress: pm.ShapeInterpolation(S, T, FM, progress=progress),
        "surface_distance": lambda progress: pm.surface_distance(T, FM, VB, FB, progress=progress),
    }


def cancel_once(call, cancel_at, limit=600.0):
    """Runs `call`, asks it to stop `cancel_at` s in; (record dict)."""
    times, asked, ended = [], threading.Event(), {}

    def progress(fraction, stage):
        times.append((time.perf_counter(), stage, round(float(fraction), 3)))
        return not asked.is_set()

    def run():
        try:
            call(progress)
            ended["how"] = "finished"
        except pm.Cancelled:
            ended["how"] = "cancelled"
        except Exception as error:  # noqa: BLE001 (reported, not raised)
            ended["how"] = f"{type(error).__name__}: {error}"
        ended["at"] = time.perf_counter()

    start = time.perf_counter()
    thread = threading.Thread(target=run, daemon=True)
    thread.start()
    thread.join(cancel_at)
    asked_at = time.perf_counter()
    asked.set()
    thread.join(limit)
    stamps = [start] + [t for t, _, _ in times if t <= asked_at]
    last = next(((f, s) for t, s, f in reversed(times) if t <= asked_at), None)
    gaps = np.diff(stamps + [asked_at])
    worst = int(np.argmax(gaps)) if len(gaps) else 0
    stage_after = next((s for t, s, _ in times if t >= stamps[worst]), "")
    return {"cancel_at_s": cancel_at, "ended": ended.get("how", "still running"),
            "latency_s": round(ended["at"] - asked_at, 3) if ended.get("how") == "cancelled" else None,
            "reports_before_cancel": len(stamps) - 1, "longest_gap_s": round(float(gaps.max()), 3),
            "longest_gap_stage": stage_after, "last_report_before_cancel": last}


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--faces", type=int, default=80_000)
    parser.add_argument("--cancel-at", type=float, nargs="+", default=[1.0, 3.0, 6.0])
    parser.add_argument("--only", nargs="*")
    args = parser.parse_args()
    worst = {}
    for name, call in calls(args.faces).items():
        if args.only and name not in args.only:
            continue
        for cancel_at in args.cancel_at:
            record = cancel_once(call, cancel_at)
            emit({"bench": "esc_latency", "call": name, "faces": args.faces, **record})
            entry = worst.setdefault(name, {"latency_s": None, "longest_gap_s": 0.0})
            entry["longest_gap_s"] = max(entry["longest_gap_s"], record["longest_gap_s"])
            if record["ended"] != "cancelled":
                break  # finished (or failed) before this cancel time: later ones would too
            entry["latency_s"] = max(entry["latency_s"] or 0.0, record["latency_s"])
    emit({"bench": "esc_latency", "summary": worst,
          "worst_latency_s": max((w["latency_s"] for w in worst.values() if w["latency_s"] is not None),
                                 default=None),
          "longest_gap_s": max((w["longest_gap_s"] for w in worst.values()), default=None)})


if __name__ == "__main__":
    main()
