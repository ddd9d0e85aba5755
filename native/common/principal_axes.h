// Principal axes of weighted points: the frame a model's spread defines,
// used to register two models from their shapes (morph/correspondence) and
// to turn a scene into a frame of its own (morph/correspondence_frame).
#pragma once

#include "mesh/types.h"

namespace paramorph {

struct PrincipalAxes {
  Eigen::Matrix3d axes;         ///< columns, largest weighted variance first, det +1
  Eigen::Vector3d variances;    ///< along each column
  Eigen::RowVector3d mean;      ///< the weighted mean
};

/// points: n by 3; weights: n non-negative with a positive sum.
PrincipalAxes principal_axes(const MatrixX3d& points, const VectorXd& weights);

}  // namespace paramorph
