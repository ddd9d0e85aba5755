#include "param/spherical/balanced_sphere_map.h"

#include <algorithm>
#include <cmath>

#include <Eigen/Geometry>

#include "common/errors.h"
#include "mesh/simplify.h"
#include "mesh/validate.h"
#include "param/spherical/map_through_proxy.h"
#include "param/spherical/sphere_map.h"
#include "param/spherical/sphere_map_barrier.h"
#include "param/spherical/untangle_sphere_map.h"

namespace paramorph::spherical {

namespace {

VectorXd triple_products(const MatrixX3d& X, const MatrixX3i& F) {
  VectorXd det(F.rows());
  for (Index f = 0; f < F.rows(); ++f) det[f] = X.row(F(f, 0)).dot(X.row(F(f, 1)).cross(X.row(F(f, 2))));
  return det;
}

/// The coarsest level's start: its conformal map (uniform weights where the
/// cotangent start folds), with faces squeezed to rounding pushed open by a
/// log barrier so the isometric energy is finite.
MatrixX3d coarsest_start(const MatrixX3d& V, const MatrixX3i& F) {
  MatrixX3d X;
  try {
    X = sphere_map(V, F).positions;
  } catch (const ComputeError&) {
    SphereMapOptions uniform;
    uniform.weights = Weights::Barycentric;
    X = sphere_map(V, F, uniform).positions;
  }
  const VectorXd det = triple_products(X, F);
  const double mean = det.mean();
  if (det.minCoeff() > 1e-10 * mean) return X;
  SphereBarrierOptions open;
  open.epsilon = 1e-8 * mean;
  open.mu_start = open.mu_end = mean;
  open.max_steps = 2000;
  const SphereBarrierResult opened = sphere_map_barrier(F, X, X, open);
  PM_REQUIRE(opened.opening_rounds == 0 || opened.rounds > 0, ComputeError,
             "balanced sphere map: the coarsest level's conformal map could not be opened");
  return opened.positions;
}

}  // namespace

BalancedSphereResult balanced_sphere_map(const MatrixX3d& V, const MatrixX3i& F, const BalancedSphereOptions& o,
                                         Progress* progress) {
  validate_arrays(V, F);
  require_closed_genus0(validate(TriMesh(V, F)));
  PM_REQUIRE(o.coarsest_faces >= 4 && std::isfinite(o.level_ratio) && o.level_ratio > 1, InvalidInputError,
             "coarsest_faces >= 4 and level_ratio > 1");
  struct Level {
    MatrixX3d V;
    MatrixX3i F;
  };
  std::vector<Level> levels{{V, F}};
  while (levels.back().F.rows() > o.coarsest_faces) {
    const Index target = std::max(o.coarsest_faces, Index(double(levels.back().F.rows()) / o.level_ratio));
    SimplifiedMesh coarse = simplify(levels.back().V, levels.back().F, target);
    if (coarse.F.rows() >= levels.back().F.rows()) break;  // nothing more may collapse
    levels.push_back({std::move(coarse.V), std::move(coarse.F)});
  }
  BalancedSphereResult result;
  for (auto level = levels.rbegin(); level != levels.rend(); ++level) result.level_faces.push_back(Index(level->F.rows()));

  const double share = 1.0 / double(levels.size());
  MatrixX3d X;
  for (std::size_t k = levels.size(); k-- > 0;) {
    const Level& level = levels[k];
    const double done = double(levels.size() - 1 - k) * share;
    ProgressWindow window(progress, done, done + share);
    if (k + 1 == levels.size()) {
      X = coarsest_start(level.V, level.F);
    } else {
      const Level& coarser = levels[k + 1];
      X = map_through_proxy(level.V, coarser.V, coarser.F, X);
      const SphereUntangleResult untangled = untangle_sphere_map(level.V, level.F, X, std::vector<char>(std::size_t(level.V.rows()), 0));
      PM_REQUIRE(untangled.folded == 0, ComputeError, "balanced sphere map: ", untangled.folded, " of ",
                 untangled.folded_before, " faces stay folded where the level of ", level.F.rows(),
                 " faces was read off the level of ", coarser.F.rows());
    }
    const IsometricSphereResult relaxed = isometric_sphere_map(level.V, level.F, X, o.isometric, window);
    X = relaxed.positions;
    result.steps += relaxed.steps;
    result.energy = relaxed.energy;
  }
  result.positions = X;
  if (progress) progress->report(1.0, "balanced sphere map");
  return result;
}

}  // namespace paramorph::spherical
