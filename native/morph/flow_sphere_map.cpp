#include "morph/flow_sphere_map.h"

#include <algorithm>
#include <cmath>

#include <Eigen/Geometry>

#include "common/errors.h"
#include "common/parallel.h"
#include "mesh/tri_mesh.h"
#include "morph/sphere_warp.h"
#include "param/spherical/relax_sphere_map.h"
#include "param/spherical/smooth_sphere_map.h"

namespace paramorph::morph {

namespace {

constexpr double kRoundoff = 1e-13;  ///< triple products above -kRoundoff are not folds

Index first_fold(const MatrixX3d& X, const MatrixX3i& F) {
  for (Index f = 0; f < F.rows(); ++f)
    if (!(X.row(F(f, 0)).dot(X.row(F(f, 1)).cross(X.row(F(f, 2)))) > -kRoundoff)) return f;
  return -1;
}

}  // namespace

SphereFlowResult flow_sphere_map(const MatrixX3i& F, const MatrixX3d& X, const MatrixX3d& from, const MatrixX3d& to,
                                 const std::vector<std::pair<Index, Index>>& pinned, const SphereFlowOptions& o,
                                 ProgressWindow progress) {
  const Index n = X.rows(), k = from.rows();
  PM_REQUIRE(to.rows() == k && from.allFinite() && to.allFinite(), InvalidInputError,
             "flow_sphere_map: from and to must be finite and of one length");
  PM_REQUIRE(o.first_step > 0 && o.first_step <= 1 && o.smallest_step > 0 && o.smallest_step <= o.first_step,
             InvalidInputError, "flow_sphere_map: 0 < smallest_step <= first_step <= 1");
  for (const auto& [v, j] : pinned)
    PM_REQUIRE(v >= 0 && v < n && j >= 0 && j < k, InvalidInputError, "flow_sphere_map: pinned vertex ", v,
               " or point ", j, " out of range");
  PM_REQUIRE(F.size() == 0 || (F.minCoeff() >= 0 && F.maxCoeff() < n), InvalidInputError,
             "flow_sphere_map: faces index vertices outside X (", n, " rows)");
  PM_REQUIRE(!o.model || o.model->rows() == n, InvalidInputError, "flow_sphere_map: the model has ",
             o.model ? o.model->rows() : 0, " vertices, X ", n);
  SphereFlowResult result;
  result.positions = X;
  MatrixX3d& Y = result.positions;
  for (const auto& [v, j] : pinned) Y.row(v) = from.row(j);
  PM_REQUIRE(first_fold(Y, F) < 0, InvalidInputError, "flow_sphere_map: the start folds face ", first_fold(Y, F));
  if (k == 0) {
    result.reached = 1;
    return result;
  }
  auto points_at = [&](double time) {
    MatrixX3d P(k, 3);
    for (Index j = 0; j < k; ++j) P.row(j) = time >= 1 ? to.row(j) : slerp(from.row(j), to.row(j), time);
    return P;
  };
  MatrixX3d at = from, trial(n, 3), moves(k, 3);
  double t = 0, h = o.first_step;
  const TriMesh mesh(X, F);
  std::vector<char> fixed(std::size_t(n), 0);
  for (const auto& [v, j] : pinned) fixed[std::size_t(v)] = 1;
  int repairs_here = 0;
  while (t < 1) {
    progress.report(t, "carrying the map");  // also between repairs and halvings: cancel is honoured there too
    h = std::min(h, 1 - t);
    const double next_t = t + h >= 1 - 1e-12 ? 1.0 : t + h;
    const MatrixX3d next = points_at(next_t);
    for (Index j = 0; j < k; ++j) moves.row(j) = log_map(at.row(j), next.row(j));
    const SphereWarpField field(at, moves);
#pragma omp parallel for schedule(static) if (worth_parallel(n))
    for (Index v = 0; v < n; ++v) trial.row(v) = exp_map(Y.row(v), field(Y.row(v)));
    for (const auto& [v, j] : pinned) trial.row(v) = next.row(j);
    const Index folded = first_fold(trial, F);
    if (folded < 0) {
      Y.swap(trial);
      at = next;
      t = next_t;
      ++result.steps;
      h = std::min(0.25, 2 * h);
      repairs_here = 0;
      progress.report(t, "carrying the map");
      continue;
    }
    // A face the step would turn over is most often a sliver (left by an
    // untangling) that any shear flips: smooth round it, then try again.
    if (repairs_here < o.repairs_per_step) {
      std::vector<Index> folding;
      for (Index f = 0; f < F.rows(); ++f)
        if (!(trial.row(F(f, 0)).dot(trial.row(F(f, 1)).cross(trial.row(F(f, 2)))) > -kRoundoff)) folding.push_back(f);
      ++repairs_here;
      ++result.repairs;
      if (spherical::smooth_sphere_map(mesh, Y, spherical::vertices_near_faces(mesh, folding, 1 + repairs_here), fixed) > 0) continue;
    }
    ++result.halved;
    h *= 0.5;
    if (h >= o.smallest_step) continue;
    if (o.model && result.relaxations < o.relaxations) {
      ++result.relaxations;
      spherical::RelaxPoorOptions relax;
      relax.threshold = 10;  // looser than for a fresh map: the flow is what squeezed them
      spherical::relax_poor_regions(*o.model, F, Y, fixed, relax);
      h = o.first_step;
      repairs_here = 0;
      continue;
    }
    // Stalled: the points nearest the folding faces.
    std::vector<std::pair<double, Index>> near;
    for (Index f = 0; f < F.rows(); ++f) {
      if (trial.row(F(f, 0)).dot(trial.row(F(f, 1)).cross(trial.row(F(f, 2)))) > -kRoundoff) continue;
      for (Index j = 0; j < k; ++j) near.emplace_back((at.row(j) - trial.row(F(f, 0))).norm(), j);
    }
    std::sort(near.begin(), near.end());
    for (const auto& [distance, j] : near)
      if (std::find(result.blocking.begin(), result.blocking.end(), j) == result.blocking.end() &&
          result.blocking.size() < 4)
        result.blocking.push_back(j);
    break;
  }
  result.reached = t;
  return result;
}

}  // namespace paramorph::morph
