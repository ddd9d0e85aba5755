"""Morphing through the module: optimize_sphere_map (thesis 4.3.3), with
Ipopt's polish (source builds that have it) and with the barrier path alone
(the released wheel, built without Ipopt)."""
import numpy as np
import pytest

import meshes
import paramorph_native as pm

HAS_IPOPT = pm.build_info()["ipopt"]
needs_ipopt = pytest.mark.skipif(not HAS_IPOPT, reason="this build has no Ipopt (PARAMORPH_WITH_IPOPT=OFF)")
SOLVERS = [pytest.param("ipopt", marks=needs_ipopt), "barrier"]
FINISHED = {"ipopt": ("Solve_Succeeded", "Solved_To_Acceptable_Level"), "barrier": ("Barrier_Converged",)}


def triple_products(X, F):
    return np.einsum("ij,ij->i", X[F[:, 0]], np.cross(X[F[:, 1]], X[F[:, 2]]))


@pytest.mark.parametrize("solver", SOLVERS)
def test_optimized_map_is_fold_free_on_the_sphere_and_closer_to_the_projection(solver):
    V, F = meshes.tentacle_sphere(subdivisions=2, tentacles=3, length=1.5)
    start = pm.sphere_map(V, F).positions
    seen = []
    r = pm.optimize_sphere_map(V, F, start, solver=solver,
                               progress=lambda fraction, stage: seen.append(fraction) or True)
    assert r.status in FINISHED[solver], r.status
    assert r.used_ipopt == (solver == "ipopt")
    assert r.flipped == 0 and r.min_triple >= r.epsilon * (1 - 1e-4) > 0
    np.testing.assert_allclose(np.linalg.norm(r.positions, axis=1), 1.0, atol=1e-12)
    assert np.all(triple_products(r.positions, F) > 0)
    assert r.start_objective < r.objective <= len(V)
    assert seen and seen[-1] == 1.0


def test_float32_input_and_a_given_target():
    V, F = meshes.icosphere(2)
    V = V * [1.5, 1.0, 0.8]
    start = pm.sphere_map(V, F).positions
    target = V / np.linalg.norm(V, axis=1, keepdims=True)
    r = pm.optimize_sphere_map(V.astype(np.float32), F.astype(np.int64), start.astype(np.float32),
                               target=target, epsilon=0.001)
    assert r.flipped == 0
    assert np.abs(r.positions - target).max() < 1e-3  # an ellipsoid's projection folds nothing


def test_errors_and_cancel():
    V, F = meshes.noisy_blob(2)
    start = pm.sphere_map(V, F).positions
    bad = start.copy()
    bad[F[0, 0]] *= -1
    with pytest.raises(pm.InvalidInputError, match="folds"):
        pm.optimize_sphere_map(V, F, bad)
    with pytest.raises(pm.InvalidInputError, match="epsilon"):
        pm.optimize_sphere_map(V, F, start, epsilon=0.0)
    Vd, Fd = meshes.open_disc()
    with pytest.raises(pm.NotClosedError):
        pm.optimize_sphere_map(Vd, Fd, np.zeros_like(Vd))
    Vt, Ft = meshes.torus()
    with pytest.raises(pm.NotGenusZeroError):
        pm.optimize_sphere_map(Vt, Ft, np.zeros_like(Vt))
    with pytest.raises(pm.Cancelled):
        pm.optimize_sphere_map(V, F, start, progress=lambda fraction, stage: False)


def test_faces_squeezed_to_rounding_by_the_conformal_map_are_opened():
    # Long tentacles: the conformal map from the Tutte start squeezes their
    # tips to triple products of about -1e-17 (rounding; init="auto" builds
    # the progressive start there instead); the barrier opens every face to
    # above epsilon before its path, and the result keeps them there (Ipopt's
    # polish is kept only if it does too).
    V, F = meshes.tentacle_sphere(2, tentacles=4)
    start = pm.sphere_map(V, F, init="stereographic").positions
    assert triple_products(start, F).min() <= 0  # the case this test is about
    r = pm.optimize_sphere_map(V, F, start)
    assert r.barrier_steps > 0
    assert r.flipped == 0 and triple_products(r.positions, F).min() >= 0.9 * r.epsilon
    assert r.epsilon == pytest.approx(0.05 * triple_products(start, F).mean())


def test_the_relaxed_radial_start_ends_nearer_the_targets_than_the_conformal_one():
    # The thesis' start (4.3.2), the radial projection relaxed until no face
    # folds, is what morph optimizes from: the conformal map (from the Tutte
    # start, as the thesis computes it) squeezes the tentacles, and opening
    # them costs objective (measured on 4 and 6 tentacles at 0.9k-4.8k
    # faces: 1.0-4.3 higher from the relaxed start).
    V, F = meshes.tentacle_sphere(2, tentacles=4)
    relaxed = pm.sphere_map(V, F, init="relaxation", max_outer_iterations=0).positions
    conformal = pm.sphere_map(V, F, init="stereographic").positions
    assert triple_products(relaxed, F).min() > 0
    from_relaxed = pm.optimize_sphere_map(V, F, relaxed)
    from_conformal = pm.optimize_sphere_map(V, F, conformal)
    assert from_relaxed.flipped == 0 and from_relaxed.min_triple >= 0.9 * from_relaxed.epsilon
    assert from_relaxed.objective > from_conformal.objective + 0.5


def test_without_a_start_the_relaxed_projection_replaces_a_squeezed_conformal_map():
    # sphere=None: morph's own start. The tentacles' conformal map is
    # squeezed to rounding, so the relaxed radial projection is used; a
    # blob's conformal map is not, so it is kept.
    V, F = meshes.tentacle_sphere(2, tentacles=4)
    relaxed = pm.sphere_map(V, F, init="relaxation", max_outer_iterations=0).positions
    chosen = pm.optimize_sphere_map(V, F)
    assert np.array_equal(chosen.positions, pm.optimize_sphere_map(V, F, relaxed).positions)
    V, F = meshes.noisy_blob(2)
    chosen = pm.optimize_sphere_map(V, F)
    assert np.array_equal(chosen.positions, pm.optimize_sphere_map(V, F, pm.sphere_map(V, F).positions).positions)


def test_weights_pull_a_vertex_to_its_target():
    # Thesis (4.12): feature points weigh more. The vertex the unweighted
    # optimum leaves farthest from its target comes much closer at weight 1000.
    V, F = meshes.noisy_blob(2)
    start = pm.sphere_map(V, F).positions
    angle = 0.4
    turn = np.array([[np.cos(angle), -np.sin(angle), 0], [np.sin(angle), np.cos(angle), 0], [0, 0, 1]])
    target = (V / np.linalg.norm(V, axis=1, keepdims=True)) @ turn
    target[:, 0] += 0.4 * np.sin(5 * V[:, 1])
    target /= np.linalg.norm(target, axis=1, keepdims=True)
    plain = pm.optimize_sphere_map(V, F, start, target=target)
    far = int(np.argmax(np.linalg.norm(plain.positions - target, axis=1)))
    before = np.linalg.norm(plain.positions[far] - target[far])
    assert before > 1e-3
    weights = np.ones(len(V))
    weights[far] = 1000.0
    r = pm.optimize_sphere_map(V, F, start, target=target, weights=weights)
    assert r.flipped == 0 and np.all(triple_products(r.positions, F) > 0)
    assert np.linalg.norm(r.positions[far] - target[far]) < 0.5 * before
    with pytest.raises(pm.InvalidInputError, match="weights"):
        pm.optimize_sphere_map(V, F, start, weights=-weights)
    with pytest.raises(pm.InvalidInputError, match="weights"):
        pm.optimize_sphere_map(V, F, start, weights=weights[:-1])


@pytest.mark.parametrize("solver", SOLVERS)
def test_a_clean_start_is_warm_started_by_the_barrier(solver):
    # A start without squeezed faces goes through the log-barrier Newton path;
    # Ipopt then needs few iterations and the result keeps 0 folds.
    V, F = meshes.noisy_blob(3)
    start = pm.sphere_map(V, F).positions
    assert triple_products(start, F).min() > 1e-12
    r = pm.optimize_sphere_map(V, F, start, solver=solver)
    assert r.barrier_steps > 0
    assert r.status in FINISHED[solver], r.status
    assert r.flipped == 0 and r.min_triple >= r.epsilon * (1 - 1e-4)
    assert r.start_objective < r.objective <= len(V)


@needs_ipopt
@pytest.mark.parametrize("case", ["tentacles relaxed", "tentacles conformal", "blob"])
def test_the_barrier_alone_reaches_ipopts_optimum(case):
    # What the released wheel (no Ipopt) gives against what Ipopt's polish
    # gives, on the same start: as fold-free, every face at or above epsilon,
    # and an objective no lower than Ipopt's beyond 1e-6 of it (measured on
    # spot, blobs and tentacles, tests/bench/morph.py: the barrier's is
    # 1e-12..3e-6 higher).
    if case == "blob":
        V, F = meshes.noisy_blob(3)
        start = pm.sphere_map(V, F).positions
    else:
        V, F = meshes.tentacle_sphere(2, tentacles=4)
        start = (pm.sphere_map(V, F, init="relaxation", max_outer_iterations=0).positions
                 if case == "tentacles relaxed" else pm.sphere_map(V, F).positions)
    ipopt = pm.optimize_sphere_map(V, F, start, solver="ipopt")
    barrier = pm.optimize_sphere_map(V, F, start, solver="barrier")
    assert not barrier.used_ipopt and barrier.iterations == 0
    assert barrier.flipped == 0 and triple_products(barrier.positions, F).min() >= barrier.epsilon
    assert barrier.epsilon == ipopt.epsilon
    assert barrier.objective >= ipopt.objective - 1e-6 * abs(ipopt.objective)


def test_auto_uses_ipopt_exactly_where_the_build_has_it():
    V, F = meshes.noisy_blob(3)
    r = pm.optimize_sphere_map(V, F, pm.sphere_map(V, F).positions)
    assert r.used_ipopt == HAS_IPOPT
    assert r.status in FINISHED["ipopt" if HAS_IPOPT else "barrier"], r.status


@pytest.mark.skipif(HAS_IPOPT, reason="this build has Ipopt")
def test_asking_for_ipopt_in_a_build_without_it_says_so():
    V, F = meshes.noisy_blob(2)
    with pytest.raises(pm.InvalidInputError, match="no Ipopt"):
        pm.optimize_sphere_map(V, F, pm.sphere_map(V, F).positions, solver="ipopt")


def test_an_unknown_solver_is_refused():
    V, F = meshes.noisy_blob(2)
    with pytest.raises(pm.InvalidInputError, match="solver"):
        pm.optimize_sphere_map(V, F, solver="newton")
