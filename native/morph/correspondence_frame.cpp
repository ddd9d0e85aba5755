#include "morph/correspondence_frame.h"

#include <cmath>

#include <Eigen/Geometry>

#include "common/errors.h"
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

}  // namespace paramorph::morph
