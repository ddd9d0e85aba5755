// Spring weights and the weighted vertex graph of the spherical solver
// (thesis 3.2.1, 3.4; DESIGN.md §4.2).
//
// Barycentric weights are 1 per edge. Conformal weights are the cotangent
// weights (cot α + cot β) / 2 with every corner angle clamped to [5°, 85°], so
// all weights are positive and symmetric — the condition of Theorem 3.1 and
// of Proposition 3.1 (renormalisation never increases the spring energy).
#pragma once

#include <Eigen/SparseCore>
#include <string>
#include <vector>

#include "mesh/tri_mesh.h"

namespace paramorph::spherical {

enum class Weights { Conformal, Barycentric };
Weights parse_weights(const std::string& name);  ///< throws InvalidInputError
std::string to_string(Weights weights);

/// Symmetric positive weights per edge of mesh.edges() (#E).
VectorXd edge_weights(const TriMesh& mesh, Weights kind,
                      double min_angle_degrees = 5.0, double max_angle_degrees = 85.0);

/// The weighted graph Laplacian L = D - W in compressed rows, laid out for
/// per-vertex kernels: row i lists its neighbours and their weights.
struct SpringGraph {
  std::vector<Index> offsets;     ///< #V+1
  std::vector<Index> neighbors;   ///< 2#E, sorted per row
  std::vector<double> weights;    ///< 2#E, w_ij > 0
  VectorXd degree;                ///< #V, D_i = sum_j w_ij

  Index num_vertices() const { return Index(degree.size()); }

  /// out = L u for an #V by 3 row-major matrix (each column independently).
  void apply(const MatrixX3d& u, MatrixX3d& out) const;
  /// Spring energy (3.4): 1/2 sum over edges w_ij |u_i - u_j|^2.
  double energy(const MatrixX3d& u) const;
  /// L + shift * D as an Eigen sparse matrix (lower and upper parts).
  Eigen::SparseMatrix<double> matrix(double diagonal_shift = 0.0) const;
};

SpringGraph build_spring_graph(const TriMesh& mesh, const VectorXd& edge_weights);

}  // namespace paramorph::spherical
