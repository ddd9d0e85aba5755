// Feature cut-and-paste building blocks (native/paste/, thesis ch. 5).
//
// Each entry point has its own block below (def_<name> in the anonymous
// namespace) and one line in bind_paste(), so blocks from different branches
// merge without touching each other.
#include <pybind11/stl.h>

#include <string>

#include "paste/rbf_interpolator.h"
#include "paste/refine_region.h"
#include "python/arrays.h"
#include "python/bindings.h"
#include "python/progress.h"

namespace paramorph::python {

namespace {

// ---------------------------------------------------------------------------
// RbfInterpolator (paste/rbf_interpolator.h)
// ---------------------------------------------------------------------------

/// (n, k) or (n,) numeric array -> n by k (n by 1) matrix; `was_vector` tells which.
Eigen::MatrixXd to_matrix(const py::handle& obj, const char* name, bool* was_vector = nullptr) {
  py::array arr = py::array::ensure(obj);
  PM_REQUIRE(arr, InvalidInputError, name, " must be a numpy array");
  const auto kind = arr.dtype().kind();
  PM_REQUIRE(kind == 'f' || kind == 'i' || kind == 'u', InvalidInputError, name,
             " must be a float array, got dtype ", std::string(py::str(arr.dtype())));
  PM_REQUIRE(arr.ndim() == 1 || arr.ndim() == 2, InvalidInputError, name,
             " must have shape (n, k) or (n,), got ", std::string(py::str(arr.attr("shape"))));
  if (was_vector) *was_vector = arr.ndim() == 1;
  auto data = py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(arr);
  const Eigen::Index rows = arr.shape(0), cols = arr.ndim() == 2 ? arr.shape(1) : 1;
  using RowMajor = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;
  return Eigen::Map<const RowMajor>(data.data(), rows, cols);
}

void def_rbf_interpolator(py::module_& m) {
  using paste::RbfInterpolator;
  py::class_<RbfInterpolator>(m, "RbfInterpolator", R"doc(RBF interpolation of thesis (5.1)/(5.2), factored once.

RbfInterpolator(centres, *, basis="polyharmonic", polynomial_degree=1, support_radius=0.0)
centres: (N, d) float, d = 2 or 3, pairwise distinct.
basis: "polyharmonic" (phi = r^3; polynomial_degree 1 or 2, default 1, the least it needs)
or "wendland" (C2, phi = (1 - r/h)^4_+ (4 r/h + 1), h = support_radius > 0;
polynomial_degree -1 (none), 0, 1 or 2).
The (N+P) x (N+P) system [Phi P; P^T 0] is LU-factored here; solve() only
back-substitutes. InvalidInputError for coincident, non-finite or non-unisolvent
centres (e.g. collinear for a linear polynomial) and bad options.)doc")
      .def(py::init([](const py::object& centres, const std::string& basis, int polynomial_degree,
                       double support_radius) {
             paste::RbfOptions o;
             o.basis = paste::parse_rbf_basis(basis);
             o.polynomial_degree = polynomial_degree;
             o.support_radius = support_radius;
             const Eigen::MatrixXd c = to_matrix(centres, "centres");
             py::gil_scoped_release release;
             return RbfInterpolator(c, o);
           }),
           py::arg("centres"), py::kw_only(), py::arg("basis") = "polyharmonic",
           py::arg("polynomial_degree") = 1, py::arg("support_radius") = 0.0)
      .def(
          "solve",
          [](const RbfInterpolator& rbf, const py::object& values) {
            bool vector = false;
            const Eigen::MatrixXd f = to_matrix(values, "values", &vector);
            Eigen::MatrixXd c;
            {
              py::gil_scoped_release release;
              c = rbf.solve(f);
            }
            return vector ? to_numpy(Eigen::VectorXd(c.col(0))) : to_numpy(c);
          },
          py::arg("values"),
          "values (N, m) or (N,) -> coefficients (N+P, m) or (N+P,) [w; c] by back-substitution.")
      .def(
          "evaluation_matrix",
          [](const RbfInterpolator& rbf, const py::object& points) {
            const Eigen::MatrixXd x = to_matrix(points, "points");
            RbfInterpolator::RowMajorXd E;
            {
              py::gil_scoped_release release;
              E = rbf.evaluation_matrix(x);
            }
            // Already row-major: one copy into numpy (E is M x (N+P), large).
            return py::array_t<double>({py::ssize_t(E.rows()), py::ssize_t(E.cols())}, E.data());
          },
          py::arg("points"),
          "points (M, d) -> (M, N+P) matrix E with s(points) = E @ coefficients.")
      .def(
          "evaluate",
          [](const RbfInterpolator& rbf, const py::object& points, const py::object& coefficients) {
            bool vector = false;
            const Eigen::MatrixXd x = to_matrix(points, "points");
            const Eigen::MatrixXd c = to_matrix(coefficients, "coefficients", &vector);
            Eigen::MatrixXd s;
            {
              py::gil_scoped_release release;
              s = rbf.evaluate(x, c);
            }
            return vector ? to_numpy(Eigen::VectorXd(s.col(0))) : to_numpy(s);
          },
          py::arg("points"), py::arg("coefficients"),
          "s(points): points (M, d), coefficients from solve() -> (M, m) (or (M,)).")
      .def_property_readonly("num_centres", &RbfInterpolator::num_centres)
      .def_property_readonly("dimension", &RbfInterpolator::dimension)
      .def_property_readonly("num_polynomial_terms", &RbfInterpolator::num_polynomial_terms)
      .def_property_readonly("rcond", &RbfInterpolator::rcond,
                             "estimated reciprocal condition number of the factored system")
      .def("__repr__", [](const RbfInterpolator& rbf) {
        return "<RbfInterpolator N=" + std::to_string(rbf.num_centres()) +
               " d=" + std::to_string(rbf.dimension()) +
               " P=" + std::to_string(rbf.num_polynomial_terms()) + ">";
      });
}


// ---------------------------------------------------------------------------
// refine_region (paste/refine_region.h)
// ---------------------------------------------------------------------------

void def_refine_region(py::module_& m) {
  using paste::RefinedRegion;
  py::class_<RefinedRegion>(m, "RefinedRegion", "Result of refine_region().")
      .def_property_readonly("V", [](const RefinedRegion& r) { return to_numpy(r.V); },
                             "(n, 3) float64: the original vertices first, unchanged, then the new "
                             "ones, flat on the original faces")
      .def_property_readonly("F", [](const RefinedRegion& r) { return to_numpy(r.F); },
                             "(m, 3) int32: untouched faces first (original order), then region "
                             "tessellations, then re-triangulated neighbours")
      .def_property_readonly("new_faces", [](const RefinedRegion& r) { return to_numpy(r.new_faces); },
                             "(k,) int32: rows of F that are not original faces")
      .def_property_readonly("base_face", [](const RefinedRegion& r) { return to_numpy(r.base_face); },
                             "(n,) int32: the original face each vertex lies on (-1: isolated)")
      .def_property_readonly("bary", [](const RefinedRegion& r) { return to_numpy(r.bary); },
                             "(n, 3) float64: barycentric coordinates in base_face")
      .def_property_readonly("limit", [](const RefinedRegion& r) { return to_numpy(r.limit); },
                             "(n, 3) float64: Loop limit positions of the whole input mesh")
      .def_property_readonly("limit_normal", [](const RefinedRegion& r) { return to_numpy(r.limit_normal); },
                             "(n, 3) float64: unit limit normals")
      .def_property_readonly("region_interior",
                             [](const RefinedRegion& r) {
                               return to_numpy(Eigen::Matrix<bool, Eigen::Dynamic, 1>(
                                   r.region_interior.cast<bool>()));
                             },
                             "(n,) bool: in the refined region and not on its rim")
      .def("__repr__", [](const RefinedRegion& r) {
        return "<RefinedRegion vertices=" + std::to_string(r.V.rows()) +
               " faces=" + std::to_string(r.F.rows()) +
               " new_faces=" + std::to_string(r.new_faces.size()) + ">";
      });
  m.def(
      "refine_region",
      [](const py::object& V, const py::object& F, const py::object& region_faces, int level,
         py::object progress) {
        const MatrixX3d v = to_vertices(V);
        const MatrixX3i f = to_faces(F);
        const std::vector<Index> region = to_indices(region_faces, "region_faces");
        PythonProgress bridge(std::move(progress));
        return run_without_gil(bridge, [&] { return paste::refine_region(v, f, region, level, bridge.get()); });
      },
      py::arg("V"), py::arg("F"), py::arg("region_faces"), py::kw_only(), py::arg("level") = 1,
      py::arg("progress") = py::none(),
      R"doc(Uniform Loop refinement of a face region, stitched to the rest (thesis 5.2).

region_faces (k,) int: faces to refine (duplicates ignored). level 0..8: each region
face becomes 4**level triangles; faces outside sharing an edge with the region are
re-triangulated to take its new vertices (no cracks, no T-junctions); the rest is
unchanged. Vertices are flat on the original faces; limit / limit_normal are the
Loop limit surface of the whole mesh there (OpenSubdiv Bfr). Raises InvalidInputError
(bad arrays, indices, level), NonManifoldError, DegenerateFaceError.)doc");
}

}  // namespace

void bind_paste(py::module_& m) {
  def_rbf_interpolator(m);
  def_refine_region(m);
}

}  // namespace paramorph::python
