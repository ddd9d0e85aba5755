"""validate() / require_closed_genus0(): reports and typed errors on the named meshes."""
import numpy as np
import pytest

import meshes
import paramorph_native as pm


@pytest.mark.parametrize("name", sorted(meshes.FAMILIES_CLOSED))
def test_closed_families_are_closed_genus0_and_outward(name):
    V, F = meshes.FAMILIES_CLOSED[name]()
    report = pm.validate(V, F)
    assert report.is_closed_genus0, report
    assert (report.genus, report.components, report.boundary_loops) == (0, 1, 0)
    assert report.euler_characteristic == 2
    assert meshes.signed_volume(V, F) > 0, "faces must face outwards"
    pm.require_closed_genus0(V, F)


def test_reports_of_broken_meshes():
    assert pm.validate(*meshes.open_disc()).boundary_loops == 1
    assert pm.validate(*meshes.torus()).genus == 1
    assert pm.validate(*meshes.two_spheres()).components == 2
    assert pm.validate(*meshes.non_manifold_edge()).non_manifold_edges.size == 1
    V, F = meshes.zero_area_face()
    assert pm.validate(V, F).degenerate_faces.tolist() == [10]


def test_float32_and_int64_give_the_same_report():
    V, F = meshes.noisy_blob(2)
    a = pm.validate(V, F)
    b = pm.validate(V.astype(np.float32), F.astype(np.int64))
    assert (a.vertices, a.faces, a.edges, a.genus) == (b.vertices, b.faces, b.edges, b.genus)


@pytest.mark.parametrize("bad", [
    lambda V, F: (V[:, :2], F),                 # wrong shape
    lambda V, F: (V, F[:, :2]),
    lambda V, F: (V.astype(np.complex128), F),  # wrong dtype
    lambda V, F: (V, F.astype(np.float64)),
])
def test_malformed_arrays_raise_invalid_input(bad):
    V, F = meshes.icosphere(1)
    with pytest.raises(pm.InvalidInputError):
        pm.validate(*bad(V, F))


def test_nan_and_out_of_range_name_the_element():
    with pytest.raises(pm.InvalidInputError, match="vertices: 5"):
        pm.validate(*meshes.nan_vertex())
    with pytest.raises(pm.InvalidInputError, match="face 7"):
        pm.validate(*meshes.out_of_range_index())


@pytest.mark.parametrize("name,error,words", [
    ("open_disc", pm.NotClosedError, "1 boundary loops"),
    ("torus", pm.NotGenusZeroError, "genus 1"),
    ("two_spheres", pm.DisconnectedError, "2 connected components"),
    ("non_manifold_edge", pm.NonManifoldError, "more than two faces"),
    ("zero_area_face", pm.DegenerateFaceError, "10"),
])
def test_require_closed_genus0_raises_the_matching_error(name, error, words):
    with pytest.raises(error, match=words) as info:
        pm.require_closed_genus0(*getattr(meshes, name)())
    assert isinstance(info.value, pm.MeshError) and isinstance(info.value, ValueError)
