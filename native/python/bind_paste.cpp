// Feature cut-and-paste (native/paste/, thesis ch. 5): extract_feature
// (paste/extract_feature.h), Feature (paste/feature.h) with to_arrays() /
// from_arrays() for storing it, sample_feature (paste/sample_feature.h), and
// the paste building blocks RbfInterpolator (paste/rbf_interpolator.h) and
// refine_region (paste/refine_region.h), and PasteSession
// (paste/paste_session.h), each in its own block below.
#include <pybind11/stl.h>

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include "paste/extract_feature.h"
#include "paste/paste_session.h"
#include "paste/rbf_interpolator.h"
#include "paste/refine_region.h"
#include "paste/sample_feature.h"
#include "python/arrays.h"
#include "python/bindings.h"
#include "python/progress.h"

namespace paramorph::python {

using paste::Feature;

namespace {

/// d[key] as an array of numeric `kinds` (numpy dtype kind letters) and
/// exactly `shape` (a -1 entry: any size).
py::array checked_array(const py::dict& d, const char* key, const char* kinds, const char* what,
                        const std::vector<py::ssize_t>& shape) {
  PM_REQUIRE(d.contains(key), InvalidInputError, "feature arrays lack \"", key, "\"");
  py::array arr = py::array::ensure(d[key]);
  PM_REQUIRE(arr && std::string(kinds).find(arr.dtype().kind()) != std::string::npos, InvalidInputError,
             "\"", key, "\" must be ", what);
  bool ok = arr.ndim() == py::ssize_t(shape.size());
  for (std::size_t k = 0; ok && k < shape.size(); ++k) ok = shape[k] < 0 || arr.shape(k) == shape[k];
  PM_REQUIRE(ok, InvalidInputError, "\"", key, "\" has shape ", std::string(py::str(arr.attr("shape"))),
             ", expected ", std::string(py::str(py::tuple(py::cast(shape)))), " (-1: any)");
  return arr;
}

/// A float64 array of exactly `shape` (a -1 entry: any size) from d[key].
py::array_t<double, py::array::c_style | py::array::forcecast> float_array(const py::dict& d, const char* key,
                                                                           std::vector<py::ssize_t> shape) {
  py::array arr = checked_array(d, key, "fi", "a numeric array", shape);
  auto out = py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(arr);
  PM_REQUIRE(std::all_of(out.data(), out.data() + out.size(), [](double x) { return std::isfinite(x); }),
             InvalidInputError, "\"", key, "\" must be finite");
  return out;
}

py::array_t<std::int64_t, py::array::c_style | py::array::forcecast> int_array(const py::dict& d, const char* key,
                                                                               std::vector<py::ssize_t> shape) {
  py::array arr = checked_array(d, key, "iu", "an integer array", shape);
  return py::array_t<std::int64_t, py::array::c_style | py::array::forcecast>::ensure(arr);
}

template <typename Matrix>
Matrix to_matrix(const py::array_t<double, py::array::c_style | py::array::forcecast>& a, Index rows) {
  Matrix m(rows, Matrix::ColsAtCompileTime == Eigen::Dynamic ? 1 : Matrix::ColsAtCompileTime);
  std::copy(a.data(), a.data() + a.size(), m.data());
  return m;
}

VectorXi to_index_vector(const py::array_t<std::int64_t, py::array::c_style | py::array::forcecast>& a,
                         std::int64_t bound, const char* key) {
  VectorXi out(a.size());
  for (py::ssize_t k = 0; k < a.size(); ++k) {
    PM_REQUIRE(a.data()[k] >= 0 && a.data()[k] < bound, InvalidInputError, "\"", key, "\" has index ",
               a.data()[k], " out of range [0, ", bound, ")");
    out[k] = Index(a.data()[k]);
  }
  return out;
}

py::array scalar(double x) { return py::array_t<double>(std::vector<py::ssize_t>{}, &x); }

py::array grid(const Feature& f, const MatrixX3d& m) {
  py::array_t<double> out({py::ssize_t(f.resolution), py::ssize_t(f.resolution), py::ssize_t(3)});
  std::copy(m.data(), m.data() + m.size(), out.mutable_data());
  return out;
}

py::array mask_grid(const Feature& f) {
  py::array_t<std::uint8_t> out({py::ssize_t(f.resolution), py::ssize_t(f.resolution)});
  for (Index k = 0; k < f.mask.size(); ++k) out.mutable_data()[k] = std::uint8_t(f.mask[k]);
  return out;
}

py::array loop_vertices(const Feature& f) {
  std::vector<Index> all;
  for (const auto& loop : f.boundary_loops) all.insert(all.end(), loop.begin(), loop.end());
  return to_numpy(all);
}

py::array loop_offsets(const Feature& f) {
  std::vector<Index> offsets{0};
  for (const auto& loop : f.boundary_loops) offsets.push_back(offsets.back() + Index(loop.size()));
  return to_numpy(offsets);
}

py::dict to_arrays(const Feature& f) {
  py::dict d;
  d["faces"] = to_numpy(f.F);
  d["vertices"] = to_numpy(f.V);
  d["uv"] = to_numpy(f.uv);
  d["base_vertices"] = to_numpy(f.base_V);
  d["base_uv"] = to_numpy(f.base_uv);
  d["boundary_vertices"] = loop_vertices(f);
  d["boundary_offsets"] = loop_offsets(f);
  d["source_faces"] = to_numpy(f.source_faces);
  d["source_vertices"] = to_numpy(f.source_vertices);
  d["origin"] = to_numpy(Eigen::VectorXd(f.origin));
  d["axes"] = to_numpy(Eigen::Matrix<double, 3, 3, Eigen::RowMajor>(f.axes));
  d["radius"] = scalar(f.radius);
  d["area"] = scalar(f.area);
  d["mean_edge_length"] = scalar(f.mean_edge_length);
  d["grid_origin"] = to_numpy(Eigen::VectorXd(f.grid_origin));
  d["grid_spacing"] = scalar(f.grid_spacing);
  d["displacement"] = grid(f, f.displacement);
  d["mask"] = mask_grid(f);
  py::array_t<std::uint8_t> carried{std::vector<py::ssize_t>{}};
  carried.mutable_data()[0] = std::uint8_t(f.carried);
  d["carried"] = carried;
  return d;
}

Feature from_arrays(const py::dict& d) {
  Feature f;
  const auto faces = int_array(d, "faces", {-1, 3});
  const auto V = float_array(d, "vertices", {-1, 3});
  const Index n = Index(V.shape(0)), m = Index(faces.shape(0));
  PM_REQUIRE(n > 0 && m > 0, InvalidInputError, "a feature needs vertices and faces");
  f.F = to_index_vector(faces, n, "faces").reshaped<Eigen::RowMajor>(m, 3);
  f.V = to_matrix<MatrixX3d>(V, n);
  f.uv = to_matrix<MatrixX2d>(float_array(d, "uv", {n, 2}), n);
  f.base_V = to_matrix<MatrixX3d>(float_array(d, "base_vertices", {n, 3}), n);
  f.base_uv = to_matrix<MatrixX2d>(float_array(d, "base_uv", {n, 2}), n);
  const VectorXi loop_vertices = to_index_vector(int_array(d, "boundary_vertices", {-1}), n, "boundary_vertices");
  const auto offsets = int_array(d, "boundary_offsets", {-1});
  PM_REQUIRE(offsets.size() >= 2 && offsets.data()[0] == 0 && offsets.data()[offsets.size() - 1] == loop_vertices.size(),
             InvalidInputError, "\"boundary_offsets\" must run from 0 to len(boundary_vertices)");
  for (py::ssize_t k = 0; k + 1 < offsets.size(); ++k) {
    PM_REQUIRE(offsets.data()[k] < offsets.data()[k + 1], InvalidInputError,
               "\"boundary_offsets\" must increase");
    f.boundary_loops.emplace_back(loop_vertices.data() + offsets.data()[k], loop_vertices.data() + offsets.data()[k + 1]);
  }
  f.source_faces = to_index_vector(int_array(d, "source_faces", {m}), std::numeric_limits<Index>::max(), "source_faces");
  f.source_vertices = to_index_vector(int_array(d, "source_vertices", {n}), std::numeric_limits<Index>::max(),
                                      "source_vertices");
  const auto origin = float_array(d, "origin", {3});
  f.origin = Eigen::Vector3d(origin.data());
  const auto axes = float_array(d, "axes", {3, 3});
  f.axes = Eigen::Map<const Eigen::Matrix<double, 3, 3, Eigen::RowMajor>>(axes.data());
  PM_REQUIRE((f.axes.transpose() * f.axes - Eigen::Matrix3d::Identity()).norm() < 1e-9 && f.axes.determinant() > 0,
             InvalidInputError, "\"axes\" must be a rotation (orthonormal, right-handed)");
  f.radius = *float_array(d, "radius", {}).data();
  f.area = *float_array(d, "area", {}).data();
  f.mean_edge_length = *float_array(d, "mean_edge_length", {}).data();
  const auto grid_origin = float_array(d, "grid_origin", {2});
  f.grid_origin = Eigen::Vector2d(grid_origin.data());
  f.grid_spacing = *float_array(d, "grid_spacing", {}).data();
  const auto displacement = float_array(d, "displacement", {-1, -1, 3});
  const py::ssize_t r = displacement.shape(0);
  PM_REQUIRE(r >= 2 && r <= paste::kMaxFeatureResolution && displacement.shape(1) == r, InvalidInputError,
             "\"displacement\" must be (r, r, 3) with 2 <= r <= ", paste::kMaxFeatureResolution);
  PM_REQUIRE(f.radius > 0 && f.grid_spacing > 0, InvalidInputError, "radius and grid_spacing must be positive");
  f.resolution = int(r);
  f.displacement = to_matrix<MatrixX3d>(displacement, Index(r * r));
  const auto mask = int_array(d, "mask", {r, r});
  f.mask.resize(Index(r * r));
  for (py::ssize_t k = 0; k < mask.size(); ++k) {
    PM_REQUIRE(mask.data()[k] == 0 || mask.data()[k] == 1, InvalidInputError, "\"mask\" must hold 0 or 1");
    f.mask[Index(k)] = Index(mask.data()[k]);
  }
  // Absent in features stored before carried features existed: not carried.
  if (d.contains("carried")) {
    const auto carried = int_array(d, "carried", {});
    PM_REQUIRE(carried.data()[0] == 0 || carried.data()[0] == 1, InvalidInputError, "\"carried\" must be 0 or 1");
    f.carried = carried.data()[0] == 1;
  }
  return f;
}

MatrixX2d to_uv_points(const py::handle& obj) {
  py::array arr = py::array::ensure(obj);
  PM_REQUIRE(arr && arr.ndim() == 2 && arr.shape(1) == 2 && (arr.dtype().kind() == 'f' || arr.dtype().kind() == 'i'),
             InvalidInputError, "uv must be a numeric (k, 2) array");
  auto data = py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(arr);
  MatrixX2d out(arr.shape(0), 2);
  std::copy(data.data(), data.data() + data.size(), out.data());
  return out;
}

}  // namespace

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
      .def_property_readonly("new_face_parents", [](const RefinedRegion& r) { return to_numpy(r.new_face_parents); },
                             "(k,) int32: per new face, the input face it lies in")
      .def_property_readonly("replaced_faces", [](const RefinedRegion& r) { return to_numpy(r.replaced_faces); },
                             "(j,) int32: input faces not kept as they were (region and stitched neighbours)")
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


// PasteSession (paste/paste_session.h)

Eigen::Vector3d to_point(const py::object& obj, const char* what) {
  const auto a = py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(obj);
  PM_REQUIRE(a && a.size() == 3, InvalidInputError, what, " must be 3 numbers (x, y, z)");
  return Eigen::Vector3d(a.data()[0], a.data()[1], a.data()[2]);
}

py::dict stats_dict(const paste::PasteStats& s) {
  py::dict d;
  d["level"] = s.level;
  d["anchor_face"] = s.anchor_face;
  d["refined_faces"] = s.refined_faces;
  d["replaced_faces"] = s.replaced_faces;
  d["moved_vertices"] = s.moved_vertices;
  d["feature_vertices"] = s.feature_vertices;
  d["control_points"] = s.control_points;
  d["lift"] = s.lift;
  d["feature_radius"] = s.feature_radius;
  d["influence_radius"] = s.influence_radius;
  d["target_map"] = s.disc_map ? "disc" : "exponential";
  d["disc_faces"] = s.disc_faces;
  d["disc_iterations"] = s.disc_iterations;
  d["map_seconds"] = s.map_seconds;
  d["setup_seconds"] = s.setup_seconds;
  d["update_seconds"] = s.update_seconds;
  return d;
}

void def_paste_session(py::module_& m) {
  using paste::PasteSession;
  py::class_<PasteSession>(m, "PasteSession", R"doc(A feature pasted onto a target, movable (thesis 5.2).

PasteSession(V, F, feature, *, anchor, rotation=0.0, scale=1.0, blend_radius=2.0,
             subdivision_level=-1, basis="polyharmonic", fit="keep_form", target_map="auto",
             progress=None)

V (n, 3), F (m, 3): the target, a manifold triangle mesh. feature: from extract_feature.
anchor (3,): snapped to the closest point of the target; the feature's frame sits there
with its normal along the surface's and its u axis along the target's X projected onto
the tangent plane (Y when X is within 25 degrees of the normal), turned by rotation
(radians). scale: uniform factor on the feature. blend_radius (> 1.1): the influence rim
in feature radii; target vertices beyond it are untouched. subdivision_level: -1 matches
the refined edges to the feature's, else 0..6. basis: RBF of the base deformation.
fit="keep_form": the feature keeps its form; an RBF over the feature's plane (factored
once) bends the target to meet its boundary. fit="follow_surface": the feature's
displacement map is laid over the target's Loop limit surface in its frame (no blend).
The faces under it are Loop-refined (OpenSubdiv) and stitched without cracks. The
target's coordinates: target_map="auto" takes its discrete exponential map around the
anchor where that is fold-free within the rim, else a fold-free disc map (the surface
within about 1.25 rims grown as a disc, flattened by the isometric solver from a Tutte
start, anchored in the same frame); "exponential" only the former (refusing where it
folds), "disc" always the latter. stats["target_map"] says which ran. It refuses
(TargetTooSmallError) only where the surface within the rim is not a disc (a hole, a
handle, a part thinner than the feature) or the feature reaches the target's boundary.
update() moves it (same result as a new session).
Raises InvalidInputError, NonManifoldError, DegenerateFaceError, TargetTooSmallError.)doc")
      .def(py::init([](const py::object& V, const py::object& F, const Feature& feature, const py::object& anchor,
                       double rotation, double scale, double blend_radius, int subdivision_level,
                       const std::string& basis, const std::string& fit, const std::string& target_map,
                       py::object progress) {
             const MatrixX3d v = to_vertices(V);
             const MatrixX3i f = to_faces(F);
             paste::PasteOptions o;
             o.anchor = to_point(anchor, "anchor");
             o.rotation = rotation;
             o.scale = scale;
             o.blend_radius = blend_radius;
             o.subdivision_level = subdivision_level;
             o.basis = paste::parse_rbf_basis(basis);
             o.fit = paste::parse_paste_fit(fit);
             o.target_map = paste::parse_target_map(target_map);
             PythonProgress bridge(std::move(progress));
             return run_without_gil(bridge, [&] { return std::make_unique<PasteSession>(v, f, feature, o, bridge.get()); });
           }),
           py::arg("V"), py::arg("F"), py::arg("feature"), py::kw_only(), py::arg("anchor"),
           py::arg("rotation") = 0.0, py::arg("scale") = 1.0, py::arg("blend_radius") = 2.0,
           py::arg("subdivision_level") = -1, py::arg("basis") = "polyharmonic", py::arg("fit") = "keep_form",
           py::arg("target_map") = "auto", py::arg("progress") = py::none())
      .def(
          "update",
          [](PasteSession& s, const py::object& anchor, const py::object& rotation, const py::object& scale) {
            const Eigen::Vector3d a = anchor.is_none() ? s.options().anchor : to_point(anchor, "anchor");
            // A number or None; anything else is the caller's mistake, said as one
            // (py::cast raised an untyped "Unable to cast Python instance").
            const auto number = [](const py::object& value, const char* name, double keep) {
              if (value.is_none()) return keep;
              PM_REQUIRE(PyFloat_Check(value.ptr()) || PyLong_Check(value.ptr()) ||
                             py::isinstance(value, py::module_::import("numpy").attr("number")),
                         InvalidInputError, name, " must be a number or None, got ",
                         std::string(py::str(py::type::of(value).attr("__name__"))));
              return value.cast<double>();
            };
            const double r = number(rotation, "rotation", s.options().rotation);
            const double k = number(scale, "scale", s.options().scale);
            py::gil_scoped_release release;
            s.update(a, r, k);
          },
          py::kw_only(), py::arg("anchor") = py::none(), py::arg("rotation") = py::none(),
          py::arg("scale") = py::none(),
          "Move, turn or scale the feature (None keeps a value); back-substitutes the factored RBF. "
          "On TargetTooSmallError the previous placement and result are kept.")
      .def(
          "result",
          [](const PasteSession& s) {
            return py::make_tuple(to_numpy(s.V()), to_numpy(s.F()), to_numpy(s.new_faces()));
          },
          "(V, F, new_faces): the target's vertices first (those within the rim moved), then new "
          "ones; the untouched faces first in their order, then the new faces (indices new_faces)")
      .def_property_readonly("replaced_faces", [](const PasteSession& s) { return to_numpy(s.replaced_faces()); },
                             "indices into the input F of the faces not kept (ascending)")
      .def_property_readonly("new_face_parents", [](const PasteSession& s) { return to_numpy(s.new_face_parents()); },
                             "per new face, the input face it lies in (for materials, UVs)")
      .def_property_readonly("anchor_point", [](const PasteSession& s) { return to_numpy(Eigen::VectorXd(s.anchor_point())); },
                             "(3,) the snapped anchor")
      .def_property_readonly("normal", [](const PasteSession& s) { return to_numpy(Eigen::VectorXd(s.normal())); },
                             "(3,) unit surface normal at the anchor")
      .def_property_readonly("anchor", [](const PasteSession& s) { return to_numpy(Eigen::VectorXd(s.options().anchor)); },
                             "(3,) the anchor as given")
      .def_property_readonly("rotation", [](const PasteSession& s) { return s.options().rotation; })
      .def_property_readonly("scale", [](const PasteSession& s) { return s.options().scale; })
      .def_property_readonly("blend_radius", [](const PasteSession& s) { return s.options().blend_radius; })
      .def_property_readonly("subdivision_level", [](const PasteSession& s) { return s.options().subdivision_level; })
      .def_property_readonly("basis", [](const PasteSession& s) {
        return s.options().basis == paste::RbfBasis::Wendland ? "wendland" : "polyharmonic";
      })
      .def_property_readonly("fit", [](const PasteSession& s) {
        return s.options().fit == paste::PasteFit::FollowSurface ? "follow_surface" : "keep_form";
      })
      .def_property_readonly("target_map", [](const PasteSession& s) {
        switch (s.options().target_map) {
          case paste::TargetMap::Exponential: return "exponential";
          case paste::TargetMap::Disc: return "disc";
          default: return "auto";
        }
      })
      .def_property_readonly("stats", [](const PasteSession& s) { return stats_dict(s.stats()); })
      .def("__repr__", [](const PasteSession& s) {
        return "<PasteSession vertices=" + std::to_string(s.V().rows()) + " faces=" + std::to_string(s.F().rows()) +
               " new_faces=" + std::to_string(s.new_faces().size()) + ">";
      });
}

}  // namespace

void bind_paste(py::module_& m) {
  def_rbf_interpolator(m);
  def_refine_region(m);
  def_paste_session(m);
  py::class_<Feature>(m, "Feature",
                      "A feature cut from a surface (extract_feature): positions in the feature frame "
                      "(origin + axes, source coordinates), its fold-free map, the base surface and its "
                      "map, and the displacement grid. to_arrays()/from_arrays() round-trip it exactly.")
      .def_property_readonly("faces", [](const Feature& f) { return to_numpy(f.F); }, "(m, 3) int32")
      .def_property_readonly("vertices", [](const Feature& f) { return to_numpy(f.V); },
                             "(n, 3) feature positions, feature frame")
      .def_property_readonly("uv", [](const Feature& f) { return to_numpy(f.uv); }, "(n, 2) feature map")
      .def_property_readonly("base_vertices", [](const Feature& f) { return to_numpy(f.base_V); },
                             "(n, 3) base surface, feature frame")
      .def_property_readonly("base_uv", [](const Feature& f) { return to_numpy(f.base_uv); },
                             "(n, 2) base map, area centroid at 0")
      .def_property_readonly("boundary_loops",
                             [](const Feature& f) {
                               py::list loops;
                               for (const auto& loop : f.boundary_loops) loops.append(to_numpy(loop));
                               return loops;
                             },
                             "list of (k,) int32 vertex loops, in the order the faces traverse them")
      .def_property_readonly("source_faces", [](const Feature& f) { return to_numpy(f.source_faces); })
      .def_property_readonly("source_vertices", [](const Feature& f) { return to_numpy(f.source_vertices); })
      .def_property_readonly("origin", [](const Feature& f) { return to_numpy(Eigen::VectorXd(f.origin)); },
                             "(3,) frame origin in source coordinates")
      .def_property_readonly("axes",
                             [](const Feature& f) { return to_numpy(Eigen::Matrix<double, 3, 3, Eigen::RowMajor>(f.axes)); },
                             "(3, 3) columns e_u, e_v, n in source coordinates: x_source = origin + axes @ x_frame")
      .def_readonly("carried", &Feature::carried,
                    "True for a long protrusion (a trunk, a horn with its root): pasted with keep_form as its own "
                    "mesh sewn into the target; its uv is the base map")
      .def_readonly("radius", &Feature::radius, "max |uv| over the boundary")
      .def_readonly("area", &Feature::area)
      .def_readonly("mean_edge_length", &Feature::mean_edge_length)
      .def_readonly("resolution", &Feature::resolution)
      .def_property_readonly("grid_origin", [](const Feature& f) { return to_numpy(Eigen::VectorXd(f.grid_origin)); },
                             "uv of grid node [0, 0]")
      .def_readonly("grid_spacing", &Feature::grid_spacing)
      .def_property_readonly("displacement", [](const Feature& f) { return grid(f, f.displacement); },
                             "(r, r, 3): node [i, j] at uv = grid_origin + grid_spacing * (j, i); "
                             "components along e_u, e_v, n of the base's local frame")
      .def_property_readonly("mask", [](const Feature& f) { return mask_grid(f); },
                             "(r, r) uint8: 1 where the node is inside the map's domain")
      .def("to_arrays", &to_arrays, "dict of numpy arrays (scalars as 0-d arrays) holding the whole feature")
      .def_static("from_arrays", &from_arrays, py::arg("arrays"),
                  "Feature from to_arrays()'s dict; shapes, index ranges and axes are checked "
                  "(InvalidInputError)")
      .def("__repr__", [](const Feature& f) {
        return "<Feature faces=" + std::to_string(f.F.rows()) + " loops=" + std::to_string(f.boundary_loops.size()) +
               " radius=" + std::to_string(f.radius) + " resolution=" + std::to_string(f.resolution) +
               (f.carried ? " carried" : "") + ">";
      });

  m.def(
      "extract_feature",
      [](const py::object& V, const py::object& F, const py::object& feature_faces, int resolution,
         const std::string& carry, const std::string& backend, py::object progress) {
        const MatrixX3d v = to_vertices(V);
        const MatrixX3i f = to_faces(F);
        const std::vector<Index> faces = to_indices(feature_faces, "feature_faces");
        paste::ExtractFeatureOptions o;
        o.resolution = resolution;
        o.carry = paste::parse_carry(carry);
        o.backend = compute::parse_backend(backend);
        PythonProgress bridge(std::move(progress));
        return run_without_gil(bridge, [&] { return paste::extract_feature(v, f, faces, o, bridge.get()); });
      },
      py::arg("V"), py::arg("F"), py::arg("feature_faces"), py::kw_only(), py::arg("resolution") = 64,
      py::arg("carry") = "auto", py::arg("backend") = "auto", py::arg("progress") = py::none(),
      R"doc(Cut a feature out of a surface for pasting (thesis 5.2): the selected faces must be one
edge-connected disc or annulus. The base surface spans its boundary (biharmonic, tangent to
the surroundings; laid flat on the boundary's plane where that folds); the base map is a
free-boundary isometric map centred at its area centroid; the feature map is isometric with its
boundary pinned to the base map. carry: "auto" (default) makes a long protrusion (no fold-free
pinned map, or its base map squeezes its walls over kCarrySqueeze times) a carried feature (Feature.carried:
pasted with keep_form as its own mesh, its uv the base map); "always" (disc selections) or
"never" (SelectionTopologyError instead). Returns a Feature
(positions in the feature frame at the base's uv = 0) with a resolution x resolution grid of
nodes over [-radius, radius]^2 holding the displacement feature - base in the base's local frame.
Raises EmptySelectionError, WholeMeshSelectedError, SelectionTopologyError, InvalidInputError,
NonManifoldError, DegenerateFaceError, ConstraintError.)doc");

  m.def(
      "sample_feature",
      [](const Feature& feature, const py::object& uv) {
        const MatrixX2d q = to_uv_points(uv);
        const paste::FeatureSample s = paste::sample_feature(feature, q);
        py::dict d;
        d["base"] = to_numpy(s.base);
        d["e_u"] = to_numpy(s.e_u);
        d["e_v"] = to_numpy(s.e_v);
        d["n"] = to_numpy(s.n);
        d["displacement"] = to_numpy(s.displacement);
        d["position"] = to_numpy(s.position);
        d["distance"] = to_numpy(s.distance);
        return d;
      },
      py::arg("feature"), py::arg("uv"),
      R"doc(The feature rebuilt at uv points (k, 2) of its domain: dict of base (base surface through
the base map), e_u, e_v, n (its local frame), displacement (bilinear from the grid), position
(base + frame @ displacement) — all (k, 3) in the feature frame — and distance (k,) to the domain.)doc");
}

}  // namespace paramorph::python
