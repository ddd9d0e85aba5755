"""The released module against the development build, side by side (issue
30: the manylinux_2_28 build, zig's clang with libc++ and static OpenBLAS and
libomp, must not be slower than Debian's GCC build). JSON lines:

    /usr/bin/python3 tests/bench/release_speed.py DIR_A DIR_B [--repeats 3]

DIR_A, DIR_B: folders holding a paramorph_native*.so for this Python (e.g.
build/python, and a release wheel unpacked). Each workload runs in a fresh
process per module, the two alternating, `repeats` times; medians and the
ratio B / A. Workloads: sphere_map of a 100k-face blob, balanced_sphere_map
of the same, and the morph of a generated cow (6k faces) into a horse (97k)."""
import argparse
import json
import statistics
import subprocess
import sys

from common import REPO, emit

CHILD = r"""
import json, sys, time
sys.path.insert(0, sys.argv[1]); sys.path.insert(0, sys.argv[2])
import paramorph_native as pm
import meshes, quadrupeds as Q
work = sys.argv[3]
if work.startswith("sphere"):
    V, F = meshes.sized_sphere_mesh(100000)
    call = (lambda: pm.sphere_map(V, F)) if work == "sphere_map" else (lambda: pm.balanced_sphere_map(V, F))
else:
    A = Q.quadruped("cow", 6000, seed=0)
    B = Q.quadruped("horse", 97000, pose=Q.WALK, seed=3)
    call = lambda: pm.morph(A[0], A[1], B[0], B[1])
start = time.perf_counter(); call()
print(json.dumps({"seconds": time.perf_counter() - start, "module": pm.__file__}))
"""


def run(module_dir, work):
    out = subprocess.run([sys.executable, "-c", CHILD, module_dir, str(REPO / "tests" / "native"), work],
                         capture_output=True, text=True, check=True)
    return json.loads(out.stdout.strip().splitlines()[-1])


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("a")
    parser.add_argument("b")
    parser.add_argument("--repeats", type=int, default=3)
    args = parser.parse_args()
    for work in ("sphere_map", "balanced_sphere_map", "morph 6k -> 97k"):
        times = {args.a: [], args.b: []}
        modules = {}
        for _ in range(args.repeats):
            for module_dir in (args.a, args.b):
                result = run(module_dir, work)
                times[module_dir].append(result["seconds"])
                modules[module_dir] = result["module"]
        a, b = (statistics.median(times[d]) for d in (args.a, args.b))
        emit({"bench": "release_speed", "work": work, "a": modules[args.a], "b": modules[args.b],
              "a_seconds_median": round(a, 3), "b_seconds_median": round(b, 3), "ratio_b_over_a": round(b / a, 3),
              "repeats": args.repeats})


if __name__ == "__main__":
    main()
