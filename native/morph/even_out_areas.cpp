// A kept topology's faces evened out before the fit (morph/even_out_areas.h).
#include "morph/even_out_areas.h"

#include "mesh/vertex_normals.h"

namespace paramorph::morph {

namespace {
constexpr int kHalvings = 12;
}

MatrixX3d even_out_areas(const MatrixX3d& X, const MatrixX3i& F, const std::vector<char>& movable, int passes,
                         double step) {
  MatrixX3d P = X;
  const Index n = X.rows(), faces = F.rows();
  MatrixX3d normals(faces, 3), centroid_sum(n, 3), vertex_normal(n, 3), move(n, 3);
  VectorXd area_sum(n);
  for (int pass = 0; pass < passes; ++pass) {
    centroid_sum.setZero();
    vertex_normal.setZero();
    area_sum.setZero();
    for (Index f = 0; f < faces; ++f) {
      normals.row(f) = face_normal(P, F, f);
      const double area = 0.5 * normals.row(f).norm();
      const Eigen::RowVector3d centroid = (P.row(F(f, 0)) + P.row(F(f, 1)) + P.row(F(f, 2))) / 3.0;
      for (int k = 0; k < 3; ++k) {
        centroid_sum.row(F(f, k)) += area * centroid;
        area_sum(F(f, k)) += area;
        vertex_normal.row(F(f, k)) += normals.row(f);
      }
    }
    for (Index v = 0; v < n; ++v) {
      move.row(v).setZero();
      if (!movable[v] || !(area_sum(v) > 0)) continue;
      Eigen::RowVector3d d = step * (centroid_sum.row(v) / area_sum(v) - P.row(v));
      const double length = vertex_normal.row(v).norm();
      if (length > 0) {
        const Eigen::RowVector3d normal = vertex_normal.row(v) / length;
        d -= d.dot(normal) * normal;
      }
      move.row(v) = d;
    }
    // Halve the move at the corners of a face it would turn over.
    VectorXd scale = VectorXd::Ones(n);
    MatrixX3d next;
    for (int halving = 0;; ++halving) {
      next = P + scale.asDiagonal() * move;
      bool turned = false;
      for (Index f = 0; f < faces; ++f)
        if (normals.row(f).squaredNorm() > 0 && face_normal(next, F, f).dot(normals.row(f)) <= 0) {
          turned = true;
          for (int k = 0; k < 3; ++k) scale(F(f, k)) = halving < kHalvings ? 0.5 * scale(F(f, k)) : 0.0;
        }
      if (!turned) break;
    }
    P = next;
  }
  return P;
}

}  // namespace paramorph::morph
