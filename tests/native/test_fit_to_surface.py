"""fit_to_surface from Python (issue 31): a kept topology, first where the
correspondence puts a coarse sphere's vertices on a many-armed target, drawn
over the target both ways — closer, its held vertices exactly in place, its
in-betweens still unfolded — and bad input refused with InvalidInputError;
the real spot onto the dancer and the lion onto the horned cow when
../shared/models is there."""
import sys
from pathlib import Path

import numpy as np
import pytest

import paramorph_native as pm
from in_betweens import inverted_share_turning, rotation
from meshes import subdivide, icosphere, tentacle_sphere


def kept_on_arms(subdivisions):
    """A sphere's vertices where the correspondence puts them on a four-armed
    target, and vertices to hold."""
    VA, FA = icosphere(subdivisions)
    VA = VA / np.linalg.norm(VA, axis=1, keepdims=True)
    VB, FB = tentacle_sphere(subdivisions=4, tentacles=4, length=2.0)
    morph = pm.morph(VA, FA, VB, FB)
    X = np.asarray(morph.target)[np.asarray(morph.vertex_of_a)]
    held = np.array([0, 5, 17, 40])  # a sphere has no tips to match: vertices held as pins would be
    return VA, FA, VB, FB, X, held


@pytest.fixture(scope="module")
def kept():
    return kept_on_arms(2)


def hausdorff(X, F, VB, FB):
    return pm.surface_distance(X, F, VB, FB).hausdorff


def test_the_fit_comes_closer_keeps_held_vertices_and_the_in_betweens_unfolded(kept):
    VA, FA, VB, FB, X, held = kept
    fit = pm.fit_to_surface(X, FA, VB, FB, held=held)
    P = np.asarray(fit.positions)
    before, after = hausdorff(X, FA, VB, FB), hausdorff(P, FA, VB, FB)
    assert after < 0.7 * before, (before, after)
    assert fit.distance_after <= fit.distance_before
    assert np.array_equal(P[held], X[held])
    half = pm.ShapeInterpolation(VA, P, FA).at(0.5)
    assert inverted_share_turning(VA, P, half, FA, 0.5) <= 0.001


def test_the_pleat_smoothing_leaves_fewer_faces_against_the_target_and_is_no_farther():
    # A finer sphere than the fixture's: the rounds leave pleats on the body
    # between the arms (2.6 % of the faces against the target, measured).
    VA, FA, VB, FB, X, held = kept_on_arms(3)
    plain = pm.fit_to_surface(X, FA, VB, FB, held=held, smooth_pleats=0)
    smoothed = pm.fit_to_surface(X, FA, VB, FB, held=held)
    assert plain.pleat_moves == 0 and smoothed.pleat_moves > 0
    assert smoothed.rounds == plain.rounds  # the same rounds, then the smoothing
    assert smoothed.facing_away_after < plain.facing_away_after
    assert smoothed.distance_after <= plain.distance_after * (1 + 1e-3)
    P = np.asarray(smoothed.positions)
    assert np.array_equal(P[held], X[held])
    half = pm.ShapeInterpolation(VA, P, FA).at(0.5)
    assert inverted_share_turning(VA, P, half, FA, 0.5) <= 0.001


def test_a_turned_scaled_moved_scene_gives_the_same_fit_moved(kept):
    _, FA, VB, FB, X, held = kept
    R, s, t = rotation([0.3, -1.0, 0.2], 2.0), 0.01, np.array([40.0, -3.0, 7.0])
    plain = np.asarray(pm.fit_to_surface(X, FA, VB, FB, held=held, rounds=30).positions)
    moved = np.asarray(pm.fit_to_surface(s * X @ R.T + t, FA, s * VB @ R.T + t, FB, held=held, rounds=30).positions)
    assert np.abs(moved - (s * plain @ R.T + t)).max() < 1e-3 * s * np.ptp(VB, axis=0).max()


def test_progress_reports_and_cancel_stops(kept):
    _, FA, VB, FB, X, _ = kept
    seen = []
    pm.fit_to_surface(X, FA, VB, FB, rounds=5, progress=lambda f, stage: seen.append(f) or True)
    assert seen[0] == 0.0 and seen[-1] == 1.0
    with pytest.raises(pm.Cancelled):
        pm.fit_to_surface(X, FA, VB, FB, progress=lambda f, stage: False)


@pytest.mark.parametrize("change", [
    {"rounds": -1}, {"patience": -1}, {"smooth_pleats": -1}, {"stiffness": float("nan")}, {"stiffness": -1.0}, {"stiffness_decay": 0.0},
    {"stiffness_decay": 1.5}, {"held": np.array([10 ** 6])}, {"held": np.array([0.5])}, {"even_out_passes": -1},
    {"even_out_step": 0.0}, {"even_out_step": 1.5}, {"even_out_step": float("nan")},
])
def test_bad_options_are_refused(kept, change):
    _, FA, VB, FB, X, _ = kept
    with pytest.raises(pm.InvalidInputError):
        pm.fit_to_surface(X, FA, VB, FB, **change)


def test_bad_arrays_are_refused(kept):
    _, FA, VB, FB, X, _ = kept
    with pytest.raises(pm.InvalidInputError):
        pm.fit_to_surface(X[:, :2], FA, VB, FB)
    with pytest.raises(pm.InvalidInputError):
        pm.fit_to_surface(X, FA + len(X), VB, FB)
    with pytest.raises(pm.InvalidInputError):
        pm.fit_to_surface(X, FA, VB, np.zeros((0, 3), dtype=np.int32))


MODELS = Path(__file__).resolve().parents[3] / "shared" / "models"


def needs_models(*names):
    """Skip unless every one of these models is in ../shared/models."""
    missing = [n for n in names if not (MODELS / f"{n}.obj").exists()]
    return pytest.mark.skipif(bool(missing), reason=f"no {', '.join(missing)} in ../shared/models")


def real_kept(a, b):
    """A's vertices where the morph's correspondence puts them on B (B
    subdivided to 50k faces or more, as the issue's figure asks), and the
    vertices it holds."""
    sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "bench"))
    from common import load_obj
    VA, FA = load_obj(MODELS / f"{a}.obj")
    VB, FB = load_obj(MODELS / f"{b}.obj")
    while len(FB) < 50000:
        VB, FB = subdivide(VB, FB)
    morph = pm.morph(VA, FA, VB, FB)
    X = np.asarray(morph.target)[np.asarray(morph.vertex_of_a)]
    held = np.unique(np.asarray(morph.pairs, dtype=np.int64).reshape(-1, 2)[:, 0])
    return VA, FA, VB, FB, X, held


@needs_models("spot", "dancer")
def test_pleats_are_smoothed_where_the_large_faces_outrun_their_sample_budget():
    # Spot (2,930 vertices) onto the dancer subdivided to 56k faces: more of
    # spot's faces are large than the budget of finer samples holds, and
    # which of them get it follows their areas. When the smoothed mesh was
    # measured on a choice of its own, a face newly inside the budget showed
    # a distance the fit had always had, far from any move, and every pass
    # went back (0 moves, 7.1 % of faces folded against the target).
    _, FA, VB, FB, X, held = real_kept("spot", "dancer")
    rounds_only = pm.fit_to_surface(X, FA, VB, FB, held=held, smooth_pleats=0)
    smoothed = pm.fit_to_surface(X, FA, VB, FB, held=held)
    assert smoothed.pleat_moves > 0
    assert smoothed.facing_away_after < 0.6 * rounds_only.facing_away_after, (
        rounds_only.facing_away_after, smoothed.facing_away_after)
    before = hausdorff(np.asarray(rounds_only.positions), FA, VB, FB)
    after = hausdorff(np.asarray(smoothed.positions), FA, VB, FB)
    assert after < 1.1 * before, (before, after)


@needs_models("lion", "horned-cow")
def test_a_decimated_source_ending_far_runs_again_from_evened_faces_and_keeps_the_closer_end():
    # The lion (5,000 vertices, its faces on the cow from a quarter of the
    # mean to fifty times it) onto the horned cow (93k faces): one run ends
    # 3.4-3.9 % of the diagonal away, so the rounds run again from its faces
    # evened out, on a schedule twice as long. That run ends at 1.7-1.9 %
    # here, as computed and from starts moved by 1e-7 to 5e-7 of the diagonal
    # (on the 150 rounds' schedule it had ended anywhere from 1.9 to 6.9 %).
    VA, FA, VB, FB, X, held = real_kept("lion", "horned-cow")
    once = pm.fit_to_surface(X, FA, VB, FB, held=held, even_out_passes=0)
    fit = pm.fit_to_surface(X, FA, VB, FB, held=held)
    P = np.asarray(fit.positions)
    diagonal = np.linalg.norm(np.ptp(VB, axis=0))
    assert once.distance_after > 0.02 * diagonal
    assert fit.rounds >= once.rounds + 2 * 150  # it ran again, the evened run's whole schedule
    assert hausdorff(P, FA, VB, FB) <= 0.03 * diagonal  # the bound; one run alone ends over it
    assert np.array_equal(P[held], X[held])
    assert inverted_share_turning(VA, P, pm.ShapeInterpolation(VA, P, FA).at(0.5), FA, 0.5) <= 0.001
