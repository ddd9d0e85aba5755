#include "mesh/signed_volume.h"

#include <Eigen/Geometry>

namespace paramorph {

double signed_volume(const MatrixX3d& V, const MatrixX3i& F) {
  // Relative to the first vertex: the sum is translation-invariant for a
  // closed mesh, and far-off models lose no digits.
  const Eigen::RowVector3d origin = V.rows() ? V.row(0).eval() : Eigen::RowVector3d::Zero();
  double volume = 0;
  for (Index f = 0; f < F.rows(); ++f)
    volume += (V.row(F(f, 0)) - origin).dot((V.row(F(f, 1)) - origin).cross(V.row(F(f, 2)) - origin));
  return volume / 6.0;
}

}  // namespace paramorph
