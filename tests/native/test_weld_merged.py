"""Welding the merged mesh (issue 17, item 3): near-coincident merged
vertices welded and slivers flipped, both ends within 1e-6 of the diagonal,
every input vertex still exactly in its place, pins exact, the sphere mesh
still a fold-free closed genus-0 triangulation."""
import functools

import numpy as np
import pytest

import paramorph_native as pm
import quadrupeds as Q


def slivers(P, F, diagonal):
    n = np.cross(P[F[:, 1]] - P[F[:, 0]], P[F[:, 2]] - P[F[:, 0]])
    return 0.5 * np.linalg.norm(n, axis=1) < 1e-12 * diagonal ** 2


# Two pairs: which slivers a morph's overlay leaves depends on its numbers'
# last bits (the release build's exp/log differ from glibc's), and on one of
# them the release build leaves only a kind the weld cannot remove (below).
PAIRS = [(0, 3), (1, 3)]


@functools.lru_cache(maxsize=None)
def welded_pair(seeds):
    A = Q.quadruped("cow", 3000, seed=seeds[0])
    B = Q.quadruped("horse", 6000, pose=Q.WALK, seed=seeds[1])
    pin = (A[2]["tail"], B[2]["tail"])
    welded = pm.morph(A[0], A[1], B[0], B[1], pins=[pin])
    raw = pm.morph(A[0], A[1], B[0], B[1], pins=[pin], weld_tolerance=0.0)
    return A, B, pin, welded, raw


@pytest.fixture(scope="module", params=PAIRS, ids=lambda seeds: f"cow{seeds[0]}-horse{seeds[1]}")
def welded_and_not(request):
    return welded_pair(request.param)


def test_welding_removes_slivers():
    removed = [welded_pair(seeds)[3].weld for seeds in PAIRS]
    assert any(w.collapsed_edges > 0 and w.slivers_after < w.slivers_before for w in removed), removed


def test_welding_keeps_both_ends_and_leaves_only_what_it_cannot_remove(welded_and_not):
    (VA, FA, _), (VB, FB, _), pin, m, raw = welded_and_not
    F, S, T = np.asarray(m.faces), np.asarray(m.source), np.asarray(m.target)
    da, db = (np.linalg.norm(np.ptp(V, axis=0)) for V in (VA, VB))
    w = m.weld
    assert w.faces_before == len(raw.faces) and w.faces_after == len(F) <= len(raw.faces)
    raw_slivers = slivers(np.asarray(raw.source), np.asarray(raw.faces), da) | \
        slivers(np.asarray(raw.target), np.asarray(raw.faces), db)
    now = slivers(S, F, da) | slivers(T, F, db)
    assert w.slivers_before == raw_slivers.sum() and w.slivers_after == now.sum() <= raw_slivers.sum()
    # What stays is what weld_merged.h says it cannot remove: a whole tiny
    # triangle around an input vertex that lies a hair from the other input's
    # edge, every side within the weld's reach (1e-4 of the diagonal) at both
    # ends, so the weld looked at it. How tiny depends on the build's and the
    # CPU's last bits (an AVX-512 machine leaves one with sides 1.5e-5).
    inputs = set(np.asarray(m.vertex_of_a).tolist()) | set(np.asarray(m.vertex_of_b).tolist())
    for face in F[now]:
        assert inputs & set(face.tolist()), face
        for P, d in ((S, da), (T, db)):
            sides = np.linalg.norm(P[face] - P[np.roll(face, 1)], axis=1)
            assert sides.max() < 1e-4 * d, (face, sides / d)
    # Both ends within 1e-6 of the diagonal of their input, both ways.
    for P, V, Fin, d in ((S, VA, FA, da), (T, VB, FB, db)):
        distance = pm.surface_distance(P, F, V, Fin)
        assert distance.hausdorff <= 1e-6 * d
    # Every input vertex is still one merged vertex, exactly at its place; the pin holds.
    np.testing.assert_array_equal(np.asarray(m.vertex_of_a), np.arange(len(VA)))  # A's vertices first, in order
    np.testing.assert_array_equal(S[np.asarray(m.vertex_of_a)], VA)
    np.testing.assert_array_equal(T[np.asarray(m.vertex_of_b)], VB)
    assert len(np.unique(np.asarray(m.vertex_of_a))) == len(VA)
    assert np.abs(T[np.asarray(m.vertex_of_a)[pin[0]]] - VB[pin[1]]).max() <= 1e-9 * db


def test_the_welded_sphere_mesh_is_still_a_fold_free_sphere(welded_and_not):
    *_, m, _ = welded_and_not
    X, F = np.asarray(m.sphere), np.asarray(m.faces)
    assert pm.validate(X, F).is_closed_genus0
    det = np.einsum("ij,ij->i", X[F[:, 0]], np.cross(X[F[:, 1]], X[F[:, 2]]))
    assert (det > 0).all()


def test_carried_corner_values_follow_the_welded_corners(welded_and_not):
    """The corners' coordinates in their input faces are mended where a weld
    moved them: A's positions carried per corner land on the merged corners."""
    (VA, FA, _), _, _, m, _ = welded_and_not
    F, S = np.asarray(m.faces), np.asarray(m.source)
    carried = np.asarray(m.carry(0, VA[FA].reshape(-1, 3)))
    diagonal = np.linalg.norm(np.ptp(VA, axis=0))
    assert np.abs(carried - S[F].reshape(-1, 3)).max() <= 2e-6 * diagonal


def test_the_weld_tolerance_is_checked():
    A = Q.quadruped("cow", 3000, seed=0)
    with pytest.raises(pm.InvalidInputError):
        pm.morph(A[0], A[1], A[0], A[1], weld_tolerance=0.5)
