"""extract_feature(): a feature cut from a surface for pasting (thesis 5.2, DESIGN.md §4.5 step 1):
base surface, fold-free maps with shared boundary, feature frame, displacement grid, typed
selection errors, exact storage round trip."""
import numpy as np
import pytest

import meshes
import paramorph_native as pm


def signed_areas(uv, F):
    (ux, uy), (vx, vy) = (uv[F[:, 1]] - uv[F[:, 0]]).T, (uv[F[:, 2]] - uv[F[:, 0]]).T
    return ux * vy - uy * vx  # not np.cross: NumPy 2 dropped 2-vectors


def to_source(feature, X):
    """Feature-frame rows X -> source coordinates."""
    return feature.origin + X @ feature.axes.T


def node_uv(feature):
    r = feature.resolution
    j, i = np.meshgrid(np.arange(r), np.arange(r))  # [i, j]: row i along v, column j along u
    return feature.grid_origin + feature.grid_spacing * np.stack([j, i], axis=-1).reshape(-1, 2)


def check_maps(feature):
    """Both maps fold-free; the feature map's boundary is the base map's, bit for bit."""
    assert (signed_areas(feature.uv, feature.faces) > 0).all()
    assert (signed_areas(feature.base_uv, feature.faces) > 0).all()
    for loop in feature.boundary_loops:
        assert np.array_equal(feature.uv[loop], feature.base_uv[loop])
    boundary = np.concatenate(feature.boundary_loops)
    assert feature.radius == pytest.approx(np.linalg.norm(feature.base_uv[boundary], axis=1).max(), rel=0, abs=0)
    # The frame: a rotation, and the base map's area centroid at uv = 0.
    assert np.allclose(feature.axes.T @ feature.axes, np.eye(3), atol=1e-12)
    assert np.linalg.det(feature.axes) > 0
    a = signed_areas(feature.base_uv, feature.faces)
    centroid = (a[:, None] * feature.base_uv[feature.faces].mean(axis=1)).sum(0) / a.sum()
    assert np.abs(centroid).max() < 1e-9 * feature.radius


H, SIGMA, RADIUS = 0.1, 0.3, 0.9  # bump_plane: cut-off at 3 sigma, where the bump is 1.2e-4 h


@pytest.fixture(scope="module")
def plane_bump():
    V, F, faces = meshes.bump_plane(n=60, height=H, sigma=SIGMA, radius=RADIUS)
    return V, F, faces, pm.extract_feature(V, F, faces, resolution=64, backend="cpu")


def test_plane_bump_base_is_the_plane_and_normal_displacement_is_the_bump(plane_bump):
    V, F, faces, feature = plane_bump
    check_maps(feature)
    assert np.array_equal(np.sort(feature.source_faces), np.sort(faces))
    # The exact path: stored positions are the source's.
    assert np.allclose(to_source(feature, feature.vertices), V[feature.source_vertices], rtol=0, atol=1e-12)
    # Base: the plane z = 0 up to the bump's tail at the rim (z ~ 1e-4 h there, with slope
    # ~ 2 R / s**2 times that, which the thin-plate fill continues inwards: measured 2.1e-3 h).
    base = to_source(feature, feature.base_vertices)
    assert np.abs(base[:, 2]).max() < 5e-3 * H
    # Frame: n = +z (faces counter-clockwise seen from +z), origin near the bump's centre.
    assert feature.axes[:, 2] @ [0, 0, 1] > 1 - 1e-9
    assert np.linalg.norm(feature.origin[:2]) < 0.05
    # Displacement at every node inside the domain: the normal component is the bump's height
    # at the feature point it reaches (within the piecewise-linear mesh's own error, 1% of h).
    inside = feature.mask.ravel() == 1
    assert inside.sum() > 0.7 * np.pi / 4 * feature.resolution ** 2
    d = feature.displacement.reshape(-1, 3)[inside]
    s = pm.sample_feature(feature, node_uv(feature)[inside])
    assert np.allclose(s["displacement"], d, rtol=0, atol=1e-12)  # bilinear at a node = the node
    p = to_source(feature, s["position"])
    r = np.linalg.norm(p[:, :2], axis=1)
    assert np.abs(d[:, 2] - H * np.exp(-r ** 2 / SIGMA ** 2)).max() < 0.01 * H
    # Tangential part: the isometric feature map slides points only a little along the base
    # (measured 2.0e-2 h).
    assert np.linalg.norm(d[:, :2], axis=1).max() < 0.05 * H


def test_rebuild_at_feature_vertices(plane_bump):
    """base(uv_i) + frame(uv_i) @ bilinear displacement(uv_i) gives back the feature's vertices."""
    _, _, _, feature = plane_bump
    s = pm.sample_feature(feature, feature.uv)
    assert s["distance"].max() < 1e-12
    err = np.linalg.norm(s["position"] - feature.vertices, axis=1)
    assert err.max() < 0.02 * H, err.max()  # bilinear at resolution 64: measured 1.1e-2 h
    # Base through the base map at the base map's own uv: the base vertices.
    b = pm.sample_feature(feature, feature.base_uv)
    assert np.allclose(b["base"], feature.base_vertices, rtol=0, atol=1e-12)


def test_sphere_bump():
    h, sigma, cap = 0.05, 0.2, 0.6
    V, F, faces = meshes.bump_sphere(subdivisions=5, height=h, sigma=sigma, cap=cap)
    feature = pm.extract_feature(V, F, faces, resolution=64, backend="cpu")
    check_maps(feature)
    base = to_source(feature, feature.base_vertices)
    assert np.abs(np.linalg.norm(base, axis=1) - 1).max() < 0.01  # close to the unit sphere's cap
    assert feature.axes[:, 2] @ [0, 0, 1] > 0.999  # outward normal at the cap's centre
    inside = feature.mask.ravel() == 1
    s = pm.sample_feature(feature, node_uv(feature)[inside])
    p = to_source(feature, s["position"])
    theta = np.arccos(np.clip(p[:, 2] / np.linalg.norm(p, axis=1), -1, 1))
    d_n = feature.displacement.reshape(-1, 3)[inside, 2]
    bump = h * np.exp(-theta ** 2 / sigma ** 2)
    # The thin-plate base is not exactly the sphere (|B| - 1 up to 3.7e-3 = 7% of h, measured):
    # against the bump alone within 10% of h; against the bump over the actual base within 2%.
    assert np.abs(d_n - bump).max() < 0.1 * h
    b = np.linalg.norm(to_source(feature, s["base"]), axis=1)
    assert np.abs(d_n - (bump + 1 - b)).max() < 0.02 * h


def test_annulus_rib():
    height = 0.08
    V, F, faces = meshes.rib_plane(n=60, height=height, width=0.08, ring=0.5)
    errors = []
    for resolution in (64, 128):
        feature = pm.extract_feature(V, F, faces, resolution=resolution, backend="cpu")
        assert len(feature.boundary_loops) == 2
        check_maps(feature)
        # uv = 0 lies in the hole: the origin is the base's tangent plane continued there
        # (the rib's tails at the rims tilt the base by ~1e-3 rad).
        assert np.abs(feature.origin).max() < 0.05 and feature.axes[:, 2] @ [0, 0, 1] > 1 - 1e-5
        inside = feature.mask.ravel() == 1
        hole = np.linalg.norm(node_uv(feature), axis=1) < 0.2  # the inner rim is at r ~ 0.24
        assert inside.any() and not (inside & hole).any()
        s = pm.sample_feature(feature, feature.uv)
        errors.append(np.linalg.norm(s["position"] - feature.vertices, axis=1).max())
    # The rib is 3 grid cells wide at resolution 64: bilinear rebuild error 6.7% of its height
    # (measured), halving with the grid spacing.
    assert errors[0] < 0.1 * height and errors[1] < 0.7 * errors[0], errors


@pytest.mark.parametrize("factor, rel", [(1024.0, 1e-14), (1e3, 1e-7)])
def test_scale_invariance(factor, rel):
    """extract_feature works at unit mean edge length: a power-of-two scale reaches it with the
    same bits (equal to round-off); 1e3 perturbs the input by round-off, which the isometric
    solver's line searches amplify to ~1e-8 relative (measured 1.1e-8), hence 1e-7 there."""
    V, F, faces = meshes.bump_plane(n=30, height=H, sigma=SIGMA, radius=RADIUS)
    a = pm.extract_feature(V, F, faces, resolution=32, backend="cpu")
    b = pm.extract_feature(factor * V, F, faces, resolution=32, backend="cpu")
    scale = np.abs(a.displacement).max()
    assert np.abs(b.displacement - factor * a.displacement).max() <= rel * factor * scale
    assert np.array_equal(a.mask, b.mask)
    assert b.radius == pytest.approx(factor * a.radius, rel=rel)
    assert b.area == pytest.approx(factor ** 2 * a.area, rel=rel)
    assert np.allclose(b.axes, a.axes, rtol=0, atol=rel)


def test_round_trip_is_exact(plane_bump):
    feature = plane_bump[3]
    arrays = feature.to_arrays()
    assert all(isinstance(v, np.ndarray) for v in arrays.values())
    again = pm.Feature.from_arrays(arrays).to_arrays()
    assert arrays.keys() == again.keys()
    for key in arrays:
        assert arrays[key].dtype == again[key].dtype and np.array_equal(arrays[key], again[key]), key
    # ... and survives plain copies (as the add-on stores them).
    copied = pm.Feature.from_arrays({k: np.array(v).copy() for k, v in arrays.items()})
    assert np.array_equal(copied.displacement, feature.displacement)
    bad = dict(arrays, uv=arrays["uv"][:-1])
    with pytest.raises(pm.InvalidInputError, match="uv"):
        pm.Feature.from_arrays(bad)
    bad = dict(arrays, faces=arrays["faces"] + len(arrays["vertices"]))
    with pytest.raises(pm.InvalidInputError, match="faces"):
        pm.Feature.from_arrays(bad)
    bad = dict(arrays, displacement=arrays["displacement"][:, :-1])
    with pytest.raises(pm.InvalidInputError, match="displacement"):
        pm.Feature.from_arrays(bad)
    bad = {k: v for k, v in arrays.items() if k != "axes"}
    with pytest.raises(pm.InvalidInputError, match="axes"):
        pm.Feature.from_arrays(bad)


# --- selection errors ------------------------------------------------------------------------

@pytest.fixture(scope="module")
def small_bump():
    return meshes.bump_plane(n=20, height=H, sigma=SIGMA, radius=RADIUS)


def test_empty_and_whole_selections(small_bump):
    V, F, _ = small_bump
    with pytest.raises(pm.EmptySelectionError):
        pm.extract_feature(V, F, np.array([], np.int32))
    with pytest.raises(pm.WholeMeshSelectedError):
        pm.extract_feature(V, F, np.arange(len(F)))
    assert issubclass(pm.EmptySelectionError, ValueError) and issubclass(pm.SelectionTopologyError, pm.MeshError)


def test_bad_indices(small_bump):
    V, F, faces = small_bump
    with pytest.raises(pm.InvalidInputError, match="out of range"):
        pm.extract_feature(V, F, np.append(faces, len(F)))
    with pytest.raises(pm.InvalidInputError, match="twice"):
        pm.extract_feature(V, F, np.append(faces, faces[0]))
    with pytest.raises(pm.InvalidInputError):
        pm.extract_feature(V, F, np.append(faces, -1))
    with pytest.raises(pm.InvalidInputError, match="resolution"):
        pm.extract_feature(V, F, faces, resolution=1)
    # A grid far too large was allocated and crashed the process (65536) or
    # raised an untyped MemoryError (40000): refused before any allocation.
    for resolution in (2049, 40000, 65536, 2**31 - 1):
        with pytest.raises(pm.InvalidInputError, match="between 2 and 2048"):
            pm.extract_feature(V, F, faces, resolution=resolution)
    # The stored form is held to the same bound.
    arrays = pm.extract_feature(V, F, faces, resolution=8).to_arrays()
    arrays["displacement"] = np.zeros((2049, 2049, 3))
    arrays["mask"] = np.ones((2049, 2049), np.uint8)
    with pytest.raises(pm.InvalidInputError, match="2 <= r <= 2048"):
        pm.Feature.from_arrays(arrays)


def test_two_pieces_are_not_connected():
    V, F = meshes.plane_grid(20)
    c = meshes.face_centroids(V, F)
    faces = np.flatnonzero((np.linalg.norm(c[:, :2] - [-0.5, 0], axis=1) < 0.3) |
                           (np.linalg.norm(c[:, :2] - [0.5, 0], axis=1) < 0.3))
    with pytest.raises(pm.SelectionTopologyError, match="not connected"):
        pm.extract_feature(V, F, faces)


def test_three_boundary_loops():
    V, F = meshes.plane_grid(20)
    c = meshes.face_centroids(V, F)
    disc = np.linalg.norm(c[:, :2], axis=1) < 0.7
    holes = (np.linalg.norm(c[:, :2] - [-0.3, 0], axis=1) < 0.12) | (np.linalg.norm(c[:, :2] - [0.3, 0], axis=1) < 0.12)
    with pytest.raises(pm.SelectionTopologyError, match="has 3 boundary loops"):
        pm.extract_feature(V, F, np.flatnonzero(disc & ~holes))


def test_handle_on_a_torus():
    """A band around the tube plus a band around the hole: a torus with a disc cut out."""
    n, m = 16, 8
    V, F = meshes.torus(n=n, m=m)
    a = np.arange(len(F)) // 2 // m  # around the hole (u index)
    b = np.arange(len(F)) // 2 % m   # around the tube (v index)
    faces = np.flatnonzero((a < 2) | (b < 2))
    with pytest.raises(pm.SelectionTopologyError, match="has handles"):
        pm.extract_feature(V, F, faces)
    # One band alone is an annulus: accepted.
    feature = pm.extract_feature(V, F, np.flatnonzero(a < 3), resolution=16, backend="cpu")
    assert len(feature.boundary_loops) == 2
    check_maps(feature)


def test_non_manifold_source():
    V, F = meshes.non_manifold_edge()
    with pytest.raises(pm.NonManifoldError):
        pm.extract_feature(V, F, np.array([0]))


def test_progress_and_cancel(small_bump):
    V, F, faces = small_bump
    seen = []
    pm.extract_feature(V, F, faces, resolution=16, backend="cpu", progress=lambda f, s: seen.append((f, s)))
    fractions = [f for f, _ in seen]
    assert fractions[0] == 0.0 and fractions[-1] == 1.0 and fractions == sorted(fractions)
    with pytest.raises(pm.Cancelled):
        pm.extract_feature(V, F, faces, progress=lambda f, s: False)
