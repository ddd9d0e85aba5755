// A kept topology's faces evened out before the fit (morph/even_out_areas.h).
#include "morph/even_out_areas.h"

#include "mesh/step_without_turning.h"
#include "mesh/vertex_normals.h"

namespace paramorph::morph {

namespace {
constexpr int kHalvings = 12;
}

MatrixX3d even_out_areas(const MatrixX3d& X, const MatrixX3i& F, const std::vector<char>& movable, int passes,
                         double step) {
  MatrixX3d P = X;
  const Index n = X.rows(), faces = F.rows();
  MatrixX3d face_normals(faces, 3), centroid_sum(n, 3), move(n, 3);
  VectorXd area_sum(n);
  for (int pass = 0; pass < passes; ++pass) {
    centroid_sum.setZero();
    area_sum.setZero();
    for (Index f = 0; f < faces; ++f) {
      face_normals.row(f) = face_normal(P, F, f);
      const double area = 0.5 * face_normals.row(f).norm();
      const Eigen::RowVector3d centroid = (P.row(F(f, 0)) + P.row(F(f, 1)) + P.row(F(f, 2))) / 3.0;
      for (int k = 0; k < 3; ++k) {
        centroid_sum.row(F(f, k)) += area * centroid;
        area_sum(F(f, k)) += area;
      }
    }
    const MatrixX3d normals = area_weighted_vertex_normals(P, F);  // each vertex's tangent plane
    for (Index v = 0; v < n; ++v) {
      move.row(v).setZero();
      if (!movable[v] || !(area_sum(v) > 0)) continue;
      const Eigen::RowVector3d d = step * (centroid_sum.row(v) / area_sum(v) - P.row(v));
      move.row(v) = d - d.dot(normals.row(v)) * normals.row(v);
    }
    P = step_without_turning(P, face_normals, move, F, kHalvings);
  }
  return P;
}

}  // namespace paramorph::morph
