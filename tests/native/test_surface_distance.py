"""Sampled distances between two surfaces (surface_distance): what Morph To
reports when it keeps the source's topology (issue 17)."""
import numpy as np
import pytest

import meshes
import paramorph_native as pm


def test_a_surface_is_at_zero_from_itself_and_offsets_are_measured():
    V, F = meshes.icosphere(3)
    same = pm.surface_distance(V, F, V, F)
    assert same.hausdorff < 1e-12
    bigger = pm.surface_distance(V, F, 1.1 * V, F)
    # 0.1 up to the chords' sag (the faces are flat, the samples partly on them).
    assert 0.09 < bigger.a_to_b < 0.12 and 0.09 < bigger.mean_a_to_b < 0.12
    assert 0.08 < bigger.b_to_a <= 0.1 + 1e-9


def test_detail_missing_from_a_coarse_copy_shows_one_way():
    """A bump on the fine surface that the coarse one lacks: its tip is the
    bump's height from the coarse surface (b_to_a); from the coarse side the
    nearest bumped surface is on the bump's flank, nearer (a_to_b)."""
    V, F = meshes.icosphere(4)
    tip = int(np.argmax(V[:, 2]))
    bump = V.copy()
    near = np.linalg.norm(V - V[tip], axis=1) < 0.3
    bump[near] *= 1.0 + 0.4 * (1 - np.linalg.norm(V[near] - V[tip], axis=1) / 0.3)[:, None]
    coarse_V, coarse_F = meshes.icosphere(2)
    d = pm.surface_distance(coarse_V, coarse_F, bump, F)
    assert d.b_to_a == pytest.approx(0.4, abs=0.03)
    assert d.a_to_b < 0.8 * d.b_to_a
    assert d.hausdorff == d.b_to_a


def test_malformed_arrays_are_refused():
    V, F = meshes.icosphere(1)
    with pytest.raises(pm.InvalidInputError):
        pm.surface_distance(V, F + len(V), V, F)


def test_progress_is_reported_and_cancels():
    V, F = meshes.icosphere(3)
    seen = []
    d = pm.surface_distance(V, F, 1.1 * V, F, progress=lambda f, stage: seen.append(f))
    assert seen[0] == 0.0 and seen[-1] == 1.0 and seen == sorted(seen)
    assert d.a_to_b == pm.surface_distance(V, F, 1.1 * V, F).a_to_b
    with pytest.raises(pm.Cancelled):
        pm.surface_distance(V, F, V, F, progress=lambda f, stage: f == 0.0)
