"""Inputs the fuzz driver (tests/fuzz) found crashing the module, each now
refused with a typed error: out-of-range faces, sphere points that are not
unit directions (NaN, inf, 0, 1e-200, 1e200) and coordinates past 1e150 given
to entry points that trusted their arrays (the morph's pieces, simplify,
surface_distance, extremity_tips, align_sphere_map: SIGSEGV, or SIGFPE from
GMP inside CGAL's closest-point tree), and a progress that cannot be called
(a TypeError at its first report, or never at all). Also a sliver whose
normal's squared length underflows (CGAL's closest point on it was NaN),
and untangle_sphere_map with a huge max_rings (it spun on long after its
patch covered the mesh)."""
import numpy as np
import pytest

import meshes
import paramorph_native as pm

V, F = meshes.icosphere(1)
SPHERE = V / np.linalg.norm(V, axis=1, keepdims=True)
OUT_OF_RANGE = F.astype(np.int64).copy()
OUT_OF_RANGE[3, 1] = 10 ** 6


def with_row(X, value, row=0):
    X = np.array(X, dtype=np.float64, copy=True)
    X[row] = value
    return X


@pytest.mark.parametrize("progress", [5, "progress", np.zeros(3)], ids=["int", "str", "array"])
@pytest.mark.parametrize("call", [
    lambda p: pm.sphere_map(V, F, progress=p),
    lambda p: pm.feature_regions(V, F, progress=p),
    lambda p: pm.balanced_sphere_map(V, F, progress=p),
    lambda p: pm.isometric_map(*meshes.open_disc(), progress=p),
    lambda p: pm.ShapeInterpolation(V, 2 * V, F, progress=p),
    lambda p: pm.surface_distance(V, F, V, F, progress=p),
], ids=["sphere_map", "feature_regions", "balanced_sphere_map", "isometric_map", "ShapeInterpolation",
        "surface_distance"])
def test_a_progress_that_cannot_be_called_is_refused_at_once(call, progress):
    with pytest.raises(pm.InvalidInputError, match="progress must be None or a callable"):
        call(progress)


@pytest.mark.parametrize("call", [
    lambda: pm.simplify(V, OUT_OF_RANGE, 20),
    lambda: pm.isometric_sphere_map(V, OUT_OF_RANGE, SPHERE),
    lambda: pm.align_sphere_map(V, OUT_OF_RANGE, SPHERE, np.array([0]), SPHERE[:1]),
    lambda: pm.extremity_tips(V, OUT_OF_RANGE, pm.segment_extremities(V, F)),
    lambda: pm.map_distortion(V, OUT_OF_RANGE, SPHERE, V, F, SPHERE),
    lambda: pm.carry_through_maps(V, OUT_OF_RANGE, SPHERE, SPHERE[:3]),
    lambda: pm.map_through_proxy(V, V, OUT_OF_RANGE, SPHERE),
    lambda: pm.surface_distance(V, F, V, OUT_OF_RANGE),
], ids=["simplify", "isometric_sphere_map", "align_sphere_map", "extremity_tips", "map_distortion",
        "carry_through_maps", "map_through_proxy", "surface_distance"])
def test_faces_out_of_range_are_refused(call):
    with pytest.raises(pm.InvalidInputError, match="out of range"):
        call()


def test_the_mesh_at_fault_is_named():
    with pytest.raises(pm.InvalidInputError, match="mesh B: .*out of range"):
        pm.map_distortion(V, F, SPHERE, V, OUT_OF_RANGE, SPHERE)
    with pytest.raises(pm.InvalidInputError, match="mesh proxy: "):
        pm.map_through_proxy(V, with_row(V, np.nan), F, SPHERE)


def test_an_empty_mesh_is_refused_by_extremity_tips():
    with pytest.raises(pm.InvalidInputError, match="empty"):
        pm.extremity_tips(np.zeros((0, 3)), F, pm.segment_extremities(V, F))


@pytest.mark.parametrize("value", [np.nan, np.inf, 0.0, 1e-200, 1e200], ids=["nan", "inf", "zero", "1e-200", "1e200"])
@pytest.mark.parametrize("call", [
    lambda X: pm.carry_through_maps(V, F, X, SPHERE[:4]),
    lambda X: pm.carry_through_maps(V, F, SPHERE, X[:4]),
    lambda X: pm.map_distortion(V, F, X, V, F, SPHERE),
    lambda X: pm.map_distortion(V, F, SPHERE, V, F, X),
    lambda X: pm.map_through_proxy(V, V, F, X),
    lambda X: pm.isometric_sphere_map(V, F, X),
], ids=["carry sphere_a", "carry points", "distortion sphere_a", "distortion sphere_b", "proxy_map",
        "isometric start"])
def test_sphere_points_must_be_directions(call, value):
    with pytest.raises(pm.InvalidInputError, match="is not a direction"):
        call(with_row(SPHERE, value))


@pytest.mark.parametrize("call", [
    lambda s: pm.surface_distance(V * s, F, V, F),
    lambda s: pm.carry_through_maps(V * s, F, SPHERE, SPHERE[:4]),
    lambda s: pm.map_distortion(V, F, SPHERE, V * s, F, SPHERE),
], ids=["surface_distance", "carry_through_maps", "map_distortion"])
def test_coordinates_whose_areas_overflow_are_refused(call):
    with pytest.raises(pm.InvalidInputError, match="scale the mesh"):
        call(1e151)


def test_a_sliver_with_a_denormal_corner_is_skipped_by_closest_points():
    # (0,0,0), (1,0,0), (d,d,d) with d = 5e-324: not exactly degenerate, but
    # its normal's squared length underflows; CGAL's projection made NaN.
    sliver = np.array([[0.0, 0, 0], [1, 0, 0], [5e-324, 5e-324, 5e-324]])
    with pytest.raises(pm.InvalidInputError, match="non-zero area"):
        pm.surface_distance(sliver, np.array([[0, 1, 2]]), V, F)
    two = np.vstack([sliver, [[0.0, 1, 0]]])
    d = pm.surface_distance(two, np.array([[0, 1, 2], [0, 1, 3]]), V, F)
    assert np.isfinite(d.hausdorff)


def test_map_through_proxy_refuses_query_points_it_cannot_place():
    with pytest.raises(pm.InvalidInputError, match="V row 2 is not a finite point"):
        pm.map_through_proxy(with_row(V, np.inf, 2), V, F, SPHERE)


def test_valid_inputs_still_answer():
    assert pm.carry_through_maps(V, F, SPHERE, SPHERE[:4]).shape == (4, 3)
    assert np.isfinite(pm.map_distortion(V, F, SPHERE, V, F, SPHERE).mean)
    assert pm.map_through_proxy(V, V, F, SPHERE).shape == V.shape
    assert pm.surface_distance(V, F, V, F).hausdorff == pytest.approx(0.0, abs=1e-12)


def test_untangle_with_a_huge_ring_budget_stops_when_the_patch_covers_the_mesh():
    X = SPHERE.copy()
    X[[0, 5]] = X[[5, 0]]  # two vertices swapped: folded faces around both
    fixed = np.array([], np.int64)
    small = pm.untangle_sphere_map(V, F, X, fixed, max_rings=10)
    huge = pm.untangle_sphere_map(V, F, X, fixed, max_rings=2 ** 31 - 1)
    # An 80-face sphere is covered long before ten rings: the same answer.
    assert np.array_equal(small[0], huge[0])
    assert small[1:] == huge[1:]


@pytest.mark.parametrize("bad", ["1.5", 1j, [1.0], np.zeros(2)], ids=repr)
def test_paste_update_refuses_a_rotation_or_scale_that_is_not_a_number(bad):
    # pybind11's cast raised an untyped "Unable to cast Python instance".
    V, F, faces = meshes.bump_plane(n=30)
    feature = pm.extract_feature(V, F, faces, resolution=32, backend="cpu")
    T, TF = meshes.plane_grid(n=30, half=2.0)
    session = pm.PasteSession(T, TF, feature, anchor=np.array([0.0, 0.0, 0.0]))
    for name in ("rotation", "scale"):
        with pytest.raises(pm.InvalidInputError, match=f"{name} must be a number or None"):
            session.update(**{name: bad})
    session.update(rotation=np.float32(0.1), scale=1)  # numpy and int numbers still work


@pytest.mark.parametrize("radius", [1e-300, 1e-200, 1.0, 1e200, 1e300], ids=repr)
def test_optimize_sphere_map_takes_a_sphere_of_any_radius(radius):
    # Seed 20261127: one row at 1e200 overflowed Eigen's normalized() to a
    # zero row, and the barrier failed on it as an untyped ComputeError.
    start = pm.sphere_map(V, F).positions
    unit = pm.optimize_sphere_map(V, F, start, solver="barrier")
    scaled = pm.optimize_sphere_map(V, F, start * radius, solver="barrier")
    np.testing.assert_allclose(scaled.positions, unit.positions, atol=1e-12)
    assert scaled.flipped == 0


@pytest.mark.parametrize("value", [1e200, 1e-200], ids=repr)
def test_optimize_sphere_map_refuses_a_sphere_whose_rows_disagree(value):
    # One vertex pushed far out along an axis: its direction changes, the
    # start folds, and the refusal says so (never a ComputeError).
    start = pm.sphere_map(V, F).positions
    with pytest.raises(pm.InvalidInputError, match="start map folds"):
        pm.optimize_sphere_map(V, F, with_row(start, value), solver="barrier")


def test_optimize_sphere_map_refuses_a_row_with_no_direction():
    start = pm.sphere_map(V, F).positions
    with pytest.raises(pm.InvalidInputError, match="sphere rows 3 are zero"):
        pm.optimize_sphere_map(V, F, with_row(start, 0.0, row=3), solver="barrier")
