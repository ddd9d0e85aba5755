"""Feature measures: concavity (thesis Def. 4.1), shape_signature and
signature_distance (thesis 3.5.3).

Concavity is checked against the analytic distance inside a dented box; the
signature ranks the same shape at two resolutions and in two poses closer than
other shapes; every invalid input raises its typed error.
"""
import numpy as np
import pytest

import meshes
import paramorph_native as pm


def dented_box(seed=0, half=(1.0, 1.5, 2.0), cells=8):
    """meshes.box with every third side-interior vertex pushed inward by a
    random depth; returns V, F and the analytic distance of every vertex to
    the box (= the hull: the corners stay), min over axes of half - |p|."""
    V, F = meshes.box(cells, half)
    half = np.asarray(half)
    on_side = np.abs(np.abs(V) - half) < 1e-12
    interior = np.flatnonzero((on_side.sum(axis=1) == 1) & (np.arange(len(V)) % 3 == 0))
    axis = np.argmax(on_side[interior], axis=1)
    depth = np.minimum(np.random.default_rng(seed).uniform(0.05, 2.5, len(interior)), half[axis])
    V = V.copy()
    V[interior, axis] -= np.sign(V[interior, axis]) * depth
    return V, F, (half - np.abs(V)).min(axis=1), interior


# --- concavity --------------------------------------------------------------------

def test_concavity_of_a_dented_box_is_the_distance_to_its_sides():
    V, F, expected, dented = dented_box()
    assert len(dented) > 50
    I = pm.concavity(V, F)
    assert I.shape == (len(V),) and I.dtype == np.float64
    np.testing.assert_allclose(I, expected, rtol=0, atol=1e-12)
    assert np.all(I[dented] > 0.04)


def test_concavity_is_zero_on_convex_meshes():
    for name, (V, F) in {"icosphere": meshes.icosphere(3), "box": meshes.box(6, (1, 2, 3))}.items():
        I = pm.concavity(V, F)
        assert I.max() < 1e-12, f"{name}: max concavity {I.max()}"
        assert I.min() >= 0.0


def test_concavity_accepts_float32_and_int64_and_is_rigid_and_scale_invariant():
    V, F = meshes.noisy_blob(3, seed=0)
    I = pm.concavity(V, F)
    assert I.max() > 0.05, "the blob should be clearly non-convex"
    V32 = V.astype(np.float32)
    np.testing.assert_array_equal(pm.concavity(V32, F.astype(np.int64)),
                                  pm.concavity(V32.astype(np.float64), F))
    np.testing.assert_allclose(pm.concavity(V32, F), I, atol=1e-5 * np.abs(V).max())
    q, _ = np.linalg.qr(np.random.default_rng(4).normal(size=(3, 3)))
    moved = V @ q.T + [300.0, -50.0, 1000.0]
    np.testing.assert_allclose(pm.concavity(moved, F), I, atol=1e-9)
    np.testing.assert_allclose(pm.concavity(1e-6 * V, F) * 1e6, I, atol=1e-12)


def test_concavity_marks_the_foot_of_every_limb():
    """Where a limb meets the body the surface is inside the hull; the limb tips are on it."""
    V, F = meshes.limb_blob(3, limbs=3)
    I = pm.concavity(V, F)
    radius = np.linalg.norm(V, axis=1)
    tips = radius > radius.max() - 0.05
    assert np.all(I[tips] < 1e-12)
    assert I.max() > 0.1


@pytest.mark.parametrize("make, error", [
    (lambda: (meshes.box(2)[0] * [1, 1, 0], meshes.box(2)[1]), pm.InvalidInputError),  # flat
    (meshes.nan_vertex, pm.InvalidInputError),
    (meshes.out_of_range_index, pm.InvalidInputError),
    (lambda: (np.zeros((3, 3)), np.array([[0, 1, 2]])), pm.InvalidInputError),       # too few
    (lambda: (np.zeros((5, 2)), np.array([[0, 1, 2]])), pm.InvalidInputError),       # V shape
    (lambda: (meshes.icosphere(1)[0].astype(str), meshes.icosphere(1)[1]), pm.InvalidInputError),
    (lambda: (meshes.icosphere(1)[0], meshes.icosphere(1)[1].astype(np.float64)), pm.InvalidInputError),
], ids=["flat", "nan", "index", "three_points", "V_shape", "V_dtype", "F_dtype"])
def test_concavity_errors_are_typed(make, error):
    V, F = make()
    with pytest.raises(error) as caught:
        pm.concavity(V, F)
    assert isinstance(caught.value, pm.MeshError) and isinstance(caught.value, ValueError)


def test_flat_mesh_error_says_why(capfd):
    V, F = meshes.box(3)
    V[:, 2] = 0.5 * V[:, 0] - V[:, 1]   # every vertex on one plane
    with pytest.raises(pm.InvalidInputError, match="plane"):
        pm.concavity(V, F)
    out, err = capfd.readouterr()
    assert out == "" and err == "", "Qhull must not print"


def test_coincident_or_collinear_points_are_said_so_not_a_qhull_internal_error():
    V, F = meshes.icosphere(1)
    with pytest.raises(pm.InvalidInputError, match="all at one place"):
        pm.concavity(np.zeros_like(V), F)  # was "Qhull could not build the hull (internal error, code 5)"
    line = np.outer(np.arange(len(V), dtype=float), [1.0, 2.0, 3.0])
    with pytest.raises(pm.InvalidInputError, match=r"one plane \(or on a line\)"):
        pm.concavity(line, F)


# --- shape signature ------------------------------------------------------------------

def test_signature_is_a_normalised_histogram_of_the_requested_size():
    V, F = meshes.noisy_blob(3, seed=2)
    for bins in (8, 32, 33):
        h = pm.shape_signature(V, F, bins=bins, log_range=3.0)
        assert h.shape == (bins,) and h.dtype == np.float64
        assert np.all(h >= 0) and abs(h.sum() - 1.0) < 1e-12


def test_signature_of_a_given_sphere_equals_the_computed_one():
    V, F = meshes.noisy_blob(3, seed=2)
    X = pm.sphere_map(V, F).positions
    np.testing.assert_allclose(pm.shape_signature(V, F, sphere=X), pm.shape_signature(V, F),
                               atol=1e-12)
    # The sphere itself as the mesh: stretch 1 everywhere, half in each central bin.
    h = pm.shape_signature(X, F, sphere=X, bins=16)
    np.testing.assert_allclose(h[7:9], [0.5, 0.5], atol=1e-9)


def test_same_shape_at_two_resolutions_and_in_two_poses_is_closer_than_other_shapes():
    straight = pm.shape_signature(*meshes.limb_blob(3))
    finer = pm.shape_signature(*meshes.limb_blob(4))
    bent = pm.shape_signature(*meshes.limb_blob(3, bend_degrees=60))
    three_limbs = pm.shape_signature(*meshes.limb_blob(3, limbs=3))
    V, F = meshes.icosphere(4)
    ellipsoid = pm.shape_signature(V * [1.0, 1.6, 0.8], F)
    d = pm.signature_distance
    same = {"two resolutions": d(straight, finer), "two poses": d(straight, bent),
            "pose and resolution": d(finer, bent)}
    other = {"three limbs": d(straight, three_limbs), "ellipsoid": d(straight, ellipsoid),
             "bent vs three limbs": d(bent, three_limbs)}
    message = f"same shape: {same}; other shapes: {other}"
    print(message)
    assert max(same.values()) < 0.5 * min(other.values()), message


def test_signature_reports_progress_and_cancels():
    V, F = meshes.noisy_blob(2, seed=1)
    seen = []
    pm.shape_signature(V, F, progress=lambda f, stage: seen.append((f, stage)))
    fractions = [f for f, _ in seen]
    assert fractions[0] == 0.0 and fractions[-1] == 1.0
    assert fractions == sorted(fractions)
    assert any(stage.startswith("sphere map") for _, stage in seen)
    with pytest.raises(pm.Cancelled):
        pm.shape_signature(V, F, progress=lambda f, stage: False)

    def boom(f, stage):
        raise KeyError("from the callback")
    with pytest.raises(KeyError, match="from the callback"):
        pm.shape_signature(V, F, progress=boom)


def test_signature_errors_are_typed():
    V, F = meshes.icosphere(2)
    with pytest.raises(pm.InvalidInputError):
        pm.shape_signature(V, F, bins=0)
    with pytest.raises(pm.InvalidInputError):
        pm.shape_signature(V, F, log_range=0.0)
    with pytest.raises(pm.InvalidInputError):
        pm.shape_signature(V, F, sphere=V[:-1])
    with pytest.raises(pm.InvalidInputError):
        pm.shape_signature(V, F, sphere=np.zeros_like(V))
    with pytest.raises(pm.NotClosedError):
        pm.shape_signature(*meshes.open_disc())
    with pytest.raises(pm.NotGenusZeroError):
        pm.shape_signature(*meshes.torus())
    with pytest.raises(pm.InvalidInputError):
        pm.shape_signature(*meshes.nan_vertex())


# --- signature distance -------------------------------------------------------------

def test_signature_distance_is_the_earth_movers_distance():
    bins, L = 16, 4.0
    width = 2 * L / bins
    a = np.zeros(bins)
    a[3:7] = [0.1, 0.4, 0.3, 0.2]
    shifted = np.roll(a, 2)
    assert pm.signature_distance(a, a) == 0.0
    assert pm.signature_distance(a, shifted) == pytest.approx(2 * width, abs=1e-14)
    assert pm.signature_distance(shifted, a) == pm.signature_distance(a, shifted)
    assert pm.signature_distance(5 * a, shifted) == pytest.approx(2 * width, abs=1e-14)
    assert pm.signature_distance(a, shifted, log_range=1.0) == pytest.approx(2 * 2.0 / bins)
    assert pm.signature_distance(a.astype(np.float32), shifted) == pytest.approx(2 * width)
    # A bin-by-bin norm saturates once histograms stop overlapping; this one keeps growing.
    far = np.roll(a, 6)
    assert pm.signature_distance(a, far) > pm.signature_distance(a, shifted)


@pytest.mark.parametrize("a, b", [
    (np.ones(8), np.ones(9)),
    (np.ones(8), np.zeros(8)),
    (np.array([1.0, -1.0, 1.0]), np.ones(3)),
    (np.array([1.0, np.nan, 1.0]), np.ones(3)),
    (np.ones((2, 4)), np.ones((2, 4))),
    (np.array([]), np.array([])),
], ids=["sizes", "zero_sum", "negative", "nan", "2d", "empty"])
def test_signature_distance_rejects_bad_histograms(a, b):
    with pytest.raises(pm.InvalidInputError):
        pm.signature_distance(a, b)
