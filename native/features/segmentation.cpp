#include "features/segmentation.h"

#include <algorithm>

#include "common/errors.h"
#include "param/spherical/sphere_quality.h"

namespace paramorph::features {

void summarise_regions(const TriMesh& mesh, Segmentation& s) {
  const MatrixX3d& V = mesh.V();
  const MatrixX3i& F = mesh.F();
  const Index regions = s.regions();
  PM_REQUIRE(Index(s.face_labels.size()) == mesh.num_faces(), InvalidInputError,
             "one label per face expected");
  const VectorXd face_area = spherical::face_areas(V, F);
  s.area = VectorXd::Zero(regions);
  s.centroid = MatrixX3d::Zero(regions, 3);
  for (Index f = 0; f < mesh.num_faces(); ++f) {
    const Index r = s.face_labels[f];
    PM_REQUIRE(r >= 0 && r < regions, InvalidInputError, "face ", f, " has label ", r,
               " outside 0..", regions - 1);
    s.area[r] += face_area[f];
    s.centroid.row(r) += face_area[f] * (V.row(F(f, 0)) + V.row(F(f, 1)) + V.row(F(f, 2))) / 3.0;
  }
  for (Index r = 0; r < regions; ++r)
    if (s.area[r] > 0) s.centroid.row(r) /= s.area[r];
  s.adjacency.clear();
  const Csr& edge_faces = mesh.edge_faces();
  for (Index e = 0; e < edge_faces.rows(); ++e)
    for (Index i = edge_faces.begin(e); i < edge_faces.end(e); ++i)
      for (Index j = i + 1; j < edge_faces.end(e); ++j) {
        const Index a = s.face_labels[edge_faces.items[i]], b = s.face_labels[edge_faces.items[j]];
        if (a != b) s.adjacency.emplace_back(std::min(a, b), std::max(a, b));
      }
  std::sort(s.adjacency.begin(), s.adjacency.end());
  s.adjacency.erase(std::unique(s.adjacency.begin(), s.adjacency.end()), s.adjacency.end());
}

}  // namespace paramorph::features
