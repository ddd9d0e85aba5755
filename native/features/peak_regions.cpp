#include "features/peak_regions.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>

#include "common/errors.h"

namespace paramorph::features {

namespace {

/// Union-find with path halving; the root of a set is its representative.
struct DisjointSets {
  std::vector<Index> parent;
  explicit DisjointSets(Index n) : parent(n) { std::iota(parent.begin(), parent.end(), Index(0)); }
  Index add() {
    parent.push_back(Index(parent.size()));
    return parent.back();
  }
  Index find(Index x) {
    while (parent[x] != x) x = parent[x] = parent[parent[x]];
    return x;
  }
};

VectorXi label_faces(const TriMesh& mesh, const std::vector<Index>& vertex_region,
                     const VectorXd& level, const std::vector<Index>& seeds) {
  const MatrixX3i& F = mesh.F();
  VectorXi face_label(mesh.num_faces());
  for (Index f = 0; f < mesh.num_faces(); ++f) {
    const Index a = vertex_region[F(f, 0)], b = vertex_region[F(f, 1)], c = vertex_region[F(f, 2)];
    if (a == b || a == c) {
      face_label[f] = a;
    } else if (b == c) {
      face_label[f] = b;
    } else {
      int best = 0;
      double closest = std::numeric_limits<double>::infinity();
      for (int k = 0; k < 3; ++k) {
        const Index v = F(f, k);
        const double d = std::abs(level[v] - level[seeds[vertex_region[v]]]);
        if (d < closest) closest = d, best = k;
      }
      face_label[f] = vertex_region[F(f, best)];
    }
  }
  return face_label;
}

}  // namespace

Segmentation peak_regions(const TriMesh& mesh, const VectorXd& level, double base,
                          double threshold) {
  const Index n = mesh.num_vertices();
  PM_REQUIRE(Index(level.size()) == n, InvalidInputError, "one level per vertex expected");
  PM_REQUIRE(level.allFinite(), InvalidInputError, "levels must be finite");
  PM_REQUIRE(std::isfinite(threshold) && threshold > 0, InvalidInputError,
             "threshold must be a positive number, got ", threshold);
  std::vector<Index> order(n);
  std::iota(order.begin(), order.end(), Index(0));
  std::sort(order.begin(), order.end(),
            [&](Index a, Index b) { return level[a] != level[b] ? level[a] > level[b] : a < b; });
  const auto peaks_end = std::find_if(order.begin(), order.end(),
                                      [&](Index v) { return level[v] <= base + threshold; });

  // Components of the vertices swept so far (the part above the current
  // level) keep their highest level and the region still growing in them;
  // regions absorbed into another are followed through `merged_into`.
  const Csr& ring = mesh.vertex_neighbors();
  DisjointSets component(n), merged_into(0);
  std::vector<double> peak(n), region_top;
  std::vector<Index> growing(n, -1), vertex_region(n, -1), region_seed;
  auto new_region = [&](Index seed) {
    region_seed.push_back(seed);
    region_top.push_back(level[seed]);
    return merged_into.add();
  };
  std::vector<Index> met, continuing;
  for (auto it = order.begin(); it != peaks_end; ++it) {
    const Index v = *it;
    met.clear();
    for (Index k = ring.begin(v); k < ring.end(v); ++k)
      if (vertex_region[ring.items[k]] >= 0) met.push_back(component.find(ring.items[k]));
    std::sort(met.begin(), met.end());
    met.erase(std::unique(met.begin(), met.end()), met.end());

    if (met.empty()) {  // a seed candidate: a local maximum
      peak[v] = level[v];
      growing[v] = vertex_region[v] = new_region(v);
      continue;
    }
    Index region = growing[met[0]];
    if (met.size() > 1) {
      // Components whose peak rose `threshold` above here are features; the
      // rest are bumps. A feature's region stops here if it spans the
      // threshold itself; everything else continues as one region.
      int features = 0;
      for (Index c : met) features += peak[c] - level[v] >= threshold;
      continuing.clear();
      for (Index c : met) {
        const bool feature = peak[c] - level[v] >= threshold;
        const bool complete = region_top[growing[c]] - level[v] >= threshold;
        if (features < 2 || !feature || !complete) continuing.push_back(growing[c]);
      }
      if (continuing.empty()) {
        region = new_region(v);
      } else {
        region = *std::max_element(continuing.begin(), continuing.end(), [&](Index a, Index b) {
          return region_top[a] < region_top[b];
        });
        for (Index r : continuing) merged_into.parent[merged_into.find(r)] = merged_into.find(region);
      }
    }
    const Index root = met[0];
    for (Index c : met) {
      peak[root] = std::max(peak[root], peak[c]);
      component.parent[c] = root;
    }
    component.parent[v] = root;
    growing[root] = vertex_region[v] = region;
  }

  // The rest: each connected part, grown from its lowest vertex.
  std::vector<Index> stack;
  for (auto it = order.rbegin(); it.base() != peaks_end; ++it) {
    if (vertex_region[*it] >= 0) continue;
    const Index region = new_region(*it);
    vertex_region[*it] = region;
    stack.assign(1, *it);
    while (!stack.empty()) {
      const Index v = stack.back();
      stack.pop_back();
      for (Index k = ring.begin(v); k < ring.end(v); ++k) {
        const Index u = ring.items[k];
        if (vertex_region[u] < 0 && level[u] <= base + threshold)
          vertex_region[u] = region, stack.push_back(u);
      }
    }
  }

  // Regions by the survivor of their merges, numbered in order of their seeds.
  const Index regions = Index(region_seed.size());
  std::vector<Index> number(regions, -1), seeds;
  for (Index r = 0; r < regions; ++r)
    if (merged_into.find(r) == r) number[r] = Index(seeds.size()), seeds.push_back(region_seed[r]);
  for (Index v = 0; v < n; ++v) vertex_region[v] = number[merged_into.find(vertex_region[v])];

  Segmentation s;
  s.face_labels = label_faces(mesh, vertex_region, level, seeds);
  std::vector<Index> kept(seeds.size(), -1);
  for (Index f = 0; f < mesh.num_faces(); ++f) kept[s.face_labels[f]] = 0;
  for (std::size_t r = 0; r < seeds.size(); ++r)
    if (kept[r] == 0) kept[r] = Index(s.seeds.size()), s.seeds.push_back(seeds[r]);
  for (Index f = 0; f < mesh.num_faces(); ++f) s.face_labels[f] = kept[s.face_labels[f]];
  split_regions(mesh, level, s);  // an arc of the join tree may run down both flanks of a ridge
  return s;
}

}  // namespace paramorph::features
