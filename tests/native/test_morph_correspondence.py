"""The morph's correspondence as an animator meets it (issue 16), on
generated quadrupeds with landmark vertices (quadrupeds.py): a re-posed,
re-tessellated, rescaled, turned, inside-out copy; a cow into a horse; pins
that hold exactly from 1 to 50; mirrored and contradictory pins; cancel.
The figures over more pairs and sizes: tests/bench/correspondence.py."""
import numpy as np
import pytest

import paramorph_native as pm
import quadrupeds as Q

from quadrupeds import folded_faces as folded, landmark_errors, landmark_vertices as landmarks, random_rotation as rotation


def landed(m, vertices_of_a):
    """Where A's vertices are at t = 1 (their merged vertices in B's shape)."""
    return np.asarray(m.target)[np.asarray(m.vertex_of_a)[vertices_of_a]]


@pytest.fixture(scope="module")
def reposed():
    """A horse, and the same horse galloping on another tessellation, a tenth
    of the size, turned, moved and inside-out."""
    VA, FA, LA = Q.quadruped("horse", 3000, seed=0)
    V, F, LB = Q.quadruped("horse", 6000, pose=Q.GALLOP, seed=4)
    VB, FB = Q.transform(V, F, scale=0.1, rotation=rotation(4), offset=(5.0, -2.0, 1.0), inside_out=True)
    return VA, FA, landmarks(LA), VB, FB, landmarks(LB), pm.morph(VA, FA, VB, FB)


def test_a_reposed_copy_matches_within_three_percent(reposed):
    VA, FA, LA, VB, FB, LB, m = reposed
    errors, own = landmark_errors(m, LA, VB, LB)
    print("re-posed copy: landmark errors", np.round(errors, 4), m.candidates[m.chosen])
    assert errors.max() < 0.03 and own.all()
    assert m.candidates[m.chosen].kind in ("extremities", "tip paths")  # the tips made it
    # The inside-out file was noticed and turned, not mirrored.
    assert m.inside_out_b and not m.inside_out_a and folded(m) == 0


def test_both_ends_are_exactly_the_models_as_placed(reposed):
    VA, FA, LA, VB, FB, LB, m = reposed
    np.testing.assert_allclose(np.asarray(m.source)[np.asarray(m.vertex_of_a)], VA, atol=1e-12)
    np.testing.assert_allclose(np.asarray(m.target)[np.asarray(m.vertex_of_b)], VB, atol=1e-12 * np.ptp(VB))
    # Merged faces face outward at both ends, B's file notwithstanding.
    F = np.asarray(m.faces)
    for positions in (np.asarray(m.source), np.asarray(m.target)):
        centred = positions - positions.mean(axis=0)
        volume = np.einsum("ij,ij->i", centred[F[:, 0]], np.cross(centred[F[:, 1]], centred[F[:, 2]])).sum()
        assert volume > 0


def test_the_automatic_choice_beats_no_pairs_and_says_why(reposed):
    *_, m = reposed
    chosen = m.candidates[m.chosen]
    none = next(c for c in m.candidates if c.kind == "none")
    scored = [c for c in m.candidates if not c.rejected]
    assert chosen.score == min(c.score for c in scored) and chosen.score < none.score
    assert {"none", "extremities", "registration"} <= {c.kind for c in m.candidates}
    for c in scored:
        assert np.isfinite(c.score) and c.distortion >= 0 and c.curvature_mismatch >= 0 and 0 <= c.turn <= np.pi
        assert c.score >= c.distortion  # the distortion is part of the score
    assert chosen.detail and "tips paired" in chosen.detail


def test_a_cow_into_a_horse_lands_every_landmark_nearest_its_own():
    VA, FA, LA = Q.quadruped("cow", 3000, seed=1)
    V, F, LB = Q.quadruped("horse", 6000, pose=Q.WALK, seed=2)
    VB, FB = Q.transform(V, F, rotation=rotation(11))
    m = pm.morph(VA, FA, VB, FB)
    errors, own = landmark_errors(m, landmarks(LA), VB, landmarks(LB))
    print("cow into horse: landmark errors", np.round(errors, 4), m.candidates[m.chosen])
    assert own.all() and errors.max() < 0.05 and folded(m) == 0


def spaced_pins(VA, FA, VB, target_of_a, count, seed=0):
    """`count` pins as an artist places them: a few edges apart on A, each to
    the vertex of B nearest where a correspondence puts it."""
    rng = np.random.default_rng(seed)
    spacing = 3 * np.linalg.norm(VA[FA[:, 0]] - VA[FA[:, 1]], axis=1).mean()
    pins = []
    for a in rng.permutation(len(VA)):
        if any(np.linalg.norm(VA[a] - VA[p]) < spacing for p, _ in pins):
            continue
        b = int(np.argmin(np.linalg.norm(VB - target_of_a[a], axis=1)))
        if all(b != q for _, q in pins):
            pins.append((int(a), b))
        if len(pins) == count:
            break
    return np.array(pins)


@pytest.mark.parametrize("count", [1, 6, 25, 50])
def test_pins_hold_exactly_and_the_map_stays_bijective(reposed, count):
    VA, FA, LA, VB, FB, LB, m_auto = reposed
    if count == 6:
        pins = np.stack([LA, LB], axis=1)
    else:
        pins = spaced_pins(VA, FA, VB, landed(m_auto, np.arange(len(VA))), count)
    m = pm.morph(VA, FA, VB, FB, pins=pins)
    # Each pinned vertex of A is the very merged vertex of its partner: at
    # t = 1 it lands on B's vertex exactly.
    merged_a = np.asarray(m.vertex_of_a)[pins[:, 0]]
    np.testing.assert_array_equal(merged_a, np.asarray(m.vertex_of_b)[pins[:, 1]])
    np.testing.assert_array_equal(np.asarray(m.target)[merged_a], VB[pins[:, 1]])
    assert np.asarray(m.pair_is_pin)[:count].all() and (np.asarray(m.pairs)[:count] == pins).all()
    assert folded(m) == 0
    errors, own = landmark_errors(m, LA, VB, LB)
    assert own.all() and errors.max() < 0.05  # pins consistent with the shape do not spoil it


def test_mirrored_pins_are_refused_by_name(reposed):
    VA, FA, LA, VB, FB, LB, _ = reposed
    # Left and right hooves swapped on B, the muzzle and tail as they are.
    swapped = LB[[1, 0, 3, 2, 4, 5]]
    with pytest.raises(pm.ConstraintError, match=r"mirrored order.*pins \d"):
        pm.morph(VA, FA, VB, FB, pins=np.stack([LA, swapped], axis=1))


def test_given_pairs_in_mirrored_order_are_a_constraint_error(reposed):
    VA, FA, LA, VB, FB, LB, _ = reposed
    swapped = LB[[1, 0, 3, 2, 4, 5]]
    with pytest.raises(pm.ConstraintError, match="given pairs are in mirrored order"):
        pm.morph(VA, FA, VB, FB, pairs=np.stack([LA, swapped], axis=1))


def test_contradictory_and_out_of_range_pins_raise_typed_errors(reposed):
    VA, FA, LA, VB, FB, LB, _ = reposed
    with pytest.raises(pm.ConstraintError, match="pins 0 and 1 both pin vertex"):
        pm.morph(VA, FA, VB, FB, pins=np.array([[LA[0], LB[0]], [LA[0], LB[1]]]))
    with pytest.raises(pm.ConstraintError, match="of B"):
        pm.morph(VA, FA, VB, FB, pins=np.array([[LA[0], LB[0]], [LA[1], LB[0]]]))
    with pytest.raises(pm.InvalidInputError, match="out of range"):
        pm.morph(VA, FA, VB, FB, pins=np.array([[0, len(VB)]]))
    with pytest.raises(pm.InvalidInputError):
        pm.morph(VA, FA, VB, FB, pins=np.array([0, 1, 2]))
    # Past 32 bits: refused, not wrapped round onto vertex LB[0].
    with pytest.raises(pm.InvalidInputError, match="out of range"):
        pm.morph(VA, FA, VB, FB, pins=np.array([[LA[0], 2**32 + LB[0]]], dtype=np.int64))


def test_cancel_while_aligning_leaves_nothing(reposed):
    VA, FA, LA, VB, FB, LB, _ = reposed
    stages = []

    def stop_in_the_correspondence(fraction, stage):
        stages.append(stage)
        return not (0.2 < fraction < 0.6)

    with pytest.raises(pm.Cancelled):
        pm.morph(VA, FA, VB, FB, progress=stop_in_the_correspondence)
    assert any("correspondence" in s for s in stages)


def test_the_preview_sees_the_inside_out_file_and_the_pins(reposed):
    VA, FA, LA, VB, FB, LB, m = reposed
    preview = pm.morph_correspondence(VA, FA, VB, FB, pins=np.stack([LA[:2], LB[:2]], axis=1))
    assert preview.inside_out_b and not preview.inside_out_a
    pairs = np.asarray(preview.pairs)
    # Automatic pairs never reuse a pinned vertex.
    assert not set(pairs[:, 0]) & set(LA[:2]) and not set(pairs[:, 1]) & set(LB[:2])
    V, F = preview.proxy_b
    assert len(F) <= 3000 and pm.validate(V, F).is_closed_genus0
