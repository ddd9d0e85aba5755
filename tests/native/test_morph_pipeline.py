"""The whole morph through the module (thesis ch. 4; issue 16): known-truth
correspondence on smooth deformations, shape keys reproducing both surfaces, a
valid merged mesh, the candidates and their scores, pins, carried corner
values, errors and cancel. Quadrupeds with landmarks: test_morph_correspondence.py."""
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
    automatic = pm.morph(VA, FA, VB, FB)
    placed = pm.morph(VA, FA, VB, FB, automatic=False)
    return VA, FA, VB, FB, automatic, placed


def correspondence_error(VA, VB, m, truth=deform):
    """Mean distance, as a share of B's bbox diagonal, between where each vertex
    of A lands on B and where the truth puts it."""
    landed = np.asarray(m.target)[np.asarray(m.vertex_of_a)]
    diagonal = np.linalg.norm(np.ptp(VB, axis=0))
    return np.linalg.norm(landed - truth(VA), axis=1).mean() / diagonal


def test_known_truth_correspondence_is_within_two_percent(truth):
    VA, FA, VB, FB, automatic, placed = truth
    error = correspondence_error(VA, VB, automatic)
    baseline = correspondence_error(VA, VB, placed)
    print(f"correspondence error: automatic {error:.4f}, as placed {baseline:.4f} of the diagonal")
    # A twist and a shear of a bumpy ball: the 3D registration's map is the
    # best candidate; the maps as placed slide the bumps by about 3%.
    assert error < 0.02 and error < baseline < 0.05
    assert automatic.candidates[automatic.chosen].kind == "registration"


def test_second_known_truth_pair_is_within_two_percent():
    # Other bumps, another deformation, other tessellations: nothing tuned to one case.
    VA, FA, VB, FB = second_known_truth_pair()
    m = pm.morph(VA, FA, VB, FB)
    error = correspondence_error(VA, VB, m, bend_and_scale)
    baseline = correspondence_error(VA, VB, pm.morph(VA, FA, VB, FB, automatic=False), bend_and_scale)
    print(f"second pair: automatic {error:.4f}, as placed {baseline:.4f} of the diagonal")
    assert error < 0.02 and error < baseline


def test_the_chosen_candidate_scores_best_and_no_pairs_competes(truth):
    *_, automatic, placed = truth
    scored = [c for c in automatic.candidates if np.isfinite(c.score)]
    kinds = {c.kind for c in automatic.candidates}
    assert {"none", "registration"} <= kinds
    assert automatic.candidates[automatic.chosen].score == min(c.score for c in scored)
    assert all(c.rejected == "" for c in scored)
    # Without automatic candidates only "none" (the models as placed) is weighed.
    assert [c.kind for c in placed.candidates] == ["none"] and len(placed.pairs) == 0


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
        # ... and the pieces tile the input: same area (no gap, no overlap; the
        # weld moves corners by at most 1e-6 of the diagonal, test_weld_merged).
        assert triangle_areas(positions, F).sum() == pytest.approx(triangle_areas(V, Fin).sum(), rel=1e-6)
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


def test_stage_timings_are_reported(truth):
    *_, m, _ = truth
    stages = [name for name, _ in m.timings]
    for stage in ("proxies and their maps", "candidates", "scores", "sphere maps of the models", "overlay", "weld",
                  "total"):
        assert stage in stages
    assert stages[-1] == "total"


def test_preview_is_what_the_morph_chooses(truth):
    VA, FA, VB, FB, m, _ = truth
    preview = pm.morph_correspondence(VA, FA, VB, FB)
    assert preview.chosen == m.chosen
    assert [(c.kind, c.detail) for c in preview.candidates] == [(c.kind, c.detail) for c in m.candidates]
    np.testing.assert_allclose([c.score for c in preview.candidates], [c.score for c in m.candidates])
    np.testing.assert_array_equal(preview.pairs, np.asarray(m.pairs)[~np.asarray(m.pair_is_pin)])


def test_given_pairs_replace_the_candidates_and_hold_exactly():
    VA, FA, VB, FB = known_truth_pair()
    # Two bump tips of A given with B's vertices nearest their true places.
    tips = [int(np.argmax(VA[:, 0])), int(np.argmax(VA[:, 2]))]
    partners = [int(np.argmin(np.linalg.norm(VB - deform(VA[t][None])[0], axis=1))) for t in tips]
    given = np.array(list(zip(tips, partners)))
    m = pm.morph(VA, FA, VB, FB, pairs=given)
    assert [c.kind for c in m.candidates] == ["given"]
    np.testing.assert_array_equal(np.asarray(m.pairs), given)
    S = np.asarray(m.sphere)
    np.testing.assert_array_equal(S[np.asarray(m.vertex_of_a)[tips]], S[np.asarray(m.vertex_of_b)[partners]])


def test_pins_hold_exactly_and_win_over_the_automatic_pairs():
    VA, FA, VB, FB = known_truth_pair()
    # Pin A's +x tip to a B vertex a little way off the truth.
    tip = int(np.argmax(VA[:, 0]))
    truth_point = deform(VA[tip][None])[0]
    d = np.linalg.norm(VB - truth_point, axis=1)
    diagonal = np.linalg.norm(np.ptp(VB, axis=0))
    off = int(np.argmin(np.abs(d - 0.08 * diagonal)))
    m = pm.morph(VA, FA, VB, FB, pins=np.array([[tip, off]]))
    assert np.asarray(m.pair_is_pin)[0] and tuple(np.asarray(m.pairs)[0]) == (tip, off)
    assert not any(a == tip or b == off for a, b in np.asarray(m.pairs)[1:])
    # One merged vertex for both: at t = 1, A's vertex is exactly B's.
    merged_a = np.asarray(m.vertex_of_a)[tip]
    assert merged_a == np.asarray(m.vertex_of_b)[off]
    np.testing.assert_array_equal(np.asarray(m.target)[merged_a], VB[off])


def test_corner_values_are_carried_through_the_barycentric_coordinates():
    VA, FA = meshes.noisy_blob(2)
    VB, FB = meshes.geodesic_sphere(6)
    m = pm.morph(VA, FA, VB, FB, automatic=False)
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
    with pytest.raises(pm.InvalidInputError, match="pin 0"):
        pm.morph(VA, FA, VA, FA, pins=np.array([[0, len(VA)]]))
    with pytest.raises(pm.ConstraintError, match="pins 0 and 1 both pin vertex 3 of A"):
        pm.morph(VA, FA, VA, FA, pins=np.array([[3, 5], [3, 9]]))
    with pytest.raises(pm.ConstraintError, match="pins 0 and 2 both pin vertex 7 of B"):
        pm.morph(VA, FA, VA, FA, pins=np.array([[1, 7], [2, 8], [4, 7]]))
    with pytest.raises(pm.Cancelled):
        pm.morph(VA, FA, VA, FA, progress=lambda fraction, stage: False)
