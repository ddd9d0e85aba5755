"""Morph To's work off the main thread: the native morph, then its
in-between shapes (as rigid as possible, issue 17, or on straight lines as
in the thesis), on the merged topology or on the source's own. Numpy and
paramorph_native only; no bpy here."""
from dataclasses import dataclass

import numpy as np

from . import repair_mesh
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
    # With Repair: the two meshes as mended (repair_mesh.Repaired), else None.
    # The merged topology is then built on them; a kept topology's shapes are
    # already back on A's own vertices.
    repaired_a: object = None
    repaired_b: object = None
    # The merged topology's Basis (result.source) in the source object's own
    # coordinates; None when the topology is kept.
    source: object = None


def key_times(in_betweens):
    """Morph times of the keys after Basis: the in-betweens, then the target (1)."""
    return [(i + 1) / (in_betweens + 1) for i in range(in_betweens + 1)]


def _repair_both(VA, FA, VB, FB, progress, options, repair):
    """With `repair`: both meshes mended (the first tenth of the progress) and
    the pins and pairs in `options` carried onto them, in place. Returns
    (Repaired A or None, Repaired B or None, the four arrays to compute on)."""
    if not repair:
        return None, None, (VA, FA, VB, FB)
    fixed_a = repair_mesh.repair(VA, FA, progress, share=0.05)
    fixed_b = repair_mesh.repair(VB, FB, lambda f, stage: progress(0.05 + 0.05 * f, stage), share=1.0)
    for name, what in (("pins", "pin"), ("pairs", "pair")):
        if options.get(name) is not None:
            options[name] = fixed_a.vertex_pairs_forward(options[name], fixed_b, what)
    return fixed_a, fixed_b, (fixed_a.V, fixed_a.F, fixed_b.V, fixed_b.F)


def morph_with_in_betweens(VA, FA, VB, FB, *, progress, in_betweens=0, interpolation="ARAP",
                           target_transform=None, to_local=None, keep_topology=False, repair=False, **options):
    """native.morph(VA, FA, VB, FB, **options), then `in_betweens` shapes: of
    the merged mesh, or with keep_topology of A's own mesh (the target sampled
    at A's vertices through the correspondence, and its distance to B).
    target_transform: 4 x 4 applied to the target's positions at the end (the
    morph ends where the target object is), or None. to_local: 3 x 3 taking
    the positions computed on to the source object's own coordinates (the
    inverse of its transform's linear part), or None. repair: mend both
    meshes first (repair_mesh; pins and pairs are carried onto the mended
    meshes). progress(fraction, stage) -> False cancels (native.Cancelled),
    also between in-betweens."""
    VA_in = np.asarray(VA, dtype=np.float64)
    fixed_a, fixed_b, (VA, FA, VB, FB) = _repair_both(VA, FA, VB, FB, progress, options, repair)
    start = 0.1 if repair else 0.0
    share = 0.85 if in_betweens and interpolation == "ARAP" else 1.0
    result = native.morph(VA, FA, VB, FB, progress=lambda f, stage: progress(start + (share - start) * f, stage),
                          **options)
    source, target, faces = np.asarray(result.source), np.asarray(result.target), np.asarray(result.faces)
    outcome = MorphOutcome(result, target, [], repaired_a=fixed_a, repaired_b=fixed_b)
    if keep_topology:
        source, target, faces = np.asarray(VA, dtype=np.float64), target[np.asarray(result.vertex_of_a)], np.asarray(FA)
        outcome.keep_topology = True
        outcome.distance = native.surface_distance(  # seconds on 100k faces: reports, so Esc acts
            target, faces, VB, FB, progress=lambda f, stage: progress(share, "checking the end shape"))
        outcome.target_diagonal = float(np.linalg.norm(np.ptp(np.asarray(VB, dtype=np.float64), axis=0)))
    if target_transform is not None:
        M = np.asarray(target_transform, dtype=np.float64)
        target = target @ M[:3, :3].T + M[:3, 3]
    # A kept topology's shapes go back onto A's own vertices; the ones repair
    # left out (loose, a smaller part) stay where they are.
    def back(X):
        if keep_topology and fixed_a is not None:
            X = fixed_a.to_input(X, VA_in)
        return X if to_local is None else X @ np.asarray(to_local, dtype=np.float64).T
    outcome.target = back(target)
    if not keep_topology:
        outcome.source = back(source)
    times = key_times(in_betweens)[:-1]
    if not times:
        return outcome
    if interpolation == "LINEAR":
        outcome.shapes = [back((1.0 - t) * source + t * target) for t in times]
        return outcome
    step = (1.0 - share) / (len(times) + 1)
    interp = native.ShapeInterpolation(source, target, faces,
                                       progress=lambda f, stage: progress(share + step * f, "in-betweens: setup"))
    for k, t in enumerate(times):
        if not progress(share + step * (k + 1), f"in-between {k + 1} of {len(times)}"):
            raise native.Cancelled("cancelled")
        outcome.shapes.append(back(interp.at(t)))
    return outcome


def correspondence(VA, FA, VB, FB, *, progress, repair=False, **options):
    """native.morph_correspondence (Preview Matches), after mending both
    meshes when `repair`. Returns (result, repaired_a, repaired_b); the
    result's pairs are on the mended meshes' vertices then."""
    fixed_a, fixed_b, (VA, FA, VB, FB) = _repair_both(VA, FA, VB, FB, progress, options, repair)
    start = 0.1 if repair else 0.0
    result = native.morph_correspondence(
        VA, FA, VB, FB, progress=lambda f, stage: progress(start + (1.0 - start) * f, stage), **options)
    return result, fixed_a, fixed_b
