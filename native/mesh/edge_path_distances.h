// Shortest-path distances along mesh edges from a set of sources (Dijkstra):
// a cheap geodesic, good where only order and rough length matter (how far
// a limb's tip is from the body, features/extremity_tips).
#pragma once

#include <vector>

#include "mesh/tri_mesh.h"

namespace paramorph {

/// #V distances from the nearest of `sources` (0 there) along edges of
/// Euclidean length; +infinity where no path reaches. With `previous`, also
/// each vertex's neighbour on a shortest path back to a source (-1 at the
/// sources and where no path reaches). Raises InvalidInputError for a source
/// out of range.
VectorXd edge_path_distances(const TriMesh& mesh, const std::vector<Index>& sources,
                             std::vector<Index>* previous = nullptr);

}  // namespace paramorph
