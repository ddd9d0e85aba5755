#include "morph/tip_assignments.h"

#include <algorithm>
#include <cmath>
#include <map>

#include "common/best_rotation.h"

namespace paramorph::morph {

std::vector<TipAssignment> tip_assignments(const MatrixX3d& tips_a, const MatrixX3d& tips_b, double max_angle,
                                           std::size_t max_count) {
  const Index m = tips_a.rows(), l = tips_b.rows();
  std::map<std::vector<std::array<Index, 2>>, double> best;  // assignment -> smallest mean angle
  Eigen::MatrixXd angle(l, m);
  for (Index i = 0; i < m; ++i)
    for (Index j = 0; j < m; ++j) {
      if (i == j) continue;
      for (Index k = 0; k < l; ++k)
        for (Index h = 0; h < l; ++h) {
          if (k == h) continue;
          MatrixX3d from(2, 3), to(2, 3);
          from << tips_b.row(k), tips_b.row(h);
          to << tips_a.row(i), tips_a.row(j);
          const Eigen::Matrix3d R = best_rotation(from, to);
          for (Index b = 0; b < l; ++b) {
            const Eigen::RowVector3d turned = tips_b.row(b) * R;
            for (Index a = 0; a < m; ++a) angle(b, a) = std::acos(std::clamp(turned.dot(tips_a.row(a)), -1.0, 1.0));
          }
          std::vector<std::array<Index, 2>> pairs;
          double sum = 0;
          for (Index b = 0; b < l; ++b) {
            Index a;
            const double nearest = angle.row(b).minCoeff(&a);
            Index back;
            angle.col(a).minCoeff(&back);
            if (nearest < max_angle && back == b) {
              pairs.push_back({a, b});
              sum += nearest;
            }
          }
          if (pairs.size() < 2) continue;
          std::sort(pairs.begin(), pairs.end());
          const double mean = sum / double(pairs.size());
          const auto [at, inserted] = best.emplace(pairs, mean);
          if (!inserted) at->second = std::min(at->second, mean);
        }
    }
  std::vector<TipAssignment> out;
  for (const auto& [pairs, mean] : best) out.push_back({pairs, mean});
  std::sort(out.begin(), out.end(), [](const TipAssignment& x, const TipAssignment& y) {
    return x.pairs.size() != y.pairs.size() ? x.pairs.size() > y.pairs.size() : x.mean_angle < y.mean_angle;
  });
  if (out.size() > max_count) out.resize(max_count);
  return out;
}

}  // namespace paramorph::morph
