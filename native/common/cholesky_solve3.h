// Solve with a sparse Cholesky factor for three right-hand sides at once.
//
// Eigen's SimplicialLLT::solve handles a multi-column right-hand side one
// column at a time, streaming the factor through memory twice per column.
// The spherical PCG applies its preconditioner to #V by 3 vectors every
// iteration; interleaving the three components streams the factor once per
// triangular sweep (measured ~2x faster on 40k–160k-vertex factors).
#pragma once

#include <Eigen/SparseCholesky>

#include "common/errors.h"
#include "mesh/types.h"

namespace paramorph {

/// X = A⁻¹ B for an Eigen SimplicialLLT factor of A; B and X are #rows by 3,
/// row-major. The factor must have been computed successfully.
template <typename Factor>
void cholesky_solve3(const Factor& factor, const MatrixX3d& B, MatrixX3d& X) {
  const auto& L = factor.matrixL().nestedExpression();  // CSC, lower, diagonal first per column
  const Index n = Index(L.rows());
  const auto* outer = L.outerIndexPtr();
  const auto* inner = L.innerIndexPtr();
  const double* values = L.valuePtr();
  MatrixX3d Y = factor.permutationP().size() > 0 ? MatrixX3d(factor.permutationP() * B) : B;
  for (Index j = 0; j < n; ++j) {  // L y = P b
    PM_REQUIRE(inner[outer[j]] == j, ComputeError, "unexpected Cholesky factor layout");
    const double d = values[outer[j]];
    const double y0 = Y(j, 0) / d, y1 = Y(j, 1) / d, y2 = Y(j, 2) / d;
    Y(j, 0) = y0;
    Y(j, 1) = y1;
    Y(j, 2) = y2;
    for (auto p = outer[j] + 1; p < outer[j + 1]; ++p) {
      const Index i = inner[p];
      const double l = values[p];
      Y(i, 0) -= l * y0;
      Y(i, 1) -= l * y1;
      Y(i, 2) -= l * y2;
    }
  }
  for (Index j = n - 1; j >= 0; --j) {  // Lᵀ z = y
    double s0 = Y(j, 0), s1 = Y(j, 1), s2 = Y(j, 2);
    for (auto p = outer[j] + 1; p < outer[j + 1]; ++p) {
      const Index i = inner[p];
      const double l = values[p];
      s0 -= l * Y(i, 0);
      s1 -= l * Y(i, 1);
      s2 -= l * Y(i, 2);
    }
    const double d = values[outer[j]];
    Y(j, 0) = s0 / d;
    Y(j, 1) = s1 / d;
    Y(j, 2) = s2 / d;
  }
  X = factor.permutationPinv().size() > 0 ? MatrixX3d(factor.permutationPinv() * Y) : Y;
}

}  // namespace paramorph
