"""Segmentations through the module: segment_extremities (3.5.1),
feature_regions and feature_points (4.5), area_stretch (Def. 3.1)."""
import numpy as np
import pytest

import meshes
import paramorph_native as pm


def regions_at(labels, F, vertices):
    """The region of a face around each vertex."""
    first_face = {}
    for f, tri in enumerate(F):
        for v in tri:
            first_face.setdefault(int(v), f)
    return [int(labels[first_face[int(v)]]) for v in vertices]


def check_consistent(V, F, s):
    labels = s.face_labels
    assert labels.shape == (len(F),) and labels.dtype == np.int32
    assert labels.min() == 0 and labels.max() == s.regions - 1
    assert len(np.unique(labels)) == s.regions
    area = 0.5 * np.linalg.norm(np.cross(V[F[:, 1]] - V[F[:, 0]], V[F[:, 2]] - V[F[:, 0]]), axis=1)
    np.testing.assert_allclose(s.area, np.bincount(labels, weights=area), rtol=1e-9)
    assert s.centroid.shape == (s.regions, 3) and len(s.seeds) == s.regions
    assert s.adjacency.shape[1] == 2 and np.all(s.adjacency[:, 0] < s.adjacency[:, 1])


@pytest.mark.parametrize("tentacles", [3, 6])
def test_each_tentacle_is_an_extremity_and_the_body_another(tentacles):
    V, F = meshes.tentacle_sphere(subdivisions=3, tentacles=tentacles, length=2.5)
    s = pm.segment_extremities(V, F)
    check_consistent(V, F, s)
    axes = meshes.tentacle_directions(tentacles)
    tips = [int(np.argmax(V @ a)) for a in axes]
    body = int(np.argmin(np.abs(np.linalg.norm(V, axis=1) - 1.0) + 10 * np.abs(V @ axes.T).max(axis=1)))
    found = regions_at(s.face_labels, F, tips + [body])
    assert len(set(found)) == tentacles + 1, (found, s.regions)
    assert s.regions == tentacles + 1


def test_a_given_sphere_gives_the_same_segmentation_and_area_stretch_matches():
    V, F = meshes.tentacle_sphere(subdivisions=3, tentacles=4, length=2.0)
    sphere = pm.sphere_map(V, F)
    np.testing.assert_allclose(pm.area_stretch(V, F, sphere.positions), sphere.area_stretch, rtol=1e-9)
    a = pm.segment_extremities(V, F, sphere=sphere.positions)
    b = pm.segment_extremities(V.astype(np.float32), F.astype(np.int64))
    assert a.regions == b.regions


def test_extremity_errors_and_cancel():
    V, F = meshes.open_disc()
    with pytest.raises(pm.NotClosedError):
        pm.segment_extremities(V, F)
    V, F = meshes.torus()
    with pytest.raises(pm.NotGenusZeroError):
        pm.segment_extremities(V, F)
    V, F = meshes.icosphere(2)
    with pytest.raises(pm.InvalidInputError, match="threshold"):
        pm.segment_extremities(V, F, threshold=0.0)
    with pytest.raises(pm.InvalidInputError, match="sphere"):
        pm.segment_extremities(V, F, sphere=np.zeros((3, 3)))
    with pytest.raises(pm.Cancelled):
        pm.segment_extremities(V, F, progress=lambda fraction, stage: False)


def test_the_six_sides_of_a_box_are_six_feature_regions():
    V, F = meshes.box(cells=6)
    s = pm.feature_regions(V, F)
    check_consistent(V, F, s)
    assert s.regions == 6
    normals = np.cross(V[F[:, 1]] - V[F[:, 0]], V[F[:, 2]] - V[F[:, 0]])
    side = np.argmax(np.abs(normals), axis=1) * 2 + (normals[np.arange(len(F)), np.argmax(np.abs(normals), axis=1)] > 0)
    for r in range(6):  # each region is exactly one side
        assert len(np.unique(side[s.face_labels == r])) == 1


def test_cad_box_boss_is_split_from_the_top_and_its_foot_is_a_pocket():
    V, F = meshes.cad_box()
    s = pm.feature_regions(V, F)
    check_consistent(V, F, s)
    # Box: 6 sides (top cut around the boss), boss: top + 4 walls.
    assert s.regions >= 11, s.regions
    top = int(np.argmax(V[:, 2]))
    corner = int(np.argmin(V.sum(axis=1)))
    assert len(set(regions_at(s.face_labels, F, [top, corner]))) == 2


def test_feature_points_mark_the_dent_bottom_and_the_corners():
    V, F = meshes.box(cells=8)
    centre = int(np.argmin(np.linalg.norm(V - [0, 0, 1], axis=1)))
    V = V.copy()
    V[centre, 2] -= 0.3  # one vertex pushed in: a pocket 0.3 deep
    concavity = pm.concavity(V, F)
    s = pm.feature_regions(V, F, concavity=concavity, concavity_threshold=0.05)
    points = pm.feature_points(V, F, s.face_labels, concavity)
    concave = [v for v, k in zip(points.vertices, points.kinds) if k > 0]
    convex = [v for v, k in zip(points.vertices, points.kinds) if k < 0]
    assert concave == [centre]
    corners = np.flatnonzero(np.all(np.isclose(np.abs(V), 1.0), axis=1))
    assert set(corners) <= set(convex)
    with pytest.raises(pm.InvalidInputError):
        pm.feature_points(V, F, s.face_labels[:-1], concavity)
    with pytest.raises(pm.InvalidInputError):
        pm.feature_regions(V, F, concavity=concavity[:-1])
    with pytest.raises(pm.InvalidInputError, match="normal_angle"):
        pm.feature_regions(V, F, normal_angle=0.0)


def test_feature_regions_errors():
    V, F = meshes.non_manifold_edge()
    with pytest.raises(pm.NonManifoldError):
        pm.feature_regions(V, F)
    V, F = meshes.nan_vertex()
    with pytest.raises(pm.InvalidInputError):
        pm.feature_regions(V, F)
    V, F = meshes.box(cells=3)
    with pytest.raises(pm.Cancelled):
        pm.feature_regions(V, F, progress=lambda fraction, stage: False)


def test_each_flat_side_of_a_cad_part_is_one_region():
    # The concavity below the hull varies across the box's top (deep at the
    # boss's foot): the sweep cuts it, the coplanar pieces are joined again.
    V, F = meshes.cad_box()
    s = pm.feature_regions(V, F)
    normals = np.cross(V[F[:, 1]] - V[F[:, 0]], V[F[:, 2]] - V[F[:, 0]])
    normals /= np.linalg.norm(normals, axis=1, keepdims=True)
    centre = V[F].mean(axis=1)
    planes = np.round(np.hstack([normals, np.sum(normals * centre, axis=1, keepdims=True)]), 6)
    _, plane_of_face = np.unique(planes, axis=0, return_inverse=True)
    for plane in np.unique(plane_of_face):
        labels = np.unique(s.face_labels[plane_of_face.ravel() == plane])
        assert len(labels) == 1, (planes[plane_of_face.ravel() == plane][0], labels)
