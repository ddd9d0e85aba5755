#include "common/principal_axes.h"

#include <Eigen/Eigenvalues>

namespace paramorph {

PrincipalAxes principal_axes(const MatrixX3d& points, const VectorXd& weights) {
  PrincipalAxes out;
  const VectorXd w = weights / weights.sum();
  out.mean = w.transpose() * points;
  const MatrixX3d centred = points.rowwise() - out.mean;
  const Eigen::Matrix3d covariance = centred.transpose() * w.asDiagonal() * centred;
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eigen(covariance);
  out.axes = eigen.eigenvectors().rowwise().reverse();
  out.variances = eigen.eigenvalues().reverse();
  if (out.axes.determinant() < 0) out.axes.col(2) *= -1;
  return out;
}

}  // namespace paramorph
