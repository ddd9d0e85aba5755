// Face adjacency of a closed manifold triangle mesh: per face and corner, the
// face across the edge opposite that corner (the convention of
// TriMesh::face_edges()). Walks across faces (point location, the spherical
// overlay of thesis 4.4) step through it.
#pragma once

#include "mesh/tri_mesh.h"

namespace paramorph {

/// #F by 3: entry (f, k) is the other face of the edge between F(f, (k+1)%3)
/// and F(f, (k+2)%3), or -1 where that edge does not have exactly two faces.
MatrixX3i face_neighbors(const TriMesh& mesh);

}  // namespace paramorph
