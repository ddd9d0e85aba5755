#include "morph/correspondence_frame.h"

#include <cmath>

#include <Eigen/Geometry>

#include "common/errors.h"
#include "common/principal_axes.h"
#include "mesh/signed_volume.h"

namespace paramorph::morph {

CorrespondenceFrame correspondence_frame(const MatrixX3d& V, const MatrixX3i& F) {
  CorrespondenceFrame frame;
  double area = 0;
  Eigen::RowVector3d weighted = Eigen::RowVector3d::Zero();
  for (Index f = 0; f < F.rows(); ++f) {
    const Eigen::RowVector3d a = V.row(F(f, 0)), b = V.row(F(f, 1)), c = V.row(F(f, 2));
    const double face_area = 0.5 * (b - a).cross(c - a).norm();
    area += face_area;
    weighted += face_area * (a + b + c) / 3.0;
  }
  PM_REQUIRE(area > 0 && std::isfinite(area), InvalidInputError, "the mesh has no area");
  frame.centre = weighted / area;
  frame.scale = std::sqrt(area);
  frame.V = (V.rowwise() - frame.centre) / frame.scale;
  frame.F = F;
  frame.inside_out = signed_volume(frame.V, F) < 0;
  if (frame.inside_out) frame.F.col(1).swap(frame.F.col(2));
  return frame;
}

Eigen::Matrix3d shape_rotation(const MatrixX3d& V, const MatrixX3i& F) {
  // Moments of the face centroids weighted by area (exact enough to pick
  // axes; the frame only has to be the same for every turn of the shape).
  VectorXd area(F.rows());
  MatrixX3d centroid(F.rows(), 3);
  for (Index f = 0; f < F.rows(); ++f) {
    const Eigen::RowVector3d a = V.row(F(f, 0)), b = V.row(F(f, 1)), c = V.row(F(f, 2));
    area[f] = 0.5 * (b - a).cross(c - a).norm();
    centroid.row(f) = (a + b + c) / 3.0;
  }
  const double total = area.sum();
  PM_REQUIRE(total > 0 && std::isfinite(total), InvalidInputError, "the mesh has no area");
  const PrincipalAxes principal = principal_axes(centroid, area);
  Eigen::Matrix3d axes = principal.axes;
  const MatrixX3d centred = centroid.rowwise() - principal.mean;
  Eigen::Vector3d skew;
  for (int k = 0; k < 3; ++k) {
    const VectorXd along = centred * axes.col(k);
    const double spread = std::sqrt(std::max(principal.variances[k], 1e-300));
    skew[k] = area.dot(along.array().cube().matrix()) / total / (spread * spread * spread);
  }
  // The two most skewed axes get positive skew; the third follows (det +1).
  int weakest = 0;
  skew.cwiseAbs().minCoeff(&weakest);
  for (int k = 0; k < 3; ++k)
    if (k != weakest && skew[k] < 0) axes.col(k) *= -1;
  if (axes.determinant() < 0) axes.col(weakest) *= -1;
  return axes.transpose();
}

}  // namespace paramorph::morph
