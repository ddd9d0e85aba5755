"""The sphere-map tools the morph is built from, through their Python API
(param/spherical/balanced_sphere_map, untangle_sphere_map; morph/
flow_sphere_map, map_distortion): the properties each promises, and typed
errors for arrays that do not fit together."""
import numpy as np
import pytest

import meshes
import paramorph_native as pm


def folded_faces(X, F):
    return int((np.einsum("ij,ij->i", X[F[:, 0]], np.cross(X[F[:, 1]], X[F[:, 2]])) <= 0).sum())


@pytest.fixture(scope="module")
def limb():
    V, F = meshes.limb_blob(3, limbs=2, length=2.0)
    return V, F, np.asarray(pm.balanced_sphere_map(V, F).positions)


def test_the_balanced_map_is_fold_free_and_gives_limbs_their_share(limb):
    V, F, X = limb
    np.testing.assert_allclose(np.linalg.norm(X, axis=1), 1, atol=1e-12)
    assert folded_faces(X, F) == 0
    # Each face's share of the sphere against its share of the surface: the
    # conformal map squeezes limbs by orders of magnitude, this map does not.
    area3 = 0.5 * np.linalg.norm(np.cross(V[F[:, 1]] - V[F[:, 0]], V[F[:, 2]] - V[F[:, 0]]), axis=1)
    area_s = 0.5 * np.linalg.norm(np.cross(X[F[:, 1]] - X[F[:, 0]], X[F[:, 2]] - X[F[:, 0]]), axis=1)
    ratio = (area_s / area_s.sum()) / (area3 / area3.sum())
    assert np.quantile(ratio, 0.01) > 0.05


def test_a_map_against_itself_has_no_distortion_and_carries_vertices_home(limb):
    V, F, X = limb
    d = pm.map_distortion(V, F, X, V, F, X)
    # Not exactly 0: faces are compared on the plane of the image's smooth
    # normal, which a coarse mesh's faces lean against a little.
    assert d.mean < 0.01 and d.folded_share == 0
    quarter_turn = np.array([[0.0, -1, 0], [1, 0, 0], [0, 0, 1]])
    assert pm.map_distortion(V, F, X, V, F, X @ quarter_turn.T).mean > 10 * d.mean
    np.testing.assert_allclose(pm.carry_through_maps(V, F, X, X), V, atol=1e-9)
    with pytest.raises(pm.InvalidInputError, match="one sphere point per vertex"):
        pm.carry_through_maps(V, F, X[:-1], X)


def test_the_flow_lands_pinned_vertices_exactly_without_folds(limb):
    V, F, X = limb
    pinned = np.array([0, len(V) // 2])
    to = X[pinned] @ np.array([[np.cos(0.3), -np.sin(0.3), 0], [np.sin(0.3), np.cos(0.3), 0], [0, 0, 1]]).T
    r = pm.flow_sphere_map(F, X, X[pinned], to, pinned)
    assert r.reached == 1
    Y = np.asarray(r.positions)
    np.testing.assert_array_equal(Y[pinned], to)
    assert folded_faces(Y, F) == 0
    with pytest.raises(pm.InvalidInputError, match="outside X"):
        pm.flow_sphere_map(F, X[:-5], X[pinned], to, pinned)


def test_untangling_repairs_a_dent_and_refuses_arrays_that_do_not_fit(limb):
    V, F, X = limb
    dented = X.copy()
    # A vertex pushed past its neighbour, as a map read off a coarser one
    # can leave it: its fan folds.
    v, w = F[0, 0], F[0, 1]
    dented[v] = X[v] + 2.5 * (X[w] - X[v])
    dented[v] /= np.linalg.norm(dented[v])
    assert folded_faces(dented, F) > 0
    repaired, before, after, patches, rings = pm.untangle_sphere_map(V, F, dented, [])
    assert before > 0 and after == 0 and folded_faces(np.asarray(repaired), F) == 0
    with pytest.raises(pm.InvalidInputError, match="one row per vertex"):
        pm.untangle_sphere_map(V, F, X[:-1], [])
    with pytest.raises(pm.InvalidInputError, match="out of range"):
        pm.untangle_sphere_map(V, F, X, [len(V)])
