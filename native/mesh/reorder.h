// Vertex and face renumbering for memory locality (thesis 3.4, Fig. 3.2):
// neighbouring vertices get nearby indices, so per-vertex kernels gathering
// over 1-rings and per-face kernels touch nearby memory.
#pragma once

#include <vector>

#include "mesh/types.h"

namespace paramorph {

struct Reordering {
  std::vector<Index> new_to_old_vertex;  ///< #V
  std::vector<Index> old_to_new_vertex;  ///< #V
  std::vector<Index> new_to_old_face;    ///< #F

  /// Rows permuted into the new order.
  MatrixX3d apply_to_vertices(const MatrixX3d& V) const;
  /// Faces renumbered and permuted; each face keeps its corner order (orientation).
  MatrixX3i apply_to_faces(const MatrixX3i& F) const;
  /// Inverse of apply_to_vertices.
  MatrixX3d restore_vertices(const MatrixX3d& X) const;
  VectorXd restore_vector(const VectorXd& x) const;
};

/// Vertices sorted along a Morton (Z-order) curve of their positions, faces by
/// their smallest new vertex index. O(#V log #V + #F log #F).
Reordering locality_order(const MatrixX3d& V, const MatrixX3i& F);

}  // namespace paramorph
