"""repair() (native/mesh/repair.h, issue 19): the meshes artists bring, made
manifold and closed, with a map back to the input and a report of each change."""
import numpy as np
import pytest

import meshes
import paramorph_native as pm


def soup(V, F):
    """Every face on its own three vertices: a mesh exported with all its
    seams split (the worst unwelded file)."""
    return V[F.reshape(-1)].copy(), np.arange(3 * len(F), dtype=np.int32).reshape(-1, 3)


def punch_holes(V, F, count, radius, seed=0):
    """Removes the faces whose centre lies within radius of `count` random
    vertices, and the vertices left in no face."""
    centres = V[F].mean(axis=1)
    keep = np.ones(len(F), bool)
    for p in V[np.random.default_rng(seed).choice(len(V), count, replace=False)]:
        keep &= np.linalg.norm(centres - p, axis=1) > radius
    return meshes._compact(V, F[keep])


def test_a_clean_mesh_comes_back_as_it_is():
    V, F = meshes.noisy_blob(3)
    r = pm.repair(V, F)
    assert not r.report.changed and r.report.changes == []
    np.testing.assert_array_equal(r.V, V)
    np.testing.assert_array_equal(r.F, F)
    np.testing.assert_array_equal(r.vertex_source, np.arange(len(V)))
    np.testing.assert_array_equal(r.face_source, np.arange(len(F)))
    np.testing.assert_array_equal(r.input_vertex_target, np.arange(len(V)))


def test_unwelded_seams_are_welded_and_every_input_vertex_maps_to_its_place():
    V, F = meshes.noisy_blob(3)
    Vs, Fs = soup(V, F)
    # Float32 rounding, as a file with split seams carries it.
    Vs = Vs + np.random.default_rng(3).normal(scale=1e-9, size=Vs.shape)
    r = pm.repair(Vs, Fs)
    assert r.report.welded_vertices == len(Vs) - len(V)
    assert pm.validate(r.V, r.F).is_closed_genus0
    assert len(r.V) == len(V) and len(r.F) == len(F)
    # Where each input vertex went is at its own place (up to the weld).
    assert np.abs(r.V[r.input_vertex_target] - Vs).max() < 1e-8
    # Kept vertices keep their input positions exactly.
    np.testing.assert_array_equal(r.V, Vs[r.vertex_source])
    assert "merged" in r.report.changes[0]


def test_a_weld_tolerance_is_relative_to_the_mesh_size():
    V, F = meshes.icosphere(2)
    for scale in (1e-3, 1e3):
        Vs, Fs = soup(V * scale, F)
        Vs[0] += 1e-4 * scale  # a seam 1e-4 of the size apart: not welded by default
        r = pm.repair(Vs, Fs, fill_holes=False)
        assert r.report.welded_vertices == len(Vs) - len(V) - 1
        assert pm.validate(r.V, r.F).boundary_loops == 1
        r = pm.repair(Vs, Fs, weld_tolerance=1e-3, fill_holes=False)
        assert r.report.welded_vertices == len(Vs) - len(V)
        assert pm.validate(r.V, r.F).is_closed_genus0


def test_holes_are_filled_with_a_fair_patch_not_a_flat_fan():
    V, F = meshes.icosphere(4)
    Vh, Fh = punch_holes(V, F, 5, 0.35)
    holes = pm.validate(Vh, Fh).boundary_loops
    assert holes >= 3
    r = pm.repair(Vh, Fh)
    after = pm.validate(r.V, r.F)
    assert after.is_closed_genus0
    assert r.report.holes_filled == holes and r.report.holes_not_filled == 0 and r.report.fairing_failed == 0
    added = r.vertex_source < 0
    assert added.sum() == r.report.fill_vertices_added > 0
    assert (r.face_source < 0).sum() == r.report.fill_faces_added
    # Faired patches bulge with the sphere; a flat cap over a hole of radius
    # 0.35 would sink its centre by 1 - cos(asin(0.35)) ~ 0.063.
    depth = 1.0 - np.linalg.norm(r.V[added], axis=1)
    assert np.abs(depth).max() < 0.02
    np.testing.assert_array_equal(r.V[~added], Vh[r.vertex_source[~added]])
    np.testing.assert_array_equal(np.sort(r.face_source[r.face_source >= 0]), np.arange(len(Fh)))


def test_inside_out_and_flipped_faces_are_turned_outward():
    V, F = meshes.noisy_blob(3)
    r = pm.repair(V, F[:, ::-1])
    assert r.report.parts_turned_outward == 1 and r.report.faces_reversed == 0
    assert meshes.signed_volume(r.V, r.F) > 0
    Ff = F.copy()
    flipped = np.arange(0, len(F), 9)
    Ff[flipped] = Ff[flipped, ::-1]
    for inside_out in (False, True):
        r = pm.repair(V, Ff[:, ::-1] if inside_out else Ff)
        assert r.report.faces_reversed == len(flipped)
        assert r.report.parts_turned_outward == int(inside_out)
        assert pm.validate(r.V, r.F).is_closed_genus0 and meshes.signed_volume(r.V, r.F) > 0
    r = pm.repair(V, F[:, ::-1], orient_outward=False)
    assert meshes.signed_volume(r.V, r.F) < 0


def test_duplicate_and_degenerate_faces_are_dropped():
    V, F = meshes.icosphere(2)
    bad = np.vstack([F, F[:4], F[4:6, ::-1], [[0, 0, 1], [2, 3, 2]]]).astype(np.int32)
    r = pm.repair(V, bad)
    assert r.report.duplicate_faces_removed == 6
    assert r.report.degenerate_faces_removed == 2
    assert pm.validate(r.V, r.F).is_closed_genus0 and len(r.F) == len(F)


def test_zero_area_faces_are_removed():
    V, F = meshes.zero_area_face()
    assert 10 in pm.validate(V, F).degenerate_faces
    r = pm.repair(V, F)
    assert r.report.degenerate_faces_removed >= 1
    report = pm.validate(r.V, r.F)
    assert len(report.degenerate_faces) == 0 and len(report.non_manifold_edges) == 0
    assert (r.input_vertex_target >= 0).all()


def test_bow_ties_and_non_manifold_edges_are_cut_apart():
    V, F = meshes.pinched_spheres()
    r = pm.repair(V, F)
    assert r.report.non_manifold_vertices_split == 1 and r.report.components == 2
    report = pm.validate(r.V, r.F)
    assert len(report.non_manifold_vertices) == 0 and report.components == 2
    r = pm.repair(V, F, keep_largest_component=True)
    assert r.report.components_removed == 1 and pm.validate(r.V, r.F).is_closed_genus0
    assert (r.input_vertex_target == -1).sum() == len(V) - len(r.V)

    V, F = meshes.non_manifold_edge()
    r = pm.repair(V, F)
    assert r.report.non_manifold_edges == 1 and r.report.single_faces_left_open == 1
    assert len(pm.validate(r.V, r.F).non_manifold_edges) == 0
    r = pm.repair(V, F, keep_largest_component=True)
    assert pm.validate(r.V, r.F).is_closed_genus0 and len(r.F) == len(F) - 1
    assert r.report.faces_removed_with_components == 1


def test_a_handle_is_not_removed():
    V, F = meshes.torus()
    r = pm.repair(V, F)
    assert not r.report.changed
    assert pm.validate(r.V, r.F).genus == 1


def test_a_scan_like_mesh_with_everything_wrong_maps_to_the_sphere():
    V, F = meshes.noisy_blob(4)
    Vh, Fh = punch_holes(V, F, 6, 0.2, seed=2)
    holes = pm.validate(Vh, Fh).boundary_loops
    Vs, Fs = soup(Vh, Fh[:, ::-1])           # unwelded and inside out
    Vs = np.vstack([Vs, [[5.0, 5.0, 5.0]]])  # a loose vertex
    Fs = np.vstack([Fs, Fs[:3]])             # duplicates
    r = pm.repair(Vs, Fs)
    assert pm.validate(r.V, r.F).is_closed_genus0
    assert r.report.holes_filled == holes >= 4 and r.report.parts_turned_outward == 1
    assert r.report.isolated_vertices_removed == 1 and r.input_vertex_target[-1] == -1
    result = pm.sphere_map(r.V, r.F)
    assert result.flipped == 0


@pytest.mark.parametrize("kwargs", [{"weld_tolerance": float("nan")}, {"weld_tolerance": -1.0},
                                    {"weld_tolerance": float("inf")}])
def test_bad_options_are_refused(kwargs):
    V, F = meshes.icosphere(1)
    with pytest.raises(pm.InvalidInputError, match="weld_tolerance"):
        pm.repair(V, F, **kwargs)


def test_a_mesh_of_only_degenerate_faces_is_refused_in_plain_words():
    with pytest.raises(pm.InvalidInputError, match="every face is degenerate"):
        pm.repair(np.zeros((3, 3)), np.array([[0, 1, 2]]))
    with pytest.raises(pm.InvalidInputError):
        pm.repair(np.zeros((0, 3)), np.zeros((0, 3), np.int32))


def test_progress_reports_and_cancels():
    V, F = punch_holes(*meshes.icosphere(4), 4, 0.3)
    reports = []
    pm.repair(V, F, progress=lambda f, s: reports.append((f, s)))
    assert reports[0] == (0.0, "welding") and reports[-1] == (1.0, "repaired")
    with pytest.raises(pm.Cancelled):
        pm.repair(V, F, progress=lambda f, s: False)


def test_a_pillow_is_not_closed_into_a_two_sided_triangle():
    # Two faces on the same three vertices: one is a duplicate, the other a
    # lone triangle that no fill can close (it would be the pillow again).
    r = pm.repair(np.eye(3), np.array([[0, 1, 2], [0, 2, 1]]))
    assert r.report.duplicate_faces_removed == 1 and r.report.single_faces_left_open == 1
    assert len(r.F) == 1 and not pm.validate(r.V, r.F).is_closed_genus0
