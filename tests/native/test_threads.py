"""Long calls release the GIL, so Python threads run them at once: two
optimize_sphere_map runs through Ipopt's sequential MUMPS once crashed the
process. Ipopt's runs now take turns; everything else is re-entrant. Run in
a child process so a crash fails the test instead of killing pytest."""
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
    results, errors = [], []

    def run(fn, check):
        try:
            results.append(check(fn()))
        except Exception as error:
            errors.append(repr(error))

    jobs = [
        (lambda: pm.optimize_sphere_map(*blob, solver=solver), lambda r: r.flipped == 0),
        (lambda: pm.optimize_sphere_map(*octopus, solver=solver), lambda r: r.flipped == 0),
        (lambda: pm.morph(*blob, *octopus), lambda m: len(m.faces) > 0),
        (lambda: pm.sphere_map(*octopus, backend="cpu"), lambda r: r.flipped == 0),
    ]
    for _ in range(2):
        threads = [threading.Thread(target=run, args=job) for job in jobs for _ in range(2)]
        for t in threads:
            t.start()
        for t in threads:
            t.join()
    print("RESULT", len(results), all(results), errors)
""")


def test_long_calls_in_several_threads_at_once():
    here = os.path.dirname(os.path.abspath(__file__))
    env = dict(os.environ, PYTHONPATH=os.path.dirname(pm.__file__))
    proc = subprocess.run([sys.executable, "-c", CHILD, here], env=env, capture_output=True, text=True, timeout=600)
    assert proc.returncode == 0, f"exit {proc.returncode} (a negative code is a signal)\n{proc.stderr[-3000:]}"
    assert "RESULT 16 True []" in proc.stdout, proc.stdout + proc.stderr[-2000:]
