"""The smallest closed meshes (a tetrahedron, a 5-vertex bipyramid, an
octahedron) through every solver path of the functions that need a closed
genus-0 mesh, each mesh in a child process: METIS's nested dissection once
divided by zero on them (SIGFPE, the process and Blender with it), so the
test must survive a crash to report it. Each call gives a valid result or a
typed MeshError, never a signal."""
import json
import os
import subprocess
import sys
import textwrap

import pytest

import paramorph_native as pm

TINY = {
    "tetrahedron": ([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]],
                    [[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]]),
    "bipyramid": ([[1, 0, 0], [-0.5, 0.8, 0], [-0.5, -0.8, 0], [0, 0, 1], [0, 0, -1]],
                  [[0, 1, 3], [1, 2, 3], [2, 0, 3], [1, 0, 4], [2, 1, 4], [0, 2, 4]]),
    "octahedron": ([[1, 0, 0], [-1, 0, 0], [0, 1, 0], [0, -1, 0], [0, 0, 1], [0, 0, -1]],
                   [[0, 2, 4], [2, 1, 4], [1, 3, 4], [3, 0, 4], [2, 0, 5], [1, 2, 5], [3, 1, 5], [0, 3, 5]]),
}

CHILD = textwrap.dedent(r"""
    import json, sys
    import numpy as np
    import paramorph_native as pm
    V = np.array(json.loads(sys.argv[1]), dtype=np.float64)
    F = np.array(json.loads(sys.argv[2]), dtype=np.int32)
    out = {}

    def call(name, fn, check):
        try:
            out[name] = "ok" if check(fn()) else "invalid result"
        except pm.MeshError as error:  # a typed refusal is a valid answer
            out[name] = "refused: " + type(error).__name__
        except Exception as error:
            out[name] = "untyped " + type(error).__name__ + ": " + str(error)

    unit = lambda P: np.allclose(np.linalg.norm(P, axis=1), 1.0)
    for solver in ("auto", "pcg", "cholesky", "jacobi"):
        for backend in ("cpu", "auto"):
            call(f"sphere_map {solver} {backend}", lambda: pm.sphere_map(V, F, solver=solver, backend=backend),
                 lambda r: r.flipped == 0 and unit(r.positions))
    call("shape_signature", lambda: pm.shape_signature(V, F), lambda h: abs(h.sum() - 1) < 1e-9)
    call("segment_extremities", lambda: pm.segment_extremities(V, F), lambda s: True)
    for solver in ("auto", "barrier"):
        call(f"optimize_sphere_map {solver}", lambda: pm.optimize_sphere_map(V, F, solver=solver),
             lambda r: r.flipped == 0 and unit(r.positions))
    call("balanced_sphere_map", lambda: pm.balanced_sphere_map(V, F), lambda r: unit(r.positions))
    call("morph", lambda: pm.morph(V, F, V * 2.0, F),
         lambda m: len(m.faces) >= len(F) and np.isfinite(np.asarray(m.target)).all())
    call("repair", lambda: pm.repair(V, F), lambda r: pm.validate(r.V, r.F).is_closed_genus0)
    call("repair of one face", lambda: pm.repair(V, F[:1]), lambda r: len(r.F) == 1)
    call("repair of two faces", lambda: pm.repair(V, F[:2]), lambda r: pm.validate(r.V, r.F).is_closed_genus0)
    call("repair inside out", lambda: pm.repair(V, F[:, ::-1]), lambda r: r.report.parts_turned_outward == 1)
    print("RESULT " + json.dumps(out))
""")


@pytest.mark.parametrize("name", sorted(TINY))
def test_tiny_closed_meshes_never_kill_the_process(name):
    V, F = TINY[name]
    env = dict(os.environ, PYTHONPATH=os.path.dirname(pm.__file__))
    proc = subprocess.run([sys.executable, "-c", CHILD, json.dumps(V), json.dumps(F)], env=env,
                          capture_output=True, text=True, timeout=300)
    assert proc.returncode == 0, f"exit {proc.returncode} (a negative code is a signal)\n{proc.stderr[-3000:]}"
    result = json.loads(next(line for line in proc.stdout.splitlines() if line.startswith("RESULT "))[7:])
    bad = {call: outcome for call, outcome in result.items() if not (outcome == "ok" or outcome.startswith("refused"))}
    assert not bad, bad
    # The closed genus-0 ones are mapped, not refused.
    assert all(outcome == "ok" for call, outcome in result.items() if call.startswith("sphere_map")), result
