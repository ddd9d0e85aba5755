// The local frame of a mapped surface (thesis 5.2: the detail is offset from
// the base surface; DESIGN.md §4.5: "vector displacement in the base's local
// frame"). At every point of the base: e_u along increasing u, n the unit
// normal (the side the faces' normals point to, outside the source), and
// e_v = n × e_u, so (e_u, e_v, n) is right-handed and orthonormal.
//
// Per vertex, the area-weighted averages of the faces' map Jacobian column
// ∂X/∂u and unit normals; at a point, these are interpolated barycentrically
// and orthonormalised (Gram–Schmidt against n), so the frame varies
// continuously over the surface and the same formula serves extraction and
// lookup.
#pragma once

#include <Eigen/Core>

#include "mesh/types.h"

namespace paramorph::paste {

struct MapFrames {
  MatrixX3d du;      ///< #V by 3: area-weighted ∂X/∂u of the faces around each vertex
  MatrixX3d normal;  ///< #V by 3: area-weighted unit face normals around each vertex
};

/// X: #V by 3 surface; F: #F by 3 faces; uv: #V by 2 fold-free map of it
/// (counter-clockwise faces keep positive area, as isometric_map gives).
MapFrames map_frames(const MatrixX3d& X, const MatrixX3i& F, const MatrixX2d& uv);

/// Orthonormal frame at barycentric point `bary` of face f: columns e_u, e_v, n.
Eigen::Matrix3d frame_at(const MapFrames& frames, const MatrixX3i& F, Index f,
                         const Eigen::Vector3d& bary);

}  // namespace paramorph::paste
