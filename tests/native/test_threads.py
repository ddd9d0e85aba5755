"""Long calls release the GIL, so Python threads run them at once, and each
must give the answer it gives alone. Two optimize_sphere_map runs through
Ipopt's sequential MUMPS once crashed the process; two CHOLMOD supernodal
factorisations at once gave wrong factors ("not positive definite" on a
positive definite matrix), because the single-threaded OpenBLAS Debian picks
by default shares its buffers between calling threads (native/common/
blas_lock.h). Run in a child process so a crash fails the test instead of
killing pytest."""
import os
import subprocess
import sys
import textwrap

import paramorph_native as pm

CHILD = textwrap.dedent(r"""
    import sys, threading
    import numpy as np
    import paramorph_native as pm
    sys.path.insert(0, sys.argv[1])
    import meshes
    solver = "ipopt" if pm.build_info()["ipopt"] else "barrier"
    blob = meshes.noisy_blob(3)
    octopus = meshes.coarse_octopus(3, limbs=4)
    # 10k vertices: large enough for CHOLMOD's supernodes to reach BLAS. With
    # progress= the factorisation runs on a thread of its own.
    V, F = meshes.noisy_blob(subdivisions=5, seed=4)
    W = V * 1.7 + 0.3 * np.sin(3 * V[:, [1, 2, 0]]) + [2.0, -1.0, 0.5]

    jobs = {  # each: positions it computes (CHOLMOD, MUMPS, both, or neither)
        "optimize blob": lambda: pm.optimize_sphere_map(*blob, solver=solver).positions,
        "barrier octopus": lambda: pm.optimize_sphere_map(*octopus, solver="barrier").positions,
        "in-betweens": lambda: pm.ShapeInterpolation(V, W, F, progress=lambda *a: None).at(0.5),
        "morph": lambda: pm.morph(*blob, *octopus).target,
        "sphere map": lambda: pm.sphere_map(*octopus, backend="cpu").positions,
    }
    alone = {name: job() for name, job in jobs.items()}
    differences, errors = [], []

    def run(name):
        try:
            got = jobs[name]()
            gap = float(np.abs(got - alone[name]).max()) if got.shape == alone[name].shape else float("inf")
            differences.append((name, gap))
        except Exception as error:
            errors.append(f"{name}: {error!r}")

    for _ in range(2):
        threads = [threading.Thread(target=run, args=(name,)) for name in jobs for _ in range(2)]
        for t in threads:
            t.start()
        for t in threads:
            t.join()
    worst = {}
    for name, gap in differences:
        worst[name] = max(worst.get(name, 0.0), gap)
    print("RESULT", len(differences), worst, errors)
    print("WORST", max(worst.values()))
""")


def test_long_calls_in_several_threads_at_once_give_their_answers_alone():
    here = os.path.dirname(os.path.abspath(__file__))
    env = dict(os.environ, PYTHONPATH=os.path.dirname(pm.__file__))
    proc = subprocess.run([sys.executable, "-c", CHILD, here], env=env, capture_output=True, text=True, timeout=600)
    assert proc.returncode == 0, f"exit {proc.returncode} (a negative code is a signal)\n{proc.stderr[-3000:]}"
    result = next(line for line in proc.stdout.splitlines() if line.startswith("RESULT"))
    assert result.startswith("RESULT 20 ") and result.endswith(" []"), proc.stdout + proc.stderr[-2000:]
    worst = float(next(line for line in proc.stdout.splitlines() if line.startswith("WORST")).split()[1])
    # The same answer as alone, to the last bit: the BLAS lock keeps the
    # factors right, the METIS lock the orderings (and so the round-off) the same.
    assert worst == 0.0, result
