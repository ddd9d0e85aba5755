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

# The operators' "Repair" option (Sphere Map, Segment Extremities, Detect
# Feature Regions, Preview Matches, Morph To).
REPAIR_PROPERTY = bpy.props.BoolProperty(
    name="Repair", default=True,
    description="Mend the mesh for the computation first: merge split seams, drop duplicate faces, turn "
                "it outward, fill holes, keep the largest part. Results are written back onto your mesh; "
                "the filled patches are not added to it")


class Repaired:
    """repair()'s result with the maps an operator needs. `V`, `F`: what to
    compute on; `input_vertices`: how many vertices the user's mesh has."""

    def __init__(self, result, input_vertices, input_faces):
        self.result = result
        self.V = np.asarray(result.V)
        self.F = np.asarray(result.F)
        self.target = np.asarray(result.input_vertex_target)
        self.vertex_source = np.asarray(result.vertex_source)
        self.face_source = np.asarray(result.face_source)
        self.input_vertices = input_vertices
        self.input_faces = input_faces
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

    def input_vertex_indices(self, indices):
        """The repaired vertex of each given input vertex (-1 where dropped)."""
        return self.target[np.asarray(indices, dtype=np.int64)]

    def face_labels_to_input(self, labels, input_faces):
        """Per-face labels on the repaired mesh -> per input triangle. A face
        repair dropped takes the label of a face at its first vertex
        (duplicates, slivers); faces of a removed part get one new label."""
        labels = np.asarray(labels)
        vertex_label = np.full(len(self.V), -1, dtype=np.int64)
        vertex_label[self.F.ravel()] = np.repeat(labels, 3)
        corner = self.target[np.asarray(input_faces)[:, 0]]
        loose = int(labels.max()) + 1 if len(labels) else 0
        fallback = np.where(corner >= 0, vertex_label[np.maximum(corner, 0)], loose)
        return self.to_input_faces(labels, np.where(fallback >= 0, fallback, loose)).astype(np.int32)

    def to_input_faces(self, face_values, fallback):
        """Per-face values on the repaired mesh -> per input triangle; faces
        repair dropped keep `fallback` (fill faces are left out)."""
        out = np.array(fallback, copy=True)
        kept = self.face_source >= 0
        out[self.face_source[kept]] = np.asarray(face_values)[kept]
        return out


def repair(V, F, progress=None, share=0.1):
    """repair(V, F) keeping the largest part, reporting progress as the first
    `share` of an operator's run. Returns a Repaired."""
    def scaled(fraction, stage):
        return True if progress is None else progress(share * fraction, f"repairing: {stage}")
    result = native.repair(V, F, keep_largest_component=True, progress=scaled)
    return Repaired(result, len(V), len(F))


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
