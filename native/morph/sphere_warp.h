// A smooth motion of the unit sphere that takes a few points exactly where
// they must go (the hard pins of a morph, DESIGN.md §4.4; issue 16): the
// points travel along great circles in small steps and every step moves the
// whole sphere by a tangent field that interpolates the points' own steps.
// The field is the biharmonic spline of R^3, phi(r) = r of the chord
// distance plus a linear polynomial (it minimises the integral of the
// squared second derivatives; no width to tune). Fewer than four points
// leave the polynomial underdetermined and the minimum-norm solution is
// taken (one point: a rotation-like drift, two: a rotation plus a stretch
// between them). Measured against the smoother r^3 (triharmonic): with 50
// pins on a horse re-posed, r^3 overshot between close pins and moved a
// hind hoof by 13% of the diagonal; r kept every landmark within 0.8%.
//
// A flow of a smooth field is a diffeomorphism, so a fine enough mesh carried
// by it does not fold; morph/flow_sphere_map checks and steps it so that no
// face does.
#pragma once

#include "mesh/types.h"

namespace paramorph::morph {

/// The tangent field interpolating displacements at points of the unit sphere.
class SphereWarpField {
 public:
  /// centres: #k by 3 unit vectors, distinct; moves: #k by 3 displacements
  /// (tangent at their centre). Raises InvalidInputError on a shape mismatch.
  SphereWarpField(const MatrixX3d& centres, const MatrixX3d& moves);
  /// The interpolated displacement at the unit vector x, projected onto x's
  /// tangent plane (equal to moves.row(j) at centre j, to rounding).
  Eigen::RowVector3d operator()(const Eigen::RowVector3d& x) const;

 private:
  MatrixX3d centres_;
  MatrixX3d coefficients_;       ///< #k by 3
  Eigen::Matrix<double, 4, 3> polynomial_;  ///< rows: 1, x, y, z
};

/// The tangent vector at a pointing to b along the great circle, as long as
/// the angle between them (the inverse of exp_map; 0 for antipodes).
Eigen::RowVector3d log_map(const Eigen::RowVector3d& a, const Eigen::RowVector3d& b);

/// x moved by the tangent vector d (the exponential map of the sphere).
Eigen::RowVector3d exp_map(const Eigen::RowVector3d& x, const Eigen::RowVector3d& d);

/// Position at time t of the great-circle path from a to b (unit vectors,
/// not antipodal): slerp, exact at t = 0 and 1.
Eigen::RowVector3d slerp(const Eigen::RowVector3d& a, const Eigen::RowVector3d& b, double t);

/// Moves `points` (unit vectors) by the flow that takes `from` (#k unit
/// vectors) to `to` along great circles in `steps` equal steps (no fold
/// checks: for targets, which need not be fold-free). Rows of `points` equal
/// to a row of `from` need not be special-cased: they land on `to` to rounding.
MatrixX3d warp_points(const MatrixX3d& points, const MatrixX3d& from, const MatrixX3d& to, int steps);

}  // namespace paramorph::morph
