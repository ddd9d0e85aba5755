"""vertex_parts, PartRider and signed_distance from Python (issue 31): a
character's separate parts found, carried exactly by a body that turns,
scales and moves, left where they were when far off, and bad input refused
with InvalidInputError."""
import numpy as np
import pytest

import paramorph_native as pm
from in_betweens import rotation
from meshes import icosphere


def body_and_eyes():
    V, F = icosphere(3)
    V = V / np.linalg.norm(V, axis=1, keepdims=True)
    eye, eye_faces = icosphere(1)
    eye = 0.15 * eye / np.linalg.norm(eye, axis=1, keepdims=True)
    left, right = eye + [1.1, 0.3, 0.0], eye + [1.1, -0.3, 0.0]
    far = eye + [0.0, 0.0, 6.0]
    parts = np.concatenate([left, right, far])
    labels = np.repeat([0, 1, 2], len(eye)).astype(np.int32)
    return V, F, parts, labels, eye_faces


def test_vertex_parts_numbers_each_connected_part_and_each_loose_vertex():
    V, F, parts, _, eye_faces = body_and_eyes()
    n = len(V)
    k = len(parts) // 3
    whole = np.concatenate([F, eye_faces + n, eye_faces + n + k, eye_faces + n + 2 * k])
    labels = np.asarray(pm.vertex_parts(whole, n + len(parts) + 1))  # the last vertex is in no face
    assert labels.shape == (n + len(parts) + 1,)
    assert len(np.unique(labels[:n])) == 1
    assert len(np.unique(labels)) == 5  # body, two eyes, the far ball, the loose vertex
    with pytest.raises(pm.InvalidInputError):
        pm.vertex_parts(whole, n)


def test_parts_follow_a_turned_scaled_moved_body_exactly_and_a_far_one_stays():
    V, F, parts, labels, _ = body_and_eyes()
    rider = pm.PartRider(V, F, parts, labels)
    assert rider.parts == 3
    np.testing.assert_array_equal(rider.riding, [True, True, False])
    assert rider.rest_gap[2] > 4.0 and rider.rest_depth[2] == 0.0
    assert (rider.rest_depth[:2] > 0).all()  # the eyes sit a little in their sockets
    R = rotation([0.2, 1.0, -0.4], 130)
    moved = 0.01 * V @ R.T + [3.0, -2.0, 1.0]  # a user's scene: turned, tiny, elsewhere
    positions, pushed = rider.at(moved)
    riding = labels < 2
    np.testing.assert_allclose(positions[riding], 0.01 * parts[riding] @ R.T + [3.0, -2.0, 1.0], atol=1e-12)
    np.testing.assert_array_equal(positions[~riding], parts[~riding])
    np.testing.assert_array_equal(pushed, 0.0)


def test_signed_distance_is_negative_inside():
    V, F, _, _, _ = body_and_eyes()
    d = np.asarray(pm.signed_distance(V, F, np.array([[0.0, 0.0, 0.0], [0.0, 0.0, 2.0]])))
    assert d[0] == pytest.approx(-1.0, abs=0.02) and d[1] == pytest.approx(1.0, abs=0.02)


def test_bad_input_is_refused():
    V, F, parts, labels, _ = body_and_eyes()
    with pytest.raises(pm.InvalidInputError):
        pm.PartRider(V, F, parts, labels[:-1])
    with pytest.raises(pm.InvalidInputError):
        pm.PartRider(V, F, parts, labels + 1)  # label 0 unused
    with pytest.raises(pm.InvalidInputError):
        pm.PartRider(V, F, parts, labels, patch_scale=0.0)
    rider = pm.PartRider(V, F, parts, labels)
    with pytest.raises(pm.InvalidInputError):
        rider.at(V[:10])


def test_vertex_parts_refuses_a_count_no_mesh_has():
    _, F, _, _, _ = body_and_eyes()
    for count in (-1, 2 ** 31 - 1):
        with pytest.raises(pm.InvalidInputError):
            pm.vertex_parts(F, count)
