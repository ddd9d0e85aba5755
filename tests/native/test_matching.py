"""Feature matching between two meshes (thesis 4.5): region_graph and
match_features.

The meshes matched are the same surface triangulated differently, then
turned by a known rotation, scaled and moved (every region pair and every
point pair must correspond under that transform), a smoothly deformed copy
(pairs must correspond under the deformation), and meshes with nothing in
common (a valid result, nothing more). Features: meshes.two_boss_part (a CAD
part, creases) and meshes.bumps_and_pits (a smooth blob, concavity); both
have no symmetry, so the right rotation is the only good one.
"""
import numpy as np
import pytest

import meshes
import paramorph_native as pm


def rotation(seed):
    q, _ = np.linalg.qr(np.random.default_rng(seed).normal(size=(3, 3)))
    return q * np.sign(np.linalg.det(q))


def diagonal(V):
    return float(np.linalg.norm(V.max(axis=0) - V.min(axis=0)))


def region_centroids(V, F, labels, regions):
    """Area-weighted centroids of each region's faces on positions V."""
    area = 0.5 * np.linalg.norm(np.cross(V[F[:, 1]] - V[F[:, 0]], V[F[:, 2]] - V[F[:, 0]]), axis=1)
    centre = V[F].mean(axis=1)
    return np.stack([(area[labels == r, None] * centre[labels == r]).sum(0) / area[labels == r].sum()
                     for r in range(regions)])


def check_valid(m, A, B):
    """Shapes, dtypes, one-to-one pairs, rotation a proper rotation."""
    (VA, FA), (VB, FB) = A, B
    assert m.labels_a.shape == (len(FA),) and m.labels_a.dtype == np.int32
    assert m.labels_b.shape == (len(FB),) and m.labels_b.dtype == np.int32
    ra, rb = len(m.centroids_a), len(m.centroids_b)
    assert m.centroids_a.shape == (ra, 3) and m.centroids_b.shape == (rb, 3)
    assert m.labels_a.max() == ra - 1 and m.labels_b.max() == rb - 1
    for pairs, n_a, n_b in ((m.region_pairs, ra, rb), (m.point_pairs, len(VA), len(VB))):
        assert pairs.ndim == 2 and pairs.shape[1] == 2 and pairs.dtype == np.int32
        if len(pairs):
            assert pairs[:, 0].min() >= 0 and pairs[:, 0].max() < n_a
            assert pairs[:, 1].min() >= 0 and pairs[:, 1].max() < n_b
        assert len(np.unique(pairs[:, 0])) == len(pairs) and len(np.unique(pairs[:, 1])) == len(pairs)
    assert m.region_scores.shape == (len(m.region_pairs),) and np.all(m.region_scores >= 0)
    assert m.point_scores.shape == (len(m.point_pairs),) and np.all(m.point_scores >= 0)
    assert set(m.point_pairs[:, 0]) <= set(m.points_a) and set(m.point_pairs[:, 1]) <= set(m.points_b)
    R = m.rotation
    assert R.shape == (3, 3)
    np.testing.assert_allclose(R @ R.T, np.eye(3), atol=1e-12)
    assert abs(np.linalg.det(R) - 1.0) < 1e-12
    for edges, regions in ((m.graph_edges_a, ra), (m.graph_edges_b, rb)):
        assert edges.shape[1] == 2 and np.all(edges[:, 0] < edges[:, 1]) and np.all(edges < regions)


SAME_SURFACE = {  # A, and the same surface triangulated differently
    "two_boss_part": (lambda: meshes.two_boss_part(8),
                      lambda: meshes.two_boss_part(12, alternate_diagonals=True)),
    "bumps_and_pits": (lambda: meshes.bumps_and_pits(meshes.icosphere(4)),
                       lambda: meshes.bumps_and_pits(meshes.geodesic_sphere(19))),
}


@pytest.mark.parametrize("seed", [1, 2])
@pytest.mark.parametrize("name", sorted(SAME_SURFACE))
def test_a_retriangulated_turned_scaled_moved_copy_matches_under_the_known_transform(name, seed):
    make_a, make_b = SAME_SURFACE[name]
    A, (V0, FB) = make_a(), make_b()
    Q, scale, shift = rotation(seed), 2.5, np.array([3.0, -1.0, 2.0])
    VB = scale * V0 @ Q.T + shift
    m = pm.match_features(*A, VB, FB)
    check_valid(m, A, (VB, FB))
    d = diagonal(A[0])
    # The rotation undoes Q (B was turned by Q about its centre).
    assert np.abs(m.rotation @ Q - np.eye(3)).max() < 0.02, m.rotation @ Q
    # Every region pair: the centroids coincide once B is moved back.
    assert len(m.region_pairs) >= 0.8 * min(len(m.centroids_a), len(m.centroids_b)) and len(m.region_pairs) >= 4
    back = (m.centroids_b - shift) @ Q / scale
    gap = np.linalg.norm(m.centroids_a[m.region_pairs[:, 0]] - back[m.region_pairs[:, 1]], axis=1) / d
    assert gap.max() < 0.01, gap
    # transform_b places B's centroids on A's paired ones.
    placed = m.transform_b(m.centroids_b)
    gap = np.linalg.norm(m.centroids_a[m.region_pairs[:, 0]] - placed[m.region_pairs[:, 1]], axis=1) / d
    assert gap.max() < 0.02, gap
    # Every point pair: the two vertices are at the same place on the surface
    # (within 5% of the diagonal: feature points are vertices, and the two
    # triangulations have different vertices), and most points are paired.
    A_points, B_points = A[0][m.point_pairs[:, 0]], V0[m.point_pairs[:, 1]]
    apart = np.linalg.norm(A_points - B_points, axis=1) / d
    assert np.all(apart < 0.05), apart
    assert len(m.point_pairs) >= 0.75 * min(len(m.points_a), len(m.points_b)), \
        (len(m.point_pairs), len(m.points_a), len(m.points_b))
    # Scores say the same: within the cut-off, close to the true distances.
    assert np.all(m.point_scores <= 0.05)
    np.testing.assert_allclose(m.point_scores, apart, atol=0.01)


def smooth_deformation(V, amount):
    x, y, z = V.T
    return np.stack([x + amount * np.sin(1.3 * y), y * (1 + 0.2 * amount * z), z + amount * np.cos(x)], 1)


@pytest.mark.parametrize("name", sorted(SAME_SURFACE))
def test_a_smoothly_deformed_copy_matches_its_corresponding_features(name):
    make_a, make_b = SAME_SURFACE[name]
    A, (V0, FB) = make_a(), make_b()
    Q = rotation(3)
    VB = smooth_deformation(V0, 0.15) @ Q.T
    m = pm.match_features(*A, VB, FB)
    check_valid(m, A, (VB, FB))
    d = diagonal(A[0])
    assert len(m.region_pairs) >= 4
    # Regions correspond where B's region lies before the deformation.
    before = region_centroids(V0, FB, m.labels_b, len(m.centroids_b))
    gap = np.linalg.norm(m.centroids_a[m.region_pairs[:, 0]] - before[m.region_pairs[:, 1]], axis=1) / d
    assert gap.max() < 0.03, gap
    # Points: at least 80% of the pairs within 5% of the diagonal (the
    # deformation moves the concavity's extrema a little along the surface).
    apart = np.linalg.norm(A[0][m.point_pairs[:, 0]] - V0[m.point_pairs[:, 1]], axis=1) / d
    assert len(apart) >= 5 and np.mean(apart < 0.05) >= 0.8, apart


@pytest.mark.parametrize("other", ["icosphere", "torus", "noisy_blob"])
def test_meshes_with_nothing_in_common_give_a_valid_result(other):
    A = meshes.two_boss_part(8)
    B = {"icosphere": lambda: meshes.icosphere(3), "torus": meshes.torus,
         "noisy_blob": lambda: meshes.noisy_blob(3, seed=5)}[other]()
    for first, second in ((A, B), (B, A)):
        m = pm.match_features(*first, *second)
        check_valid(m, first, second)
        assert np.all(m.region_scores < 0.5)  # max_region_score


def test_results_are_deterministic():
    A = meshes.bumps_and_pits()
    V, F = meshes.bumps_and_pits(meshes.geodesic_sphere(17))
    B = (V @ rotation(4).T, F)
    one, two = pm.match_features(*A, *B), pm.match_features(*A, *B)
    for name in ("region_pairs", "region_scores", "point_pairs", "point_scores", "rotation",
                 "labels_a", "labels_b", "graph_edges_a", "graph_edges_b"):
        np.testing.assert_array_equal(getattr(one, name), getattr(two, name), err_msg=name)


def test_options_reach_the_matching():
    A = meshes.bumps_and_pits()
    V, F = meshes.bumps_and_pits(meshes.geodesic_sphere(19))
    B = (V @ rotation(1).T, F)
    default = pm.match_features(*A, *B)
    assert len(default.region_pairs) >= 4 and len(default.point_pairs) >= 10
    # A tiny point cut-off: fewer pairs, all within it.
    tight = pm.match_features(*A, *B, max_point_distance=0.01)
    assert 0 < len(tight.point_pairs) < len(default.point_pairs)
    assert np.all(tight.point_scores <= 0.01)
    # A cap on the region score below every pair's score: no pairs at all.
    capped = pm.match_features(*A, *B, max_region_score=0.5 * default.region_scores.min())
    assert len(capped.region_pairs) == 0 and len(capped.point_pairs) == 0
    # Segmentation options are those of feature_regions.
    part = meshes.two_boss_part(8)
    fine, coarse = pm.match_features(*part, *part), pm.match_features(*part, *part, normal_angle=179.0)
    assert len(coarse.centroids_a) < len(fine.centroids_a)


def test_errors_are_typed_and_name_the_mesh():
    good = meshes.two_boss_part(4)
    broken = {pm.NonManifoldError: meshes.non_manifold_edge(), pm.InvalidInputError: meshes.nan_vertex(),
              pm.DegenerateFaceError: meshes.zero_area_face()}
    for error, bad in broken.items():
        with pytest.raises(error, match="mesh A"):
            pm.match_features(*bad, *good)
        with pytest.raises(error, match="mesh B"):
            pm.match_features(*good, *bad)
    V, F = meshes.box(2)
    with pytest.raises(pm.InvalidInputError, match="mesh B.*plane"):
        pm.match_features(*good, V * [1, 1, 0], F)
    with pytest.raises(pm.InvalidInputError):
        pm.match_features(good[0][:, :2], good[1], *good)
    for option in ({"alignment_nodes": 0}, {"max_region_score": 0.0}, {"outlier_factor": 0.5},
                   {"max_point_distance": -1.0}, {"long_edge_factor": 0.0}, {"normal_angle": 0.0}):
        with pytest.raises(pm.InvalidInputError):
            pm.match_features(*good, *good, **option)


def test_progress_is_reported_and_cancels():
    A, B = meshes.two_boss_part(4), meshes.bumps_and_pits(meshes.icosphere(2))
    seen = []
    pm.match_features(*A, *B, progress=lambda f, stage: seen.append((f, stage)))
    fractions = [f for f, _ in seen]
    assert fractions[0] == 0.0 and fractions[-1] == 1.0 and fractions == sorted(fractions)
    with pytest.raises(pm.Cancelled):
        pm.match_features(*A, *B, progress=lambda f, stage: False)
    with pytest.raises(pm.Cancelled):  # the first report goes through, a later one cancels
        pm.match_features(*A, *B, progress=lambda f, stage: f == 0.0)

    def boom(f, stage):
        raise KeyError("from the callback")
    with pytest.raises(KeyError, match="from the callback"):
        pm.match_features(*A, *B, progress=boom)


# --- region graph ---------------------------------------------------------------

def test_region_graph_of_a_box_has_exact_lengths_and_drops_the_long_edges():
    """Box with half extents (1, 2, 4): the distance between the centres of
    two adjacent sides is the sum of their half extents across the shared
    edge (x-y: 3, x-z: 5, y-z: 6), exact along the grid lines."""
    V, F = meshes.box(8, (1.0, 2.0, 4.0))
    s = pm.feature_regions(V, F)
    assert s.regions == 6
    axis = np.argmax(np.abs(s.centroid), axis=1)   # the axis each side faces
    expected = {frozenset((0, 1)): 3.0, frozenset((0, 2)): 5.0, frozenset((1, 2)): 6.0}
    g = pm.region_graph(V, F, s)
    assert len(g.edges) == 12 and len(g.dropped) == 0 and np.all(g.degree == 4)
    for (a, b), length in zip(g.edges, g.lengths):
        assert length == pytest.approx(expected[frozenset((axis[a], axis[b]))], abs=1e-12)
    # Median 5: with factor 1.1 the four y-z edges (6 > 5.5) go; they are the
    # shortest edge of neither side, so the x sides keep 4 and the others 2.
    g = pm.region_graph(V, F, s, long_edge_factor=1.1)
    assert len(g.dropped) == 4 and g.dropped_lengths == pytest.approx([6.0] * 4)
    assert all({axis[a], axis[b]} == {1, 2} for a, b in g.dropped)
    np.testing.assert_array_equal(g.degree, np.where(axis == 0, 4, 2))
    # A tiny factor drops all but each side's shortest edges: none is isolated.
    g = pm.region_graph(V, F, s, long_edge_factor=1e-3)
    assert np.all(g.degree >= 1)
    assert V[g.anchors] == pytest.approx(s.centroid)  # anchors: the centres of the sides
    with pytest.raises(pm.InvalidInputError):
        pm.region_graph(V, F, s, long_edge_factor=0.0)
    with pytest.raises(pm.InvalidInputError):
        pm.region_graph(V, F[:-1], s)
