"""Sphere maps of real and long-limbed characters (issue 28): sphere_map and
balanced_sphere_map on every mesh in ../shared/models (meshes with holes
repaired first, as the add-on does; skipped cleanly without the folder) and
on generated hard cases (stars with 6-12 arms 20-40 times as long as wide,
coiled tubes, at 50k-100k faces), optionally while other processes keep the
cores busy.

    /usr/bin/python3 tests/bench/sphere_models.py [--repeats 3] [--busy 2]
        [--only cat dancer ...] [--no-generated] [--build-dir build]

One JSON line per (mesh, function): faces, median and worst seconds, folds
(faces whose triple product is <= 0), squeezed (faces within rounding of 0:
<= 1e-13), the smallest triple product, the area-weighted quasi-conformal
distortion (1 = conformal), the isometric energy over its minimum (1 = an
isometry), and how the map was made (start, outer steps, stop reason). A
call that raises prints its error instead. Each call runs in a child process
with a time limit, so a crawl shows as a timeout, not a hung bench."""
import argparse
import json
import os
import statistics
import subprocess
import sys

from common import MODELS, REPO, emit

CHILD = r"""
import json, sys, time
sys.path[:0] = [sys.argv[1], sys.argv[2], sys.argv[3]]
import numpy as np, paramorph_native as pm, meshes
from common import load_obj, MODELS
from sphere import quasi_conformal

name, function, repeats = sys.argv[4], sys.argv[5], int(sys.argv[6])
GENERATED = {
    "star6-20x": lambda: meshes.star(6, aspect=20, subdivisions=5),
    "star12-20x": lambda: meshes.star(12, aspect=20),
    "star8-40x": lambda: meshes.star(8, aspect=40),
    "coiled-tube-100k": lambda: meshes.coiled_tube(turns=6, around=32),
    "thin-coiled-tube-90k": lambda: meshes.coiled_tube(turns=4, radius=0.05, around=24),
}
repaired = False
if name in GENERATED:
    V, F = GENERATED[name]()
else:
    V, F = load_obj(MODELS / f"{name}.obj")
    if not pm.validate(V, F).is_closed_genus0:
        r = pm.repair(V, F)
        V, F, repaired = r.V, r.F, True
call = {"sphere_map": lambda: pm.sphere_map(V, F), "balanced_sphere_map": lambda: pm.balanced_sphere_map(V, F)}[function]
times, result, error = [], None, None
for _ in range(repeats):
    start = time.perf_counter()
    try:
        result = call()
    except Exception as e:
        error = f"{type(e).__name__}: {e}"
        times.append(time.perf_counter() - start)
        break
    times.append(time.perf_counter() - start)
out = {"mesh": name, "function": function, "faces": int(len(F)), "repaired": repaired, "seconds": times}
if error:
    out["error"] = error[:300]
else:
    X = np.asarray(result.positions)
    det = np.einsum("ij,ij->i", X[F[:, 0]], np.cross(X[F[:, 1]], X[F[:, 2]]))
    out.update(folds=int((det <= 0).sum()), squeezed=int((det <= 1e-13).sum()), min_triple=float(det.min()),
               quasi_conformal=round(quasi_conformal(V, X, F), 3))
    try:
        out["isometric_energy"] = round(pm.isometric_sphere_map(V, F, X, max_steps=0).start_energy, 4)
    except Exception:  # a face at rounding: the energy is infinite
        out["isometric_energy"] = None
    if function == "sphere_map":
        out.update(start=getattr(result, "initial_map", "stereographic"), outer=result.outer_iterations,
                   partial=getattr(result, "partial_steps", 0),
                   stop=result.stop_reason)
    else:
        out.update(newton_steps=result.steps)
print(json.dumps(out))
"""


def run(name, function, repeats, timeout):
    build = str(REPO / os.environ.get("PARAMORPH_BUILD_DIR", "build") / "python")
    args = [sys.executable, "-c", CHILD, build, str(REPO / "tests" / "native"), str(REPO / "tests" / "bench"),
            name, function, str(repeats)]
    try:
        done = subprocess.run(args, capture_output=True, text=True, timeout=timeout)
    except subprocess.TimeoutExpired:
        return {"mesh": name, "function": function, "error": f"timeout: over {timeout} s"}
    if done.returncode != 0:
        return {"mesh": name, "function": function, "error": (done.stderr or "")[-300:]}
    out = json.loads(done.stdout.splitlines()[-1])
    times = out.pop("seconds")
    out["seconds"] = round(statistics.median(times), 3)
    out["worst_seconds"] = round(max(times), 3)
    return out


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--repeats", type=int, default=3)
    parser.add_argument("--busy", type=int, default=0, help="busy processes kept running alongside (issue 28: 2)")
    parser.add_argument("--only", nargs="*", default=None, help="mesh names (model stems or generated names)")
    parser.add_argument("--no-generated", action="store_true")
    parser.add_argument("--functions", nargs="*", default=["sphere_map", "balanced_sphere_map"])
    parser.add_argument("--timeout", type=float, default=600)
    args = parser.parse_args()
    names = sorted(p.stem for p in MODELS.glob("*.obj")) if MODELS.is_dir() else []
    if not names:
        print(f"sphere_models: no {MODELS}: the real characters are skipped", file=sys.stderr)
    if not args.no_generated:
        names += ["star6-20x", "star12-20x", "star8-40x", "coiled-tube-100k", "thin-coiled-tube-90k"]
    if args.only:
        names = [n for n in names if n in args.only]
    busy = [subprocess.Popen([sys.executable, "-c", "while True: pass"]) for _ in range(args.busy)]
    try:
        for name in names:
            for function in args.functions:
                record = run(name, function, args.repeats, args.timeout)
                record["busy"] = args.busy
                emit(record)
    finally:
        for process in busy:
            process.kill()


if __name__ == "__main__":
    main()
