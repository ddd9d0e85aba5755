#include "morph/sphere_warp.h"

#include <cmath>

#include <Eigen/QR>

#include "common/errors.h"
#include "common/parallel.h"

namespace paramorph::morph {

namespace {

double kernel(const Eigen::RowVector3d& a, const Eigen::RowVector3d& b) { return (a - b).norm(); }

}  // namespace

Eigen::RowVector3d log_map(const Eigen::RowVector3d& a, const Eigen::RowVector3d& b) {
  const Eigen::RowVector3d v = b - a.dot(b) * a;
  const double s = v.norm();
  if (s == 0) return Eigen::RowVector3d::Zero();
  return std::atan2(s, a.dot(b)) / s * v;
}

SphereWarpField::SphereWarpField(const MatrixX3d& centres, const MatrixX3d& moves) : centres_(centres) {
  const Index k = centres.rows();
  PM_REQUIRE(moves.rows() == k, InvalidInputError, "SphereWarpField: ", k, " centres but ", moves.rows(),
             " moves");
  // [Phi P; P^T 0] [c; a] = [moves; 0]: the interpolation conditions and the
  // side conditions that make the spline the smoothest one.
  Eigen::MatrixXd system = Eigen::MatrixXd::Zero(k + 4, k + 4);
  for (Index i = 0; i < k; ++i) {
    for (Index j = 0; j < k; ++j) system(i, j) = kernel(centres.row(i), centres.row(j));
    system(i, k) = system(k, i) = 1.0;
    for (int d = 0; d < 3; ++d) system(i, k + 1 + d) = system(k + 1 + d, i) = centres(i, d);
  }
  Eigen::MatrixXd rhs = Eigen::MatrixXd::Zero(k + 4, 3);
  rhs.topRows(k) = moves;
  // Minimum norm where the polynomial is underdetermined (fewer than four
  // points, or all on one circle).
  const Eigen::MatrixXd solution = system.completeOrthogonalDecomposition().solve(rhs);
  coefficients_ = solution.topRows(k);
  polynomial_ = solution.bottomRows(4);
}

Eigen::RowVector3d SphereWarpField::operator()(const Eigen::RowVector3d& x) const {
  Eigen::RowVector3d d = polynomial_.row(0) + x * polynomial_.bottomRows(3);
  for (Index j = 0; j < centres_.rows(); ++j) d += kernel(x, centres_.row(j)) * coefficients_.row(j);
  return d - d.dot(x) * x;
}

Eigen::RowVector3d exp_map(const Eigen::RowVector3d& x, const Eigen::RowVector3d& d) {
  const double angle = d.norm();
  if (angle == 0) return x;
  return (std::cos(angle) * x + (std::sin(angle) / angle) * d).normalized();
}

Eigen::RowVector3d slerp(const Eigen::RowVector3d& a, const Eigen::RowVector3d& b, double t) {
  if (t <= 0) return a;
  if (t >= 1) return b;
  return exp_map(a, t * log_map(a, b));
}

MatrixX3d warp_points(const MatrixX3d& points, const MatrixX3d& from, const MatrixX3d& to, int steps) {
  PM_REQUIRE(from.rows() == to.rows() && steps > 0, InvalidInputError,
             "warp_points: from and to must have the same rows, steps > 0");
  MatrixX3d out = points;
  if (from.rows() == 0) return out;
  MatrixX3d at = from, next(from.rows(), 3), moves(from.rows(), 3);
  for (int s = 1; s <= steps; ++s) {
    for (Index j = 0; j < from.rows(); ++j) {
      next.row(j) = slerp(from.row(j), to.row(j), double(s) / steps);
      moves.row(j) = log_map(at.row(j), next.row(j));
    }
    const SphereWarpField field(at, moves);
#pragma omp parallel for schedule(static) if (worth_parallel(out.rows()))
    for (Index v = 0; v < out.rows(); ++v) out.row(v) = exp_map(out.row(v), field(out.row(v)));
    at = next;
  }
  return out;
}

}  // namespace paramorph::morph
