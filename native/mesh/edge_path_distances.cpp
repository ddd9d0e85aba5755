#include "mesh/edge_path_distances.h"

#include <functional>
#include <limits>
#include <queue>
#include <utility>

#include "common/errors.h"

namespace paramorph {

VectorXd edge_path_distances(const TriMesh& mesh, const std::vector<Index>& sources, std::vector<Index>* previous) {
  const Index n = mesh.num_vertices();
  if (previous) previous->assign(std::size_t(n), -1);
  const Csr& ring = mesh.vertex_neighbors();
  VectorXd dist = VectorXd::Constant(n, std::numeric_limits<double>::infinity());
  using Entry = std::pair<double, Index>;  // ties settle the lower vertex first
  std::priority_queue<Entry, std::vector<Entry>, std::greater<>> queue;
  for (const Index s : sources) {
    PM_REQUIRE(s >= 0 && s < n, InvalidInputError, "source vertex ", s, " out of range (", n, " vertices)");
    dist[s] = 0.0;
    queue.push({0.0, s});
  }
  const MatrixX3d& V = mesh.V();
  while (!queue.empty()) {
    const auto [d, v] = queue.top();
    queue.pop();
    if (d > dist[v]) continue;  // stale entry
    for (Index k = ring.begin(v); k < ring.end(v); ++k) {
      const Index u = ring.items[k];
      const double du = d + (V.row(u) - V.row(v)).norm();
      if (du < dist[u]) {
        dist[u] = du;
        if (previous) (*previous)[std::size_t(u)] = v;
        queue.push({du, u});
      }
    }
  }
  return dist;
}

}  // namespace paramorph
