"""Spherical overlay of two sphere maps (thesis 4.4): pm.overlay -> MergedTopology.

Every case goes through check_merged(), which asserts what the merged
topology promises: spherical areas sum to 4 pi, no folded triangle, a closed
consistently oriented 2-manifold of Euler characteristic 2, every input vertex
present once, barycentric coordinates that reproject onto the merged vertices,
and every edge of A and of B covered by a chain of merged edges (the merged
triangles of the two faces of an input edge meet along a path from one end of
the edge to the other)."""
import numpy as np
import pytest

import meshes
import paramorph_native as pm

TOL = 1e-6  # the default merge_tolerance
THIN = 0.5  # pm overlay's sliver bound: no triangle thinner than THIN * the tolerance used


def rotation(seed, angle=None):
    """A random rotation, or one by `angle` radians about a random axis."""
    rng = np.random.default_rng(seed)
    axis = rng.normal(size=3)
    axis /= np.linalg.norm(axis)
    if angle is None:
        angle = rng.uniform(0.5, 3.0)
    K = np.array([[0, -axis[2], axis[1]], [axis[2], 0, -axis[0]], [-axis[1], axis[0], 0]])
    return np.eye(3) + np.sin(angle) * K + (1 - np.cos(angle)) * K @ K


def spherical_areas(V, F):
    """Signed spherical triangle areas (Van Oosterom & Strackee)."""
    a, b, c = V[F[:, 0]], V[F[:, 1]], V[F[:, 2]]
    det = np.einsum("ij,ij->i", a, np.cross(b, c))
    dots = np.einsum("ij,ij->i", a, b) + np.einsum("ij,ij->i", b, c) + np.einsum("ij,ij->i", c, a)
    return 2 * np.arctan2(det, 1 + dots)


def orientations(V, F):
    """det(a, b, c) through edge differences, (b - a) x (c - a) . (a + b + c):
    the differences of nearby unit vectors are exact, so tiny triangles keep
    their sign (the plain triple product's rounding is ~1e-16 absolute)."""
    a, b, c = V[F[:, 0]], V[F[:, 1]], V[F[:, 2]]
    return np.einsum("ij,ij->i", np.cross(b - a, c - a), a + b + c)


def altitudes(V, F):
    """Per triangle: twice its flat area over its longest side (edge differences)."""
    a, b, c = V[F[:, 0]], V[F[:, 1]], V[F[:, 2]]
    longest = np.sqrt(np.maximum.reduce([((b - a) ** 2).sum(1), ((c - b) ** 2).sum(1), ((a - c) ** 2).sum(1)]))
    return np.linalg.norm(np.cross(b - a, c - a), axis=1) / longest


def half_edges(F):
    return np.concatenate([F[:, [0, 1]], F[:, [1, 2]], F[:, [2, 0]]])


def reproject(X, F, face, bary):
    p = np.einsum("ij,ijk->ik", bary, X[F[face]])
    return p / np.linalg.norm(p, axis=1, keepdims=True)


def check_chains(r, X, F, source_face, vertex_of, name):
    """Every input edge is a chain of merged edges: the merged edges between
    triangles of its two faces form a path from one end to the other, and
    merged triangles of faces that share no edge never meet along an edge."""
    K = len(r.F)
    he = half_edges(r.F)
    tri = np.tile(np.arange(K), 3)
    order = {(int(u), int(v)): int(t) for (u, v), t in zip(he, tri)}
    twin_tri = np.array([order[(int(v), int(u))] for u, v in he])
    fa, fb = source_face[tri], source_face[twin_tri]
    seam = fa < fb  # each seam edge once
    pairs = {}
    for (u, v), f, g in zip(he[seam], fa[seam], fb[seam]):
        pairs.setdefault((int(f), int(g)), []).append((int(u), int(v)))
    input_edges = {}
    for f in range(len(F)):
        for k in range(3):
            u, v = int(F[f, k]), int(F[f, (k + 1) % 3])
            input_edges.setdefault((min(u, v), max(u, v)), []).append(f)
    expected = {tuple(sorted(fs)): e for e, fs in input_edges.items()}
    assert set(pairs) == set(expected), f"{name}: merged seams between faces that share no edge"
    for faces, (u, v) in expected.items():
        links = pairs[faces]
        adjacency = {}
        for p, q in links:
            adjacency.setdefault(p, []).append(q)
            adjacency.setdefault(q, []).append(p)
        ends = [w for w, n in adjacency.items() if len(n) == 1]
        assert all(len(n) <= 2 for n in adjacency.values()), f"{name}: edge {u}-{v} branches"
        assert sorted(ends) == sorted([vertex_of[u], vertex_of[v]]), f"{name}: edge {u}-{v} not a path between its ends"
        # A path visits every link once: walk it.
        seen, prev, at = 1, -1, vertex_of[u]
        while at != vertex_of[v]:
            nxt = [w for w in adjacency[at] if w != prev][0]
            prev, at, seen = at, nxt, seen + 1
        assert seen == len(links) + 1, f"{name}: edge {u}-{v} has a loose piece"


def check_merged(r, XA, FA, XB, FB, tol=TOL, slivers=False):
    M, K = len(r.V), len(r.F)
    # The tolerance used: the one asked for unless a map has thinner faces.
    assert 1e-15 <= r.stats.merge_tolerance <= tol
    tol = r.stats.merge_tolerance
    # How far merging moved a vertex off its input points and arcs: the
    # tolerance, or a few where a turned-over tiny cell was repaired.
    assert r.stats.max_merge_distance <= 16 * tol
    moved = max(tol, r.stats.max_merge_distance)
    assert r.V.dtype == np.float64 and r.F.dtype == np.int32 and r.F.shape == (K, 3)
    np.testing.assert_allclose(np.linalg.norm(r.V, axis=1), 1.0, atol=1e-14)
    s = r.stats
    assert s.folded == 0 and s.open_edges == 0 and s.degenerate_cells == 0
    # Covers the sphere once, no fold (exact count above, robust floating sign here).
    assert abs(spherical_areas(r.V, r.F).sum() - 4 * np.pi) < 1e-9
    assert (orientations(r.V, r.F) > 0).all()
    # Closed, consistently oriented 2-manifold, Euler characteristic 2.
    he = half_edges(r.F)
    keys = he[:, 0].astype(np.int64) * M + he[:, 1]
    assert len(np.unique(keys)) == 3 * K, "a directed edge is used twice"
    assert np.isin(he[:, 1].astype(np.int64) * M + he[:, 0], keys).all(), "an edge has one face"
    assert M - 3 * K // 2 + K == 2
    assert len(np.unique(r.F)) == M, "a merged vertex is in no triangle"
    # Every input vertex is one merged vertex, at its place (within tol).
    for X, vertex_of, kinds in ((XA, r.vertex_of_a, (0, 2)), (XB, r.vertex_of_b, (1, 2))):
        assert len(vertex_of) == len(X) and len(np.unique(vertex_of)) == len(X)
        assert np.isin(r.vertex_kind[vertex_of], kinds).all()
        assert np.linalg.norm(r.V[vertex_of] - X / np.linalg.norm(X, axis=1, keepdims=True), axis=1).max() <= moved + 1e-15
    np.testing.assert_array_equal(r.vertex_of_a, np.arange(len(XA)))
    assert ((r.vertex_kind == 0) | (r.vertex_kind == 2)).sum() == len(XA)
    assert ((r.vertex_kind == 1) | (r.vertex_kind == 2)).sum() == len(XB)
    # Barycentric coordinates: convex, and they reproject onto V.
    for X, F, face, bary, source, corner in ((XA, FA, r.face_a, r.bary_a, r.source_face_a, r.corner_bary_a),
                                             (XB, FB, r.face_b, r.bary_b, r.source_face_b, r.corner_bary_b)):
        assert bary.shape == (M, 3) and corner.shape == (K, 9)
        assert (bary >= 0).all() and np.allclose(bary.sum(1), 1, atol=1e-12)
        assert np.linalg.norm(reproject(X, F, face, bary) - r.V, axis=1).max() <= moved + 1e-14
        cb = corner.reshape(K * 3, 3)
        assert (cb >= 0).all() and np.allclose(cb.sum(1), 1, atol=1e-12)
        at = reproject(X, F, np.repeat(source, 3), cb)
        assert np.linalg.norm(at - r.V[r.F.reshape(-1)], axis=1).max() <= moved + 1e-14
    # No slivers: every triangle at least THIN tolerances high on the sphere
    # (unless a map's own faces are that thin: `slivers` allowed then).
    h = altitudes(r.V, r.F)
    assert s.min_altitude == pytest.approx(h.min(), rel=1e-6, abs=1e-300)
    assert s.thin_triangles == (h < THIN * tol).sum()
    if not slivers:
        assert s.thin_triangles == 0 and h.min() >= THIN * tol
    check_chains(r, XA, FA, r.source_face_a, r.vertex_of_a, "A")
    check_chains(r, XB, FB, r.source_face_b, r.vertex_of_b, "B")
    # Euler on the arrangement: faces = |FA| + |FB| + crossings - 2 before merging.
    assert s.cells == len(FA) + len(FB) + s.crossings - 2


def sphere_map_of(V, F):
    X = pm.sphere_map(V, F).positions
    return X / np.linalg.norm(X, axis=1, keepdims=True)


# --- generic cases -----------------------------------------------------------------

def test_two_different_geodesic_spheres():
    XA, FA = meshes.icosphere(2)
    XB, FB = meshes.geodesic_sphere(5)
    XB = XB @ rotation(1).T
    r = pm.overlay(XA, FA, XB, FB)
    check_merged(r, XA, FA, XB, FB)
    # Generic position: nothing merged, every crossing is a vertex, and the
    # merged faces follow from Euler (K = 2 M - 4, M = VA + VB + crossings).
    assert r.stats.merged_vertices == 0 and r.stats.crossings > 0
    assert len(r.V) == len(XA) + len(XB) + r.stats.crossings
    assert np.bincount(r.vertex_kind, minlength=4).tolist() == [len(XA), len(XB), 0, r.stats.crossings]
    assert len(r.F) == len(FA) + len(FB) + 2 * r.stats.crossings + 4


@pytest.mark.parametrize("seed", [0, 1])
def test_sphere_maps_of_noisy_blobs(seed):
    VA, FA = meshes.noisy_blob(2, seed=seed)
    VB, FB = meshes.tentacle_sphere(2, tentacles=3, length=1.0)
    XA, XB = sphere_map_of(VA, FA), sphere_map_of(VB, FB) @ rotation(seed).T
    r = pm.overlay(XA, FA, XB, FB)
    check_merged(r, XA, FA, XB, FB)
    # Swapping the maps gives the same arrangement (the perturbation is B's).
    r2 = pm.overlay(XB, FB, XA, FA)
    check_merged(r2, XB, FB, XA, FA)
    assert r2.stats.crossings == r.stats.crossings and len(r2.F) == len(r.F)


# --- degenerate cases ------------------------------------------------------------------

def test_a_map_with_itself_is_the_map():
    XA, FA = meshes.icosphere(2)
    r = pm.overlay(XA, FA, XA, FA)
    check_merged(r, XA, FA, XA, FA)
    assert (r.vertex_kind == 2).all() and len(r.V) == len(XA)
    assert r.stats.max_merge_distance < 1e-15
    np.testing.assert_allclose(r.V, XA, rtol=0, atol=1e-15)  # renormalised: an ulp
    np.testing.assert_array_equal(r.vertex_of_b, np.arange(len(XA)))
    assert canonical(r.F) == canonical(FA)


def canonical(F):
    """Triangles as a set, each rotated to start at its smallest index."""
    F = np.asarray(F)
    k = np.argmin(F, axis=1)
    rows = np.arange(len(F))
    return {tuple(t) for t in np.stack([F[rows, k], F[rows, (k + 1) % 3], F[rows, (k + 2) % 3]], 1).tolist()}


def test_refinement_with_vertices_on_every_edge_and_vertex():
    # B = A subdivided: B's vertices lie on A's vertices and (within rounding)
    # on the middles of A's edges, B's edges run along A's. The overlay is B.
    XA, FA = meshes.icosphere(2)
    XB, FB = meshes.icosphere(3)
    for X1, F1, X2, F2 in ((XA, FA, XB, FB), (XB, FB, XA, FA)):
        r = pm.overlay(X1, F1, X2, F2)
        check_merged(r, X1, F1, X2, F2)
        assert len(r.F) == len(FB) and len(r.V) == len(XB)
        assert (r.vertex_kind == 2).sum() == len(XA) and (r.vertex_kind == 3).sum() == 0


def test_vertices_exactly_on_edges_of_a_great_circle():
    # A cube-like octahedron split along the equator z = 0: B's equator
    # vertices lie exactly (z == 0.0) on A's equator edges.
    XA, FA = octahedron()
    angles = np.linspace(0, 2 * np.pi, 9)[:-1] + 0.1
    ring = np.stack([np.cos(angles), np.sin(angles), np.zeros_like(angles)], 1)
    XB = np.vstack([[[0, 0, 1], [0, 0, -1]], ring])
    n = len(angles)
    FB = np.array([[0, 2 + i, 2 + (i + 1) % n] for i in range(n)] +
                  [[1, 2 + (i + 1) % n, 2 + i] for i in range(n)], dtype=np.int32)
    r = pm.overlay(XA, FA, XB, FB)
    check_merged(r, XA, FA, XB, FB)
    # Poles coincide, the equator is one chain through A's 4 and B's 8
    # points, no crossing survives.
    assert (r.vertex_kind == 2).sum() == 2 and (r.vertex_kind == 3).sum() == 0
    assert len(r.V) == 6 + 10 - 2 and r.stats.max_merge_distance < 1e-15


def octahedron():
    X = np.array([[0, 0, 1], [0, 0, -1], [1, 0, 0], [0, 1, 0], [-1, 0, 0], [0, -1, 0]], dtype=float)
    F = np.array([[0, 2, 3], [0, 3, 4], [0, 4, 5], [0, 5, 2],
                  [1, 3, 2], [1, 4, 3], [1, 5, 4], [1, 2, 5]], dtype=np.int32)
    return X, F


@pytest.mark.parametrize("angle", [1e-15, 1e-12, 1e-10, 1e-7])
def test_tiny_rotations_merge_back_to_the_map(angle):
    # B = A turned by far less than the tolerance: no cracks, folds or
    # slivers, just A again with every vertex of both.
    XA, FA = meshes.icosphere(3)
    XB = XA @ rotation(5, angle).T
    r = pm.overlay(XA, FA, XB, FA)
    check_merged(r, XA, FA, XB, FA)
    assert (r.vertex_kind == 2).all() and canonical(r.F) == canonical(FA)
    # Refined copy turned: the overlay is the refinement.
    XS, FS = meshes.icosphere(4)
    r = pm.overlay(XA, FA, XS @ rotation(6, angle).T, FS)
    check_merged(r, XA, FA, XS @ rotation(6, angle).T, FS)
    assert len(r.F) == len(FS) and (r.vertex_kind == 3).sum() == 0


@pytest.mark.parametrize("angle", [1.5e-6, 2e-6, 5e-6, 3e-5, 1e-3])
def test_rotations_near_the_tolerance_stay_valid(angle):
    # Between the tolerance and visible size the overlay keeps real but tiny
    # cells; they must still be a valid, fold-free triangulation.
    XA, FA = meshes.icosphere(3)
    XS, FS = meshes.icosphere(4)
    for seed in range(3):
        R = rotation(10 + seed, angle)
        r = pm.overlay(XA, FA, XA @ R.T, FA)
        check_merged(r, XA, FA, XA @ R.T, FA)
        r = pm.overlay(XA, FA, XS @ R.T, FS)
        check_merged(r, XA, FA, XS @ R.T, FS)


def near_arcs(XA, FA, XB, d, seed, count=40):
    """XB with `count` vertices moved to `d` radians off A's nearest arc (on
    either side, the foot inside the arc): a vertex of B almost on an edge of
    A, crossings of that edge with the vertex's edges within ~d of it."""
    E = np.unique(np.sort(half_edges(FA), axis=1), axis=0)
    p0, p1 = XA[E[:, 0]], XA[E[:, 1]]
    n = np.cross(p0, p1)
    n /= np.linalg.norm(n, axis=1, keepdims=True)
    rng = np.random.default_rng(seed)
    XB, moved = XB.copy(), 0
    for v in rng.permutation(len(XB)):
        s = n @ XB[v]
        foot = XB[v] - s[:, None] * n
        foot /= np.linalg.norm(foot, axis=1, keepdims=True)
        inside = (np.einsum("ij,ij->i", np.cross(n, p0), foot) >= 0) & \
                 (np.einsum("ij,ij->i", np.cross(p1, n), foot) >= 0)
        e = np.argmin(np.where(inside, np.abs(s), np.inf))
        if not inside[e] or abs(s[e]) > 0.01:
            continue
        Q = foot[e] + d * rng.choice([-1, 1]) * n[e]
        XB[v] = Q / np.linalg.norm(Q)
        moved += 1
        if moved == count:
            break
    return XB


def near_vertices(XA, XB, d, seed, count=40):
    """XB with up to `count` vertices moved to `d` radians from A's nearest
    vertex in a random direction: two vertices almost coincide, and the
    crossings of their edges lie within ~d of each other."""
    rng = np.random.default_rng(seed)
    XB = XB.copy()
    for v in rng.permutation(len(XB))[:3 * count]:
        u = np.argmax(XA @ XB[v])
        if np.linalg.norm(XB[v] - XA[u]) > 0.02:
            continue
        t = rng.normal(size=3)
        t -= (t @ XA[u]) * XA[u]
        Q = XA[u] + d * t / np.linalg.norm(t)
        XB[v] = Q / np.linalg.norm(Q)
    return XB


def ellipsoid(X, axes):
    return X * np.asarray(axes)


def positions(V, F, face, bary):
    """Each merged vertex on a mesh, as morph() makes it: its barycentric
    coordinates in its face, applied to the mesh's vertices."""
    return np.einsum("ij,ijk->ik", bary, V[F[face]])


@pytest.mark.parametrize("case", ["arc", "vertex", "turned"])
@pytest.mark.parametrize("d", [1e-10, 1e-9, 1e-8, 1e-7, 1.5e-6, 3e-6])
def test_near_degenerate_inputs_make_no_slivers(case, d):
    # A vertex of B within d of an arc of A, two vertices within d (their
    # crossings within ~d of each other), B = A turned by d: below the
    # tolerance they merge, above it they stay; either way no triangle is
    # thinner than THIN tolerances on the sphere (check_merged), and the
    # per-side 3D positions (two ellipsoids the maps stand for) have no face
    # that validate() calls degenerate.
    XA, FA = meshes.icosphere(3)
    if case == "turned":
        XB, FB = XA, FA
        XB_moved = XA @ rotation(7, d).T
    else:
        XB, FB = meshes.geodesic_sphere(7)
        XB = XB @ rotation(1).T
        XB_moved = near_arcs(XA, FA, XB, d, seed=2) if case == "arc" else near_vertices(XA, XB, d, seed=2)
    r = pm.overlay(XA, FA, XB_moved, FB)
    check_merged(r, XA, FA, XB_moved, FB)
    if d < TOL:  # merged: every near vertex lies on the arc or vertex
        assert r.stats.merged_vertices > 0 and r.stats.max_merge_distance <= TOL
    assert pm.validate(r.V, r.F).degenerate_faces.size == 0
    VA3, VB3 = ellipsoid(XA, (1.0, 0.6, 1.4)), ellipsoid(XB, (1.3, 0.9, 0.7))
    for V, F, face, bary, source, corner in ((VA3, FA, r.face_a, r.bary_a, r.source_face_a, r.corner_bary_a),
                                             (VB3, FB, r.face_b, r.bary_b, r.source_face_b, r.corner_bary_b)):
        P = positions(V, F, face, bary)
        assert pm.validate(P, r.F).degenerate_faces.size == 0
        # Every merged triangle lies in its source face: its corners there
        # are where the per-vertex coordinates put them.
        at = np.einsum("ij,ijk->ik", corner.reshape(-1, 3), V[F[np.repeat(source, 3)]])
        diagonal = np.linalg.norm(np.ptp(V, axis=0))
        assert np.abs(at - P[r.F.reshape(-1)]).max() < 1e-9 * diagonal


def test_merge_tolerance_decides_what_is_one_point():
    XA, FA = meshes.icosphere(2)
    XB = XA @ rotation(3, 1e-7).T
    apart = pm.overlay(XA, FA, XB, FA, merge_tolerance=1e-9)  # 1e-7 > 1e-9: two vertices each
    check_merged(apart, XA, FA, XB, FA, tol=1e-9)
    assert (apart.vertex_kind == 2).sum() == 0 and apart.stats.merge_tolerance == 1e-9
    together = pm.overlay(XA, FA, XB, FA)  # the default, 1e-6
    check_merged(together, XA, FA, XB, FA)
    assert together.stats.merge_tolerance == 1e-6
    assert (together.vertex_kind == 2).all() and canonical(together.F) == canonical(FA)


def test_thin_faces_lower_the_tolerance_and_nothing_breaks():
    # A conformal map of long tentacles (from the Tutte start: init "auto"
    # would not squeeze them) squeezes faces to altitudes of ~1e-12: merging
    # at 1e-9 would have to join vertices of that map, so the tolerance drops
    # below its detail, and the overlay stays valid.
    V, F = meshes.tentacle_sphere(2, tentacles=4, length=4.0)
    X = pm.sphere_map(V, F, init="stereographic").positions
    X /= np.linalg.norm(X, axis=1, keepdims=True)
    XI, FI = meshes.icosphere(3)
    XI = XI @ rotation(1).T
    r = pm.overlay(X, F, XI, FI)
    assert r.stats.merge_tolerance < 1e-11
    check_merged(r, X, F, XI, FI)
    # The same map against itself turned by about its own detail cannot be
    # resolved in double precision: a valid result or an error, never a
    # broken mesh.
    XB = X @ rotation(2, 1e-12).T
    try:
        r = pm.overlay(X, F, XB, F)
    except pm.InvalidInputError as error:
        assert "nearly coincide" in str(error)
    else:
        check_merged(r, X, F, XB, F)


# --- input checks -------------------------------------------------------------------

def test_errors():
    XA, FA = meshes.icosphere(2)
    folded = XA.copy()
    folded[FA[0, 0]] = -folded[FA[0, 0]]
    with pytest.raises(pm.InvalidInputError, match="sphere_b: the map folds [0-9]+ faces"):
        pm.overlay(XA, FA, folded, FA)
    with pytest.raises(pm.InvalidInputError, match="not unit vectors"):
        pm.overlay(XA * 1.01, FA, XA, FA)
    with pytest.raises(pm.InvalidInputError, match="shape"):
        pm.overlay(XA[:, :2], FA, XA, FA)
    with pytest.raises(pm.InvalidInputError, match="out of range"):
        pm.overlay(XA, FA, XA, FA + len(XA))
    with pytest.raises(pm.InvalidInputError, match="merge_tolerance"):
        pm.overlay(XA, FA, XA, FA, merge_tolerance=-1.0)
    Vd, Fd = meshes.open_disc()
    with pytest.raises(pm.NotClosedError, match="sphere_a"):
        pm.overlay(Vd / np.linalg.norm(Vd, axis=1, keepdims=True), Fd, XA, FA)
    Vt, Ft = meshes.torus()
    with pytest.raises(pm.NotGenusZeroError):
        pm.overlay(XA, FA, Vt / np.linalg.norm(Vt, axis=1, keepdims=True), Ft)
    with pytest.raises(pm.InvalidInputError, match="covers the sphere 2 times"):
        pm.overlay(*double_cover(), XA, FA)
    with pytest.raises(pm.Cancelled):
        pm.overlay(XA, FA, XA, FA, progress=lambda fraction, stage: False)


def double_cover():
    """A closed genus-0 mesh whose positive faces wrap the sphere twice: a
    bipyramid over 8 equator points that go around the equator twice in
    quarter turns, the poles joined to all of them."""
    n = 8
    angles = np.arange(n) * np.pi / 2 + 0.1 * (np.arange(n) >= 4)
    ring = np.stack([np.cos(angles), np.sin(angles), np.zeros(n)], 1)
    X = np.vstack([[[0, 0, 1], [0, 0, -1]], ring])
    F = np.array([[0, 2 + i, 2 + (i + 1) % n] for i in range(n)] +
                 [[1, 2 + (i + 1) % n, 2 + i] for i in range(n)], dtype=np.int32)
    return X, F


def test_progress_is_reported():
    XA, FA = meshes.icosphere(2)
    seen = []
    pm.overlay(XA, FA, XA @ rotation(2).T, FA, progress=lambda fraction, stage: seen.append(fraction) or True)
    assert seen[0] == 0.0 and seen[-1] == 1.0 and seen == sorted(seen)
