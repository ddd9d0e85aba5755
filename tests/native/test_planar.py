"""isometric_map(): fold-free constrained isometric planar maps (thesis ch. 2),
on both backends."""
import numpy as np
import pytest

import meshes
import paramorph_native as pm
import planar_meshes


def folded(uv, F):
    (ux, uy), (vx, vy) = (uv[F[:, 1]] - uv[F[:, 0]]).T, (uv[F[:, 2]] - uv[F[:, 0]]).T
    return np.flatnonzero(ux * vy - uy * vx <= 0)  # not np.cross: NumPy 2 dropped 2-vectors


def boundary_vertices(V, F):
    edges = np.sort(np.concatenate([F[:, [0, 1]], F[:, [1, 2]], F[:, [2, 0]]]), axis=1)
    unique, counts = np.unique(edges, axis=0, return_counts=True)
    return np.unique(unique[counts == 1])


@pytest.mark.parametrize("name", sorted(planar_meshes.FAMILIES))
def test_free_boundary_maps_are_fold_free_and_descend(name):
    V, F = planar_meshes.FAMILIES[name]()
    result = pm.isometric_map(V, F, backend="cpu")
    assert result.uv.shape == (len(V), 2) and np.isfinite(result.uv).all()
    assert folded(result.uv, F).size == 0 and result.flipped == 0, name
    history = np.asarray(result.energy_history)
    assert np.all(np.diff(history) <= 0), f"{name}: energy rose"
    assert result.metrics["symmetric_dirichlet"] >= 4.0 - 1e-9
    assert result.metrics["area_min"] <= 1.0 + 1e-9 <= result.metrics["area_max"] + 2e-9


def twist(points, center, radius):
    """θ(r) = 45°·clamp((1 - r)/0.5, 0, 1), r the distance from the centre over radius."""
    d = points - center
    r = np.linalg.norm(d, axis=1) / radius
    theta = np.deg2rad(45.0) * np.clip((1.0 - r) / 0.5, 0.0, 1.0)
    c, s = np.cos(theta), np.sin(theta)
    return center + np.column_stack([c * d[:, 0] - s * d[:, 1], s * d[:, 0] + c * d[:, 1]])


@pytest.mark.parametrize("init", ["tutte", "free", "given"])
def test_twist_pins_are_exact_and_fold_free(init):
    V, F = planar_meshes.bumpy_disc(16, 64)
    tutte = pm.isometric_map(V, F, init="tutte", max_iterations=0, backend="cpu").uv
    center = tutte.mean(axis=0)
    radius = np.linalg.norm(tutte - center, axis=1).max()
    warped = twist(tutte, center, radius)
    assert folded(warped, F).size == 0, "the warp itself must not fold (a solution exists)"
    boundary = boundary_vertices(V, F)
    rng = np.random.default_rng(0)
    interior = np.setdiff1d(np.arange(len(V)), boundary)
    chosen = rng.choice(interior, size=int(0.05 * len(V)) + 1, replace=False)
    pins = np.concatenate([boundary, chosen])
    start = tutte if init == "given" else init
    result = pm.isometric_map(V, F, pinned=pins, pinned_uv=warped[pins], init=start,
                              backend="cpu")
    assert folded(result.uv, F).size == 0 and result.flipped == 0
    assert np.array_equal(result.uv[pins], warped[pins])  # exact, not approximately
    assert np.all(np.diff(result.energy_history) <= 0)


def test_rigid_rotation_near_the_boundary_never_returns_folds_silently():
    V, F = planar_meshes.bumpy_disc(10, 40)
    tutte = pm.isometric_map(V, F, init="tutte", max_iterations=0, backend="cpu").uv
    boundary = boundary_vertices(V, F)
    near = np.flatnonzero((np.linalg.norm(tutte, axis=1) > 0.7) &
                          (np.linalg.norm(tutte, axis=1) < 0.95))[:8]
    rotated = tutte[near] @ np.array([[0.0, -1.0], [1.0, 0.0]]).T
    pins = np.concatenate([boundary, near])
    targets = np.vstack([tutte[boundary], rotated])
    try:
        result = pm.isometric_map(V, F, pinned=pins, pinned_uv=targets, init=tutte, backend="cpu")
    except pm.ConstraintError as error:
        assert "folded" in str(error)
    else:
        assert folded(result.uv, F).size == 0 and result.flipped == 0
        assert np.array_equal(result.uv[pins], targets)
    best = pm.isometric_map(V, F, pinned=pins, pinned_uv=targets, init=tutte, backend="cpu",
                            allow_folds=True)
    assert best.flipped == folded(best.uv, F).size


def test_soft_pins_pull_towards_their_targets():
    V, F = planar_meshes.bumpy_disc()
    free = pm.isometric_map(V, F, backend="cpu").uv
    soft = np.array([0, 5, 40])
    targets = free[soft] + 0.05
    weak = pm.isometric_map(V, F, soft=soft, soft_uv=targets, soft_weight=1.0, backend="cpu").uv
    strong = pm.isometric_map(V, F, soft=soft, soft_uv=targets, soft_weight=1e4, backend="cpu").uv
    err = lambda uv: np.linalg.norm(uv[soft] - targets)  # noqa: E731
    assert err(strong) < err(weak)
    assert folded(strong, F).size == 0


@pytest.mark.skipif(not pm.opencl_available(), reason="no usable OpenCL device")
@pytest.mark.parametrize("name", sorted(planar_meshes.FAMILIES))
def test_opencl_and_cpu_agree(name):
    V, F = planar_meshes.FAMILIES[name]()
    # The first steps take the same path to rounding (the only difference is
    # the order of the energy sum); later ones may part, but reach the same map.
    early = {b: pm.isometric_map(V, F, backend=b, max_iterations=3) for b in ("cpu", "opencl")}
    assert early["opencl"].backend == "opencl" and early["cpu"].backend == "cpu"
    scale = np.abs(early["cpu"].uv).max()
    assert np.abs(early["cpu"].uv - early["opencl"].uv).max() <= 1e-8 * scale
    final = {b: pm.isometric_map(V, F, backend=b, tol=1e-10) for b in ("cpu", "opencl")}
    for result in final.values():
        assert result.flipped == 0 and folded(result.uv, F).size == 0
        assert np.all(np.diff(result.energy_history) <= 0)
    e_cpu, e_ocl = (final[b].energy_history[-1] for b in ("cpu", "opencl"))
    assert abs(e_cpu - e_ocl) <= 1e-6 * e_cpu, (e_cpu, e_ocl)


def test_twist_agrees_on_both_backends():
    if not pm.opencl_available():
        pytest.skip("no usable OpenCL device")
    V, F = planar_meshes.bumpy_disc(12, 48)
    tutte = pm.isometric_map(V, F, init="tutte", max_iterations=0, backend="cpu").uv
    center = tutte.mean(axis=0)
    warped = twist(tutte, center, np.linalg.norm(tutte - center, axis=1).max())
    boundary = boundary_vertices(V, F)
    pins = np.concatenate([boundary, np.setdiff1d(np.arange(len(V)), boundary)[::17]])
    runs = {b: pm.isometric_map(V, F, pinned=pins, pinned_uv=warped[pins], init="tutte",
                                backend=b, tol=1e-10) for b in ("cpu", "opencl")}
    for result in runs.values():
        assert result.flipped == 0 and np.array_equal(result.uv[pins], warped[pins])
    # Pinned: the minimiser is unique, so the maps themselves agree.
    assert np.abs(runs["cpu"].uv - runs["opencl"].uv).max() <= 1e-5 * np.abs(tutte).max()


@pytest.mark.parametrize("mesh,kwargs,error,words", [
    (meshes.icosphere(2), {}, pm.NotOpenError, "closed"),
    (meshes.torus(), {}, pm.NotOpenError, "closed"),
    (meshes.nan_vertex(), {}, pm.InvalidInputError, r"vert\w*: 5"),
    (planar_meshes.bumpy_disc(), dict(pinned=[3, 3], pinned_uv=[[0, 0], [1, 1]]),
     pm.ConstraintError, "twice"),
    (planar_meshes.bumpy_disc(), dict(pinned=[10 ** 6], pinned_uv=[[0, 0]]),
     pm.InvalidInputError, "out of range"),
    (planar_meshes.bumpy_disc(), dict(backend="cuda"), pm.InvalidInputError, "backend"),
])
def test_errors(mesh, kwargs, error, words):
    V, F = mesh
    with pytest.raises(error, match=words):
        pm.isometric_map(V, F, **kwargs)


def test_genus_one_patch_is_rejected():
    V, F = meshes.torus(24, 12)
    cut = F[V[F].mean(axis=1)[:, 0] < 0.9]  # an open patch that still has the handle
    used = np.unique(cut)
    remap = -np.ones(len(V), np.int64)
    remap[used] = np.arange(len(used))
    report = pm.validate(V[used], remap[cut].astype(np.int32))
    if report.genus != 1:
        pytest.skip(f"cut did not keep the handle (genus {report.genus})")
    with pytest.raises(pm.NotGenusZeroError, match="genus 1"):
        pm.isometric_map(V[used], remap[cut].astype(np.int32))


def test_metrics_follow_the_thesis_tables_definitions():
    # A flat grid mapped by (x, y) -> (2x, y/2): every face has σ = (2, 1/2),
    # so the area is kept (σ1σ2 = 1) and the stretch is known in closed form.
    i, j = np.meshgrid(np.arange(9), np.arange(7), indexing="ij")
    V = np.column_stack([i.ravel() / 8.0, j.ravel() / 8.0, np.zeros(i.size)])
    idx = lambda a, b: a * 7 + b  # noqa: E731
    F = np.array([f for a in range(8) for b in range(6)
                  for f in ([idx(a, b), idx(a + 1, b), idx(a + 1, b + 1)],
                            [idx(a, b), idx(a + 1, b + 1), idx(a, b + 1)])], dtype=np.int32)
    stretched = V[:, :2] * [2.0, 0.5]
    m = pm.isometric_map(V, F, init=stretched, max_iterations=0, backend="cpu").metrics
    l2 = np.sqrt((4.0 + 0.25) / 2.0)
    expected = dict(area_min=1.0, area_max=1.0, area_rms=0.0, angular=3.0, l2_min=l2, l2_max=l2,
                    l2_rms=l2 - 1.0, symmetric_dirichlet=4.0 + 0.25 + 0.25 + 4.0)
    for name, value in expected.items():
        assert m[name] == pytest.approx(value, abs=1e-9), name
    identity = pm.isometric_map(V, F, init=V[:, :2] * 3.0, max_iterations=0, backend="cpu").metrics
    assert identity["symmetric_dirichlet"] == pytest.approx(4.0)  # scale is normalised away
    assert identity["l2_rms"] == pytest.approx(0.0, abs=1e-9)
