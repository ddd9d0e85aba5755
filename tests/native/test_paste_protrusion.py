"""Copy Feature on long protrusions (issue 32; paste/extract_feature.h Carry,
paste/paste_session.h A FEATURE CARRIED AS ITS OWN MESH): tubes closed at
their tip, straight, bent like a horn and hanging like a trunk, up to 6.4
times as long as wide, copy as carried features and paste closed at random
anchors of a smooth target with their own triangles placed rigidly; the
errors speak of the selection, never of pins."""
from pathlib import Path

import numpy as np
import pytest

import meshes
import paramorph_native as pm

MODELS = Path(__file__).resolve().parents[3] / "shared" / "models"
LENGTHS = [(1.0, 0), (2.0, 0), (3.0, 0), (3.0, 60), (3.0, 150)]  # 2.1x to 6.3x as long as wide


def used_part(V, F):
    """The vertices the faces use, renumbered (a carried paste leaves the
    target's vertices inside the hole unused)."""
    used, inverse = np.unique(np.asarray(F), return_inverse=True)
    return np.asarray(V)[used], inverse.reshape(-1, 3).astype(np.int32)


def closed_and_oriented(V2, F2):
    V, F = used_part(V2, F2)
    r = pm.validate(V, F)
    return (r.boundary_edges == 0 and len(r.non_manifold_edges) == 0
            and len(r.inconsistent_orientation_edges) == 0 and r.components == 1)


def smooth_target():
    """An ellipsoid (a smooth target with a frame of its own)."""
    V, F = meshes.icosphere(4)
    return V * np.array([1.3, 1.0, 0.8]), F


@pytest.fixture(scope="module")
def features():
    out = {}
    for length, bend in LENGTHS:
        V, F, selection, ratio = meshes.protrusion(length, bend)
        out[(length, bend)] = (pm.extract_feature(V, F, selection), ratio)
    return out


def test_long_protrusions_copy_as_carried_parts_and_a_stub_does_not(features):
    for (length, bend), (feature, ratio) in features.items():
        assert feature.carried, f"{ratio:.1f}x bent {bend}: not carried"
        assert len(feature.boundary_loops) == 1
        # Its map is the base map: fold-free, the same boundary.
        assert np.array_equal(feature.uv, feature.base_uv)
    V, F, selection, ratio = meshes.protrusion(0.5)
    stub = pm.extract_feature(V, F, selection)
    assert ratio < 1.1 and not stub.carried  # a stub as long as wide stays a relief, resampled as before


@pytest.mark.parametrize("key", LENGTHS, ids=lambda k: f"{k[0]}-bent{k[1]}")
def test_pasted_closed_at_nine_of_ten_random_anchors_with_the_parts_own_shape(features, key):
    feature, _ = features[key]
    T, TF = smooth_target()
    scale = 0.15 / feature.radius
    rng = np.random.default_rng(3)
    took = 0
    own = np.asarray(feature.vertices)
    pairs = rng.integers(0, len(own), size=(200, 2))
    for v in rng.choice(len(T), size=10, replace=False):
        try:
            s = pm.PasteSession(T, TF, feature, anchor=T[v], scale=scale)
        except pm.TargetTooSmallError:
            continue
        took += 1
        V2, F2, new_faces = (np.asarray(a) for a in s.result())
        assert closed_and_oriented(V2, F2)
        # The part's own vertices last, placed rigidly at the scale asked for.
        placed = V2[len(T):]
        assert len(placed) == len(own)
        d_own = np.linalg.norm(own[pairs[:, 0]] - own[pairs[:, 1]], axis=1)
        d_placed = np.linalg.norm(placed[pairs[:, 0]] - placed[pairs[:, 1]], axis=1)
        np.testing.assert_allclose(d_placed, scale * d_own, rtol=1e-9, atol=1e-12)
        # The seam lies on the target around the root, facing out as it does.
        seam = F2[new_faces[:len(new_faces) - len(feature.faces)]]
        normals = np.cross(V2[seam[:, 1]] - V2[seam[:, 0]], V2[seam[:, 2]] - V2[seam[:, 0]])
        assert len(seam) > 0 and np.all(normals @ s.normal > 0)
        # Nothing beyond the blend moved; the target's untouched faces come first, as they were.
        far = np.linalg.norm(T - s.anchor_point, axis=1) > 1.01 * s.stats["influence_radius"] * 1.5
        np.testing.assert_array_equal(V2[:len(T)][far], T[far])
    assert took >= 9


def test_on_a_flat_target_the_part_is_its_own_shape_exactly(features):
    feature, _ = features[(3.0, 150)]
    P, PF = meshes.plane_grid(n=60, half=1.0)
    scale = 0.25 / feature.radius
    s = pm.PasteSession(P, PF, feature, anchor=np.zeros(3), scale=scale)
    V2, F2, _ = s.result()
    placed = s.anchor_point + s.stats["lift"] * s.normal + scale * np.asarray(feature.vertices)
    d = pm.surface_distance(placed, np.asarray(feature.faces), np.asarray(V2), np.asarray(F2))
    diagonal = np.linalg.norm(np.ptp(placed, axis=0))
    assert d.a_to_b <= 1e-9 * diagonal
    assert s.stats["feature_vertices"] == len(feature.vertices)


def test_an_update_equals_a_fresh_paste_and_a_refused_one_keeps_the_last(features):
    feature, _ = features[(2.0, 0)]
    T, TF = smooth_target()
    scale = 0.15 / feature.radius
    s = pm.PasteSession(T, TF, feature, anchor=T[5], scale=scale)
    s.update(anchor=T[40], rotation=0.7, scale=0.8 * scale)
    fresh = pm.PasteSession(T, TF, feature, anchor=T[40], rotation=0.7, scale=0.8 * scale)
    for a, b in zip(s.result(), fresh.result()):
        np.testing.assert_array_equal(np.asarray(a), np.asarray(b))
    before = [np.asarray(a).copy() for a in s.result()]
    with pytest.raises(pm.TargetTooSmallError):
        s.update(anchor=T[40], rotation=0.0, scale=50 * scale)  # wider than the target
    for a, b in zip(s.result(), before):
        np.testing.assert_array_equal(np.asarray(a), b)


def test_follow_surface_still_pastes_a_carried_part_resampled(features):
    feature, _ = features[(2.0, 0)]
    T, TF = smooth_target()
    s = pm.PasteSession(T, TF, feature, anchor=T[5], scale=0.15 / feature.radius, fit="follow_surface")
    V2, F2, _ = s.result()
    assert closed_and_oriented(np.asarray(V2), np.asarray(F2))


def test_a_scaled_moved_source_gives_the_same_part_at_its_scale():
    V, F, selection, _ = meshes.protrusion(3.0, 60)
    a = pm.extract_feature(V, F, selection)
    b = pm.extract_feature(37.0 * V + np.array([5.0, -2.0, 9.0]), F, selection)
    assert a.carried and b.carried
    np.testing.assert_allclose(np.asarray(b.vertices), 37.0 * np.asarray(a.vertices), atol=1e-8 * 37)
    turned = V @ np.array([[0.0, -1.0, 0.0], [1.0, 0.0, 0.0], [0.0, 0.0, 1.0]]).T
    c = pm.extract_feature(turned, F, selection)
    assert c.carried
    pairs = np.random.default_rng(0).integers(0, len(V), size=(100, 2))
    own, other = np.asarray(a.vertices), np.asarray(c.vertices)
    k = pairs[:, 0] < len(own)
    pairs = pairs[k] % len(own)
    np.testing.assert_allclose(np.linalg.norm(other[pairs[:, 0]] - other[pairs[:, 1]], axis=1),
                               np.linalg.norm(own[pairs[:, 0]] - own[pairs[:, 1]], axis=1), rtol=1e-9, atol=1e-12)


def test_the_carried_flag_round_trips_and_older_stored_features_read_as_not_carried(features):
    feature, _ = features[(2.0, 0)]
    arrays = feature.to_arrays()
    assert int(arrays["carried"]) == 1
    assert pm.Feature.from_arrays(arrays).carried
    older = {k: v for k, v in arrays.items() if k != "carried"}
    assert not pm.Feature.from_arrays(older).carried
    with pytest.raises(pm.InvalidInputError):
        pm.Feature.from_arrays({**arrays, "carried": np.array(2)})


def test_selections_that_cannot_be_copied_say_why_without_pins():
    V, F, selection, _ = meshes.protrusion(3.0)
    # The tube without its tip: a ring around a long part.
    tip = V[F[selection]].mean(axis=1) @ meshes.tentacle_directions(1, 1)[0]
    ring = selection[tip < np.quantile(tip, 0.7)].astype(np.int32)
    with pytest.raises(pm.SelectionTopologyError) as ring_error:
        pm.extract_feature(V, F, ring)
    with pytest.raises(pm.SelectionTopologyError) as never_error:
        pm.extract_feature(V, F, selection, carry="never")
    with pytest.raises(pm.SelectionTopologyError):
        pm.extract_feature(V, F, ring, carry="always")
    with pytest.raises(pm.InvalidInputError):
        pm.extract_feature(V, F, selection, carry="sideways")
    for error in (ring_error.value, never_error.value):
        assert "pin" not in str(error) and "select" in str(error)


@pytest.mark.skipif(not (MODELS / "landmarks.json").is_file(), reason="../shared/models is not here")
@pytest.mark.parametrize("model,tip", [("cat", "tail"), ("lion", "front_left_hoof"), ("horned-cow", "horn")])
def test_real_protrusions_copy_and_paste_onto_the_cartoon_cow(model, tip):
    import json
    import sys
    sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "bench"))
    from common import load_obj
    from paste_protrusion import tip_selection
    V, F = load_obj(MODELS / f"{model}.obj")
    landmarks = json.loads((MODELS / "landmarks.json").read_text())[f"{model}.obj"]
    vertex = int(np.argmax(V[:, 0])) if tip == "horn" else landmarks[tip]
    selection = tip_selection(V, F, vertex, 0.15 * np.linalg.norm(np.ptp(V, axis=0)))
    feature = pm.extract_feature(V, F, selection.astype(np.int32))
    assert feature.carried
    T, TF = load_obj(MODELS / "spot.obj")
    scale = 0.06 * np.linalg.norm(np.ptp(T, axis=0)) / feature.radius
    took = 0
    for v in np.random.default_rng(7).choice(len(T), size=10, replace=False):
        try:
            s = pm.PasteSession(T, TF, feature, anchor=T[v], scale=scale)
        except pm.TargetTooSmallError:
            continue
        took += closed_and_oriented(*(np.asarray(a) for a in s.result()[:2]))
    assert took >= 8  # spot has horns, ears and legs a paste at a random vertex may not fit on
