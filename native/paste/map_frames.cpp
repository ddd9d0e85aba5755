#include "paste/map_frames.h"

#include <Eigen/Geometry>
#include <cmath>

namespace paramorph::paste {

MapFrames map_frames(const MatrixX3d& X, const MatrixX3i& F, const MatrixX2d& uv) {
  MapFrames out{MatrixX3d::Zero(X.rows(), 3), MatrixX3d::Zero(X.rows(), 3)};
  for (Index f = 0; f < Index(F.rows()); ++f) {
    const Eigen::Vector3d x0 = X.row(F(f, 0)), x1 = X.row(F(f, 1)), x2 = X.row(F(f, 2));
    const Eigen::Vector2d u0 = uv.row(F(f, 0)), u1 = uv.row(F(f, 1)), u2 = uv.row(F(f, 2));
    Eigen::Matrix<double, 3, 2> dX;
    dX << x1 - x0, x2 - x0;
    Eigen::Matrix2d dU;
    dU << u1 - u0, u2 - u0;
    const double det = dU.determinant();
    if (!(std::abs(det) > 0)) continue;
    const Eigen::Matrix<double, 3, 2> J = dX * dU.inverse();  // columns ∂X/∂u, ∂X/∂v
    const Eigen::Vector3d cross = (x1 - x0).cross(x2 - x0);
    const double area = 0.5 * cross.norm();
    if (!(area > 0)) continue;
    for (int k = 0; k < 3; ++k) {
      out.du.row(F(f, k)) += area * J.col(0).transpose();
      out.normal.row(F(f, k)) += 0.5 * cross.transpose();  // = area · unit normal
    }
  }
  return out;
}

Eigen::Matrix3d frame_at(const MapFrames& frames, const MatrixX3i& F, Index f,
                         const Eigen::Vector3d& bary) {
  Eigen::Vector3d du = Eigen::Vector3d::Zero(), n = Eigen::Vector3d::Zero();
  for (int k = 0; k < 3; ++k) {
    du += bary[k] * frames.du.row(F(f, k)).transpose();
    n += bary[k] * frames.normal.row(F(f, k)).transpose();
  }
  n.normalize();
  const Eigen::Vector3d eu = (du - du.dot(n) * n).normalized();
  Eigen::Matrix3d R;
  R << eu, n.cross(eu), n;
  return R;
}

}  // namespace paramorph::paste
