// The length of a point set's axis-aligned bounding-box diagonal: the scale
// that tolerances given "as a share of the diagonal" are measured against.
#pragma once

#include "mesh/types.h"

namespace paramorph {

/// V: #V by 3. 0 for no rows.
inline double bounding_box_diagonal(const MatrixX3d& V) {
  return V.rows() ? (V.colwise().maxCoeff() - V.colwise().minCoeff()).norm() : 0.0;
}

}  // namespace paramorph
