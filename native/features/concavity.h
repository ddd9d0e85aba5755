// Concavity intensity (thesis 4.5, Def. 4.1): the distance of every vertex of
// a mesh from the convex hull of the mesh (DESIGN.md §4.3).
//
// The hull comes from Qhull (reentrant C library, merged coplanar facets);
// for a point inside a convex polytope the distance to its boundary is the
// smallest distance to a facet's plane, so I(v) = min_f (h_f - n_f · v) over
// the hull's outward unit normals n_f and support values h_f. The minimum is
// found without testing every facet against every vertex: vertices are
// sorted along a Morton curve and split in halves recursively; each node
// bounds its vertices by an oriented box (their principal axes) and keeps only
// the facets that can still be the nearest to one of them (exact pruning, see
// depth_below_planes). Hull vertices are 0 without any test. Worst case
// O(#V · #facets); on a 164k-vertex noisy sphere (2.2k facets) or a 100k-vertex
// blob with 55k hull vertices (109k facets) Qhull dominates the time.
#pragma once

#include <vector>

#include "mesh/types.h"

namespace paramorph::features {

/// The facet planes of a 3D convex hull. A point p lies inside when
/// normals.row(f) · (p - origin) + offsets[f] <= 0 for every facet f.
struct ConvexHull {
  Eigen::Vector3d origin = Eigen::Vector3d::Zero();  ///< planes are written relative to it
  MatrixX3d normals;                                 ///< #facets by 3 outward unit normals
  VectorXd offsets;             ///< #facets; -offsets[f] is the support value about origin
  std::vector<Index> vertices;  ///< input points that are hull vertices, ascending
};

/// Convex hull of `points` (#P by 3, finite) with Qhull. Coplanar facets are
/// merged, so a box has 6 planes whatever its tessellation. Qhull prints
/// nothing. Throws InvalidInputError when the points span no volume (fewer
/// than 4 points, all on one plane, line or point) or Qhull fails otherwise.
ConvexHull convex_hull(const MatrixX3d& points);

/// Per point (#P): min over the hull's facets of -(n_f · (p - origin) + offset_f),
/// the distance to the hull's boundary for a point inside it (negative
/// outside, by at most the distance to the nearest plane). Same result as the
/// brute-force minimum over all facets; runs in parallel (OpenMP).
VectorXd depth_below_planes(const MatrixX3d& points, const ConvexHull& hull);

/// Concavity intensity I(v) of every vertex (Def. 4.1): its Euclidean distance
/// to the convex hull of the mesh, in the units of V. 0 on hull vertices and
/// on points lying on a hull facet (a flat side of a box), > 0 inside.
///
/// V: #V by 3 positions. F: #F by 3 vertex indices, 0-based (checked with
/// validate_arrays; the hull is that of all rows of V). Returns #V, >= 0.
/// Invariant under rigid motions, scales linearly with the mesh.
/// Throws InvalidInputError for malformed arrays or a flat mesh (no volume).
VectorXd concavity(const MatrixX3d& V, const MatrixX3i& F);

}  // namespace paramorph::features
