#include "features/extremity_tips.h"

#include <algorithm>
#include <cmath>
#include <numeric>

#include "common/errors.h"
#include "features/peak_regions.h"
#include "mesh/edge_path_distances.h"

namespace paramorph::features {

ExtremityTips extremity_tips(const MatrixX3d& V, const MatrixX3i& F, const Segmentation& s, double prominence) {
  PM_REQUIRE(s.face_labels.size() == F.rows(), InvalidInputError, "the segmentation labels ",
             s.face_labels.size(), " faces, the mesh has ", F.rows());
  PM_REQUIRE(std::isfinite(prominence) && prominence >= 0, InvalidInputError, "prominence must be >= 0");
  ExtremityTips tips;
  const Index regions = s.regions();
  if (regions == 0) return tips;
  Eigen::Index body;
  s.area.maxCoeff(&body);
  tips.body = Index(body);
  if (regions == 1) return tips;
  const TriMesh mesh(V, F);
  std::vector<Index> sources;
  VectorXi region_of = VectorXi::Constant(V.rows(), -1);  // a vertex's extremity (body wins a shared vertex)
  for (Index f = 0; f < F.rows(); ++f)
    for (int k = 0; k < 3; ++k) {
      const Index v = F(f, k);
      if (s.face_labels[f] == tips.body) sources.push_back(v), region_of[v] = tips.body;
      else if (region_of[v] < 0) region_of[v] = s.face_labels[f];
    }
  const VectorXd dist = edge_path_distances(mesh, sources);
  std::vector<Index> candidates;
  if (prominence > 0) {
    // Peaks of the distance standing out by `prominence`: the seeds of its
    // join-tree regions above the body.
    VectorXd level = dist;
    for (Index v = 0; v < level.size(); ++v)
      if (!std::isfinite(level[v])) level[v] = 0;
    const Segmentation peaks = peak_regions(mesh, level, 0.0, prominence);
    for (const Index seed : peaks.seeds)
      if (region_of[seed] != tips.body && level[seed] > prominence) candidates.push_back(seed);
  }
  // Every extremity has at least its farthest vertex.
  std::vector<Index> farthest(regions, -1);
  for (Index v = 0; v < V.rows(); ++v) {
    const Index r = region_of[v];
    if (r < 0 || r == tips.body || !std::isfinite(dist[v])) continue;
    if (farthest[r] < 0 || dist[v] > dist[farthest[r]]) farthest[r] = v;
  }
  for (Index r = 0; r < regions; ++r)
    if (farthest[r] >= 0 && std::none_of(candidates.begin(), candidates.end(), [&](Index c) { return region_of[c] == r; }))
      candidates.push_back(farthest[r]);
  std::sort(candidates.begin(), candidates.end(), [&](Index a, Index b) { return dist[a] != dist[b] ? dist[a] > dist[b] : a < b; });
  candidates.erase(std::unique(candidates.begin(), candidates.end()), candidates.end());
  for (const Index v : candidates) {
    tips.vertices.push_back(v);
    tips.regions.push_back(region_of[v]);
    tips.lengths.push_back(dist[v]);
  }
  return tips;
}

}  // namespace paramorph::features
