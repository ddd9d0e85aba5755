// fill_between_loops: triangulate the plane region between closed loops of
// segments (DESIGN.md §4.5; the seam of a feature pasted as its own mesh,
// paste/paste_session.h "A FEATURE CARRIED AS ITS OWN MESH"): the hole cut
// in the target around the feature's base and the feature's boundary, both
// drawn in the feature plane, are joined by triangles that use only their
// vertices.
//
// A constrained Delaunay triangulation (CGAL, exact predicates) of the loops'
// points with every segment as a constraint; its faces are kept where they
// lie inside an odd number of loops (between an outer loop and the loop
// inside it; an island inside the inner loop would be odd again). Loops must
// not cross or touch each other: a crossing is reported, a point lying on
// another loop's segment is not (the caller keeps the loops apart).
#pragma once

#include <Eigen/Core>
#include <array>
#include <optional>
#include <vector>

#include "mesh/types.h"

namespace paramorph::paste {

/// points: the loops' vertices in the plane (each point once); segments:
/// index pairs into points, every loop's edges. Returns the triangles (rows
/// of point indices, counter-clockwise in the plane) filling the region
/// inside an odd number of loops; std::nullopt when a point is given twice
/// or segments cross (the triangulation would need a point that is not one
/// of `points`).
std::optional<MatrixX3i> fill_between_loops(const std::vector<Eigen::Vector2d>& points,
                                            const std::vector<std::array<Index, 2>>& segments);

}  // namespace paramorph::paste
