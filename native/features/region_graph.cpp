// Region adjacency graph and its reduction (features/region_graph.h, thesis 4.5).
#include "features/region_graph.h"

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <queue>

#include "common/errors.h"
#include "mesh/validate.h"

namespace paramorph::features {

namespace {

/// Per region, its vertex nearest its centroid (ties: the lower index).
std::vector<Index> region_anchors(const MatrixX3d& V, const MatrixX3i& F, const Segmentation& s) {
  const Index regions = s.regions();
  std::vector<Index> anchor(regions, -1);
  std::vector<double> best(regions, std::numeric_limits<double>::infinity());
  for (Index f = 0; f < Index(F.rows()); ++f) {
    const Index r = s.face_labels[f];
    for (int k = 0; k < 3; ++k) {
      const Index v = F(f, k);
      const double d = (V.row(v) - s.centroid.row(r)).squaredNorm();
      if (d < best[r] || (d == best[r] && v < anchor[r])) best[r] = d, anchor[r] = v;
    }
  }
  return anchor;
}

/// Shortest-path distances along mesh edges from `source` to each of
/// `targets`, stopping once all are settled. `dist` is a #V scratch array
/// filled with infinity, returned to that state.
std::vector<double> distances_to(const TriMesh& mesh, const VectorXd& edge_length, Index source,
                                 const std::vector<Index>& targets, std::vector<double>& dist) {
  const Csr& ring = mesh.vertex_neighbors();
  const Csr& ring_edges = mesh.vertex_neighbor_edges();
  std::vector<Index> touched{source};
  using Entry = std::pair<double, Index>;  // ties settle the lower vertex first
  std::priority_queue<Entry, std::vector<Entry>, std::greater<>> queue;
  dist[source] = 0.0;
  queue.push({0.0, source});
  std::vector<Index> pending(targets);
  std::sort(pending.begin(), pending.end());
  pending.erase(std::unique(pending.begin(), pending.end()), pending.end());
  Index remaining = Index(pending.size());
  while (!queue.empty() && remaining > 0) {
    const auto [d, v] = queue.top();
    queue.pop();
    if (d > dist[v]) continue;  // stale entry
    if (std::binary_search(pending.begin(), pending.end(), v)) --remaining;
    for (Index k = ring.begin(v); k < ring.end(v); ++k) {
      const Index u = ring.items[k];
      const double du = d + edge_length[ring_edges.items[k]];
      if (du < dist[u]) {
        if (std::isinf(dist[u])) touched.push_back(u);
        dist[u] = du;
        queue.push({du, u});
      }
    }
  }
  std::vector<double> out;
  out.reserve(targets.size());
  for (Index t : targets) out.push_back(dist[t]);
  for (Index v : touched) dist[v] = std::numeric_limits<double>::infinity();
  return out;
}

}  // namespace

RegionGraph region_graph(const MatrixX3d& V, const MatrixX3i& F, const Segmentation& s,
                         const RegionGraphOptions& o) {
  validate_arrays(V, F);
  PM_REQUIRE(o.long_edge_factor > 0 && !std::isnan(o.long_edge_factor), InvalidInputError,
             "long_edge_factor must be > 0, got ", o.long_edge_factor);
  const Index regions = s.regions();
  PM_REQUIRE(s.face_labels.size() == F.rows(), InvalidInputError, "segmentation has ",
             s.face_labels.size(), " face labels for ", F.rows(), " faces");
  PM_REQUIRE(s.face_labels.size() == 0 ||
                 (s.face_labels.minCoeff() >= 0 && s.face_labels.maxCoeff() < regions),
             InvalidInputError, "face labels must lie in [0, ", regions, ")");
  PM_REQUIRE(s.centroid.rows() == regions, InvalidInputError, "segmentation has ",
             s.centroid.rows(), " centroids for ", regions,
             " regions (summarise_regions fills them)");
  for (const auto& [a, b] : s.adjacency)
    PM_REQUIRE(0 <= a && a < b && b < regions, InvalidInputError, "adjacency pair (", a, ", ", b,
               ") is not a < b within [0, ", regions, ")");

  RegionGraph g;
  g.anchors = region_anchors(V, F, s);
  for (Index r = 0; r < regions; ++r)
    PM_REQUIRE(g.anchors[r] >= 0, InvalidInputError, "region ", r, " has no faces");

  // Geodesic length of every adjacency edge, from the lower region's anchor.
  const TriMesh mesh(V, F);
  const MatrixX2i& E = mesh.edges();
  VectorXd edge_length(E.rows());
  for (Index e = 0; e < Index(E.rows()); ++e)
    edge_length[e] = (V.row(E(e, 0)) - V.row(E(e, 1))).norm();
  std::vector<std::pair<Index, Index>> adjacency = s.adjacency;
  std::sort(adjacency.begin(), adjacency.end());
  adjacency.erase(std::unique(adjacency.begin(), adjacency.end()), adjacency.end());
  std::vector<double> length(adjacency.size());
  std::vector<double> scratch(V.rows(), std::numeric_limits<double>::infinity());
  for (std::size_t i = 0; i < adjacency.size();) {
    const Index a = adjacency[i].first;
    std::size_t j = i;
    std::vector<Index> targets;
    for (; j < adjacency.size() && adjacency[j].first == a; ++j)
      targets.push_back(g.anchors[adjacency[j].second]);
    const std::vector<double> d = distances_to(mesh, edge_length, g.anchors[a], targets, scratch);
    for (std::size_t k = i; k < j; ++k) {
      PM_REQUIRE(std::isfinite(d[k - i]), InvalidInputError, "regions ", a, " and ",
                 adjacency[k].second, " are listed as adjacent but are not connected on the mesh");
      length[k] = d[k - i];
    }
    i = j;
  }

  // Reduction: long relative to the median, unless a region's shortest edge.
  std::vector<double> shortest(regions, std::numeric_limits<double>::infinity());
  for (std::size_t k = 0; k < adjacency.size(); ++k) {
    shortest[adjacency[k].first] = std::min(shortest[adjacency[k].first], length[k]);
    shortest[adjacency[k].second] = std::min(shortest[adjacency[k].second], length[k]);
  }
  double median = 0.0;
  if (!length.empty()) {
    std::vector<double> sorted = length;
    std::sort(sorted.begin(), sorted.end());
    const std::size_t n = sorted.size();
    median = n % 2 ? sorted[n / 2] : 0.5 * (sorted[n / 2 - 1] + sorted[n / 2]);
  }
  const double limit = o.long_edge_factor * median;
  g.degree.assign(regions, 0);
  for (std::size_t k = 0; k < adjacency.size(); ++k) {
    const auto [a, b] = adjacency[k];
    const bool keep = length[k] <= limit || length[k] <= shortest[a] || length[k] <= shortest[b];
    if (keep) {
      g.edges.push_back(adjacency[k]);
      g.lengths.push_back(length[k]);
      ++g.degree[a], ++g.degree[b];
    } else {
      g.dropped.push_back(adjacency[k]);
      g.dropped_lengths.push_back(length[k]);
    }
  }
  return g;
}

}  // namespace paramorph::features
