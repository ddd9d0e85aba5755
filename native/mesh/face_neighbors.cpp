// Face adjacency (mesh/face_neighbors.h) from TriMesh's edge -> faces lists.
#include "mesh/face_neighbors.h"

namespace paramorph {

MatrixX3i face_neighbors(const TriMesh& mesh) {
  const MatrixX3i& FE = mesh.face_edges();
  const Csr& edge_faces = mesh.edge_faces();
  MatrixX3i N(mesh.num_faces(), 3);
  for (Index f = 0; f < mesh.num_faces(); ++f)
    for (int k = 0; k < 3; ++k) {
      const Index e = FE(f, k);
      if (edge_faces.size(e) != 2) {
        N(f, k) = -1;
        continue;
      }
      const Index first = edge_faces.items[edge_faces.begin(e)];
      N(f, k) = first != f ? first : edge_faces.items[edge_faces.begin(e) + 1];
    }
  return N;
}

}  // namespace paramorph
