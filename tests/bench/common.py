"""Shared pieces of the benchmarks: module import, OBJ loading, timing, JSON out."""
import json
import os
import statistics
import sys
import time
from pathlib import Path

REPO = Path(__file__).resolve().parents[2]
MODELS = REPO.parent / "shared" / "models"


def import_native():
    build = REPO / os.environ.get("PARAMORPH_BUILD_DIR", "build") / "python"
    sys.path.insert(0, str(build))
    sys.path.insert(0, str(REPO / "tests" / "native"))
    import paramorph_native  # noqa: E402

    return paramorph_native


def load_obj(path):
    """Vertices (n,3) float64 and triangles (m,3) int32 (polygons fan-triangulated)."""
    import numpy as np

    verts, faces = [], []
    with open(path) as fh:
        for line in fh:
            if line.startswith("v "):
                verts.append([float(x) for x in line.split()[1:4]])
            elif line.startswith("f "):
                idx = [int(tok.split("/")[0]) for tok in line.split()[1:]]
                idx = [i - 1 if i > 0 else len(verts) + i for i in idx]
                for k in range(1, len(idx) - 1):
                    faces.append([idx[0], idx[k], idx[k + 1]])
    return np.asarray(verts, dtype=np.float64), np.asarray(faces, dtype=np.int32)


def median_run(fn, repeats=3):
    """Runs fn() `repeats` times; returns (median seconds, last result)."""
    times, result = [], None
    for _ in range(repeats):
        start = time.perf_counter()
        result = fn()
        times.append(time.perf_counter() - start)
    return statistics.median(times), result


def emit(record):
    print(json.dumps(record), flush=True)
