// Vertex normals: the area-weighted average of the unit normals of the faces
// around each vertex (the paste's surface frames and anchor normals), and a
// face's own normal.
#pragma once

#include <Eigen/Geometry>

#include "mesh/types.h"

namespace paramorph {

/// Face f's normal times twice its area (not unit; zero for a degenerate
/// face): (V[F(f,1)] - V[F(f,0)]) x (V[F(f,2)] - V[F(f,0)]).
inline Eigen::RowVector3d face_normal(const MatrixX3d& V, const MatrixX3i& F, Index f) {
  const Eigen::RowVector3d a = V.row(F(f, 0));
  return (V.row(F(f, 1)) - a).cross(V.row(F(f, 2)) - a);
}

/// V: #V by 3, F: #F by 3 (counter-clockwise seen from outside). Returns #V
/// by 3 unit normals on the faces' side; zero rows for vertices in no face
/// (or whose faces cancel out).
MatrixX3d area_weighted_vertex_normals(const MatrixX3d& V, const MatrixX3i& F);

}  // namespace paramorph
