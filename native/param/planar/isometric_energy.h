// The isometric energy of a planar map (thesis 2.2.4, eq. 2.19) and the
// largest step before a triangle inverts (2.3.2).
//
// Per face, with the ideal triangle's three factors [p, q, r] =
// [λ, λ cot α, λ cot β] (α, β the 3D angles at corners 0 and 1,
// 1/λ = sqrt(2 E (cot α + cot β)), E the 3D area), the shape matrix of the
// map is S = A W⁻¹ = [p e1, (q + r) e2 - q e1] with e1 = u1 - u0, e2 = u2 - u0.
// η_isometric = η_shape · η_area = |S|²_F (1 + det(S)⁻²), which is the
// symmetric Dirichlet energy |J|² + |J⁻¹|² of the map (4 for an isometry).
// The total is weighted by 3D face area, so it does not depend on the
// resolution; it is +inf as soon as a face has det(S) <= 0 (the barrier that
// keeps a descent from a fold-free map fold-free).
#pragma once

#include "mesh/types.h"

namespace paramorph::planar {

struct IsometricFactors {
  /// #F by 3: [λ, λ cot α, λ cot β] per face.
  Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor> factors;
  VectorXd area;  ///< #F 3D areas (the weights)
};

/// Factors from the 3D mesh. V: #V by 3, F: #F by 3 (non-degenerate faces).
IsometricFactors isometric_factors(const MatrixX3d& V, const MatrixX3i& F);

/// Σ area_f · η_f for the map uv (#V by 2); +inf when a face is inverted or
/// degenerate. When `gradient` is given it receives dE/duv (#V by 2; left
/// unspecified when the energy is infinite).
double isometric_energy(const IsometricFactors& factors, const MatrixX3i& F,
                        const MatrixX2d& uv, MatrixX2d* gradient = nullptr);

/// Largest t > 0 such that every face of uv + s·d keeps det > 0 for all
/// s in [0, t): the smallest positive root over faces of the quadratic
/// det(A(uv + t d)) = 0. +inf when no face ever inverts along d. Expects
/// every face of uv to have positive determinant.
double max_feasible_step(const MatrixX3i& F, const MatrixX2d& uv, const MatrixX2d& d);

}  // namespace paramorph::planar
