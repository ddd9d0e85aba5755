// Newton systems for energies of a sphere map (one unit vector per vertex)
// that are sums over faces and vertices: each vertex moves in two tangent
// coordinates (v <- normalise(v + T_v u_v)), each face adds a 6 by 6 block
// and each vertex a 2 by 2 one. The sparsity is built once per mesh and
// analysed once (CHOLMOD supernodal LLT, the better of AMD and METIS), so a
// step costs one numeric factorisation. Fixed vertices (hard pins) get the
// identity: their step is exactly 0. Used by the morph's log-barrier maps
// (param/spherical/sphere_map_barrier) and the isometric sphere map
// (param/spherical/isometric_sphere_map).
#pragma once

#include <functional>
#include <memory>
#include <vector>

#include "mesh/types.h"

namespace paramorph::spherical {

using Mat32 = Eigen::Matrix<double, 3, 2>;
using Mat6 = Eigen::Matrix<double, 6, 6>;
using Vec6 = Eigen::Matrix<double, 6, 1>;

/// Two orthonormal tangent directions at the unit vector v (columns).
Mat32 tangent_basis(const Eigen::Vector3d& v);

/// The nearest positive semi-definite matrix (negative eigenvalues set to 0).
Mat6 project_psd(const Mat6& H);

class TangentNewton {
 public:
  /// F: the faces; vertices: #V; fixed: vertices that never move. tick:
  /// called every 20 ms while the analysis and each factorisation run (on
  /// a thread of their own, common/report_while.h: seconds at 400k faces);
  /// it may throw Cancelled.
  TangentNewton(const MatrixX3i& F, Index vertices, const std::vector<Index>& fixed = {},
                std::function<void()> tick = {});
  ~TangentNewton();
  TangentNewton(const TangentNewton&) = delete;
  TangentNewton& operator=(const TangentNewton&) = delete;

  /// Starts a system at the points X: tangent bases, zero matrix and gradient.
  void begin(const MatrixX3d& X);
  /// The tangent basis of vertex v at the last begin().
  const Mat32& basis(Index v) const { return bases_[std::size_t(v)]; }
  /// Adds face f's gradient and Hessian in its corners' tangent coordinates
  /// (corner k: rows 2k, 2k+1). Not thread-safe: blocks are added in order.
  void add_face(Index f, const Vec6& gradient, const Mat6& hessian);
  /// Adds a vertex's own gradient and Hessian (2 and 2 by 2).
  void add_vertex(Index v, const Eigen::Vector2d& gradient, const Eigen::Matrix2d& hessian);
  /// The Newton step for the system added since begin() (#2V, 0 at fixed
  /// vertices): the matrix is scaled to unit diagonal, factored, and shifted
  /// by a growing multiple of the identity only if it is not positive definite.
  /// Raises ComputeError when no shift helps.
  VectorXd solve();
  /// The gradient added since begin() (#2V, 0 at fixed vertices).
  const VectorXd& gradient() const { return gradient_; }
  /// X moved by t * step (fixed vertices copied bit for bit) into out.
  void move(const MatrixX3d& X, const VectorXd& step, double t, MatrixX3d& out) const;
  bool is_fixed(Index v) const { return fixed_[std::size_t(v)] != 0; }
  int factorizations() const { return factorizations_; }

 private:
  struct Solver;
  MatrixX3i F_;
  std::vector<char> fixed_;
  std::vector<Mat32> bases_;
  VectorXd gradient_;
  std::shared_ptr<Solver> solver_;  ///< shared with a factorisation a cancel left running
  std::function<void()> tick_;
  int factorizations_ = 0;
};

}  // namespace paramorph::spherical
