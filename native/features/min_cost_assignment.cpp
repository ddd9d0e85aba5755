// Minimum-cost assignment (features/min_cost_assignment.h).
#include "features/min_cost_assignment.h"

#include <limits>

#include "common/errors.h"

namespace paramorph::features {

std::vector<Index> min_cost_assignment(const Eigen::MatrixXd& cost) {
  PM_REQUIRE(cost.allFinite(), InvalidInputError, "assignment costs must be finite");
  const bool transposed = cost.rows() > cost.cols();
  const Eigen::MatrixXd a = transposed ? Eigen::MatrixXd(cost.transpose()) : cost;
  const Index n = Index(a.rows()), m = Index(a.cols());  // n <= m
  std::vector<Index> out(cost.rows(), -1);
  if (n == 0) return out;

  // Shortest augmenting paths with row potentials u and column potentials v
  // (1-based, column 0 is the virtual start); match[j] is the row on column j.
  const double inf = std::numeric_limits<double>::infinity();
  std::vector<double> u(n + 1, 0.0), v(m + 1, 0.0);
  std::vector<Index> match(m + 1, 0), way(m + 1, 0);
  for (Index i = 1; i <= n; ++i) {
    match[0] = i;
    Index j0 = 0;
    std::vector<double> minv(m + 1, inf);
    std::vector<char> used(m + 1, false);
    do {
      used[j0] = true;
      const Index i0 = match[j0];
      double delta = inf;
      Index j1 = 0;
      for (Index j = 1; j <= m; ++j) {
        if (used[j]) continue;
        const double reduced = a(i0 - 1, j - 1) - u[i0] - v[j];
        if (reduced < minv[j]) minv[j] = reduced, way[j] = j0;
        if (minv[j] < delta) delta = minv[j], j1 = j;
      }
      for (Index j = 0; j <= m; ++j) {
        if (used[j])
          u[match[j]] += delta, v[j] -= delta;
        else
          minv[j] -= delta;
      }
      j0 = j1;
    } while (match[j0] != 0);
    do {  // flip the augmenting path
      const Index j1 = way[j0];
      match[j0] = match[j1];
      j0 = j1;
    } while (j0 != 0);
  }
  for (Index j = 1; j <= m; ++j) {
    if (match[j] == 0) continue;
    if (transposed)
      out[j - 1] = match[j] - 1;
    else
      out[match[j] - 1] = j - 1;
  }
  return out;
}

}  // namespace paramorph::features
