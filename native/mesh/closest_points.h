// Closest points on a triangle mesh (thesis 4.4 needs positions on the
// models; here: the 3D registration of morph/register_surfaces and the
// transfer of A's sphere map to B's registered vertices). A CGAL AABB tree
// over the faces, built once and queried many times.
#pragma once

#include <memory>

#include "mesh/types.h"

namespace paramorph {

struct ClosestPoints {
  VectorXi face;       ///< #Q: the face holding each closest point
  MatrixX3d bary;      ///< #Q by 3: its barycentric coordinates in that face (>= 0, sum 1)
  MatrixX3d points;    ///< #Q by 3: the closest points
  VectorXd distance;   ///< #Q: distance from each query to its closest point
};

/// Solver object: `ClosestPointTree tree(V, F)` once, then `tree.query(Q)`.
/// V, F: a triangle mesh (#V by 3, #F by 3, 0-based; faces of zero area, or
/// slivers whose area is zero to rounding, are skipped). Q: #Q by 3 finite query points. The tree works on V scaled by a
/// power of two to a largest coordinate in [1, 2) (exact, so answers are the
/// same), so coordinates near 1e150 or 1e-150 do not overflow or underflow
/// CGAL's constructions; queries farther than 1e100 times that from the
/// origin raise InvalidInputError.
class ClosestPointTree {
 public:
  ClosestPointTree(const MatrixX3d& V, const MatrixX3i& F);
  ~ClosestPointTree();
  ClosestPointTree(ClosestPointTree&&) noexcept;
  ClosestPointTree& operator=(ClosestPointTree&&) noexcept;
  /// hint: an earlier answer for nearby queries (e.g. the previous round of
  /// an ICP), whose points bound the search: much faster when Q moved little.
  ClosestPoints query(const MatrixX3d& Q, const ClosestPoints* hint = nullptr) const;

 private:
  struct Tree;
  std::unique_ptr<Tree> tree_;
  MatrixX3d V_;         ///< V times scale_
  MatrixX3i F_;
  double scale_ = 1.0;  ///< a power of two
};

}  // namespace paramorph
