#include "features/protrusion_tips.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>

#include "common/errors.h"
#include "mesh/edge_path_distances.h"
#include "mesh/tri_mesh.h"

namespace paramorph::features {

namespace {

/// Farthest-point samples along edges, from vertex 0: they spread over the
/// surface whatever its tessellation, so the average weighs area, not vertex
/// density (a scan's dense face would otherwise pull every average to it).
std::vector<Index> spread_samples(const TriMesh& mesh, std::size_t count) {
  std::vector<Index> out{0};
  VectorXd nearest = edge_path_distances(mesh, {0});
  while (out.size() < std::min<std::size_t>(count, std::size_t(mesh.num_vertices()))) {
    Index next = 0;
    double farthest = -1;
    for (Index v = 0; v < nearest.size(); ++v)
      if (std::isfinite(nearest[v]) && nearest[v] > farthest) farthest = nearest[v], next = v;
    if (farthest <= 0) break;
    out.push_back(next);
    nearest = nearest.cwiseMin(edge_path_distances(mesh, {next}));
  }
  return out;
}

}  // namespace

ProtrusionTips protrusion_tips(const MatrixX3d& V, const MatrixX3i& F, const ProtrusionOptions& o) {
  PM_REQUIRE(std::isfinite(o.radius) && o.radius > 0 && o.samples >= 1, InvalidInputError,
             "protrusion_tips: radius > 0 and at least one sample");
  ProtrusionTips out;
  const TriMesh mesh(V, F);
  const Index n = mesh.num_vertices();
  out.average_distance = VectorXd::Zero(n);
  if (n == 0) return out;
  const std::vector<Index> samples = spread_samples(mesh, o.samples);
  VectorXd reached = VectorXd::Zero(n);
  for (const Index s : samples) {
    const VectorXd d = edge_path_distances(mesh, {s});
    for (Index v = 0; v < n; ++v)
      if (std::isfinite(d[v])) out.average_distance[v] += d[v], reached[v] += 1;
  }
  for (Index v = 0; v < n; ++v)
    out.average_distance[v] = reached[v] > 0 ? out.average_distance[v] / reached[v] : 0.0;
  out.average_distance.minCoeff(&out.core);

  std::vector<Index> order(static_cast<std::size_t>(n));
  std::iota(order.begin(), order.end(), Index(0));
  std::stable_sort(order.begin(), order.end(),
                   [&](Index a, Index b) { return out.average_distance[a] > out.average_distance[b]; });
  const double median = out.average_distance[order[order.size() / 2]];
  const Csr& ring = mesh.vertex_neighbors();
  std::vector<Index> previous;
  const VectorXd from_core = edge_path_distances(mesh, {out.core}, &previous);
  for (const Index v : order) {
    if (out.average_distance[v] <= median || out.vertices.size() >= o.max_tips) break;
    // A maximum over its ring first (cheap: most vertices are on a slope),
    // then over the whole radius.
    bool highest = true;
    for (Index k = ring.begin(v); k < ring.end(v) && highest; ++k)
      highest = out.average_distance[ring.items[k]] <= out.average_distance[v];
    if (!highest || !std::isfinite(from_core[v])) continue;
    const VectorXd around = edge_path_distances(mesh, {v});
    for (Index u = 0; u < n && highest; ++u)
      highest = !(around[u] <= o.radius && out.average_distance[u] > out.average_distance[v]);
    if (!highest) continue;
    std::vector<Index> path{v};
    while (path.back() != out.core) path.push_back(previous[std::size_t(path.back())]);
    std::reverse(path.begin(), path.end());
    out.vertices.push_back(v);
    out.paths.push_back(std::move(path));
  }
  return out;
}

}  // namespace paramorph::features
