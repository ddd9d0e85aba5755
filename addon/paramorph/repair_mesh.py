"""Repair before the operators that need a closed genus-0 mesh (issue 19).

The native repair() runs first, in the operator's own job (progress, Esc):
it welds split seams, drops duplicate and degenerate faces, orients the mesh
outward, cuts non-manifold spots apart, fills holes with faired patches and
keeps the largest part. The operator computes on that mesh; its results come
back onto the user's own vertices and polygons through repair()'s map. Faces
a hole fill added never reach the user's mesh."""
import bpy
import numpy as np

from .native import native

# The operators' "Repair" option (Sphere Map, Segment Extremities, Rank Similar
# Shapes, Preview Matches, Morph To).
REPAIR_PROPERTY = bpy.props.BoolProperty(
    name="Repair", default=True,
    description="Mend the mesh for the computation first: merge split seams, drop duplicate faces, turn "
                "it outward, fill holes, keep the largest part. Results are written back onto your mesh; "
                "the filled patches are not added to it")


class Repaired:
    """repair()'s result with the maps an operator needs. `V`, `F`: what to
    compute on; `changes`: repair's sentences."""

    def __init__(self, result, input_faces):
        """input_faces: the faces repair() was given."""
        self.result = result
        self._input_faces = np.asarray(input_faces)
        self.V = np.asarray(result.V)
        self.F = np.asarray(result.F)
        self.target = np.asarray(result.input_vertex_target)
        self.vertex_source = np.asarray(result.vertex_source)
        self.face_source = np.asarray(result.face_source)
        self.changes = list(result.report.changes)

    @property
    def changed(self):
        return bool(self.changes)

    def summary(self):
        """'repaired: merged 12 vertices ...; filled 5 holes (869 faces added)', or ''."""
        return "repaired: " + "; ".join(self.changes) if self.changes else ""

    def kept_vertices(self):
        """Mask of the user's vertices that are in the repaired mesh."""
        return self.target >= 0

    def to_input(self, values, fallback):
        """Per-vertex `values` on the repaired mesh -> per input vertex; the
        vertices repair dropped (loose, in a removed part) keep `fallback`."""
        out = np.array(fallback, copy=True)
        kept = self.target >= 0
        out[kept] = np.asarray(values)[self.target[kept]]
        return out

    def vertex_pairs_back(self, pairs, other):
        """(k, 2) pairs of repaired vertices (this mesh, `other`) -> the user's
        vertices; pairs on a vertex a hole fill added are left out."""
        pairs = np.asarray(pairs, dtype=np.int64).reshape(-1, 2)
        out = np.stack([self.vertex_source[pairs[:, 0]], other.vertex_source[pairs[:, 1]]], axis=1)
        return out[(out >= 0).all(axis=1)].astype(np.int32)

    def face_labels_to_input(self, labels):
        """Per-face labels on the repaired mesh -> per input triangle. A face
        repair dropped takes the label of a face at its first vertex
        (duplicates, slivers); faces of a removed part get one new label."""
        labels = np.asarray(labels)
        vertex_label = np.full(len(self.V), -1, dtype=np.int64)
        vertex_label[self.F.ravel()] = np.repeat(labels, 3)
        corner = self.target[self._input_faces[:, 0]]
        loose = int(labels.max()) + 1 if len(labels) else 0
        fallback = np.where(corner >= 0, vertex_label[np.maximum(corner, 0)], loose)
        return self.to_input_faces(labels, np.where(fallback >= 0, fallback, loose)).astype(np.int32)

    def vertex_pairs_forward(self, pairs, other, what="pin"):
        """(k, 2) pairs of (this mesh's, `other` Repaired's) input vertices ->
        the repaired vertices; a pair on a vertex repair dropped is an error."""
        pairs = np.asarray(pairs, dtype=np.int64).reshape(-1, 2)
        out = np.stack([self.target[pairs[:, 0]], other.target[pairs[:, 1]]], axis=1).astype(np.int32)
        bad = np.flatnonzero((out < 0).any(axis=1))
        if len(bad):
            k = int(bad[0])
            raise native.InvalidInputError(
                f"{what} {k} ({pairs[k, 0]}, {pairs[k, 1]}) is on a loose vertex or a smaller part that "
                "Repair leaves out: move it onto the main part, or turn Repair off")
        return out

    def triangle_maps(self, tri_poly, tri_loops):
        """The polygon and the three loops of the user's mesh behind each
        repaired triangle, corner by corner (so UV seams keep their sides).
        A triangle a hole fill added borrows those of a neighbouring one."""
        m = len(self.F)
        poly = np.full(m, -1, dtype=np.int64)
        loops = np.full((m, 3), -1, dtype=np.int64)
        kept = np.flatnonzero(self.face_source >= 0)
        source = self.face_source[kept]
        # Input corners as repaired vertices, matched to the repaired corners.
        corners = self.target[self._input_faces[source]]          # (k, 3)
        match = self.F[kept][:, :, None] == corners[:, None, :]  # (k, 3 repaired, 3 input)
        whole = match.any(axis=2).all(axis=1)
        which = match.argmax(axis=2)
        rows = kept[whole]
        poly[rows] = tri_poly[source[whole]]
        loops[rows] = np.take_along_axis(tri_loops[source[whole]], which[whole], axis=1)
        missing = poly < 0
        if missing.any():
            donor = np.where(missing, -1, np.arange(m))
            a, b = _face_neighbours(self.F)
            changed = True
            while changed:  # spread the kept faces' looks into the fills, ring by ring
                changed = False
                for x, y in ((a, b), (b, a)):
                    take = (donor[x] < 0) & (donor[y] >= 0)
                    if take.any():
                        donor[x[take]] = donor[y[take]]
                        changed = True
            donor[donor < 0] = kept[0] if len(kept) else 0
            poly[missing] = poly[donor[missing]]
            loops[missing] = loops[donor[missing]]
        return poly.astype(np.int32), loops.astype(np.int32)

    def to_input_faces(self, face_values, fallback):
        """Per-face values on the repaired mesh -> per input triangle; faces
        repair dropped keep `fallback` (fill faces are left out)."""
        out = np.array(fallback, copy=True)
        kept = self.face_source >= 0
        out[self.face_source[kept]] = np.asarray(face_values)[kept]
        return out


def _face_neighbours(F):
    """(a, b): the pairs of faces sharing an edge."""
    edges = np.sort(np.concatenate([F[:, [0, 1]], F[:, [1, 2]], F[:, [2, 0]]]), axis=1)
    face = np.tile(np.arange(len(F)), 3)
    order = np.lexsort((edges[:, 1], edges[:, 0]))
    edges, face = edges[order], face[order]
    same = (edges[1:] == edges[:-1]).all(axis=1)
    return face[:-1][same], face[1:][same]


def repair(V, F, progress=None, share=0.1):
    """repair(V, F) keeping the largest part, reporting progress as the first
    `share` of an operator's run. Returns a Repaired."""
    def scaled(fraction, stage):
        return True if progress is None else progress(share * fraction, f"repairing: {stage}")
    result = native.repair(V, F, keep_largest_component=True, progress=scaled)
    return Repaired(result, F)


def after_repair(progress, share=0.1):
    """progress for the work after repair: fractions moved into [share, 1]."""
    if progress is None:
        return None
    return lambda fraction, stage: progress(share + (1.0 - share) * fraction, stage)


def repaired_call(function):
    """function(V, F, progress=..., **options) run on the repaired mesh.
    The returned callable gives (Repaired, result)."""
    def call(V, F, *, progress=None, **options):
        fixed = repair(V, F, progress)
        return fixed, function(fixed.V, fixed.F, progress=after_repair(progress), **options)
    return call


def with_summary(line, fixed):
    """An operator's report line with what repair changed, if anything."""
    return f"{line}; {fixed.summary()}" if fixed is not None and fixed.changed else line
