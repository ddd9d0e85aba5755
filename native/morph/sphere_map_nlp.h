// The nonlinear program of the optimized sphere map (thesis 4.3.3, (4.8)-(4.10)),
// as plain functions of the stacked coordinates x = (x_0, y_0, z_0, x_1, ...):
// what morph/optimize_sphere_map hands to Ipopt, kept apart so its
// derivatives can be checked against finite differences.
//
// Objective (minimised): f(x) = -sum_i v_i^0 . v_i.
// Constraints: g_i = |v_i|^2 (= 1), i < #V; g_{#V+f} = det(v_a, v_b, v_c) (>= eps).
// Sparse derivatives in triplet form, structure fixed at construction:
// Jacobian rows i: 3 entries (2 v_i); rows #V+f: 9 entries (v_b x v_c, v_c x v_a,
// v_a x v_b). Lagrangian Hessian, lower triangle: 3 diagonal entries per vertex
// (2 lambda_i) and one 3x3 block per edge (the triple products' mixed
// second derivatives, -[v_t]x for the pair (u, w) of a face (u, w, t)).
#pragma once

#include <array>
#include <vector>

#include "mesh/tri_mesh.h"

namespace paramorph::morph {

/// Triple products of unit vectors above -kTripleRoundoff are not folds
/// (rounding), for optimize_sphere_map and its Ipopt polish alike.
constexpr double kTripleRoundoff = 1e-13;

class SphereMapNlp {
 public:
  /// mesh: the triangulation; target: #V by 3 v_i^0.
  SphereMapNlp(const TriMesh& mesh, MatrixX3d target);

  Index num_variables() const { return 3 * vertices_; }
  Index num_constraints() const { return vertices_ + faces_; }
  Index jacobian_nonzeros() const { return Index(jac_row_.size()); }
  Index hessian_nonzeros() const { return Index(hess_row_.size()); }

  double objective(const double* x) const;
  void objective_gradient(const double* x, double* grad) const;
  void constraints(const double* x, double* g) const;
  /// Smallest face triple product at x (a fold where <= 0).
  double min_triple(const double* x) const;

  const std::vector<Index>& jacobian_rows() const { return jac_row_; }
  const std::vector<Index>& jacobian_cols() const { return jac_col_; }
  void jacobian_values(const double* x, double* values) const;

  const std::vector<Index>& hessian_rows() const { return hess_row_; }
  const std::vector<Index>& hessian_cols() const { return hess_col_; }
  /// sigma * Hess f + sum_k lambda_k Hess g_k (f's Hessian is 0).
  void hessian_values(const double* x, double sigma, const double* lambda, double* values) const;

 private:
  Index vertices_, faces_;
  MatrixX3i F_;
  MatrixX3d target_;
  std::vector<Index> jac_row_, jac_col_, hess_row_, hess_col_;
  /// Per face and corner k: the edge opposite k (between corners k+1, k+2)
  /// and whether its stored block (row = larger vertex) is row F(f, k+1).
  MatrixX3i face_edge_;
  std::vector<std::array<bool, 3>> block_from_first_;
  Index edge_block_start_;  ///< Hessian entries of edge e start at edge_block_start_ + 9 e
};

}  // namespace paramorph::morph
