// Vertex normals: the area-weighted average of the unit normals of the faces
// around each vertex (the paste's surface frames and anchor normals).
#pragma once

#include "mesh/types.h"

namespace paramorph {

/// V: #V by 3, F: #F by 3 (counter-clockwise seen from outside). Returns #V
/// by 3 unit normals on the faces' side; zero rows for vertices in no face
/// (or whose faces cancel out).
MatrixX3d area_weighted_vertex_normals(const MatrixX3d& V, const MatrixX3i& F);

}  // namespace paramorph
