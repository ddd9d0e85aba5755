"""Morph To's work off the main thread: the native morph, then its
in-between shapes (as rigid as possible, issue 17, or on straight lines as
in the thesis), on the merged topology or on the source's own. Numpy and
paramorph_native only; no bpy here."""
from dataclasses import dataclass, field

import numpy as np

from .. import repair_mesh
from ..native import native


@dataclass
class RidingParts:
    """The source's separate parts (eyes, teeth, buttons: what Repair leaves
    out of the morphed body), carried by the body (native.PartRider)."""
    vertices: np.ndarray   # (p,) their vertices, in the source's numbering
    part_of: np.ndarray    # (p,) which part each vertex is in, 0..k-1
    triangles: np.ndarray  # rows of the source's triangles that lie in them
    riding: np.ndarray     # (k,) bool: carried (else left where it was, far from the body)
    pushed: np.ndarray     # (k,) the most each part was pushed out of the body at a key
    # (k,) bool: a lone vertex of the body itself that Repair left out (a
    # seam's or a bow-tie's), carried like a part but not one.
    stray: np.ndarray = None
    # Merged topology: the parts' vertices in the source object's own
    # coordinates at rest and at each key after it (the in-betweens, then
    # the target); the kept topology has them in its own shapes.
    basis: np.ndarray = None
    shapes: list = field(default_factory=list)

    @property
    def separate(self):
        """(k,) bool: a separate part (not a stray vertex of the body)."""
        return ~self.stray


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
    # The share of its faces left folded against the target's (pleats that
    # shade as creases; FitToSurface.facing_away_after).
    folded: float = 0.0
    # With Repair: the two meshes as mended (repair_mesh.Repaired), else None.
    # The merged topology is then built on them; a kept topology's shapes are
    # already back on A's own vertices.
    repaired_a: object = None
    repaired_b: object = None
    # The merged topology's Basis (result.source) in the source object's own
    # coordinates; None when the topology is kept.
    source: object = None
    # The source's separate parts riding along (RidingParts), or None.
    parts: object = None


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


def separate_parts(V_in, F_in, fixed):
    """RidingParts (without positions) for the vertices Repair left out of
    the source (`fixed`: its Repaired): each connected part it left out
    whole, and each lone vertex it left out of the body's own part (a stray);
    the triangles among them. None when there are none (or no repair)."""
    if fixed is None:
        return None
    vertices = np.flatnonzero(~fixed.kept_vertices())
    if not len(vertices):
        return None
    F_in = np.asarray(F_in, dtype=np.int64).reshape(-1, 3)
    labels = np.asarray(native.vertex_parts(F_in, len(V_in)))
    in_body = np.isin(labels[vertices], labels[fixed.kept_vertices()])
    # Strays are parts of one vertex each, numbered after the real parts.
    keys = np.where(in_body, labels.max() + 1 + np.arange(len(vertices)), labels[vertices])
    _, first, part_of = np.unique(keys, return_index=True, return_inverse=True)
    left_out = np.zeros(len(V_in), dtype=bool)
    left_out[vertices] = True
    triangles = np.flatnonzero(left_out[F_in].all(axis=1))
    k = len(first)
    return RidingParts(vertices, part_of.astype(np.int32).ravel(), triangles, np.ones(k, dtype=bool), np.zeros(k),
                       stray=in_body[first])


def morph_with_in_betweens(VA, FA, VB, FB, *, progress, in_betweens=0, interpolation="ARAP",
                           target_transform=None, to_local=None, keep_topology=False, repair=False, target_turn=None,
                           **options):
    """native.morph(VA, FA, VB, FB, **options), then `in_betweens` shapes: of
    the merged mesh, or with keep_topology of A's own mesh (the target sampled
    at A's vertices through the correspondence, then fitted to B both ways by
    native.fit_to_surface, and its distance to B).
    target_transform: 4 x 4 applied to the target's positions at the end (the
    morph ends where the target object is), or None. to_local: 3 x 3 taking
    the positions computed on to the source object's own coordinates (the
    inverse of its transform's linear part), or None. repair: mend both
    meshes first (repair_mesh; pins and pairs are carried onto the mended
    meshes). progress(fraction, stage) -> False cancels (native.Cancelled),
    also between in-betweens. target_turn: 3 x 3, the turn of the target
    as placed (its object's rotation), or None: a kept topology's distance
    is reported as a share of the diagonal of the target's own box, the
    same however the target is turned. The source's separate parts that repair
    leaves out of the morph ride along the body through every key
    (outcome.parts)."""
    VA_in, FA_in = np.asarray(VA, dtype=np.float64), FA
    fixed_a, fixed_b, (VA, FA, VB, FB) = _repair_both(VA, FA, VB, FB, progress, options, repair)
    parts = separate_parts(VA_in, FA_in, fixed_a)
    start = 0.1 if repair else 0.0
    share = 0.85 if in_betweens and interpolation == "ARAP" else 1.0
    # A kept topology is then fitted to the target: the last third of the morph's share.
    fitted = start + (share - start) * (0.65 if keep_topology else 1.0)
    result = native.morph(VA, FA, VB, FB, progress=lambda f, stage: progress(start + (fitted - start) * f, stage),
                          **options)
    source, target, faces = np.asarray(result.source), np.asarray(result.target), np.asarray(result.faces)
    outcome = MorphOutcome(result, target, [], repaired_a=fixed_a, repaired_b=fixed_b)
    if keep_topology:
        source, target, faces = np.asarray(VA, dtype=np.float64), target[np.asarray(result.vertex_of_a)], np.asarray(FA)
        # A's vertices sit where the correspondence put them on B; drawn over
        # B both ways (its legs, tail and muzzle get their share), the pins
        # and matched tips held where they are.
        held = np.unique(np.asarray(result.pairs, dtype=np.int64).reshape(-1, 2)[:, 0])
        fit = native.fit_to_surface(target, faces, VB, FB, held=held,
                                    progress=lambda f, stage: progress(fitted + (share - fitted) * f, stage))
        target = np.asarray(fit.positions)
        outcome.keep_topology = True
        outcome.folded = fit.facing_away_after
        outcome.distance = native.surface_distance(  # seconds on 100k faces: reports, so Esc acts
            target, faces, VB, FB, progress=lambda f, stage: progress(share, "checking the end shape"))
        own = np.asarray(VB, dtype=np.float64) @ (np.eye(3) if target_turn is None else np.asarray(target_turn))
        outcome.target_diagonal = float(np.linalg.norm(np.ptp(own, axis=0)))
    if target_transform is not None:
        M = np.asarray(target_transform, dtype=np.float64)
        target = target @ M[:3, :3].T + M[:3, 3]
    local = (lambda X: X) if to_local is None else (lambda X: X @ np.asarray(to_local, dtype=np.float64).T)
    rider = None
    if parts is not None:
        rider = native.PartRider(source, faces, VA_in[parts.vertices], parts.part_of)
        parts.riding = np.asarray(rider.riding)
        outcome.parts = parts
        if not keep_topology:
            parts.basis = local(VA_in[parts.vertices])

    # Each body shape back in the source's own coordinates; a kept
    # topology's onto A's own vertices, with its separate parts carried.
    def back(X):
        if rider is not None:
            carried, pushed = rider.at(X)
            parts.pushed = np.maximum(parts.pushed, pushed)
        if keep_topology and fixed_a is not None:
            X = fixed_a.to_input(X, VA_in)
            if rider is not None:
                X[parts.vertices] = carried
        elif rider is not None:
            parts.shapes.append(local(carried))
        return local(X)
    times = key_times(in_betweens)[:-1]
    if interpolation == "LINEAR" or not times:
        outcome.shapes = [back((1.0 - t) * source + t * target) for t in times]
    else:
        step = (1.0 - share) / (len(times) + 1)
        interp = native.ShapeInterpolation(
            source, target, faces, progress=lambda f, stage: progress(share + step * f, "in-betweens: setup"))
        for k, t in enumerate(times):
            if not progress(share + step * (k + 1), f"in-between {k + 1} of {len(times)}"):
                raise native.Cancelled("cancelled")
            outcome.shapes.append(back(interp.at(t)))
    outcome.target = back(target)  # last: the parts' shapes end with the target's
    if not keep_topology:
        outcome.source = local(source)
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
