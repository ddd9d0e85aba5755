"""The morph on real characters however the scene is turned, and its
fallbacks (issue 29): the same correspondence for a common rotation, scale
and shift of both meshes; a proxy whose map cannot be read onto the model
falls back to the model's own map and says so. Real pairs from
../shared/models run when the folder is there."""
import json
from pathlib import Path

import numpy as np
import pytest

import meshes
import paramorph_native as pm
import quadrupeds as Q
from in_betweens import rotation
from quadrupeds import folded_faces, landmark_vertices

MODELS = Path(__file__).resolve().parents[3] / "shared" / "models"


# (rotation, uniform scale, shift) applied to both meshes: a y-up file in a
# z-up scene, a turn about the vertical, and arbitrary ones scaled and moved.
TURNS = [(rotation([1, 0, 0], 90), 1.0, np.zeros(3)),
         (rotation([0, 1, 0], 60), 1.0, np.zeros(3)),
         (rotation([0, 0, 1], 135), 2.5, np.array([3.0, -1.0, 2.0])),
         (rotation([0.3, 0.8, -0.5], 77), 0.01, np.array([0.1, 0.2, 0.3]))]


def landed(morph, LA):
    return np.asarray(morph.target)[np.asarray(morph.vertex_of_a)[LA]]


def turned_answers(VA, FA, VB, FB, LA, turns):
    """Where A's landmarks land on B as placed and under each turn (turned
    back), and the morphs."""
    out = []
    for R, scale, shift in [(np.eye(3), 1.0, np.zeros(3))] + turns:
        m = pm.morph(VA @ R.T * scale + shift, FA, VB @ R.T * scale + shift, FB)
        assert folded_faces(m) == 0
        out.append((((landed(m, LA) - shift) / scale) @ R, m))
    return out


def test_turning_the_scene_turns_the_answer_with_it():
    VA, FA, LA = Q.quadruped("cow", 3000, seed=1)
    VB, FB, LB = Q.quadruped("horse", 6000, pose=Q.WALK, seed=2)
    answers = turned_answers(VA, FA, VB, FB, landmark_vertices(LA), TURNS[:3])
    diagonal = np.linalg.norm(np.ptp(VB, axis=0))
    placed = answers[0][0]
    for points, m in answers[1:]:
        moved = np.linalg.norm(points - placed, axis=1).max() / diagonal
        assert moved < 0.005, f"a landmark moved {100 * moved:.2f} % of the diagonal with the scene"
        assert m.candidates[m.chosen].kind == answers[0][1].candidates[answers[0][1].chosen].kind


def test_a_proxy_that_cannot_be_read_onto_the_model_falls_back_to_its_own_map():
    # A coiled tube's 300-face proxy cuts across its turns: read back onto
    # the tube, its map keeps folds.
    VA, FA = meshes.coiled_tube()
    VB, FB = meshes.star(6, 20.0, 3)
    m = pm.morph(VA, FA, VB, FB, proxy_faces=300)
    assert any(note.startswith("mesh A: its own sphere map") for note in m.fallbacks), m.fallbacks
    assert folded_faces(m) == 0
    # Every vertex of both inputs is in the merged mesh.
    assert len(np.unique(np.asarray(m.vertex_of_a))) == len(VA)
    assert len(np.unique(np.asarray(m.vertex_of_b))) == len(VB)


def test_no_fallback_is_reported_where_none_was_needed():
    VA, FA, _ = Q.quadruped("cow", 3000, seed=1)
    VB, FB, _ = Q.quadruped("horse", 4000, seed=3)
    assert list(pm.morph(VA, FA, VB, FB).fallbacks) == []


def load(name):
    import sys
    sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "bench"))
    from common import load_obj
    return load_obj(MODELS / f"{name}.obj")


def landmarks(a, b):
    """Both models' landmark vertices (landmarks.json), in the same order."""
    marks = json.loads((MODELS / "landmarks.json").read_text())
    names = list(marks[f"{a}.obj"])
    return (np.array([marks[f"{a}.obj"][n] for n in names]), np.array([marks[f"{b}.obj"][n] for n in names]))


needs_models = pytest.mark.skipif(not (MODELS / "landmarks.json").exists(), reason="no ../shared/models")


@needs_models
@pytest.mark.parametrize("a, b", [("cat", "lion"), ("horned-cow", "lion")])
def test_real_animals_the_same_however_turned_and_every_landmark_nearest_its_own(a, b):
    # horned cow -> lion: its landmarks moved 52 % with the scene before the
    # shape's own frame, and its muzzle went to an ear before the mirror.
    (VA, FA), (VB, FB) = load(a), load(b)
    LA, LB = landmarks(a, b)
    answers = turned_answers(VA, FA, VB, FB, LA, [TURNS[0], TURNS[3]])
    diagonal = np.linalg.norm(np.ptp(VB, axis=0))
    for points, _ in answers:
        distances = np.linalg.norm(points[:, None] - VB[LB][None], axis=2) / diagonal
        assert (np.argmin(distances, axis=1) == np.arange(len(LB))).all()
        assert np.diag(distances).mean() < 0.05 and np.diag(distances).max() < 0.10
        assert np.linalg.norm(points - answers[0][0], axis=1).max() / diagonal < 0.005


def set_down(V, R):
    """V turned by R about its own centre: a model set down by hand."""
    centre = V.mean(axis=0)
    return (V - centre) @ R.T + centre


def test_a_source_set_down_askew_is_straightened_by_its_tips():
    VA, FA, LA = Q.quadruped("cow", 3000, seed=1)  # z up, x along the body
    VB, FB, LB = Q.quadruped("horse", 6000, pose=Q.WALK, seed=2)
    askew = rotation([0, 0, 1], 40) @ rotation([1, 0, 0], -10)
    straight = pm.morph_correspondence(VA, FA, VB, FB)
    assert straight.placement_turn == 0.0  # the tips pair as placed: nothing to straighten
    turned = pm.morph_correspondence(set_down(VA, askew), FA, VB, FB)
    angle = np.degrees(np.arccos((np.trace(askew) - 1) / 2))
    assert abs(np.degrees(turned.placement_turn) - angle) < 10, (np.degrees(turned.placement_turn), angle)
    assert np.degrees(turned.placement_turn) <= np.degrees(0.8)  # within max_placement_turn
    m = pm.morph(set_down(VA, askew), FA, VB, FB)
    assert folded_faces(m) == 0
    errors, own = Q.landmark_errors(m, landmark_vertices(LA), VB, landmark_vertices(LB))
    assert own.all() and errors.max() < 0.05


# A lion or a cow set down by hand beside the horned cow or the lion, turned
# about its own centre: about the vertical (+y in these files), and tilted or
# pitched. Before, each came out with a landmark 15-29 % of the diagonal
# from its partner (a muzzle, or the lion's front hoof): their tips paired
# fewer as placed than once straightened.
@needs_models
@pytest.mark.parametrize("a, b, turn", [
    ("lion", "horned-cow", rotation([0, 1, 0], 20) @ rotation([1, 0, 0], 10)),
    ("lion", "horned-cow", rotation([0, 1, 0], 40) @ rotation([1, 0, 0], -10)),
    ("horned-cow", "lion", rotation([0, 1, 0], -30)),
    ("horned-cow", "lion", rotation([1, 0, 0], -15))])
def test_real_animals_set_down_askew_land_every_landmark_nearest_its_own(a, b, turn):
    (VA, FA), (VB, FB) = load(a), load(b)
    LA, LB = landmarks(a, b)
    diagonal = np.linalg.norm(np.ptp(VB, axis=0))
    m = pm.morph(set_down(VA, turn) + [diagonal, 0, 0], FA, VB, FB)
    assert folded_faces(m) == 0 and m.placement_turn > 0
    distances = np.linalg.norm(landed(m, LA)[:, None] - VB[LB][None], axis=2) / diagonal
    assert (np.argmin(distances, axis=1) == np.arange(len(LB))).all()
    assert np.diag(distances).mean() < 0.05 and np.diag(distances).max() < 0.10


@needs_models
@pytest.mark.parametrize("a, b", [("dancer", "cat"), ("horned-cow", "samba"), ("samba", "dancer")])
def test_real_characters_morph_without_error(a, b):
    (VA, FA), (VB, FB) = load(a), load(b)
    m = pm.morph(VA, FA, VB, FB)
    assert folded_faces(m) == 0
    assert len(np.unique(np.asarray(m.vertex_of_a))) == len(VA)


def test_with_three_or_more_pins_tips_pair_by_their_distances_to_the_pins():
    VA, FA, LA = Q.quadruped("cow", 3000, seed=1)
    VB, FB, LB = Q.quadruped("horse", 6000, pose=Q.WALK, seed=2)
    la, lb = landmark_vertices(LA), landmark_vertices(LB)
    hooves = np.stack([la[:4], lb[:4]], axis=1)
    by_pins = [c for c in pm.morph_correspondence(VA, FA, VB, FB, pins=hooves).candidates
               if c.kind == "pin distances"]
    # Muzzle, tail and a horn or ear: far from every hoof, they pair.
    assert len(by_pins) == 1 and len(by_pins[0].proxy_pairs) >= 2 and np.isfinite(by_pins[0].score)
    two = pm.morph_correspondence(VA, FA, VB, FB, pins=hooves[:2]).candidates
    assert not any(c.kind == "pin distances" for c in two)


@pytest.mark.parametrize("tolerance", [-5.0, 1e300, float("nan")])
def test_a_bad_overlay_option_is_refused_up_front_as_invalid_input(tolerance):
    # Not a ComputeError from the finer-proxy retry (fuzz seed 2 found it).
    V, F = meshes.icosphere(1)
    with pytest.raises(pm.InvalidInputError, match="merge_tolerance"):
        pm.morph(V, F, V, F, merge_tolerance=tolerance)
