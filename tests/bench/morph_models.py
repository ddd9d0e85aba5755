"""The morph on every pair of real characters in ../shared/models (issue 29),
JSON lines:

    /usr/bin/python3 tests/bench/morph_models.py [--pairs cat>lion,...] [--pinned] [--turns] [--askew] [--zoomout]

Every ordered pair of the closed genus-0 characters (cat, lion, horned-cow,
samba, dancer): whether pm.morph succeeds, its seconds, the candidate chosen
and what it fell back on (Morph.fallbacks). Where both have landmarks
(landmarks.json: four hooves, muzzle, tail): where A's landmark vertex lands
on B at t = 1, its distance to B's own as a share of B's bounding-box
diagonal (mean, max, each) and how many land nearest their own counterpart.
--pinned: again with the four hooves pinned (muzzle and tail automatic).
--turns: again with both meshes turned (90 deg about x, 60 deg about the
vertical, 135 deg about z with scale 2.5 and a shift, an arbitrary turn with
scale 0.01): the largest distance of a landmark from where it landed as
placed, as a share of the diagonal (target 0.5 %).
--askew: again with the source alone set down by hand beside the target,
turned about its own centre (ASKEW: about the vertical, +y in these files,
and tilted): the landmarks as above, and how far the morph straightened
the placement (Morph.placement_turn, degrees).
--zoomout: ZoomOut's numbers beside ours (tests/bench/zoomout.py; needs
pyfmaps, e.g. in a venv with numpy < 2).
Targets (issue 29): no error; no pins: each landmark nearest its own, mean
<= 5 %, each <= 10 %; hooves pinned: muzzle and tail <= 5 %."""
import argparse
import itertools
import json
import time

import numpy as np

from common import MODELS, emit, import_native, load_obj

pm = import_native()
from in_betweens import rotation  # noqa: E402  (tests/native, on sys.path after import_native)

CHARACTERS = ["cat", "lion", "horned-cow", "samba", "dancer"]
HOOVES = ["front_right_hoof", "front_left_hoof", "hind_right_hoof", "hind_left_hoof"]


TURNS = [("x 90", rotation([1, 0, 0], 90), 1.0, np.zeros(3)),
         ("vertical 60", rotation([0, 1, 0], 60), 1.0, np.zeros(3)),
         ("z 135, x2.5, moved", rotation([0, 0, 1], 135), 2.5, np.array([3.0, -1.0, 2.0])),
         ("arbitrary 77, x0.01", rotation([0.3, 0.8, -0.5], 77), 0.01, np.array([0.1, 0.2, 0.3]))]

UP, ACROSS, ALONG = [0, 1, 0], [1, 0, 0], [0, 0, 1]
ASKEW = [("20 about the vertical, tilted 10", rotation(UP, 20) @ rotation(ACROSS, 10)),
         ("30 about the vertical", rotation(UP, -30)),
         ("pitched 15", rotation(ACROSS, -15)),
         ("rolled 15", rotation(ALONG, 15)),
         ("40 about the vertical, pitched 10", rotation(UP, 40) @ rotation(ACROSS, -10))]


def landed(morph, LA):
    return np.asarray(morph.target)[np.asarray(morph.vertex_of_a)[LA]]


def scores(points, VB, LB, names):
    distances = np.linalg.norm(points[:, None] - VB[LB][None], axis=2) / np.linalg.norm(np.ptp(VB, axis=0))
    errors = np.diag(distances)
    return {"landmark_error": {n: round(float(e), 4) for n, e in zip(names, errors)},
            "mean": round(float(errors.mean()), 4), "max": round(float(errors.max()), 4),
            "nearest_own": int((np.argmin(distances, axis=1) == np.arange(len(LB))).sum())}


def run(VA, FA, VB, FB, **kw):
    start = time.perf_counter()
    try:
        morph = pm.morph(VA, FA, VB, FB, **kw)
    except Exception as error:  # a failure is a figure here
        return None, {"error": f"{type(error).__name__}: {error}", "seconds": round(time.perf_counter() - start, 2)}
    chosen = morph.candidates[morph.chosen]
    return morph, {"seconds": round(time.perf_counter() - start, 2), "chosen": f"{chosen.kind}: {chosen.detail}",
                   "fallbacks": list(morph.fallbacks)}


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--pairs", help="comma-separated a>b (default: every ordered pair)")
    parser.add_argument("--pinned", action="store_true")
    parser.add_argument("--turns", action="store_true")
    parser.add_argument("--askew", action="store_true")
    parser.add_argument("--zoomout", action="store_true")
    args = parser.parse_args()
    if not (MODELS / "landmarks.json").exists():
        emit({"bench": "morph_models", "skipped": f"no models folder at {MODELS}"})
        return
    landmarks = json.loads((MODELS / "landmarks.json").read_text())
    meshes = {name: load_obj(MODELS / f"{name}.obj") for name in CHARACTERS if (MODELS / f"{name}.obj").exists()}
    zoomout = None
    if args.zoomout:
        try:
            import zoomout
        except ImportError as error:
            emit({"bench": "morph_models", "zoomout": f"skipped: {error}"})
    wanted = set(args.pairs.split(",")) if args.pairs else None
    for a, b in itertools.permutations(meshes, 2):
        if wanted and f"{a}>{b}" not in wanted:
            continue
        (VA, FA), (VB, FB) = meshes[a], meshes[b]
        record = {"bench": "morph_models", "pair": f"{a} -> {b}", "faces": [len(FA), len(FB)]}
        morph, outcome = run(VA, FA, VB, FB)
        record.update(outcome)
        marks = a + ".obj" in landmarks and b + ".obj" in landmarks
        if marks:
            names = list(landmarks[a + ".obj"])
            LA = np.array([landmarks[a + ".obj"][n] for n in names])
            LB = np.array([landmarks[b + ".obj"][n] for n in names])
            if morph is not None:
                placed = landed(morph, LA)
                record.update(scores(placed, VB, LB, names))
        emit(record)
        if not marks:
            continue
        if args.pinned:
            pins = np.array([[landmarks[a + ".obj"][n], landmarks[b + ".obj"][n]] for n in HOOVES])
            pinned, outcome = run(VA, FA, VB, FB, pins=pins)
            extra = scores(landed(pinned, LA), VB, LB, names) if pinned is not None else {}
            emit({"bench": "morph_models", "pair": f"{a} -> {b}", "pins": "four hooves", **outcome, **extra})
        if args.turns and morph is not None:
            diagonal = np.linalg.norm(np.ptp(VB, axis=0))
            for name, R, scale, shift in TURNS:
                turned, outcome = run(VA @ R.T * scale + shift, FA, VB @ R.T * scale + shift, FB)
                if turned is not None:
                    back = ((landed(turned, LA) - shift) / scale) @ R
                    outcome["moved_from_placed"] = round(float(np.linalg.norm(back - placed, axis=1).max() / diagonal), 4)
                    outcome.update(scores(back, VB, LB, names))
                emit({"bench": "morph_models", "pair": f"{a} -> {b}", "turn": name, **outcome})
        if args.askew:
            diagonal = np.linalg.norm(np.ptp(VB, axis=0))
            centre = VA.mean(axis=0)
            for name, R in ASKEW:
                set_down = (VA - centre) @ R.T + centre + np.array([diagonal, 0.0, 0.0])
                askew, outcome = run(set_down, FA, VB, FB)
                if askew is not None:
                    outcome["straightened_degrees"] = round(float(np.degrees(askew.placement_turn)), 1)
                    outcome.update(scores(landed(askew, LA), VB, LB, names))
                emit({"bench": "morph_models", "pair": f"{a} -> {b}", "askew": name, **outcome})
        if zoomout is not None:
            for hints in (None, "four hooves"):
                pairs = None if hints is None else [(landmarks[a + ".obj"][n], landmarks[b + ".obj"][n]) for n in HOOVES]
                start = time.perf_counter()
                corr = zoomout.zoomout_correspondence(VA, FA, VB, FB, hints=pairs)
                emit({"bench": "morph_models", "pair": f"{a} -> {b}", "method": "ZoomOut (pyfmaps)",
                      "hints": hints or "none", "seconds": round(time.perf_counter() - start, 2),
                      **scores(VB[corr[LA]], VB, LB, names)})


if __name__ == "__main__":
    main()
