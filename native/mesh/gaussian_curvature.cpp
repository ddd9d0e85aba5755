#include "mesh/gaussian_curvature.h"

#include <cmath>

#include <Eigen/Geometry>

namespace paramorph {

VectorXd smoothed_gaussian_curvature(const TriMesh& mesh, int smoothing) {
  const MatrixX3d& V = mesh.V();
  const MatrixX3i& F = mesh.F();
  const Index n = mesh.num_vertices();
  VectorXd defect = VectorXd::Constant(n, 2 * M_PI), area = VectorXd::Zero(n);
  for (Index f = 0; f < F.rows(); ++f) {
    const Eigen::RowVector3d p[3] = {V.row(F(f, 0)), V.row(F(f, 1)), V.row(F(f, 2))};
    const double a = 0.5 * (p[1] - p[0]).cross(p[2] - p[0]).norm();
    for (int k = 0; k < 3; ++k) {
      const Eigen::RowVector3d u = p[(k + 1) % 3] - p[k], v = p[(k + 2) % 3] - p[k];
      defect[F(f, k)] -= std::atan2(u.cross(v).norm(), u.dot(v));
      area[F(f, k)] += a / 3.0;
    }
  }
  VectorXd K(n);
  for (Index v = 0; v < n; ++v) K[v] = area[v] > 0 ? defect[v] / area[v] : 0.0;
  const Csr& ring = mesh.vertex_neighbors();
  VectorXd next(n);
  for (int round = 0; round < smoothing; ++round) {
    for (Index v = 0; v < n; ++v) {
      double sum = area[v] * K[v], weight = area[v];
      for (Index k = ring.begin(v); k < ring.end(v); ++k) {
        sum += area[ring.items[k]] * K[ring.items[k]];
        weight += area[ring.items[k]];
      }
      next[v] = weight > 0 ? sum / weight : 0.0;
    }
    K.swap(next);
  }
  return K;
}

}  // namespace paramorph
