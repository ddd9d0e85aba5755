#include "common/best_rotation.h"

#include <Eigen/Geometry>
#include <Eigen/LU>
#include <Eigen/SVD>

#include "common/errors.h"

namespace paramorph {

Eigen::Matrix3d best_rotation(const MatrixX3d& from, const MatrixX3d& to, const VectorXd& weights) {
  PM_REQUIRE(from.rows() == to.rows() && (weights.size() == 0 || weights.size() == from.rows()),
             InvalidInputError, "best_rotation: mismatched rows");
  if (from.rows() == 0) return Eigen::Matrix3d::Identity();
  if (from.rows() == 1)
    return Eigen::Quaterniond::FromTwoVectors(from.row(0).transpose(), to.row(0).transpose())
        .toRotationMatrix()
        .transpose();
  const Eigen::Matrix3d covariance =
      weights.size() ? Eigen::Matrix3d(from.transpose() * weights.asDiagonal() * to) : Eigen::Matrix3d(from.transpose() * to);
  Eigen::JacobiSVD<Eigen::Matrix3d> svd(covariance, Eigen::ComputeFullU | Eigen::ComputeFullV);
  Eigen::Matrix3d flip = Eigen::Matrix3d::Identity();
  flip(2, 2) = (svd.matrixU() * svd.matrixV().transpose()).determinant() < 0 ? -1.0 : 1.0;
  return svd.matrixU() * flip * svd.matrixV().transpose();
}

}  // namespace paramorph
