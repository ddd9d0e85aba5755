#include "mesh/cotangent_weights.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>

namespace paramorph {

VectorXd clamped_cotangent_weights(const TriMesh& mesh, double min_angle_degrees,
                                   double max_angle_degrees) {
  const double lo = min_angle_degrees * M_PI / 180.0;
  const double hi = max_angle_degrees * M_PI / 180.0;
  const MatrixX3d& V = mesh.V();
  const MatrixX3i& F = mesh.F();
  const MatrixX3i& FE = mesh.face_edges();
  VectorXd w = VectorXd::Zero(mesh.edges().rows());
  // Serial scatter: each edge receives from two faces; cheap next to any solve
  // and the summation order stays deterministic.
  for (Index f = 0; f < mesh.num_faces(); ++f) {
    for (int k = 0; k < 3; ++k) {
      const Eigen::Vector3d a = V.row(F(f, k));
      const Eigen::Vector3d e1 = V.row(F(f, (k + 1) % 3)).transpose() - a;
      const Eigen::Vector3d e2 = V.row(F(f, (k + 2) % 3)).transpose() - a;
      const double angle = std::atan2(e1.cross(e2).norm(), e1.dot(e2));
      w[FE(f, k)] += 0.5 / std::tan(std::clamp(angle, lo, hi));
    }
  }
  return w;
}

}  // namespace paramorph
