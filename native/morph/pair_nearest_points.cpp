// Mutually nearest feature points of one kind (morph/pair_nearest_points.h).
#include "morph/pair_nearest_points.h"

#include <limits>

#include "common/errors.h"

namespace paramorph::morph {

PointPairs pair_nearest_points(const MatrixX3d& PA, const std::vector<int>& kinds_a,
                               const MatrixX3d& PB, const std::vector<int>& kinds_b,
                               double max_distance) {
  PM_REQUIRE(Index(kinds_a.size()) == PA.rows() && Index(kinds_b.size()) == PB.rows(), InvalidInputError,
             "one kind per feature point expected");
  const Index na = Index(PA.rows()), nb = Index(PB.rows());
  const double inf = std::numeric_limits<double>::infinity();
  std::vector<Index> nearest_a(na, -1), nearest_b(nb, -1);
  std::vector<double> best_a(na, inf), best_b(nb, inf);
  for (Index p = 0; p < na; ++p)
    for (Index q = 0; q < nb; ++q) {
      if (kinds_a[p] != kinds_b[q]) continue;
      const double d = (PA.row(p) - PB.row(q)).norm();
      if (d > max_distance) continue;
      if (d < best_a[p]) best_a[p] = d, nearest_a[p] = q;
      if (d < best_b[q]) best_b[q] = d, nearest_b[q] = p;
    }
  PointPairs out;
  for (Index p = 0; p < na; ++p)
    if (nearest_a[p] >= 0 && nearest_b[nearest_a[p]] == p) {
      out.pairs.push_back({p, nearest_a[p]});
      out.distances.push_back(best_a[p]);
    }
  return out;
}

}  // namespace paramorph::morph
