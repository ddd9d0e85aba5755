#include "morph/tip_path_pairs.h"

#include <algorithm>
#include <cmath>

#include "common/errors.h"
#include "features/min_cost_assignment.h"

namespace paramorph::morph {

namespace {

/// Each tip's path as `samples` points at equal arc length from the core,
/// each coordinate relative to the model's area-weighted mean and over its
/// standard deviation: rows of samples x 3 values per tip.
Eigen::MatrixXd sampled_paths(const MatrixX3d& V, const VectorXd& area, const features::ProtrusionTips& tips,
                              int samples) {
  const double total = area.sum();
  const Eigen::RowVector3d mean = (area.transpose() * V) / total;
  Eigen::RowVector3d spread = ((V.rowwise() - mean).array().square().colwise() * area.array()).colwise().sum() / total;
  spread = spread.cwiseSqrt();
  // At least half the widest: a quadruped's width is a quarter of its
  // length, and the core (where the flat average distance is least) wanders
  // across it between two animals; over its own spread that offset outweighed
  // a leg's whole length (lion -> cat: every right pair cost 1-1.9, now 0.6-1.1).
  spread = spread.cwiseMax(0.5 * spread.maxCoeff()).cwiseMax(1e-300);
  Eigen::MatrixXd out(Index(tips.paths.size()), 3 * samples);
  for (std::size_t t = 0; t < tips.paths.size(); ++t) {
    const std::vector<Index>& path = tips.paths[t];
    std::vector<double> length{0.0};
    for (std::size_t k = 1; k < path.size(); ++k)
      length.push_back(length.back() + (V.row(path[k]) - V.row(path[k - 1])).norm());
    std::size_t segment = 0;
    for (int s = 0; s < samples; ++s) {
      const double at = length.back() * double(s) / double(samples - 1);
      while (segment + 2 < path.size() && length[segment + 1] < at) ++segment;
      Eigen::RowVector3d p = V.row(path[segment]);
      if (segment + 1 < path.size()) {
        const double span = length[segment + 1] - length[segment];
        const double u = span > 0 ? std::clamp((at - length[segment]) / span, 0.0, 1.0) : 0.0;
        p = (1 - u) * V.row(path[segment]) + u * V.row(path[segment + 1]);
      }
      out.block(Index(t), 3 * s, 1, 3) = (p - mean).cwiseQuotient(spread);
    }
  }
  return out;
}

}  // namespace

std::vector<TipPathPair> tip_path_pairs(const MatrixX3d& VA, const VectorXd& area_a, const features::ProtrusionTips& tips_a,
                                        const MatrixX3d& VB, const VectorXd& area_b, const features::ProtrusionTips& tips_b,
                                        int samples, double max_cost, const VectorXd& loneliness_a,
                                        const VectorXd& loneliness_b, double mirror_weight) {
  PM_REQUIRE(samples >= 2 && area_a.size() == VA.rows() && area_b.size() == VB.rows() && area_a.sum() > 0 &&
                 area_b.sum() > 0,
             InvalidInputError, "tip_path_pairs: two or more samples and a positive area per vertex row");
  const bool mirrored = loneliness_a.size() > 0 || loneliness_b.size() > 0;
  PM_REQUIRE(!mirrored || (loneliness_a.size() == Index(tips_a.paths.size()) &&
                           loneliness_b.size() == Index(tips_b.paths.size())),
             InvalidInputError, "tip_path_pairs: a loneliness per tip of each model, or none for either");
  PM_REQUIRE(std::isfinite(mirror_weight) && mirror_weight >= 0, InvalidInputError,
             "tip_path_pairs: mirror_weight >= 0");
  std::vector<TipPathPair> out;
  if (tips_a.paths.empty() || tips_b.paths.empty()) return out;
  const Eigen::MatrixXd pa = sampled_paths(VA, area_a, tips_a, samples), pb = sampled_paths(VB, area_b, tips_b, samples);
  Eigen::MatrixXd cost(pa.rows(), pb.rows());
  for (Index i = 0; i < pa.rows(); ++i)
    for (Index j = 0; j < pb.rows(); ++j) {
      cost(i, j) = std::sqrt((pa.row(i) - pb.row(j)).squaredNorm() / samples);
      if (mirrored) cost(i, j) += mirror_weight * std::abs(loneliness_a[i] - loneliness_b[j]);
    }
  const std::vector<Index> assigned = features::min_cost_assignment(cost);
  for (Index i = 0; i < pa.rows(); ++i) {
    const Index j = assigned[std::size_t(i)];
    if (j >= 0 && cost(i, j) < max_cost)
      out.push_back({tips_a.vertices[std::size_t(i)], tips_b.vertices[std::size_t(j)], cost(i, j)});
  }
  std::sort(out.begin(), out.end(), [](const TipPathPair& x, const TipPathPair& y) { return x.cost < y.cost; });
  return out;
}

}  // namespace paramorph::morph
