"""Small meshes on a busy machine: the calls an operator makes on a few
hundred faces, timed while other processes keep every core busy, with
OpenMP's default threads and with one thread. Loops run once per sweep or
iteration pay a parallel region's join each time, and a thread descheduled
there stalls the others (native/common/parallel.h); below kParallelMinimum
items they now run on one thread, so both columns should agree.

    /usr/bin/python3 tests/bench/busy_machine.py [--busy 6] [--repeats 5]

Prints one JSON line per call: median and worst seconds with default
threads and with OMP_NUM_THREADS=1, and their ratio."""
import argparse
import json
import os
import subprocess
import sys

from common import REPO, emit

CHILD = r"""
import json, sys, time
sys.path[:0] = [sys.argv[1], sys.argv[2]]
import numpy as np, paramorph_native as pm, meshes
octopus = meshes.coarse_octopus(2, limbs=6)  # 320 faces; its cotangent start folds: 20,000 relaxation sweeps
blob, limbs = meshes.noisy_blob(3), meshes.coarse_octopus(3, limbs=4)  # 1280 faces each
calls = {
    "sphere_map 320 faces": lambda: pm.sphere_map(*octopus, backend="cpu"),
    "morph 1280 onto 1280 faces": lambda: pm.morph(*blob, *limbs),
}
out = {}
for name, call in calls.items():
    times = []
    for _ in range(int(sys.argv[3])):
        start = time.perf_counter(); call(); times.append(time.perf_counter() - start)
    out[name] = sorted(times)
print(json.dumps(out))
"""


def timings(threads, repeats):
    env = dict(os.environ)
    env.pop("OMP_NUM_THREADS", None)
    if threads:
        env["OMP_NUM_THREADS"] = str(threads)
    build = str(REPO / os.environ.get("PARAMORPH_BUILD_DIR", "build") / "python")
    run = subprocess.run([sys.executable, "-c", CHILD, build, str(REPO / "tests" / "native"), str(repeats)],
                         env=env, capture_output=True, text=True, check=True)
    return json.loads(run.stdout.splitlines()[-1])


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--busy", type=int, default=6, help="busy processes kept running alongside")
    parser.add_argument("--repeats", type=int, default=5)
    args = parser.parse_args()
    busy = [subprocess.Popen([sys.executable, "-c", "while True: pass"]) for _ in range(args.busy)]
    try:
        default, single = timings(None, args.repeats), timings(1, args.repeats)
    finally:
        for process in busy:
            process.kill()
    for name in default:
        d, s = default[name], single[name]
        emit({"call": name, "busy_processes": args.busy, "cores": os.cpu_count(),
              "median_s": round(d[len(d) // 2], 4), "worst_s": round(d[-1], 4),
              "one_thread_median_s": round(s[len(s) // 2], 4), "one_thread_worst_s": round(s[-1], 4),
              "median_ratio": round(d[len(d) // 2] / s[len(s) // 2], 2)})


if __name__ == "__main__":
    main()
