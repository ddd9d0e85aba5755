#include "mesh/weld_vertices.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <numeric>
#include <unordered_map>
#include <vector>

#include "common/errors.h"

namespace paramorph {

namespace {

Index root(std::vector<Index>& parent, Index v) {
  while (parent[std::size_t(v)] != v) v = parent[std::size_t(v)] = parent[std::size_t(parent[std::size_t(v)])];
  return v;
}

void join(std::vector<Index>& parent, Index a, Index b) {
  a = root(parent, a);
  b = root(parent, b);
  if (a == b) return;
  if (a < b) parent[std::size_t(b)] = a;  // the lowest index names the cluster
  else parent[std::size_t(a)] = b;
}

struct CellHash {
  std::size_t operator()(const std::array<std::int64_t, 3>& c) const {
    std::uint64_t h = std::uint64_t(c[0]) * 73856093u;
    h ^= std::uint64_t(c[1]) * 19349663u + (h << 6) + (h >> 2);
    h ^= std::uint64_t(c[2]) * 83492791u + (h << 6) + (h >> 2);
    return std::size_t(h);
  }
};

}  // namespace

VectorXi weld_vertices(const MatrixX3d& V, double tolerance) {
  PM_REQUIRE(std::isfinite(tolerance) && tolerance >= 0, InvalidInputError,
             "the weld tolerance must be finite and >= 0, got ", tolerance);
  const Index n = Index(V.rows());
  std::vector<Index> parent(static_cast<std::size_t>(n));
  std::iota(parent.begin(), parent.end(), 0);
  if (tolerance == 0) {
    // Exact duplicates: neighbours in lexicographic order.
    std::vector<Index> order(static_cast<std::size_t>(n));
    std::iota(order.begin(), order.end(), 0);
    auto less = [&](Index a, Index b) {
      for (int k = 0; k < 3; ++k)
        if (V(a, k) != V(b, k)) return V(a, k) < V(b, k);
      return a < b;
    };
    std::sort(order.begin(), order.end(), less);
    for (std::size_t i = 1; i < order.size(); ++i)
      if (V.row(order[i]) == V.row(order[i - 1])) join(parent, order[i], order[i - 1]);
  } else {
    // Cells as wide as the tolerance: any two vertices within it lie in
    // neighbouring cells.
    const Eigen::RowVector3d low = V.colwise().minCoeff();
    std::unordered_map<std::array<std::int64_t, 3>, std::vector<Index>, CellHash> cells;
    cells.reserve(static_cast<std::size_t>(n));
    std::vector<std::array<std::int64_t, 3>> cell_of(static_cast<std::size_t>(n));
    for (Index v = 0; v < n; ++v) {
      for (int k = 0; k < 3; ++k)
        cell_of[std::size_t(v)][std::size_t(k)] = std::int64_t(std::floor((V(v, k) - low(k)) / tolerance));
      cells[cell_of[std::size_t(v)]].push_back(v);
    }
    const double tolerance2 = tolerance * tolerance;
    for (Index v = 0; v < n; ++v) {
      const auto& c = cell_of[std::size_t(v)];
      for (std::int64_t dx = -1; dx <= 1; ++dx)
        for (std::int64_t dy = -1; dy <= 1; ++dy)
          for (std::int64_t dz = -1; dz <= 1; ++dz) {
            const auto it = cells.find({c[0] + dx, c[1] + dy, c[2] + dz});
            if (it == cells.end()) continue;
            for (Index w : it->second)
              if (w < v && (V.row(v) - V.row(w)).squaredNorm() <= tolerance2) join(parent, v, w);
          }
    }
  }
  VectorXi into(n);
  for (Index v = 0; v < n; ++v) into(v) = root(parent, v);
  return into;
}

}  // namespace paramorph
