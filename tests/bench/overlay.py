"""Spherical overlay benchmarks (thesis 4.4; issue 5's figure: two 100k-face
maps in <= 3 s on this machine), JSON lines:

    /usr/bin/python3 tests/bench/overlay.py [--faces 100000] [--repeats 5]

Workloads, all on precomputed sphere maps (pm.sphere_map, not timed):
- blob-vs-geodesic: the map of meshes.sized_sphere_mesh(faces) against a
  geodesic sphere of about as many faces (another resolution), turned at random;
- blob-vs-turned-blob: that map against itself turned at random (same resolution);
- blob-vs-itself: the map with itself (every vertex coincident: all merging);
- spot-vs-blob: the real model spot (shared models, when present) against a blob
  map of similar size.
Each line: sizes, the median of `repeats` runs and the median of each phase
(validate, arrangement, merge, triangulate, attributes), crossings, merged size,
and the checks the result reports (folded, open_edges, degenerate_cells)."""
import argparse
import statistics
import sys
import time

import numpy as np

from common import MODELS, emit, import_native, load_obj

pm = import_native()
import meshes  # noqa: E402  (tests/native, on sys.path after import_native)

PHASES = ("validate", "arrangement", "merge", "triangulate", "attributes")


def turned(X, seed):
    q, _ = np.linalg.qr(np.random.default_rng(seed).normal(size=(3, 3)))
    return X @ (q * np.sign(np.linalg.det(q))).T


def unit_map(V, F):
    X = pm.sphere_map(V, F).positions
    return X / np.linalg.norm(X, axis=1, keepdims=True)


def workloads(faces):
    V, F = meshes.sized_sphere_mesh(faces)
    blob = unit_map(V, F)
    frequency = int(round((faces / 20.0) ** 0.5)) - 2  # another resolution, about as many faces
    XG, FG = meshes.geodesic_sphere(frequency)
    yield "blob-vs-geodesic", blob, F, turned(XG, 1), FG
    yield "blob-vs-turned-blob", blob, F, turned(blob, 2), F
    yield "blob-vs-itself", blob, F, blob, F
    spot = MODELS / "spot.obj"
    if spot.exists():
        VS, FS = load_obj(spot)
        V2, F2 = meshes.sized_sphere_mesh(len(FS))
        yield "spot-vs-blob", unit_map(VS, FS), FS, turned(unit_map(V2, F2), 3), F2


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--faces", type=int, default=100000)
    parser.add_argument("--repeats", type=int, default=5)
    args = parser.parse_args()
    for name, XA, FA, XB, FB in workloads(args.faces):
        times, phases, r = [], {p: [] for p in PHASES}, None
        for _ in range(args.repeats):
            start = time.perf_counter()
            r = pm.overlay(XA, FA, XB, FB)
            times.append(time.perf_counter() - start)
            for p in PHASES:
                phases[p].append(getattr(r.stats, "seconds_" + p))
        s = r.stats
        emit({"bench": "overlay", "workload": name, "faces_a": len(FA), "faces_b": len(FB),
              "seconds_median": round(statistics.median(times), 3),
              "seconds_min": round(min(times), 3),
              "phases_median": {p: round(statistics.median(v), 3) for p, v in phases.items()},
              "crossings": s.crossings, "cells": s.cells, "merged_vertices": len(r.V),
              "merged_faces": len(r.F), "vertices_merged_away": s.merged_vertices,
              "folded": s.folded, "open_edges": s.open_edges,
              "degenerate_cells": s.degenerate_cells, "repeats": args.repeats})


if __name__ == "__main__":
    sys.exit(main())
