// Feature measures of a mesh (native/features/): concavity (features/concavity.h),
// shape_signature and signature_distance (features/shape_signature.h).
//
// One def_<function> per entry point below, each with its docstring; add a
// new one and call it from bind_features() at the end of the file.
#include "features/concavity.h"
#include "features/shape_signature.h"
#include "python/arrays.h"
#include "python/bindings.h"
#include "python/progress.h"

namespace paramorph::python {

namespace {

void def_concavity(py::module_& m) {
  m.def(
      "concavity",
      [](const py::object& V, const py::object& F) {
        const MatrixX3d v = to_vertices(V);
        const MatrixX3i f = to_faces(F);
        VectorXd I;
        {
          py::gil_scoped_release release;
          I = features::concavity(v, f);
        }
        return to_numpy(I);
      },
      py::arg("V"), py::arg("F"),
      R"doc(Concavity intensity of every vertex (thesis Def. 4.1): its distance to the
convex hull of the mesh, in the units of V.

V: (n, 3) float64 or float32 vertex positions. F: (m, 3) int32 or int64 triangles
(0-based; checked, the hull is that of all of V).
Returns (n,) float64, >= 0: 0 on the hull (corners and flat sides alike), the
distance to the nearest hull facet inside. Invariant under rigid motions,
linear in the mesh's scale. The hull comes from Qhull (coplanar facets merged).
Raises InvalidInputError (a MeshError) for malformed arrays or a flat mesh
(all vertices in one plane: the hull has no volume).)doc");
}

void def_shape_signature(py::module_& m) {
  m.def(
      "shape_signature",
      [](const py::object& V, const py::object& F, int bins, double log_range,
         const py::object& sphere, py::object progress) {
        features::SignatureOptions o;
        o.bins = bins;
        o.log_range = log_range;
        if (!sphere.is_none()) o.sphere = to_vertices(sphere, "sphere");
        const MatrixX3d v = to_vertices(V);
        const MatrixX3i f = to_faces(F);
        PythonProgress bridge(std::move(progress));
        const VectorXd h = run_without_gil(
            bridge, [&] { return features::shape_signature(v, f, o, bridge.get()); });
        return to_numpy(h);
      },
      py::arg("V"), py::arg("F"), py::kw_only(), py::arg("bins") = 32, py::arg("log_range") = 4.0,
      py::arg("sphere") = py::none(), py::arg("progress") = py::none(),
      R"doc(Shape signature (thesis 3.5.3): histogram of the log area stretch of a
conformal map onto the sphere, weighted by surface area so it does not depend
on the tessellation. Compare signatures with signature_distance().

V: (n, 3) float64 or float32. F: (m, 3) int32 or int64, counter-clockwise seen
from outside. Per face, stretch s = (face area / total area) / (sphere face area /
total sphere area); the face adds its area share at ln s. bins: number of bins
covering ln s in [-log_range, log_range]; values beyond count in the end bins;
each face's weight is split linearly between the two nearest bin centres.
sphere: (n, 3) positions on the unit sphere (e.g. sphere_map(V, F).positions);
when None the conformal sphere_map is computed, and the mesh must be closed,
connected, manifold and genus 0.
progress: callable(fraction, stage) -> bool; returning False raises Cancelled.
Returns (bins,) float64 summing to 1.
Raises InvalidInputError (bad options, a sphere of the wrong shape, zero area),
sphere_map's MeshError subclasses (NotClosedError, NotGenusZeroError, ...),
Cancelled.)doc");
}

void def_signature_distance(py::module_& m) {
  m.def(
      "signature_distance",
      [](const py::object& a, const py::object& b, double log_range) {
        return features::signature_distance(to_vector(a, "a"), to_vector(b, "b"), log_range);
      },
      py::arg("a"), py::arg("b"), py::kw_only(), py::arg("log_range") = 4.0,
      R"doc(Distance between two shape signatures made with the same bins and log_range:
the earth mover's distance in log-stretch units (L1 distance of the cumulative
sums times the bin width 2 * log_range / bins). A histogram shifted by one bin
is one bin width away, so small shifts give small distances. Inputs are
normalised to sum 1. Symmetric, 0 for equal signatures, at most 2 * log_range.

a, b: (bins,) arrays. Raises InvalidInputError when their sizes differ, or one
is empty, has negative or non-finite entries, or sums to 0.)doc");
}

}  // namespace

void bind_features(py::module_& m) {
  def_concavity(m);
  def_shape_signature(m);
  def_signature_distance(m);
}

}  // namespace paramorph::python
