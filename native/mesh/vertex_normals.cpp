#include "mesh/vertex_normals.h"

namespace paramorph {

MatrixX3d area_weighted_vertex_normals(const MatrixX3d& V, const MatrixX3i& F) {
  MatrixX3d N = MatrixX3d::Zero(V.rows(), 3);
  for (Index f = 0; f < Index(F.rows()); ++f) {
    const Eigen::RowVector3d n = face_normal(V, F, f);  // twice the area times the unit normal
    for (int k = 0; k < 3; ++k) N.row(F(f, k)) += n;
  }
  for (Index v = 0; v < Index(V.rows()); ++v) {
    const double len = N.row(v).norm();
    if (len > 0) N.row(v) /= len;
  }
  return N;
}

}  // namespace paramorph
