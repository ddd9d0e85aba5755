"""Morph To's work off the main thread: the native morph, then its
in-between shapes (as rigid as possible, issue 17, or on straight lines as
in the thesis), on the merged topology or on the source's own. Numpy and
paramorph_native only; no bpy here."""
from dataclasses import dataclass

import numpy as np

from .native import native


@dataclass
class MorphOutcome:
    result: object            # paramorph_native.Morph
    target: np.ndarray        # (M, 3) the merged vertices at t = 1, in the source's frame
    shapes: list              # [(M, 3)] the in-betweens at key_times(...)[:-1]
    # Keeping the source's topology: target and shapes are then (#VA, 3), A's
    # own vertices; `distance` (paramorph_native.SurfaceDistance) from that
    # t = 1 shape to the target, and the target's diagonal, both in B's frame.
    keep_topology: bool = False
    distance: object = None
    target_diagonal: float = 0.0


def key_times(in_betweens):
    """Morph times of the keys after Basis: the in-betweens, then the target (1)."""
    return [(i + 1) / (in_betweens + 1) for i in range(in_betweens + 1)]


def morph_with_in_betweens(VA, FA, VB, FB, *, progress, in_betweens=0, interpolation="ARAP",
                           target_transform=None, keep_topology=False, **options):
    """native.morph(VA, FA, VB, FB, **options), then `in_betweens` shapes: of
    the merged mesh, or with keep_topology of A's own mesh (the target sampled
    at A's vertices through the correspondence, and its distance to B).
    target_transform: 4 x 4 taking the target's coordinates to the source's
    (the morph ends where the target object is), or None. progress(fraction,
    stage) -> False cancels (native.Cancelled), also between in-betweens."""
    share = 0.85 if in_betweens and interpolation == "ARAP" else 1.0
    result = native.morph(VA, FA, VB, FB, progress=lambda f, stage: progress(share * f, stage), **options)
    source, target, faces = np.asarray(result.source), np.asarray(result.target), np.asarray(result.faces)
    outcome = MorphOutcome(result, target, [])
    if keep_topology:
        source, target, faces = np.asarray(VA, dtype=np.float64), target[np.asarray(result.vertex_of_a)], np.asarray(FA)
        outcome.keep_topology = True
        outcome.distance = native.surface_distance(target, faces, VB, FB)
        outcome.target_diagonal = float(np.linalg.norm(np.ptp(np.asarray(VB, dtype=np.float64), axis=0)))
    if target_transform is not None:
        M = np.asarray(target_transform, dtype=np.float64)
        target = target @ M[:3, :3].T + M[:3, 3]
    outcome.target = target
    times = key_times(in_betweens)[:-1]
    if not times:
        return outcome
    if interpolation == "LINEAR":
        outcome.shapes = [(1.0 - t) * source + t * target for t in times]
        return outcome
    if not progress(share, "in-betweens: factoring"):
        raise native.Cancelled("cancelled")
    interp = native.ShapeInterpolation(source, target, faces)
    for k, t in enumerate(times):
        if not progress(share + (1.0 - share) * (k + 1) / (len(times) + 1), f"in-between {k + 1} of {len(times)}"):
            raise native.Cancelled("cancelled")
        outcome.shapes.append(interp.at(t))
    return outcome
