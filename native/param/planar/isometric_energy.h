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

#include <Eigen/Dense>
#include <limits>

#include "mesh/types.h"

namespace paramorph::planar {

struct IsometricFactors {
  /// #F by 3: [λ, λ cot α, λ cot β] per face.
  Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor> factors;
  VectorXd area;  ///< #F 3D areas (the weights)
};

/// Shape matrix S = [p e1, (q + r) e2 - q e1] of a face with UV corners u0..u2.
inline Eigen::Matrix2d shape_matrix(double p, double q, double r, const Eigen::Vector2d& u0,
                                    const Eigen::Vector2d& u1, const Eigen::Vector2d& u2) {
  const Eigen::Vector2d e1 = u1 - u0, e2 = u2 - u0;
  Eigen::Matrix2d S;
  S.col(0) = p * e1;
  S.col(1) = (q + r) * e2 - q * e1;
  return S;
}

/// One face's isometric energy area·η and, when `g` is given, its gradient
/// with respect to the face's three uv corners (g[0..2]); +inf (g untouched)
/// when det(S) <= 0. The arithmetic every backend runs (kernels/planar.cl
/// repeats it in OpenCL C).
inline double face_isometric_energy(double p, double q, double r, double area,
                                    const Eigen::Vector2d& u0, const Eigen::Vector2d& u1,
                                    const Eigen::Vector2d& u2, Eigen::Vector2d* g = nullptr) {
  const Eigen::Matrix2d S = shape_matrix(p, q, r, u0, u1, u2);
  const double det = S(0, 0) * S(1, 1) - S(0, 1) * S(1, 0);
  if (!(det > 0.0)) return std::numeric_limits<double>::infinity();
  const double frob = S.squaredNorm(), inv_det2 = 1.0 / (det * det);
  if (g) {
    // dη/dS = 2S(1 + det⁻²) - 2|S|² det⁻³ cof(S); S = [e1 e2] B with
    // B = [[p, -q], [0, q + r]], so dE/d[e1 e2] = dS Bᵀ.
    Eigen::Matrix2d cof;
    cof << S(1, 1), -S(1, 0), -S(0, 1), S(0, 0);
    const Eigen::Matrix2d dS = area * (2.0 * (1.0 + inv_det2) * S - 2.0 * frob * inv_det2 / det * cof);
    g[1] = p * dS.col(0) - q * dS.col(1);
    g[2] = (q + r) * dS.col(1);
    g[0] = -(g[1] + g[2]);
  }
  return area * frob * (1.0 + inv_det2);
}

/// Smallest t > 0 with det(e1 + t f1, e2 + t f2) = 0 for a face with corner
/// positions u and displacements d (det > 0 at t = 0); +inf if none.
double face_first_inversion(const Eigen::Vector2d& u0, const Eigen::Vector2d& u1,
                            const Eigen::Vector2d& u2, const Eigen::Vector2d& d0,
                            const Eigen::Vector2d& d1, const Eigen::Vector2d& d2);

/// Factors from the 3D mesh. V: #V by 3, F: #F by 3 (non-degenerate faces).
IsometricFactors isometric_factors(const MatrixX3d& V, const MatrixX3i& F);

/// Σ area_f · η_f for the map uv (#V by 2); +inf when a face is inverted or
/// degenerate. When `gradient` is given it receives dE/duv (#V by 2; left
/// unspecified when the energy is infinite). Serial reference; solvers use
/// IsometricKernels (param/planar/isometric_kernels.h).
double isometric_energy(const IsometricFactors& factors, const MatrixX3i& F,
                        const MatrixX2d& uv, MatrixX2d* gradient = nullptr);

/// Largest t > 0 such that every face of uv + s·d keeps det > 0 for all
/// s in [0, t): the smallest positive root over faces of the quadratic
/// det(A(uv + t d)) = 0. +inf when no face ever inverts along d. Expects
/// every face of uv to have positive determinant.
double max_feasible_step(const MatrixX3i& F, const MatrixX2d& uv, const MatrixX2d& d);

}  // namespace paramorph::planar
