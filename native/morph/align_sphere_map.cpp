#include "morph/align_sphere_map.h"

#include <algorithm>
#include <cmath>

#include <Eigen/Cholesky>
#include <Eigen/Geometry>
#include <Eigen/LU>
#include <Eigen/SVD>

#include "common/best_rotation.h"
#include "common/errors.h"
#include "morph/radial_projection.h"

namespace paramorph::morph {

namespace {

double angle(const Eigen::RowVector3d& a, const Eigen::RowVector3d& b) {
  return std::atan2(a.cross(b).norm(), a.dot(b));
}

/// Weighted Kabsch (best_rotation), but the identity where the points do not
/// pin a rotation down (fewer than 3, or all on one great circle through a pole).
Eigen::Matrix3d pinned_rotation(const MatrixX3d& from, const MatrixX3d& to, const VectorXd& w) {
  if (from.rows() < 3) return Eigen::Matrix3d::Identity();
  const Eigen::Matrix3d covariance = from.transpose() * w.asDiagonal() * to;
  const Eigen::Vector3d singular = Eigen::JacobiSVD<Eigen::Matrix3d>(covariance).singularValues();
  if (singular[1] < 1e-9 * singular[0]) return Eigen::Matrix3d::Identity();
  return best_rotation(from, to, w);
}

/// Gaussian RBF interpolation of the offsets `to - from` at the points
/// `from` (a little smoothing keeps close pairs with conflicting offsets
/// from ringing); returns the displaced, renormalised `points`.
MatrixX3d warp(const MatrixX3d& points, const MatrixX3d& from, const MatrixX3d& to, double width) {
  const Index k = from.rows();
  if (k == 0) return points;
  const double scale = 1.0 / (2.0 * std::sin(0.5 * width));  // chord length of the width
  auto kernel = [scale](const Eigen::RowVector3d& a, const Eigen::RowVector3d& b) {
    const double r = (a - b).norm() * scale;
    return std::exp(-r * r);
  };
  Eigen::MatrixXd phi(k, k);
  for (Index i = 0; i < k; ++i)
    for (Index j = 0; j < k; ++j) phi(i, j) = kernel(from.row(i), from.row(j));
  phi.diagonal().array() += 1e-6;
  const Eigen::MatrixXd coefficients = phi.ldlt().solve(Eigen::MatrixXd(to - from));
  MatrixX3d warped(points.rows(), 3);
  for (Index v = 0; v < points.rows(); ++v) {
    Eigen::RowVector3d offset = Eigen::RowVector3d::Zero();
    for (Index i = 0; i < k; ++i) offset += kernel(points.row(v), from.row(i)) * coefficients.row(i);
    const Eigen::RowVector3d moved = points.row(v) + offset;
    warped.row(v) = moved.norm() > 1e-12 ? (moved / moved.norm()).eval() : points.row(v);
  }
  return warped;
}

double default_width(const MatrixX3d& points) {
  const Index k = points.rows();
  if (k < 2) return 1.2;
  double sum = 0;
  for (Index i = 0; i < k; ++i) {
    double nearest = M_PI;
    for (Index j = 0; j < k; ++j)
      if (j != i) nearest = std::min(nearest, angle(points.row(i), points.row(j)));
    sum += nearest;
  }
  return std::clamp(1.5 * sum / double(k), 0.2, 1.2);
}

}  // namespace

AlignSphereResult align_sphere_map(const MatrixX3d& V, const MatrixX3i& F, const MatrixX3d& sphere,
                                   const std::vector<Index>& vertices, const MatrixX3d& targets,
                                   const VectorXd& weights, const AlignSphereOptions& o,
                                   Progress* progress) {
  const Index pairs = Index(vertices.size());
  PM_REQUIRE(targets.rows() == pairs && targets.allFinite(), InvalidInputError,
             "targets must be a finite (", pairs, ", 3) array, one per paired vertex");
  for (Index i = 0; i < pairs; ++i)
    PM_REQUIRE(targets.row(i).norm() > 0, InvalidInputError, "target ", i,
               " is the zero vector: a target is a direction on the sphere");
  PM_REQUIRE(weights.size() == 0 || weights.size() == pairs, InvalidInputError,
             "weights must have one value per pair (", pairs, "), got ", weights.size());
  PM_REQUIRE(weights.size() == 0 || (weights.allFinite() && (weights.array() > 0).all()), InvalidInputError,
             "pair weights must be positive and finite");
  PM_REQUIRE(std::isfinite(o.feature_weight) && o.feature_weight > 0, InvalidInputError,
             "feature_weight must be positive");
  PM_REQUIRE(std::isfinite(o.warp_width) && o.warp_width >= 0 && o.warp_width < M_PI,
             InvalidInputError, "warp_width is an angle in [0, pi)");
  for (const Index v : vertices)
    PM_REQUIRE(v >= 0 && v < V.rows(), InvalidInputError, "paired vertex ", v,
               " is not a vertex of the mesh (", V.rows(), " vertices)");
  const VectorXd w = weights.size() ? weights : VectorXd::Ones(pairs);

  MatrixX3d base = o.target ? *o.target : radial_projection(V, F);
  PM_REQUIRE(base.rows() == V.rows() && base.allFinite(), InvalidInputError,
             "target must be a finite (", V.rows(), ", 3) array");
  base.rowwise().normalize();
  MatrixX3d goal = targets.rowwise().normalized();
  MatrixX3d paired(pairs, 3);
  for (Index i = 0; i < pairs; ++i) paired.row(i) = base.row(vertices[i]);

  AlignSphereResult result;
  result.rotation = pinned_rotation(paired, goal, w);
  base = base * result.rotation;
  paired = paired * result.rotation;
  for (Index i = 0; i < pairs; ++i) result.mean_error_rotated += angle(paired.row(i), goal.row(i));
  if (pairs) result.mean_error_rotated /= double(pairs);

  const double width = o.warp_width > 0 ? o.warp_width : default_width(paired);
  MatrixX3d aimed = warp(base, paired, goal, width);

  // The pairs' own targets, weighted: (4.12)'s dot products at the paired
  // vertices on top of the warped targets everywhere.
  VectorXd vertex_weight = VectorXd::Ones(V.rows());
  MatrixX3d pull = aimed;
  for (Index i = 0; i < pairs; ++i) pull.row(vertices[i]) += o.feature_weight * w[i] * goal.row(i);
  for (Index v = 0; v < V.rows(); ++v) {
    vertex_weight[v] = pull.row(v).norm();
    if (vertex_weight[v] > 0) pull.row(v) /= vertex_weight[v];
    else {  // opposite pulls cancel: keep the warped target, weight 1
      pull.row(v) = aimed.row(v);
      vertex_weight[v] = 1.0;
    }
  }

  OptimizeSphereOptions solve;
  solve.epsilon = o.epsilon;
  solve.max_iterations = o.max_iterations;
  solve.tol = o.tol;
  solve.solver = o.solver;
  solve.target = pull;
  solve.weights = vertex_weight;
  result.solve = optimize_sphere_map(V, F, sphere, solve, progress);
  result.positions = result.solve.positions;
  for (Index i = 0; i < pairs; ++i) {
    const double e = angle(result.positions.row(vertices[i]), goal.row(i));
    result.mean_error += e;
    result.max_error = std::max(result.max_error, e);
  }
  if (pairs) result.mean_error /= double(pairs);
  return result;
}

}  // namespace paramorph::morph
