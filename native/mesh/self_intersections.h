// Faces of a triangle mesh that pass through other faces: how in-betweens
// are judged (issue 17: legs as stacked sheets, pleats along a flank), through
// CGAL's self-intersection test (box intersection, exact predicates).
#pragma once

#include <vector>

#include "mesh/types.h"

namespace paramorph {

struct SelfIntersections {
  /// Per face: 1 where it meets a face it shares no vertex or edge with
  /// (two faces sharing an edge or vertex that meet beyond it count too).
  std::vector<char> intersecting;
  Index intersecting_faces = 0;  ///< how many faces are marked
  Index pairs = 0;               ///< intersecting pairs of faces
  Index degenerate_faces = 0;    ///< faces of zero area (not tested)
};

/// V, F: any triangle mesh, closed or not. A non-manifold vertex or edge is
/// cut apart first, so faces that meet only there count as intersecting.
/// InvalidInputError for indices out of range or non-finite positions.
SelfIntersections self_intersections(const MatrixX3d& V, const MatrixX3i& F);

}  // namespace paramorph
