"""Tips that pair by what they are (issue 29): protrusion tips (local maxima
of the average geodesic distance) on every hoof, muzzle and tail of a
generated quadruped, the paths from the core out to them, and a morph whose
tails find each other when one hangs and the other is raised. The real
animals of ../shared/models run when the folder is there."""
import itertools
import json

import numpy as np
import pytest

import paramorph_native as pm
import quadrupeds as Q
from quadrupeds import folded_faces, landmark_errors, landmark_vertices
from test_morph_scene import MODELS, load, needs_models


def unit_area(V, F):
    area = 0.5 * np.linalg.norm(np.cross(V[F[:, 1]] - V[F[:, 0]], V[F[:, 2]] - V[F[:, 0]]), axis=1).sum()
    return (V - V.mean(axis=0)) / np.sqrt(area)


@pytest.mark.parametrize("kind", ["horse", "cow"])
def test_a_tip_on_every_hoof_muzzle_and_tail(kind):
    V, F, L = Q.quadruped(kind, 3000, seed=3)
    V = unit_area(V, F)
    tips = pm.protrusion_tips(V, F)
    T = V[np.asarray(tips.vertices)]
    for name, vertex in L.items():
        nearest = np.linalg.norm(T - V[vertex], axis=1).min()
        assert nearest < 0.06, f"{kind}: no tip within {nearest:.3f} of the {name}"
    assert len(tips.vertices) <= 24


def test_paths_run_along_edges_from_the_core_to_each_tip():
    V, F, _ = Q.quadruped("horse", 3000, seed=1)
    V = unit_area(V, F)
    tips = pm.protrusion_tips(V, F)
    average = np.asarray(tips.average_distance)
    assert tips.core == int(np.argmin(average))
    edges = {tuple(sorted(e)) for f in F for e in ((f[0], f[1]), (f[1], f[2]), (f[2], f[0]))}
    heights = average[np.asarray(tips.vertices)]
    assert (np.diff(heights) <= 0).all()  # highest first
    for tip, path in zip(tips.vertices, tips.paths):
        assert path[0] == tips.core and path[-1] == tip
        assert all(tuple(sorted((int(u), int(v)))) in edges for u, v in zip(path, path[1:]))


def test_protrusion_tips_refuse_a_radius_that_is_not_positive():
    V, F, _ = Q.quadruped("horse", 3000, seed=1)
    for radius in (0.0, -1.0, float("nan")):
        with pytest.raises(pm.InvalidInputError):
            pm.protrusion_tips(V, F, radius=radius)


def test_a_hanging_tail_finds_a_raised_one():
    # The cow's tail hangs along its hocks, the horse's is raised: their tips
    # are far apart, the paths out to them both leave the body at its back.
    VA, FA, LA = Q.quadruped("cow", 3000, pose={"tail": -20.0}, seed=1)
    VB, FB, LB = Q.quadruped("horse", 6000, pose={"tail": 60.0}, seed=2)
    m = pm.morph(VA, FA, VB, FB)
    errors, own = landmark_errors(m, landmark_vertices(LA), VB, landmark_vertices(LB))
    chosen = m.candidates[m.chosen]
    print("hanging tail into a raised one:", np.round(errors, 4), chosen)
    assert own.all() and errors.max() < 0.05 and folded_faces(m) == 0
    assert chosen.tip_disagreement < 0.5


ANIMAL_PAIRS = list(itertools.permutations(["cat", "lion", "horned-cow"], 2))


def animal_pair(pair):
    """Both meshes and their landmark vertices in the same order (A's names)."""
    marks = json.loads((MODELS / "landmarks.json").read_text())
    names = list(marks[f"{pair[0]}.obj"])
    (VA, FA), (VB, FB) = load(pair[0]), load(pair[1])
    LA = np.array([marks[f"{pair[0]}.obj"][n] for n in names])
    LB = np.array([marks[f"{pair[1]}.obj"][n] for n in names])
    return VA, FA, LA, VB, FB, LB, names


@needs_models
@pytest.mark.parametrize("pair", ANIMAL_PAIRS, ids=lambda p: f"{p[0]}-{p[1]}")
def test_real_animals_land_every_landmark_nearest_its_own(pair):
    VA, FA, LA, VB, FB, LB, _ = animal_pair(pair)
    m = pm.morph(VA, FA, VB, FB)
    errors, own = landmark_errors(m, LA, VB, LB)
    print(pair, np.round(100 * errors, 1), m.candidates[m.chosen])
    # The scanned cow grazes: its muzzle points down and its ears forward-up
    # like a cat's muzzle; only the mirror (ears come in twins) tells them
    # apart (16-19 % before it).
    assert own.all() and errors.mean() <= 0.05 and errors.max() <= 0.10


@needs_models
@pytest.mark.parametrize("pair", ANIMAL_PAIRS, ids=lambda p: f"{p[0]}-{p[1]}")
def test_real_animals_with_four_hooves_pinned_morph_and_hold_the_pins(pair):
    # Never an error with consistent pins: a hoof's tip beside its pin is
    # not paired as well (the two held apart stalled lion -> horned cow).
    VA, FA, LA, VB, FB, LB, names = animal_pair(pair)
    hooves = [k for k, name in enumerate(names) if name.endswith("hoof")]
    pins = np.stack([LA[hooves], LB[hooves]], axis=1)
    m = pm.morph(VA, FA, VB, FB, pins=pins)
    np.testing.assert_array_equal(np.asarray(m.target)[np.asarray(m.vertex_of_a)[pins[:, 0]]], VB[pins[:, 1]])
    assert folded_faces(m) == 0
    errors, own = landmark_errors(m, LA, VB, LB)
    print(pair, np.round(100 * errors, 1), m.candidates[m.chosen], list(m.fallbacks))
    muzzle, tail = errors[names.index("muzzle")], errors[names.index("tail")]
    assert own.all() and muzzle <= 0.05
    # The horned cow's tail landmark is the back-most point of its hanging
    # tail, 8.8 % of its diagonal above the tail's end: a cat's or a lion's
    # tail tip lands on the end, and the cow's landmark half way up theirs.
    assert tail <= (0.10 if "horned-cow" in pair else 0.05)
