// The cotangent Laplacian of the free vertices as the initial inverse Hessian
// of L-BFGS (thesis 2.3.1 uses L-BFGS itself as the preconditioner of NCG;
// here the Laplacian shapes L-BFGS's H0, as in Zhu et al.'s blended
// quasi-Newton methods).
//
// Near an isometry the Hessian of the isometric energy (2.19) is, per
// coordinate, close to a multiple of the Dirichlet (cotangent) Laplacian: the
// stiff, mesh-dependent part that makes plain L-BFGS slow on fine meshes.
// With H0 = P⁻¹ the quasi-Newton pairs only have to learn the smooth, low-rank
// rest. P is the Laplacian with clamped (positive) weights, hard pins removed
// (Dirichlet rows), soft pins' penalty Hessian on the diagonal, and — when
// nothing pins the map — a tiny shift that removes the translation null space.
// Factored once (sparse Cholesky, METIS ordering).
#pragma once

#include <Eigen/SparseCore>
#include <memory>
#include <vector>

#include "mesh/tri_mesh.h"
#include "param/planar/lbfgs.h"

namespace paramorph::planar {

/// Rows of the free vertices: slot[v] is v's row, or -1 when v is fixed.
struct FreeVertices {
  std::vector<Index> slot;
  std::vector<Index> vertices;  ///< free vertices in row order
};
FreeVertices free_vertices(const std::vector<char>& fixed);

/// L_ff: the weighted graph Laplacian (edge weights w, #E aligned with
/// mesh.edges()) restricted to the free vertices, lower triangle only.
Eigen::SparseMatrix<double> free_laplacian(const TriMesh& mesh, const VectorXd& w,
                                           const FreeVertices& free);

class LaplacianPreconditioner {
 public:
  /// diagonal: #V extra Hessian diagonal per vertex (soft pins), may be empty.
  LaplacianPreconditioner(const TriMesh& mesh, const FreeVertices& free, const VectorXd& diagonal);
  ~LaplacianPreconditioner();

  /// x (interleaved u, v of the free vertices) <- P⁻¹ x.
  void apply(VectorXd& x) const;
  /// sᵀ P s for interleaved s.
  double quadratic(const VectorXd& s) const;

 private:
  struct Factor;
  Eigen::SparseMatrix<double> lower_;
  std::unique_ptr<Factor> factor_;
};

/// The L-BFGS hooks (H0 = P⁻¹ shape) of a preconditioner that outlives them.
LbfgsPreconditioner laplacian_lbfgs_preconditioner(const LaplacianPreconditioner& laplacian);

}  // namespace paramorph::planar
