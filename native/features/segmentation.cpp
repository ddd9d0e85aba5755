#include "features/segmentation.h"

#include <algorithm>
#include <numeric>

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

void split_regions(const TriMesh& mesh, const VectorXd& level, Segmentation& s,
                   const std::function<bool(Index, Index)>& joined) {
  const MatrixX3i& F = mesh.F();
  const MatrixX3i& face_edges = mesh.face_edges();
  const Csr& edge_faces = mesh.edge_faces();
  VectorXi piece = VectorXi::Constant(mesh.num_faces(), -1);
  std::vector<Index> seeds, stack, origin;
  std::vector<bool> seed_used(s.seeds.size(), false);
  for (Index start = 0; start < mesh.num_faces(); ++start) {
    if (piece[start] >= 0) continue;
    const Index label = s.face_labels[start], id = Index(seeds.size());
    Index highest = F(start, 0);
    bool has_seed = false;
    piece[start] = id;
    stack.assign(1, start);
    while (!stack.empty()) {
      const Index f = stack.back();
      stack.pop_back();
      for (int k = 0; k < 3; ++k) {
        const Index v = F(f, k);
        has_seed = has_seed || v == s.seeds[label];
        if (level[v] > level[highest]) highest = v;
        const Index e = face_edges(f, k);
        for (Index i = edge_faces.begin(e); i < edge_faces.end(e); ++i) {
          const Index g = edge_faces.items[i];
          if (piece[g] < 0 && s.face_labels[g] == label && (!joined || joined(f, g)))
            piece[g] = id, stack.push_back(g);
        }
      }
    }
    const bool keeps_seed = has_seed && !seed_used[label];
    seed_used[label] = seed_used[label] || keeps_seed;
    seeds.push_back(keeps_seed ? s.seeds[label] : highest);
    origin.push_back(2 * label + (keeps_seed ? 0 : 1));
  }
  std::vector<Index> order(seeds.size()), number(seeds.size());
  std::iota(order.begin(), order.end(), Index(0));
  std::stable_sort(order.begin(), order.end(), [&](Index a, Index b) { return origin[a] < origin[b]; });
  s.seeds.clear();
  for (Index i = 0; i < Index(order.size()); ++i) number[order[i]] = i, s.seeds.push_back(seeds[order[i]]);
  for (Index f = 0; f < mesh.num_faces(); ++f) s.face_labels[f] = number[piece[f]];
  summarise_regions(mesh, s);
}

}  // namespace paramorph::features
