#include "paste/locate_in_map.h"

namespace paramorph::paste {

namespace {
MatrixX3d lift(const MatrixX2d& uv) {
  MatrixX3d out = MatrixX3d::Zero(uv.rows(), 3);
  out.leftCols<2>() = uv;
  return out;
}
}  // namespace

MapLocator::MapLocator(const MatrixX2d& uv, const MatrixX3i& F) : tree_(lift(uv), F) {}

MapLocation MapLocator::locate(const MatrixX2d& Q) const {
  ClosestPoints c = tree_.query(lift(Q));
  return {std::move(c.face), std::move(c.bary), std::move(c.distance)};
}

Eigen::MatrixXd interpolate(const MatrixX3i& F, const MapLocation& at, const Eigen::MatrixXd& X) {
  Eigen::MatrixXd out(at.face.size(), X.cols());
  for (Index q = 0; q < Index(at.face.size()); ++q) {
    const Index f = at.face[q];
    out.row(q) = at.bary(q, 0) * X.row(F(f, 0)) + at.bary(q, 1) * X.row(F(f, 1)) +
                 at.bary(q, 2) * X.row(F(f, 2));
  }
  return out;
}

}  // namespace paramorph::paste
