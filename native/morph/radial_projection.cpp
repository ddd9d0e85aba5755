#include "morph/radial_projection.h"

#include "param/spherical/sphere_quality.h"

namespace paramorph::morph {

MatrixX3d radial_projection(const MatrixX3d& V, const MatrixX3i& F) {
  const VectorXd area = spherical::face_areas(V, F);
  Eigen::RowVector3d centroid = Eigen::RowVector3d::Zero();
  for (Index f = 0; f < F.rows(); ++f)
    centroid += area[f] * (V.row(F(f, 0)) + V.row(F(f, 1)) + V.row(F(f, 2))) / 3.0;
  if (area.sum() > 0) centroid /= area.sum();
  MatrixX3d projected = V.rowwise() - centroid;
  for (Index v = 0; v < projected.rows(); ++v) {
    const double length = projected.row(v).norm();
    projected.row(v) = length > 0 ? (projected.row(v) / length).eval() : Eigen::RowVector3d(0, 0, 1);
  }
  return projected;
}

}  // namespace paramorph::morph
