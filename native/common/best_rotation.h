// The proper rotation that best turns one set of points onto another
// (weighted Kabsch): sphere maps are turned onto each other, onto their
// targets and onto their models' directions all through the morph.
#pragma once

#include "mesh/types.h"

namespace paramorph {

/// R (rows: p R) minimising sum_i w_i |from_i R - to_i|^2 over proper
/// rotations (det +1): U diag(1, 1, +-1) V^T of the weighted covariance
/// from^T W to. One row: the shortest rotation turning its direction onto
/// the other's; no rows: the identity. weights: #rows non-negative (empty:
/// all 1).
Eigen::Matrix3d best_rotation(const MatrixX3d& from, const MatrixX3d& to, const VectorXd& weights = {});

}  // namespace paramorph
