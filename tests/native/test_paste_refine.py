"""Uniform Loop refinement of a face region (pm.refine_region, thesis 5.2): the
Python face of paste/refine_region. Watertight stitching, untouched outside,
flat positions on their base faces, limit surface of the whole mesh, errors."""
import numpy as np
import pytest

import meshes
import paramorph_native as pm


def edge_face_counts(F):
    e = np.sort(np.concatenate([F[:, [0, 1]], F[:, [1, 2]], F[:, [2, 0]]]), axis=1)
    _, counts = np.unique(e, axis=0, return_counts=True)
    return counts


def euler(V, F):
    return len(V) - len(edge_face_counts(F)) + len(F)


def check(V, F, region, level, r):
    assert np.array_equal(r.V[: len(V)], V)
    counts = edge_face_counts(r.F)
    assert counts.max() <= 2  # no T-junction or non-manifold edge
    assert (counts == 1).sum() >= (edge_face_counts(F) == 1).sum()
    assert euler(r.V, r.F) == euler(V, F)
    report = pm.validate(r.V, r.F)
    assert len(report.degenerate_faces) == 0 and len(report.non_manifold_vertices) == 0
    assert len(report.inconsistent_orientation_edges) == 0
    # Flat positions on their base faces.
    assert np.all(r.base_face >= 0)
    assert np.allclose(r.bary.sum(axis=1), 1.0, atol=1e-12) and r.bary.min() >= -1e-12
    flat = np.einsum("ik,ikj->ij", r.bary, V[F[r.base_face]])
    assert np.abs(flat - r.V).max() < 1e-12
    assert np.allclose(np.linalg.norm(r.limit_normal, axis=1), 1.0)
    # Untouched faces first, new ones after.
    assert np.array_equal(r.new_faces, np.arange(len(r.F) - len(r.new_faces), len(r.F)))
    assert len(r.new_faces) >= len(set(region)) * 4**level


@pytest.mark.parametrize("level", [1, 2])
def test_refine_region_closed_sphere(level):
    V, F = meshes.icosphere(2)
    region = np.flatnonzero(V[F].mean(axis=1)[:, 2] > 0.2)
    r = pm.refine_region(V, F, region, level=level)
    check(V, F, region, level, r)
    assert np.all(edge_face_counts(r.F) == 2)  # still closed
    # Faces not touching the region by an edge come first, unchanged.
    touching = np.zeros(len(F), bool)
    touching[region] = True
    e_of = lambda f: {tuple(sorted((F[f, k], F[f, (k + 1) % 3]))) for k in range(3)}  # noqa: E731
    region_edges = set().union(*(e_of(f) for f in region))
    for f in range(len(F)):
        if e_of(f) & region_edges:
            touching[f] = True
    kept = F[~touching]
    assert np.array_equal(r.F[: len(kept)], kept)
    # New vertices in the region: limit on the smooth sphere-ish surface, normals outward.
    assert np.all(np.einsum("ij,ij->i", r.limit_normal, r.limit) > 0.9 * np.linalg.norm(r.limit, axis=1))
    assert r.region_interior.dtype == bool and r.region_interior.sum() > 0


def test_refine_region_open_disc_keeps_its_boundary():
    V, F = meshes.open_disc()
    # A region along the boundary: faces touching a boundary vertex.
    counts = {}
    for f in F:
        for k in range(3):
            key = tuple(sorted((f[k], f[(k + 1) % 3])))
            counts[key] = counts.get(key, 0) + 1
    boundary_vertices = {v for e, c in counts.items() if c == 1 for v in e}
    region = [i for i, f in enumerate(F) if set(f.tolist()) & boundary_vertices][::2]
    r = pm.refine_region(V, F, region, level=2)
    check(V, F, region, 2, r)
    report_before, report_after = pm.validate(V, F), pm.validate(r.V, r.F)
    assert report_after.boundary_loops == report_before.boundary_loops == 1
    # Boundary vertices are never region interior.
    out_counts = {}
    for f in r.F:
        for k in range(3):
            key = tuple(sorted((f[k], f[(k + 1) % 3])))
            out_counts[key] = out_counts.get(key, 0) + 1
    rim = {v for e, c in out_counts.items() if c == 1 for v in e}
    assert not r.region_interior[list(rim)].any()


def test_refine_region_plane_limit_is_the_plane():
    n = 5
    x, y = np.meshgrid(np.linspace(0, 1, n + 1), np.linspace(0, 1, n + 1), indexing="ij")
    V = np.column_stack([x.ravel(), y.ravel(), np.zeros(x.size)])
    F = []
    for i in range(n):
        for j in range(n):
            a, b = i * (n + 1) + j, (i + 1) * (n + 1) + j
            F += [[a, b, b + 1], [a, b + 1, a + 1]]
    F = np.array(F, dtype=np.int32)
    region = np.arange(0, len(F), 3)
    r = pm.refine_region(V, F, region, level=3)
    check(V, F, region, 3, r)
    assert np.abs(r.limit[:, 2]).max() < 1e-12
    assert np.allclose(r.limit_normal, [0, 0, 1], atol=1e-9)


def test_refine_region_level_zero_returns_the_input():
    V, F = meshes.icosphere(1)
    r = pm.refine_region(V, F, np.arange(10), level=0)
    assert np.array_equal(r.V, V) and np.array_equal(r.F, F) and len(r.new_faces) == 0


def test_refine_region_errors():
    V, F = meshes.icosphere(1)
    with pytest.raises(pm.InvalidInputError):
        pm.refine_region(V, F, [len(F)], level=1)
    with pytest.raises(pm.InvalidInputError):
        pm.refine_region(V, F, [0], level=-1)
    with pytest.raises(pm.InvalidInputError):
        pm.refine_region(V, F, [[0, 1]], level=1)
    with pytest.raises(pm.NonManifoldError):
        pm.refine_region(*meshes.non_manifold_edge(), [0], level=1)
    with pytest.raises(pm.NonManifoldError):
        pm.refine_region(*meshes.pinched_spheres(), [0], level=1)
    with pytest.raises(pm.NonManifoldError):
        pm.refine_region(*meshes.flipped_face(), [0], level=1)
    with pytest.raises(pm.DegenerateFaceError):
        pm.refine_region(*meshes.zero_area_face(), [0], level=1)
    with pytest.raises(pm.InvalidInputError):
        pm.refine_region(*meshes.nan_vertex(), [0], level=1)


def test_refine_region_keeps_genus_and_isolated_vertices():
    V, F = meshes.torus()
    region = np.arange(0, len(F), 2)  # every other face: neighbours with 1, 2 and 3 split edges
    r = pm.refine_region(V, F, region, level=2)
    check(V, F, region, 2, r)
    report = pm.validate(r.V, r.F)
    assert report.genus == 1 and report.boundary_edges == 0
    V, F = meshes.loose_vertex()
    r = pm.refine_region(V, F, np.arange(5), level=1)
    loose = len(V) - 1
    assert r.base_face[loose] == -1
    assert np.array_equal(r.limit[loose], V[loose]) and not r.limit_normal[loose].any()


def test_refining_next_to_a_vertex_of_valence_2000_is_sound():
    # The limit of every vertex of a fan went through the O(valence^2) patch
    # of a face at the pole: 35 s here before vertex limits came from their masks.
    n = 2000
    angle = np.arange(n) * 2 * np.pi / n
    V = np.vstack([np.c_[np.cos(angle), np.sin(angle), 0.05 * np.sin(5 * angle)], [[0, 0, 1], [0, 0, -1]]])
    F = np.array([[i, (i + 1) % n, n] for i in range(n)] + [[(i + 1) % n, i, n + 1] for i in range(n)], np.int32)
    r = pm.refine_region(V, F, [0, 1, 2], level=2)
    assert pm.validate(r.V, r.F).is_closed_genus0
    limit = np.asarray(r.limit)
    assert np.isfinite(limit).all() and np.isfinite(np.asarray(r.limit_normal)).all()
    assert np.abs(limit[:n, 2]).max() < 0.05  # the ring's limit stays near the ring
