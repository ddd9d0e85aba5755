"""Options and inputs that are numbers but not sensible ones (NaN, negative,
infinite, a zero direction, coordinates whose area overflows) are refused
with InvalidInputError naming them, instead of being accepted and giving a
silent wrong answer (inf, nan) or an untyped failure later (issue 19)."""
import numpy as np
import pytest

import meshes
import paramorph_native as pm

NAN, INF = float("nan"), float("inf")
BLOB = meshes.noisy_blob(2)
DISC = meshes.open_disc()


@pytest.mark.parametrize("value", [NAN, -1.0, INF, 0.0], ids=repr)
def test_sphere_map_tol(value):
    with pytest.raises(pm.InvalidInputError, match="tol"):
        pm.sphere_map(*BLOB, tol=value)


@pytest.mark.parametrize("value", [NAN, -1.0, INF], ids=repr)
def test_sphere_map_outer_tol(value):
    with pytest.raises(pm.InvalidInputError, match="outer_tol"):
        pm.sphere_map(*BLOB, outer_tol=value)


@pytest.mark.parametrize("name", ["tol", "soft_weight"])
@pytest.mark.parametrize("value", [NAN, -1.0, INF], ids=repr)
def test_isometric_map_tolerance_and_weight(name, value):
    with pytest.raises(pm.InvalidInputError, match=name):
        pm.isometric_map(*DISC, **{name: value})


@pytest.mark.parametrize("name,value", [("tol", NAN), ("tol", -1.0), ("tol", INF), ("epsilon", NAN),
                                        ("epsilon", -1.0), ("epsilon", 2.0)], ids=repr)
def test_optimize_sphere_map_options(name, value):
    with pytest.raises(pm.InvalidInputError, match=name):
        pm.optimize_sphere_map(*BLOB, **{name: value})


def test_area_stretch_refuses_what_would_make_it_inf_or_nan():
    V, F = BLOB
    sphere = pm.sphere_map(V, F).positions
    assert np.isfinite(pm.area_stretch(V, F, sphere)).all()
    bad = sphere.copy()
    bad[0] = np.nan
    with pytest.raises(pm.InvalidInputError, match="finite"):
        pm.area_stretch(V, F, bad)
    with pytest.raises(pm.InvalidInputError, match="mapped surface"):
        pm.area_stretch(V, F, np.zeros_like(sphere))
    with pytest.raises(pm.InvalidInputError, match="scale the mesh"):
        pm.area_stretch(V * 1e200, F, sphere)


def test_align_sphere_map_refuses_a_zero_target_and_bad_weights():
    V, F = BLOB
    sphere = pm.sphere_map(V, F).positions
    vertices = np.array([0, 5], np.int32)
    targets = sphere[vertices].copy()
    good = pm.align_sphere_map(V, F, sphere, vertices, targets)
    assert np.isfinite(good.mean_error)
    targets[1] = 0.0
    with pytest.raises(pm.InvalidInputError, match="zero vector"):
        pm.align_sphere_map(V, F, sphere, vertices, targets)
    with pytest.raises(pm.InvalidInputError, match="positive and finite"):
        pm.align_sphere_map(V, F, sphere, vertices, sphere[vertices], weights=[1.0, NAN])


@pytest.mark.parametrize("solver", ["barrier"] + (["ipopt"] if pm.build_info()["ipopt"] else []))
@pytest.mark.parametrize("scale", [1e300, 1e-300])
def test_optimize_sphere_map_with_huge_or_tiny_weights_solves_as_with_ones(scale, solver):
    # The maximiser does not change with the weights' scale; 1e300 left the
    # feasible set ("ComputeError: sphere_map_barrier: left the feasible set").
    V, F = BLOB
    sphere = pm.sphere_map(V, F).positions
    ones = pm.optimize_sphere_map(V, F, sphere, solver=solver)
    scaled = pm.optimize_sphere_map(V, F, sphere, solver=solver, weights=np.full(len(V), scale))
    assert scaled.min_triple > 0 and np.isfinite(scaled.objective)
    assert np.abs(np.asarray(scaled.positions) - np.asarray(ones.positions)).max() < 1e-4
    assert scaled.objective == pytest.approx(scale * ones.objective, rel=1e-6)
