#include "features/mirror_plane.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include <Eigen/Eigenvalues>

#include "common/errors.h"
#include "common/principal_axes.h"
#include "mesh/closest_points.h"

namespace paramorph::features {

namespace {

MatrixX3d reflect(const MatrixX3d& V, const Eigen::RowVector3d& normal, double offset) {
  const VectorXd side = (V * normal.transpose()).array() - offset;
  return V - 2.0 * side * normal;
}

double median(const VectorXd& values) {
  std::vector<double> sorted(values.data(), values.data() + values.size());
  std::nth_element(sorted.begin(), sorted.begin() + std::ptrdiff_t(sorted.size() / 2), sorted.end());
  return sorted[sorted.size() / 2];
}

}  // namespace

MirrorPlane mirror_plane(const MatrixX3d& V, const MatrixX3i& F, const VectorXd& area, int iterations) {
  PM_REQUIRE(area.size() == V.rows() && V.rows() > 0 && F.rows() > 0 && iterations >= 1 && area.minCoeff() >= 0 &&
                 area.sum() > 0,
             InvalidInputError, "mirror_plane: a weight >= 0 per vertex with a positive sum, and iterations >= 1");
  const ClosestPointTree tree(V, F);
  const PrincipalAxes axes = principal_axes(V, area);
  MirrorPlane best;
  best.mean_distance = std::numeric_limits<double>::infinity();
  for (int k = 0; k < 3; ++k) {
    Eigen::RowVector3d normal = axes.axes.col(k).transpose();
    double offset = axes.mean.dot(normal);
    for (int it = 0; it < iterations; ++it) {
      const ClosestPoints partner = tree.query(reflect(V, normal, offset));
      // Pairs farther than three times the median are what the symmetry
      // does not hold for (a turned head, a swung tail): left out of the fit.
      const double cut = 3.0 * median(partner.distance);
      const VectorXd w = (partner.distance.array() <= cut).select(area, 0.0);
      if (!(w.sum() > 0)) break;
      // The mirror swaps each vertex and its partner: the plane's normal is
      // the direction their differences agree on, its offset their midpoints'.
      const MatrixX3d across = V - partner.points;
      const Eigen::Matrix3d spread = across.transpose() * w.asDiagonal() * across;
      const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eigen(spread);
      Eigen::RowVector3d next = eigen.eigenvectors().col(2).transpose();
      if (next.dot(normal) < 0) next = -next;
      normal = next;
      offset = (w.transpose() * (0.5 * (V + partner.points) * normal.transpose())).value() / w.sum();
    }
    const double mean = area.dot(tree.query(reflect(V, normal, offset)).distance) / area.sum();
    if (mean < best.mean_distance) best = {normal, offset, mean};
  }
  return best;
}

VectorXd mirror_loneliness(const MatrixX3d& points, const MirrorPlane& plane) {
  const MatrixX3d mirrored = reflect(points, plane.normal, plane.offset);
  VectorXd out = VectorXd::Ones(points.rows());
  for (Index i = 0; i < points.rows(); ++i) {
    const double own = (mirrored.row(i) - points.row(i)).norm();
    double other = std::numeric_limits<double>::infinity();
    for (Index j = 0; j < points.rows(); ++j)
      if (j != i) other = std::min(other, (mirrored.row(i) - points.row(j)).norm());
    if (std::isfinite(other) && own + other > 0) out[i] = other / (own + other);
  }
  return out;
}

}  // namespace paramorph::features
