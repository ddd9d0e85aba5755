// numpy <-> Eigen conversions shared by the bindings: checked shapes and dtypes,
// InvalidInputError (not a TypeError) for anything malformed.
#pragma once

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <array>
#include <cstdint>
#include <limits>
#include <string>
#include <vector>

#include "common/errors.h"
#include "mesh/types.h"
#include "mesh/validate.h"

namespace paramorph::python {

namespace py = pybind11;

/// (n, 3) float64 or float32 (any contiguity) -> MatrixX3d copy.
inline MatrixX3d to_vertices(const py::handle& obj, const char* name = "V") {
  py::array arr = py::array::ensure(obj);
  PM_REQUIRE(arr, InvalidInputError, name, " must be a numpy array");
  const auto kind = arr.dtype().kind();
  PM_REQUIRE(kind == 'f' || kind == 'i' || kind == 'u', InvalidInputError, name,
             " must be float64 or float32, got dtype ", std::string(py::str(arr.dtype())));
  PM_REQUIRE(arr.ndim() == 2 && arr.shape(1) == 3, InvalidInputError, name,
             " must have shape (n, 3), got ", std::string(py::str(arr.attr("shape"))));
  auto data = py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(arr);
  MatrixX3d out(arr.shape(0), 3);
  if (arr.shape(0) > 0) std::copy(data.data(), data.data() + data.size(), out.data());
  return out;
}

/// (m, 3) int32 or int64 -> MatrixX3i copy; values checked to fit int32.
inline MatrixX3i to_faces(const py::handle& obj, const char* name = "F") {
  py::array arr = py::array::ensure(obj);
  PM_REQUIRE(arr, InvalidInputError, name, " must be a numpy array");
  const auto kind = arr.dtype().kind();
  PM_REQUIRE(kind == 'i' || kind == 'u', InvalidInputError, name,
             " must be int32 or int64, got dtype ", std::string(py::str(arr.dtype())));
  PM_REQUIRE(arr.ndim() == 2 && arr.shape(1) == 3, InvalidInputError, name,
             " must have shape (m, 3), got ", std::string(py::str(arr.attr("shape"))));
  auto data = py::array_t<std::int64_t, py::array::c_style | py::array::forcecast>::ensure(arr);
  MatrixX3i out(arr.shape(0), 3);
  const std::int64_t* p = data.data();
  for (py::ssize_t k = 0; k < data.size(); ++k) {
    PM_REQUIRE(p[k] >= 0 && p[k] <= std::numeric_limits<Index>::max(), InvalidInputError,
               name, " has index ", p[k], " at face ", k / 3, ", out of range");
    out.data()[k] = Index(p[k]);
  }
  return out;
}

/// (n,) float64 or float32 (or integer) -> VectorXd copy.
inline VectorXd to_vector(const py::handle& obj, const char* name) {
  py::array arr = py::array::ensure(obj);
  PM_REQUIRE(arr, InvalidInputError, name, " must be a numpy array");
  const auto kind = arr.dtype().kind();
  PM_REQUIRE(kind == 'f' || kind == 'i' || kind == 'u', InvalidInputError, name,
             " must be float64 or float32, got dtype ", std::string(py::str(arr.dtype())));
  PM_REQUIRE(arr.ndim() == 1, InvalidInputError, name, " must have shape (n,), got ",
             std::string(py::str(arr.attr("shape"))));
  auto data = py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(arr);
  VectorXd out(arr.shape(0));
  if (arr.shape(0) > 0) std::copy(data.data(), data.data() + data.size(), out.data());
  return out;
}

/// (k,) integer array (None: empty) -> indices, each checked to fit an Index.
inline std::vector<Index> to_indices(const py::object& obj, const char* name) {
  if (obj.is_none()) return {};
  py::array arr = py::array::ensure(obj);
  if (arr && arr.ndim() == 1 && arr.size() == 0) return {};  // [] arrives as float64
  PM_REQUIRE(arr && (arr.dtype().kind() == 'i' || arr.dtype().kind() == 'u') && arr.ndim() == 1,
             InvalidInputError, name, " must be a 1-D integer array");
  auto data = py::array_t<std::int64_t, py::array::c_style | py::array::forcecast>::ensure(arr);
  std::vector<Index> out(data.size());
  for (py::ssize_t k = 0; k < data.size(); ++k) {
    PM_REQUIRE(data.data()[k] >= 0 && data.data()[k] <= std::numeric_limits<Index>::max(),
               InvalidInputError, name, " index ", data.data()[k], " is out of range");
    out[k] = Index(data.data()[k]);
  }
  return out;
}

/// (k, 2) integer array -> index pairs, each checked to fit an Index.
inline std::vector<std::array<Index, 2>> to_index_pairs(const py::handle& obj, const char* name) {
  py::array arr = py::array::ensure(obj);
  PM_REQUIRE(arr, InvalidInputError, name, " must be a numpy array");
  const auto kind = arr.dtype().kind();
  PM_REQUIRE(kind == 'i' || kind == 'u', InvalidInputError, name, " must be an integer array, got dtype ",
             std::string(py::str(arr.dtype())));
  PM_REQUIRE(arr.ndim() == 2 && arr.shape(1) == 2, InvalidInputError, name,
             " must have shape (k, 2), got ", std::string(py::str(arr.attr("shape"))));
  auto data = py::array_t<std::int64_t, py::array::c_style | py::array::forcecast>::ensure(arr);
  std::vector<std::array<Index, 2>> out(std::size_t(arr.shape(0)));
  for (std::size_t k = 0; k < out.size(); ++k)
    for (int j = 0; j < 2; ++j) {
      const std::int64_t v = data.data()[2 * k + j];
      PM_REQUIRE(v >= 0 && v <= std::numeric_limits<Index>::max(), InvalidInputError, name, " has index ",
                 v, " in row ", k, ", out of range");
      out[k][j] = Index(v);
    }
  return out;
}

/// A mesh's arrays checked as validate_arrays does (not empty, finite
/// coordinates whose face areas neither overflow nor underflow, indices in
/// range), before any work; `mesh` ("A", "proxy") prefixes the message when
/// a function takes several meshes. For the entry points whose core function
/// trusts its arrays (the morph's pieces, simplify, extremity_tips).
inline void require_mesh(const MatrixX3d& V, const MatrixX3i& F, const char* mesh = nullptr) {
  if (mesh)
    for_mesh(mesh, [&] { validate_arrays(V, F); });
  else
    validate_arrays(V, F);
}

/// Points on the unit sphere (a sphere map, points to read through one):
/// finite, of length within a factor 2 of 1 (rounding, float32 or a map
/// not quite renormalised pass; a zero row, or one at 1e200 among unit
/// ones, does not), and `rows` of them when rows >= 0 ("one per vertex of <of>").
inline void require_directions(const MatrixX3d& X, const char* name, Index rows = -1, const char* of = "the mesh") {
  PM_REQUIRE(rows < 0 || X.rows() == rows, InvalidInputError, name, ": one sphere point per vertex of ", of, " (",
             rows, ") is needed, got ", X.rows());
  for (Index i = 0; i < X.rows(); ++i) {
    const double length = X.row(i).allFinite() ? X.row(i).norm() : 0.0;
    PM_REQUIRE(length >= 0.5 && length <= 2.0, InvalidInputError, name, " row ", i, " (", X(i, 0), ", ", X(i, 1),
               ", ", X(i, 2), ") is not a direction: points on the unit sphere are needed");
  }
}

/// Points in space (query points): finite and within validate_arrays' range.
inline void require_points(const MatrixX3d& P, const char* name) {
  for (Index i = 0; i < P.rows(); ++i)
    PM_REQUIRE(P.row(i).allFinite() && P.row(i).cwiseAbs().maxCoeff() <= 1e150, InvalidInputError, name, " row ",
               i, " is not a finite point within 1e150 (", P(i, 0), ", ", P(i, 1), ", ", P(i, 2), ")");
}

/// Eigen row-major matrix -> new numpy array (copy; results are small relative to solves).
template <typename Derived>
py::array to_numpy(const Eigen::MatrixBase<Derived>& m) {
  using Scalar = typename Derived::Scalar;
  Eigen::Matrix<Scalar, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor> rm = m;
  if (m.cols() == 1)
    return py::array_t<Scalar>({py::ssize_t(rm.rows())}, rm.data());
  return py::array_t<Scalar>({py::ssize_t(rm.rows()), py::ssize_t(rm.cols())}, rm.data());
}

template <typename T>
py::array to_numpy(const std::vector<T>& v) {
  return py::array_t<T>({py::ssize_t(v.size())}, v.data());
}

}  // namespace paramorph::python
