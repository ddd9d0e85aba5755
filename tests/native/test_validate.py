"""validate() / require_closed_genus0() on the named meshes of meshes.py.

Every validator is checked on meshes that must trip it and on meshes that
must not (a validator that checks the wrong thing is a classic bug), and the
mesh factory itself is checked for the properties its docstrings promise.
"""
import re

import numpy as np
import pytest

import meshes
import paramorph_native as pm

CLOSED = sorted(meshes.FAMILIES_CLOSED)
INDEX_ARRAYS = ["non_manifold_edges", "non_manifold_edge_vertices", "non_manifold_vertices",
                "degenerate_faces", "isolated_vertices", "inconsistent_orientation_edges",
                "inconsistent_orientation_edge_vertices"]
COUNTS = ["vertices", "faces", "edges", "components", "boundary_loops", "boundary_edges",
          "euler_characteristic", "genus", "is_closed_genus0"]


def unique_edges(F):
    """(E, 2) sorted undirected edges and, per face corner k, the edge opposite k."""
    half = np.concatenate([F[:, [1, 2]], F[:, [2, 0]], F[:, [0, 1]]])
    edges, inverse = np.unique(np.sort(half, axis=1), axis=0, return_inverse=True)
    return edges, inverse.reshape(3, -1).T


def concave_edge_count(V, F):
    """Interior edges where the surface folds inwards (the far vertex of one
    face lies above the plane of the other); zero exactly for convex shapes."""
    _, face_edge = unique_edges(F)
    by_edge = np.argsort(face_edge.ravel(), kind="stable")
    f = by_edge // 3
    f1, f2 = f[0::2], f[1::2]                       # closed manifold: two faces per edge
    normal = np.cross(V[F[f1, 1]] - V[F[f1, 0]], V[F[f1, 2]] - V[F[f1, 0]])
    far = V[F[f2, by_edge[1::2] % 3]]               # corner of f2 opposite the shared edge
    height = np.einsum("ij,ij->i", normal / np.linalg.norm(normal, axis=1)[:, None], far - V[F[f1, 0]])
    scale = np.linalg.norm(V.max(0) - V.min(0))
    return int((height > 1e-9 * scale).sum())


def triangle_angles_deg(V, F):
    a, b, c = V[F[:, 0]], V[F[:, 1]], V[F[:, 2]]

    def angle(p, q, r):
        u, w = q - p, r - p
        cos = np.einsum("ij,ij->i", u, w) / np.linalg.norm(u, axis=1) / np.linalg.norm(w, axis=1)
        return np.degrees(np.arccos(np.clip(cos, -1, 1)))

    return np.stack([angle(a, b, c), angle(b, c, a), angle(c, a, b)], 1)


def face_areas(V, F):
    return 0.5 * np.linalg.norm(np.cross(V[F[:, 1]] - V[F[:, 0]], V[F[:, 2]] - V[F[:, 0]]), axis=1)


# --- the mesh factory keeps its promises ------------------------------------------

@pytest.mark.parametrize("name", CLOSED)
def test_closed_families_are_closed_genus0_and_outward(name):
    V, F = meshes.FAMILIES_CLOSED[name]()
    assert V.dtype == np.float64 and V.ndim == 2 and V.shape[1] == 3
    assert F.dtype == np.int32 and F.ndim == 2 and F.shape[1] == 3
    assert len(F) < 20000, "default sizes stay small for parametrized tests"
    report = pm.validate(V, F)
    assert report.is_closed_genus0, report
    assert (report.genus, report.components, report.boundary_loops, report.boundary_edges) == (0, 1, 0, 0)
    assert report.euler_characteristic == 2
    assert 2 * report.edges == 3 * report.faces
    for name_ in INDEX_ARRAYS:
        assert getattr(report, name_).size == 0, name_
    assert meshes.signed_volume(V, F) > 0, "faces must face outwards"
    pm.require_closed_genus0(V, F)


@pytest.mark.parametrize("name", CLOSED)
def test_closed_families_are_deterministic(name):
    (V1, F1), (V2, F2) = meshes.FAMILIES_CLOSED[name](), meshes.FAMILIES_CLOSED[name]()
    assert np.array_equal(V1, V2) and np.array_equal(F1, F2)


def test_convexity_of_each_family():
    assert concave_edge_count(*meshes.icosphere(3)) == 0
    for name in ["noisy_blob", "tentacle_sphere", "cad_box"]:
        assert concave_edge_count(*meshes.FAMILIES_CLOSED[name]()) > 0, name


def test_tentacles_are_long_and_thin():
    V, F = meshes.tentacle_sphere(4, tentacles=6, length=4.0)
    axes = meshes.tentacle_directions(6, seed=1)
    along = V @ axes.T                                             # (n, 6)
    nearest = np.argmax(along, axis=1)
    height = along[np.arange(len(V)), nearest]
    off_axis = np.linalg.norm(V - height[:, None] * axes[nearest], axis=1)
    finger = height > 1.5                                          # well outside the unit body
    assert set(nearest[finger]) == set(range(6)), "every tentacle is there"
    for k in range(6):
        assert 4.5 < height[nearest == k].max() < 5.5, "3-5 body radii beyond the body"
    assert off_axis[finger].max() < 0.25, "fingers are thin (body radius 1)"


def test_cad_box_is_planar_axis_aligned_with_sharp_edges():
    V, F = meshes.cad_box(10)
    n = np.cross(V[F[:, 1]] - V[F[:, 0]], V[F[:, 2]] - V[F[:, 0]])
    n /= np.linalg.norm(n, axis=1)[:, None]
    assert np.allclose(np.sort(np.abs(n), axis=1), [0, 0, 1]), "every face is axis-aligned"
    # Exactly the 6 box directions plus nothing else, and a raised boss on top.
    assert len(np.unique(np.round(n).astype(int), axis=0)) == 6
    top = V[:, 2].max()
    assert top > 0.5 + 1e-9 and np.isclose(V[:, 2].min(), -0.5)


def test_bad_triangulation_is_bad():
    V, F = meshes.bad_triangulation()
    angles = triangle_angles_deg(V, F)
    areas = face_areas(V, F)
    assert angles.min() < 1.0, "slivers"
    assert angles.max() > 170.0, "very obtuse triangles"
    assert areas.max() / areas.min() > 1e3, "mixed sizes"


@pytest.mark.parametrize("target", [1000, 10000, 100000])
def test_sized_sphere_mesh_hits_its_target(target):
    V, F = meshes.sized_sphere_mesh(target)
    assert abs(len(F) - target) / target < 0.1
    assert pm.validate(V, F).is_closed_genus0
    assert meshes.signed_volume(V, F) > 0


def test_geodesic_sphere_counts():
    for frequency in [1, 2, 3, 7]:
        V, F = meshes.geodesic_sphere(frequency)
        assert len(F) == 20 * frequency ** 2
        assert len(V) == 10 * frequency ** 2 + 2      # Euler: V = F / 2 + 2
        assert np.allclose(np.linalg.norm(V, axis=1), 1.0)


# --- reports --------------------------------------------------------------------------

def test_report_of_an_open_disc():
    V, F = meshes.open_disc()
    r = pm.validate(V, F)
    assert (r.boundary_loops, r.components, r.genus) == (1, 1, 0)
    assert r.boundary_edges > 0 and not r.is_closed_genus0
    assert r.euler_characteristic == 1


def test_report_of_a_torus():
    r = pm.validate(*meshes.torus())
    assert (r.genus, r.euler_characteristic, r.boundary_loops) == (1, 0, 0)
    assert not r.is_closed_genus0


def test_report_of_two_spheres():
    r = pm.validate(*meshes.two_spheres())
    assert r.components == 2 and r.genus == -1 and not r.is_closed_genus0


def test_report_lists_the_non_manifold_edge_by_its_vertices():
    V, F = meshes.non_manifold_edge()
    r = pm.validate(V, F)
    assert r.non_manifold_edges.size == 1
    assert r.non_manifold_edge_vertices.tolist() == [sorted(F[0, :2].tolist())]
    assert r.non_manifold_vertices.size == 0 and r.genus == -1


def test_report_lists_the_pinched_vertex():
    r = pm.validate(*meshes.pinched_spheres())
    assert r.non_manifold_vertices.tolist() == [0]
    assert r.non_manifold_edges.size == 0 and r.components == 1


def test_report_lists_the_flipped_face_edges():
    V, F = meshes.flipped_face(5)
    r = pm.validate(V, F)
    assert sorted(map(tuple, r.inconsistent_orientation_edge_vertices.tolist())) == \
        sorted(tuple(sorted(F[5, [i, (i + 1) % 3]].tolist())) for i in range(3))


def test_report_lists_zero_area_face_and_loose_vertex():
    assert pm.validate(*meshes.zero_area_face()).degenerate_faces.tolist() == [10]
    V, F = meshes.loose_vertex()
    r = pm.validate(V, F)
    assert r.isolated_vertices.tolist() == [len(V) - 1]
    assert r.genus == 0 and not r.is_closed_genus0


@pytest.mark.parametrize("name", sorted(meshes.FAMILIES_BROKEN))
def test_broken_families_are_not_closed_genus0(name):
    assert not pm.validate(*meshes.FAMILIES_BROKEN[name]()).is_closed_genus0


def test_report_arrays_are_int32_and_read_only_attributes():
    r = pm.validate(*meshes.non_manifold_edge())
    for name in INDEX_ARRAYS:
        assert getattr(r, name).dtype == np.int32, name
    assert r.non_manifold_edge_vertices.shape == (1, 2)
    assert pm.validate(*meshes.icosphere(1)).non_manifold_edge_vertices.shape == (0, 2)
    with pytest.raises(AttributeError):
        r.genus = 0
    assert re.search(r"genus=-1 .*non_manifold_edges=1 .*is_closed_genus0=False", repr(r))


def test_float32_and_int64_give_the_same_report():
    V, F = meshes.zero_area_face()
    V32 = V.astype(np.float32)  # the same values in both dtypes
    tolerance = 1e-8  # float32 rounding leaves "zero" areas near 5e-10 (relative) here
    a = pm.validate(V32.astype(np.float64), F, relative_area_tolerance=tolerance)
    b = pm.validate(V32, F.astype(np.int64), relative_area_tolerance=tolerance)
    assert a.degenerate_faces.tolist() == [10]
    for name in COUNTS:
        assert getattr(a, name) == getattr(b, name), name
    for name in INDEX_ARRAYS:
        assert np.array_equal(getattr(a, name), getattr(b, name)), name
    c = pm.validate(np.asfortranarray(V), F.copy(order="F"))  # any memory layout
    assert c.degenerate_faces.tolist() == [10]


def test_area_tolerance_is_an_option():
    V, F = meshes.zero_area_face()
    V32 = V.astype(np.float32)
    assert pm.validate(V32, F, relative_area_tolerance=1e-8).degenerate_faces.tolist() == [10]
    with pytest.raises(pm.DegenerateFaceError, match=r"faces 10\b"):
        pm.require_closed_genus0(V32, F, relative_area_tolerance=1e-8)
    # A well-shaped mesh stays clean at that tolerance, and every face is flagged
    # at an absurd one (the option is really used).
    V, F = meshes.icosphere(4)
    assert pm.validate(V.astype(np.float32), F, relative_area_tolerance=1e-8).degenerate_faces.size == 0
    assert pm.validate(V, F, relative_area_tolerance=1.0).degenerate_faces.size == len(F)
    for bad in [-1.0, float("nan"), float("inf")]:
        with pytest.raises(pm.InvalidInputError, match="relative_area_tolerance"):
            pm.validate(V, F, relative_area_tolerance=bad)


def test_report_is_unchanged_by_scaling():
    V, F = meshes.noisy_blob(2)
    for scale in [1e-6, 1e6]:
        r = pm.validate(V * scale, F)
        assert r.is_closed_genus0 and r.degenerate_faces.size == 0, scale


# --- malformed arrays ------------------------------------------------------------------

@pytest.mark.parametrize("bad", [
    lambda V, F: (V[:, :2], F),                       # wrong shapes
    lambda V, F: (V, F[:, :2]),
    lambda V, F: (V.ravel(), F),
    lambda V, F: (V, F[None]),
    lambda V, F: (V.astype(np.complex128), F),        # wrong dtypes
    lambda V, F: (V, F.astype(np.float64)),
    lambda V, F: (V.astype(str), F),
    lambda V, F: (V[:0], F[:0]),                      # empty
    lambda V, F: (V, F[:0]),
], ids=["V2d", "F2cols", "V1d", "F3d", "Vcomplex", "Ffloat", "Vstr", "empty", "nofaces"])
def test_malformed_arrays_raise_invalid_input(bad):
    V, F = meshes.icosphere(1)
    with pytest.raises(pm.InvalidInputError):
        pm.validate(*bad(V, F))
    with pytest.raises(pm.InvalidInputError):
        pm.require_closed_genus0(*bad(V, F))


def test_nan_and_inf_name_the_vertices():
    with pytest.raises(pm.InvalidInputError, match=r"NaN or inf.* 1 vertex: 5\b"):
        pm.validate(*meshes.nan_vertex())
    V, F = meshes.nan_vertex()
    V[9, 2] = np.inf
    with pytest.raises(pm.InvalidInputError, match=r"2 vertices: 5, 9\b"):
        pm.validate(V, F)


def test_out_of_range_indices_name_the_face_and_value():
    V, F = meshes.out_of_range_index()
    with pytest.raises(pm.InvalidInputError, match=rf"face 7 has vertex index {len(V) + 10}, out of range"):
        pm.validate(V, F)
    F = meshes.icosphere(1)[1].copy()
    F[3, 1] = -1
    with pytest.raises(pm.InvalidInputError, match=r"face 3"):
        pm.validate(V, F)
    with pytest.raises(pm.InvalidInputError, match="out of range"):
        pm.validate(V, F.astype(np.int64) + 2 ** 31)  # does not fit int32


# --- require_closed_genus0: the matching typed error, with a useful message ---------

@pytest.mark.parametrize("name", CLOSED)
def test_require_closed_genus0_accepts_closed_families(name):
    assert pm.require_closed_genus0(*meshes.FAMILIES_CLOSED[name]()) is None


def expect_error(mesh, error, *patterns):
    with pytest.raises(error) as info:
        pm.require_closed_genus0(*mesh)
    assert type(info.value) is error, f"got {type(info.value).__name__}: {info.value}"
    for pattern in patterns:
        assert re.search(pattern, str(info.value)), f"{pattern!r} not in {info.value}"
    return str(info.value)


def test_not_closed_names_loops_and_edges():
    mesh = meshes.open_disc()
    r = pm.validate(*mesh)
    expect_error(mesh, pm.NotClosedError,
                 rf"mesh is not closed: it has 1 boundary loop \(hole\) with {r.boundary_edges} boundary edges",
                 "fill the holes")
    # Two holes: cut both caps.
    V, F = meshes.icosphere(2)
    keep = np.abs(V[F].mean(axis=1)[:, 2]) < 0.5
    expect_error((V, F[keep]), pm.NotClosedError, r"2 boundary loops \(holes\)")


def test_not_genus_zero_says_the_genus():
    expect_error(meshes.torus(), pm.NotGenusZeroError, r"genus 1 \(1 handle\)", "genus-0")


def test_disconnected_counts_components_and_names_loose_vertices():
    expect_error(meshes.two_spheres(), pm.DisconnectedError, "2 connected components")
    V, F = meshes.loose_vertex()
    expect_error((V, F), pm.DisconnectedError, rf"1 loose vertex in no face \({len(V) - 1}\)")


def test_non_manifold_names_vertex_pairs_and_vertices():
    V, F = meshes.non_manifold_edge()
    a, b = sorted(F[0, :2].tolist())
    expect_error((V, F), pm.NonManifoldError, "more than two faces", re.escape(f"({a}, {b})"))
    expect_error(meshes.pinched_spheres(), pm.NonManifoldError, "single fan", r"vertices 0\b")
    expect_error(meshes.flipped_face(), pm.NonManifoldError, "consistently oriented", "Recalculate")


def test_degenerate_names_the_face():
    expect_error(meshes.zero_area_face(), pm.DegenerateFaceError, r"1 degenerate face .*faces 10\b")


def test_error_classes_form_one_family():
    for error in [pm.NotClosedError, pm.NotGenusZeroError, pm.DisconnectedError,
                  pm.NonManifoldError, pm.DegenerateFaceError, pm.InvalidInputError]:
        assert issubclass(error, pm.MeshError) and issubclass(error, ValueError), error
    assert issubclass(pm.MeshError, ValueError)


def test_open_entry_points_report_orientation_not_closedness():
    """An open mesh with a flipped face: the planar map, the feature cut and the region refiner
    all say it is not consistently oriented (naming the edges), not that it has holes."""
    V, F = meshes.plane_grid(6)
    F = F.copy()
    F[10] = F[10][::-1]
    for call in (lambda: pm.isometric_map(V, F), lambda: pm.refine_region(V, F, [1, 2]),
                 lambda: pm.extract_feature(V, F, np.arange(len(F) // 2))):
        with pytest.raises(pm.NonManifoldError, match="consistently oriented.*Recalculate"):
            call()


# --- messages that name the real fault (issue 19) ---------------------------------------------

def test_a_face_naming_a_vertex_twice_is_said_so_not_a_non_manifold_edge():
    V, F = meshes.icosphere(2)
    F = F.copy()
    F[7, 1] = F[7, 0]
    report = pm.validate(V, F)
    assert list(report.repeated_vertex_faces) == [7] and 7 in list(report.degenerate_faces)
    with pytest.raises(pm.DegenerateFaceError, match=r"1 face naming one vertex twice: faces 7;"):
        pm.require_closed_genus0(V, F)


def test_duplicate_faces_are_said_so_not_inconsistent_orientation():
    V, F = meshes.icosphere(2)
    for extra in (F[[3, 9]], F[[3]][:, ::-1]):  # the same faces again, or one turned
        doubled = np.vstack([F, extra])
        report = pm.validate(V, doubled)
        assert list(report.duplicate_faces) == list(range(len(F), len(F) + len(extra)))
        with pytest.raises(pm.NonManifoldError, match="duplicate face"):
            pm.require_closed_genus0(V, doubled)


@pytest.mark.parametrize("scale,word", [(1e200, "overflow"), (1e-200, "round to zero")])
def test_coordinates_too_large_or_small_for_areas_ask_for_scaling(scale, word):
    V, F = meshes.icosphere(2)
    with pytest.raises(pm.InvalidInputError, match=f"would {word} in double precision; scale the mesh"):
        pm.validate(V * scale, F)
    with pytest.raises(pm.InvalidInputError, match="scale the mesh"):
        pm.sphere_map(V * scale, F)
    # Large and small but sane scales still validate.
    assert pm.validate(V * 1e12, F).is_closed_genus0 and pm.validate(V * 1e-12, F).is_closed_genus0


def test_a_pillow_of_two_faces_is_refused_at_once_not_after_relaxation_sweeps():
    # Two faces on the same three vertices pass every count (closed, chi = 2)
    # but enclose nothing: sphere_map spent its relaxation sweeps and raised
    # ComputeError. Also as a separate piece glued to nothing else.
    V = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0]], float)
    F = np.array([[0, 1, 2], [0, 2, 1]], np.int32)
    report = pm.validate(V, F)
    assert list(report.duplicate_faces) == [1] and not report.is_closed_genus0
    with pytest.raises(pm.NonManifoldError, match="1 duplicate face .*enclosing nothing"):
        pm.require_closed_genus0(V, F)
    with pytest.raises(pm.NonManifoldError, match="duplicate face"):
        pm.sphere_map(V, F)
