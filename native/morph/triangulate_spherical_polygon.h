// Triangulating one cell of the spherical overlay (thesis 4.4: "these regions
// are always convex, therefore it is straightforward to triangulate them").
// After merging (merge_close_vertices.h) a cell may have corners on a straight
// side (angle pi) or, within the merge tolerance, slightly reflex ones, where
// a plain fan would make zero-area or folded triangles. So the triangulation
// is chosen: among all triangulations of the polygon by its diagonals, one
// whose triangles are all positively oriented (exact orientation()) and whose
// worst triangle is best shaped, by dynamic programming over the diagonals.
#pragma once

#include <Eigen/Core>
#include <array>

namespace paramorph::morph {

/// Most corners triangulate_spherical_polygon() takes (a cell has at most 6).
constexpr int kMaxPolygonCorners = 16;

/// corners: n unit vectors, 3 <= n <= kMaxPolygonCorners, a simple polygon
/// counter-clockwise seen from outside, within a hemisphere. Writes n - 2
/// triangles of corner indices (counter-clockwise) to `triangles`. Returns
/// true when every triangle has det > 0 exactly; false when no triangulation
/// does (a polygon of zero area), `triangles` then holding one regardless.
/// Triangle quality: det(a, b, c) / (|a - b|^2 + |b - c|^2 + |c - a|^2).
bool triangulate_spherical_polygon(const Eigen::Vector3d* corners, int n,
                                   std::array<int, 3>* triangles);

}  // namespace paramorph::morph
