"""The whole morph through the module (thesis ch. 4): known-truth
correspondence, shape keys reproducing both surfaces, a valid merged mesh,
pins, carried corner values, errors and cancel."""
import numpy as np
import pytest

import meshes
import paramorph_native as pm

BUMPS = np.array([[1, 0, 0], [-1, 0, 0], [0, 1, 0], [0, -1, 0], [0, 0, 1], [0, 0, -1],
                  [0.6, 0.6, 0.5], [-0.5, 0.6, -0.6]], dtype=np.float64)
HEIGHTS = np.array([0.35, -0.2, 0.3, 0.25, -0.25, 0.4, -0.2, 0.3])


def bumpy(P):
    """A star-shaped surface over unit directions P: bumps (tips) and dents (pockets)."""
    B = BUMPS / np.linalg.norm(BUMPS, axis=1, keepdims=True)
    r = 1.0 + (HEIGHTS * np.exp(-(1.0 - P @ B.T) / 0.04)).sum(axis=1)
    return P * r[:, None]


def deform(X):
    """A smooth, non-radial deformation: a twist about z and a sideways shear."""
    angle = 0.35 * X[:, 2]
    c, s = np.cos(angle), np.sin(angle)
    Y = np.stack([c * X[:, 0] - s * X[:, 1], s * X[:, 0] + c * X[:, 1], X[:, 2]], axis=1)
    Y[:, 0] += 0.12 * X[:, 2] ** 2
    return Y * [1.1, 0.95, 1.0]


def known_truth_pair():
    """A: the bumpy surface on an icosphere; B: the same surface on a geodesic
    sphere of another frequency (different topology), deformed."""
    PA, FA = meshes.icosphere(4)
    PB, FB = meshes.geodesic_sphere(13)
    return bumpy(PA), FA, deform(bumpy(PB)), FB


SECOND_BUMPS = np.array([[0.8, 0.3, 0.5], [-0.7, -0.6, 0.2], [0.1, -0.9, -0.4], [-0.3, 0.8, 0.6],
                         [0.5, -0.2, -0.9], [-0.9, 0.2, -0.3], [0.2, 0.4, -0.8], [0.6, 0.7, -0.1],
                         [-0.2, -0.3, 1.0]], dtype=np.float64)
SECOND_HEIGHTS = np.array([0.3, 0.35, -0.25, 0.25, 0.4, -0.2, 0.3, -0.2, 0.3])


def second_bumpy(P):
    """Another star-shaped surface: other bump and dent directions, narrower."""
    B = SECOND_BUMPS / np.linalg.norm(SECOND_BUMPS, axis=1, keepdims=True)
    r = 1.0 + (SECOND_HEIGHTS * np.exp(-(1.0 - P @ B.T) / 0.035)).sum(axis=1)
    return P * r[:, None]


def bend_and_scale(X):
    """Another smooth deformation: a bend about the y axis (curvature 0.3)
    and an anisotropic scale."""
    k = 0.3
    radius = 1.0 / k - X[:, 2]
    Y = np.stack([radius * np.sin(k * X[:, 0]), X[:, 1], 1.0 / k - radius * np.cos(k * X[:, 0])], axis=1)
    return Y * [0.9, 1.2, 1.05]


def second_known_truth_pair():
    """A: the second surface on a geodesic sphere; B: the same on an icosphere
    turned about z (other tessellations than the first pair), bent and scaled."""
    PA, FA = meshes.geodesic_sphere(14)
    PB, FB = meshes.icosphere(4)
    c, s = np.cos(0.4), np.sin(0.4)
    PB = PB @ np.array([[c, -s, 0], [s, c, 0], [0, 0, 1]]).T
    return second_bumpy(PA), FA, bend_and_scale(second_bumpy(PB)), FB


def closed_manifold(F):
    edges = np.sort(np.concatenate([F[:, [0, 1]], F[:, [1, 2]], F[:, [2, 0]]]), axis=1)
    _, counts = np.unique(edges, axis=0, return_counts=True)
    directed = np.concatenate([F[:, [0, 1]], F[:, [1, 2]], F[:, [2, 0]]])
    return np.all(counts == 2) and len(np.unique(directed, axis=0)) == len(directed)


def triangle_areas(V, F):
    return 0.5 * np.linalg.norm(np.cross(V[F[:, 1]] - V[F[:, 0]], V[F[:, 2]] - V[F[:, 0]]), axis=1)


@pytest.fixture(scope="module")
def truth():
    VA, FA, VB, FB = known_truth_pair()
    with_features = pm.morph(VA, FA, VB, FB)
    without = pm.morph(VA, FA, VB, FB, features=False)
    return VA, FA, VB, FB, with_features, without


def correspondence_error(VA, VB, m, truth=deform):
    """Mean distance, as a share of B's bbox diagonal, between where each vertex
    of A lands on B and where the truth puts it."""
    landed = np.asarray(m.target)[np.asarray(m.vertex_of_a)]
    diagonal = np.linalg.norm(np.ptp(VB, axis=0))
    return np.linalg.norm(landed - truth(VA), axis=1).mean() / diagonal


def test_known_truth_correspondence_is_close_and_pairs_land_together(truth):
    VA, FA, VB, FB, with_features, without = truth
    error = correspondence_error(VA, VB, with_features)
    baseline = correspondence_error(VA, VB, without)
    print(f"correspondence error: features {error:.4f}, without {baseline:.4f} of the diagonal")
    assert len(with_features.pairs) >= 4
    assert error < 0.05 and baseline < 0.05
    # The aligned map brings every pair together (4.12).
    assert with_features.mean_pair_error < 1e-3


def test_known_truth_correspondence_is_within_two_percent_with_features(truth):
    VA, FA, VB, FB, with_features, without = truth
    error = correspondence_error(VA, VB, with_features)
    assert error < 0.02 and error < correspondence_error(VA, VB, without)


def test_second_known_truth_pair_is_within_two_percent_with_features():
    # Other bumps, another deformation, other tessellations: nothing tuned to one case.
    VA, FA, VB, FB = second_known_truth_pair()
    with_features = pm.morph(VA, FA, VB, FB)
    without = pm.morph(VA, FA, VB, FB, features=False)
    error = correspondence_error(VA, VB, with_features, bend_and_scale)
    baseline = correspondence_error(VA, VB, without, bend_and_scale)
    print(f"second pair: features {error:.4f}, without {baseline:.4f} of the diagonal")
    assert error < 0.02 and error < baseline
    assert len(with_features.pairs) >= 4 and with_features.mean_pair_error < 1e-3


def test_shape_keys_reproduce_both_surfaces_and_the_merged_mesh_is_valid(truth):
    VA, FA, VB, FB, m, _ = truth
    F = np.asarray(m.faces)
    for V, Fin, positions, side in ((VA, FA, np.asarray(m.source), 0), (VB, FB, np.asarray(m.target), 1)):
        diagonal = np.linalg.norm(np.ptp(V, axis=0))
        source_face = np.asarray(m.source_face_a if side == 0 else m.source_face_b)
        # Every merged corner lies in the plane of its input face ...
        a, b, c = (V[Fin[source_face, k]] for k in range(3))
        normal = np.cross(b - a, c - a)
        normal /= np.linalg.norm(normal, axis=1, keepdims=True)
        for k in range(3):
            off = np.abs(np.einsum("ij,ij->i", positions[F[:, k]] - a, normal))
            assert off.max() < 1e-6 * diagonal
        # ... and the pieces tile the input: same area (no gap, no overlap).
        assert triangle_areas(positions, F).sum() == pytest.approx(triangle_areas(V, Fin).sum(), rel=1e-9)
        # Input vertices are merged vertices, at their own place.
        of = np.asarray(m.vertex_of_a if side == 0 else m.vertex_of_b)
        np.testing.assert_allclose(positions[of], V, atol=1e-9 * diagonal)
    assert closed_manifold(F)
    assert len(m.sphere) - len(np.unique(np.sort(np.concatenate([F[:, [0, 1]], F[:, [1, 2]], F[:, [2, 0]]]), axis=1), axis=0)) + len(F) == 2
    S = np.asarray(m.sphere)
    a, b, c = S[F[:, 0]], S[F[:, 1]], S[F[:, 2]]
    # Edge differences: exact enough for the overlay's tiny (but positive) triangles.
    assert np.all(np.einsum("ij,ij->i", np.cross(b - a, c - a), a + b + c) > 0)
    report = pm.validate(np.asarray(m.source), F)
    assert report.boundary_loops == 0 and report.components == 1 and report.genus == 0


def test_merged_mesh_has_no_degenerate_faces(truth):
    # Degenerate by validate()'s relative area test, on both shape keys, and
    # no sliver on the sphere (the overlay's guarantee: altitude >= half the
    # tolerance used). Paired feature points land ~1e-8 apart on the two maps:
    # at a 1e-9 tolerance that left 148 tiny triangles here.
    *_, m, without = truth
    for morph in (m, without):
        F = np.asarray(morph.faces)
        for positions in (morph.source, morph.target):
            assert pm.validate(np.asarray(positions), F).degenerate_faces.size == 0
        assert pm.validate(np.asarray(morph.sphere), F).degenerate_faces.size == 0
        stats = morph.merged.stats
        assert stats.thin_triangles == 0 and stats.min_altitude >= 0.5 * stats.merge_tolerance


def test_stage_timings_and_pairs_are_reported(truth):
    *_, m, without = truth
    stages = [name for name, _ in m.timings]
    for stage in ("sphere map A", "sphere map B", "optimize A", "match features", "align B", "overlay"):
        assert stage in stages
    assert "match features" not in [name for name, _ in without.timings]
    assert np.asarray(m.pairs).shape[1] == 2 and not np.asarray(m.pair_is_pin).any()


def test_preview_pairs_are_the_pairs_the_morph_uses(truth):
    VA, FA, VB, FB, m, _ = truth
    preview = pm.morph_pairs(VA, FA, VB, FB)
    assert preview.fold_share < 0.01 and m.registration_fold_share == pytest.approx(preview.fold_share)
    np.testing.assert_array_equal(preview.pairs, m.pairs)
    assert preview.registration_cost == pytest.approx(m.registration_cost)
    # Given back as `pairs` (as Morph To does with previewed pairs), the morph
    # keeps the registration's targets: the same correspondence.
    again = pm.morph(VA, FA, VB, FB, pairs=preview.pairs)
    np.testing.assert_array_equal(again.pairs, m.pairs)
    assert correspondence_error(VA, VB, again) == pytest.approx(correspondence_error(VA, VB, m), abs=1e-6)
    unregistered = pm.morph_pairs(VA, FA, VB, FB, register_surfaces=False)
    assert unregistered.registration_cost is None
    np.testing.assert_array_equal(unregistered.pairs, unregistered.match.point_pairs)


def test_registration_is_left_out_for_unlike_shapes():
    # A bumpy ball into a ball with long tentacles: a 3D fit squeezes the
    # tentacles onto the ball (small closest-point cost, carried map folds),
    # so the morph falls back to B's radial projection and the match's pairs.
    PA, FA = meshes.icosphere(3)
    VA = bumpy(PA)
    VB, FB = meshes.tentacle_sphere(3)
    unlike = pm.morph_pairs(VA, FA, VB, FB)
    assert unlike.fold_share > 0.01 and unlike.registration_cost is None
    np.testing.assert_array_equal(unlike.pairs, unlike.match.point_pairs)
    forced = pm.morph_pairs(VA, FA, VB, FB, max_fold_share=1.0)
    assert forced.registration_cost is not None and forced.fold_share == pytest.approx(unlike.fold_share)
    m = pm.morph(VA, FA, VB, FB)
    assert m.registration_cost is None and m.registration_fold_share == pytest.approx(unlike.fold_share)
    assert pm.validate(np.asarray(m.target), np.asarray(m.faces)).boundary_loops == 0


def test_pins_win_over_the_automatic_pairs():
    VA, FA, VB, FB = known_truth_pair()
    # Pin A's +x tip to a B vertex a little way off the truth.
    tip = int(np.argmax(VA[:, 0]))
    truth = deform(VA[tip][None])[0]
    d = np.linalg.norm(VB - truth, axis=1)
    diagonal = np.linalg.norm(np.ptp(VB, axis=0))
    off = int(np.argmin(np.abs(d - 0.08 * diagonal)))
    m = pm.morph(VA, FA, VB, FB, pins=np.array([[tip, off]]))
    assert np.asarray(m.pair_is_pin)[0] and tuple(np.asarray(m.pairs)[0]) == (tip, off)
    assert not any(a == tip or b == off for a, b in np.asarray(m.pairs)[1:])
    landed = np.asarray(m.target)[np.asarray(m.vertex_of_a)[tip]]
    assert np.linalg.norm(landed - VB[off]) < 0.01 * diagonal


def test_corner_values_are_carried_through_the_barycentric_coordinates():
    VA, FA = meshes.noisy_blob(2)
    VB, FB = meshes.geodesic_sphere(6)
    m = pm.morph(VA, FA, VB, FB, features=False)
    # A linear function of position, given per corner, is reproduced exactly.
    corner_positions = VA[FA.reshape(-1)]
    carried = np.asarray(m.carry(0, corner_positions))
    F = np.asarray(m.faces)
    np.testing.assert_allclose(carried, np.asarray(m.source)[F.reshape(-1)], atol=1e-9)
    with pytest.raises(pm.InvalidInputError):
        m.carry(0, corner_positions[:5])


def test_errors_name_the_mesh_and_cancel_stops():
    VA, FA = meshes.noisy_blob(2)
    Vt, Ft = meshes.torus()
    with pytest.raises(pm.NotGenusZeroError, match="mesh B"):
        pm.morph(VA, FA, Vt, Ft)
    Vd, Fd = meshes.open_disc()
    with pytest.raises(pm.NotClosedError, match="mesh A"):
        pm.morph(Vd, Fd, VA, FA)
    with pytest.raises(pm.InvalidInputError, match="pin"):
        pm.morph(VA, FA, VA, FA, pins=np.array([[0, len(VA)]]))
    with pytest.raises(pm.Cancelled):
        pm.morph(VA, FA, VA, FA, progress=lambda fraction, stage: False)
