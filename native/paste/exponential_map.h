// Local 2D coordinates of a surface around a point: the discrete exponential
// map (Schmidt, Grimm and Wyvill, "Interactive decal compositing with
// discrete exponential maps", SIGGRAPH 2006). The paste uses it as the
// target's parameterization (thesis 5.2: the feature's boundary is "projected
// on the base surface" and located by the base's (s,t) coordinates; DESIGN.md
// §4.5 step 2): |q| follows geodesic distance, so a feature cut from a curved
// surface lands on a like surface at its own size, and the map does not fold
// where the surface turns away from the anchor's normal (up to the cut
// locus), unlike a projection onto the tangent plane.
//
// Vertices are visited in Dijkstra order of edge-path distance from the
// anchor; each gets the average, weighted by 1 / |edge|², of what its already
// visited neighbours predict: their coordinates plus the edge expressed in
// their tangent frame (turned along the path by the smallest rotation between
// neighbouring normals) at the edge's full length.
#pragma once

#include <Eigen/Core>
#include <vector>

#include "mesh/tri_mesh.h"

namespace paramorph::paste {

struct ExponentialMap {
  std::vector<Index> vertices;          ///< the vertices reached, in visiting order
  std::vector<Eigen::Vector2d> q;       ///< #V: coordinates of reached vertices (0 elsewhere)
  std::vector<char> reached;            ///< #V: 1 where q is set
};

/// mesh: a manifold triangle mesh; vertex_normals: #V by 3 unit normals;
/// anchor_face, anchor: the face holding the anchor point and the point;
/// tangent, normal: orthonormal, the frame at the anchor (q = (1, 0) along
/// tangent, (0, 1) along normal x tangent). radius > 0: vertices are expanded
/// while their |q| or path distance is below it, so every vertex within
/// radius (and its one ring) is reached; the anchor face's corners always are.
ExponentialMap exponential_map(const TriMesh& mesh, const MatrixX3d& vertex_normals, Index anchor_face,
                               const Eigen::Vector3d& anchor, const Eigen::Vector3d& tangent,
                               const Eigen::Vector3d& normal, double radius);

/// t turned by the smallest rotation taking the unit normal `from` to `to`,
/// made orthonormal to `to`: how the map carries the anchor's frame to a vertex.
Eigen::Vector3d transport_tangent(const Eigen::Vector3d& t, const Eigen::Vector3d& from, const Eigen::Vector3d& to);

}  // namespace paramorph::paste
