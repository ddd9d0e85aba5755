#include "morph/pinned_sphere_map.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <map>
#include <set>

#include <Eigen/Geometry>
#include <Eigen/LU>
#include <Eigen/SVD>

#include "common/best_rotation.h"
#include "common/errors.h"
#include "mesh/tri_mesh.h"
#include "mesh/validate.h"
#include "morph/optimize_sphere_map.h"
#include "morph/pin_order.h"
#include "morph/radial_projection.h"
#include "param/spherical/sphere_map_barrier.h"
#include "morph/sphere_warp.h"
#include "param/spherical/untangle_sphere_map.h"

namespace paramorph::morph {

namespace {

/// Triple products above -kRoundoff are not folds (as in optimize_sphere_map).
constexpr double kRoundoff = 1e-13;

MatrixX3d rows_of(const MatrixX3d& X, const std::vector<Index>& rows) {
  MatrixX3d out(Index(rows.size()), 3);
  for (std::size_t k = 0; k < rows.size(); ++k) out.row(Index(k)) = X.row(rows[k]);
  return out;
}

/// Every point moved by the nudge of the pin whose support holds it: pin j
/// moves `from` j onto `to` j and its neighbourhood with it, falling off
/// smoothly to nothing at half the way to the nearest other pin (so the
/// supports do not overlap), or at four times its own move where that is
/// nearer.
MatrixX3d nudge_to_pins(const MatrixX3d& X, const MatrixX3d& from, const MatrixX3d& to) {
  const Index k = from.rows();
  VectorXd radius(k);
  for (Index j = 0; j < k; ++j) {
    double nearest = 2.0;
    for (Index i = 0; i < k; ++i)
      if (i != j) nearest = std::min(nearest, (from.row(i) - from.row(j)).norm());
    radius[j] = std::min(0.5 * nearest, std::max(4.0 * (to.row(j) - from.row(j)).norm(), 1e-12));
  }
  MatrixX3d out = X.rowwise().normalized();
#pragma omp parallel for schedule(static)
  for (Index v = 0; v < X.rows(); ++v) {
    const Eigen::RowVector3d x = out.row(v);
    for (Index j = 0; j < k; ++j) {
      const double r = (x - from.row(j)).norm() / radius[j];
      if (r >= 1) continue;
      const double w = (1 - r * r) * (1 - r * r);  // smooth, 1 at the pin, 0 with its slope at the rim
      const Eigen::RowVector3d move = log_map(from.row(j), to.row(j));
      out.row(v) = exp_map(x, w * (move - move.dot(x) * x));
      break;
    }
  }
  return out;
}

bool fold_free(const MatrixX3d& X, const MatrixX3i& F) {
  for (Index f = 0; f < F.rows(); ++f)
    if (!(X.row(F(f, 0)).dot(X.row(F(f, 1)).cross(X.row(F(f, 2)))) > -kRoundoff)) return false;
  return true;
}

}  // namespace

PinnedSphereResult pinned_sphere_map(const MatrixX3d& V, const MatrixX3i& F, const MatrixX3d& sphere,
                                     const std::vector<Index>& pinned, const MatrixX3d& pins_in,
                                     const PinnedSphereOptions& o, Progress* progress) {
  const auto started = std::chrono::steady_clock::now();
  validate_arrays(V, F);
  const TriMesh mesh(V, F);
  require_closed_genus0(validate(mesh));
  const Index n = V.rows(), k = Index(pinned.size());
  PM_REQUIRE(sphere.rows() == n && sphere.allFinite(), InvalidInputError, "sphere must be a finite (", n,
             ", 3) array, one point per vertex");
  PM_REQUIRE(pins_in.rows() == k && pins_in.allFinite() && (k == 0 || pins_in.rowwise().norm().minCoeff() > 0),
             InvalidInputError, "pins must be a finite, non-zero (", k, ", 3) array, one per pinned vertex");
  PM_REQUIRE(std::isfinite(o.epsilon) && o.epsilon > 0 && o.epsilon < 1 && std::isfinite(o.mu_ratio) &&
                 o.mu_ratio > 0 && o.mu_ratio <= 1 && o.max_steps >= 0 && o.warp_steps > 0,
             InvalidInputError, "epsilon in (0, 1), mu_ratio in (0, 1], max_steps >= 0, warp_steps > 0");
  std::map<Index, Index> pin_of_vertex;
  for (Index j = 0; j < k; ++j) {
    const Index v = pinned[std::size_t(j)];
    PM_REQUIRE(v >= 0 && v < n, InvalidInputError, "pin ", j, ": vertex ", v, " is not a vertex of the mesh (",
               n, " vertices)");
    const auto [at, inserted] = pin_of_vertex.emplace(v, j);
    PM_REQUIRE(inserted, ConstraintError, "pins ", at->second, " and ", j, " both pin vertex ", v);
  }
  // Unit pins are used as given, bit for bit (A's map positions: the overlay
  // then sees one point).
  MatrixX3d pins = pins_in;
  for (Index j = 0; j < k; ++j)
    if (std::abs(pins.row(j).norm() - 1) > 1e-12) pins.row(j).normalize();
  for (Index i = 0; i < k; ++i)
    for (Index j = i + 1; j < k; ++j)
      PM_REQUIRE((pins.row(i) - pins.row(j)).norm() > 1e-12, ConstraintError, "pins ", i, " and ", j,
                 " (vertices ", pinned[std::size_t(i)], " and ", pinned[std::size_t(j)],
                 ") must go to the same point of the sphere");

  // A face whose three corners are all pinned cannot move: its pins must
  // keep it turned the right way.
  for (Index f = 0; f < F.rows(); ++f) {
    const auto a = pin_of_vertex.find(F(f, 0)), b = pin_of_vertex.find(F(f, 1)), c = pin_of_vertex.find(F(f, 2));
    if (a == pin_of_vertex.end() || b == pin_of_vertex.end() || c == pin_of_vertex.end()) continue;
    PM_REQUIRE(pins.row(a->second).dot(pins.row(b->second).cross(pins.row(c->second))) > 0, ConstraintError,
               "pins ", a->second, ", ", b->second, " and ", c->second, " pin the corners of face ", f,
               " turned over");
  }
  VectorXd weights = VectorXd::Ones(n);
  if (o.weights) {
    weights = *o.weights;
    PM_REQUIRE(weights.size() == n && weights.allFinite() && (weights.array() >= 0).all() && weights.sum() > 0,
               InvalidInputError, "weights must be ", n, " finite non-negative numbers, not all 0");
  }
  MatrixX3d start = sphere.rowwise().normalized();
  // The start is needed (and must be fold-free) only where the targets
  // cannot be untangled (step 2).
  std::vector<Index> start_folds;
  for (Index f = 0; f < F.rows(); ++f)
    if (!(start.row(F(f, 0)).dot(start.row(F(f, 1)).cross(start.row(F(f, 2)))) > -kRoundoff))
      start_folds.push_back(f);
  PinnedSphereResult result;
  MatrixX3d target = o.target ? *o.target : radial_projection(V, F);
  PM_REQUIRE(target.rows() == n && target.allFinite(), InvalidInputError, "target must be a finite (", n,
             ", 3) array");
  for (Index v = 0; v < n; ++v) {
    const double length = target.row(v).norm();
    target.row(v) = length > 0 ? (target.row(v) / length).eval() : start.row(v);
  }

  // The pins' order: on B's own (fold-free, orientation-preserving) map
  // against the pins. A mirror image cannot be reached without turning the
  // map inside out.
  if (k >= 3) {
    const PinOrder order = pin_order(rows_of(start_folds.empty() ? start : target, pinned), pins);
    PM_REQUIRE(!order.mirrored(), ConstraintError, mirrored_pins_message(order));
  }

  // 1. Targets turned to the pins, then warped onto them: targets built
  // around the pins (a correspondence read through proxies misses a pin by
  // about a proxy's edge) get a local nudge round each pin; others (a
  // radial projection) the smooth global warp.
  double largest_miss = 0;
  for (Index j = 0; j < k; ++j)
    largest_miss = std::max(largest_miss, (target.row(pinned[std::size_t(j)]).normalized() - pins.row(j)).norm());
  if (k && largest_miss < o.local_nudge) {
    result.rotation = Eigen::Matrix3d::Identity();
    target = nudge_to_pins(target, rows_of(target, pinned), pins);
  } else if (k) {
    result.rotation = best_rotation(rows_of(target, pinned), pins, VectorXd::Ones(k));
    target = target * result.rotation;
    target = warp_points(target, rows_of(target, pinned), pins, o.warp_steps);
  } else {
    result.rotation = Eigen::Matrix3d::Identity();
  }
  for (Index j = 0; j < k; ++j) target.row(pinned[std::size_t(j)]) = pins.row(j);
  result.target = target;
  const MatrixX3d pull = weights.asDiagonal() * target;

  // 2. Where the targets themselves fold little (a correspondence carried
  // through sphere maps: only faces across kinks of the carrying map), they
  // are the start, untangled by the barrier's opening rounds: far fewer
  // steps than bringing a distant map to them. Else the start map is turned
  // to the targets, then flowed onto the pins.
  {
    const VectorXd target_det = face_triple_products(target, F);
    const Index target_folds = Index((target_det.array() <= 0).count());
    if (double(target_folds) <= o.max_target_folds * double(F.rows())) {
      MatrixX3d untangled = target;
      std::vector<char> fixed(std::size_t(n), 0);
      for (const Index v : pinned) fixed[std::size_t(v)] = 1;
      result.untangle = spherical::untangle_sphere_map(V, F, untangled, fixed);
      result.start_from_target = result.untangle.folded == 0;
      if (result.start_from_target) start = untangled;
    }
  }
  if (!result.start_from_target) {
    if (o.fallback_start) {
      start = o.fallback_start().rowwise().normalized();
      start_folds.clear();
      for (Index f = 0; f < F.rows(); ++f)
        if (!(start.row(F(f, 0)).dot(start.row(F(f, 1)).cross(start.row(F(f, 2)))) > -kRoundoff))
          start_folds.push_back(f);
    }
    PM_REQUIRE(start_folds.empty(), InvalidInputError, "the targets could not be untangled and the start map folds ",
               start_folds.size(), " faces (", format_indices(start_folds), "): give a fold-free sphere map");
    start = start * best_rotation(start, target, weights);
  }
  const VectorXd start_det = face_triple_products(start, F);
  const double mean_det = std::abs(start_det.mean());
  const double pull_scale = pull.rowwise().norm().mean();
  spherical::SphereBarrierOptions barrier;
  barrier.epsilon = o.epsilon * mean_det;
  barrier.mu_start = mean_det * pull_scale;
  barrier.fixed = pinned;
  ProgressWindow flow_progress(progress, 0.0, 0.3);
  if (progress) progress->report(0.0, "pinned sphere map");
  if (k && !result.start_from_target) {
    const MatrixX3d from = rows_of(start, pinned);
    MatrixX3d at = from;
    double t = 0, h = 1.0 / 16;
    auto pins_at = [&](double time) {
      MatrixX3d P(k, 3);
      for (Index j = 0; j < k; ++j) P.row(j) = time >= 1 ? pins.row(j) : slerp(from.row(j), pins.row(j), time);
      return P;
    };
    MatrixX3d trial(n, 3);
    while (t < 1) {
      h = std::min(h, 1 - t);
      const double next_t = t + h >= 1 - 1e-12 ? 1.0 : t + h;
      const MatrixX3d next = pins_at(next_t);
      MatrixX3d moves(k, 3);
      for (Index j = 0; j < k; ++j) moves.row(j) = log_map(at.row(j), next.row(j));
      const SphereWarpField field(at, moves);
#pragma omp parallel for schedule(static)
      for (Index v = 0; v < n; ++v) trial.row(v) = exp_map(start.row(v), field(start.row(v)));
      for (Index j = 0; j < k; ++j) trial.row(pinned[std::size_t(j)]) = next.row(j);
      if (fold_free(trial, F)) {
        start.swap(trial);
        at = next;
        t = next_t;
        ++result.flow_steps;
        h = std::min(0.25, 2 * h);
        flow_progress.report(t, "pinned sphere map: moving the pins");
        continue;
      }
      ++result.flow_rejected;
      h *= 0.5;
      if (h >= 1.0 / 4096) continue;
      // Stalled: relax the free vertices towards the targets warped to
      // where the pins are now, then go on.
      if (result.flow_relaxations >= 12) {
        // Name the pins nearest the faces the last step would fold.
        std::vector<std::pair<double, Index>> near;
        for (Index f = 0; f < F.rows(); ++f) {
          if (trial.row(F(f, 0)).dot(trial.row(F(f, 1)).cross(trial.row(F(f, 2)))) > -kRoundoff) continue;
          for (Index j = 0; j < k; ++j) near.emplace_back((at.row(j) - trial.row(F(f, 0))).norm(), j);
        }
        std::sort(near.begin(), near.end());
        std::vector<Index> named;
        for (const auto& [distance, j] : near)
          if (std::find(named.begin(), named.end(), j) == named.end() && named.size() < 4) named.push_back(j);
        throw ConstraintError(detail::concat(
            "the pins cannot all be reached without folding the map (stalled at ", int(100 * t),
            "% of the way, near pins ", format_indices(named), "): pins very close together on one mesh and "
            "further apart on the other, or crossing each other's way, are the usual cause"));
      }
      ++result.flow_relaxations;
      spherical::SphereBarrierOptions relax = barrier;
      relax.mu_end = 1e-2 * relax.mu_start;
      relax.max_steps = 40;
      relax.epsilon = std::min(barrier.epsilon, 0.5 * std::max(face_triple_products(start, F).minCoeff(), 0.0));
      if (!(relax.epsilon > 0)) relax.epsilon = 1e-3 * barrier.epsilon;
      const MatrixX3d here = warp_points(target, rows_of(target, pinned), at, o.warp_steps);
      const spherical::SphereBarrierResult relaxed =
          spherical::sphere_map_barrier(F, weights.asDiagonal() * here, start, relax, ProgressWindow());
      start = relaxed.positions;
      h = 1.0 / 16;
    }
    for (Index j = 0; j < k; ++j) start.row(pinned[std::size_t(j)]) = pins.row(j);
  }

  // 3. The barrier path with the pins fixed. As in optimize_sphere_map, the
  // bound is lowered to half the start's smallest face (faces squeezed to
  // rounding aside: the barrier opens those), so the path needs no opening
  // rounds for faces the start keeps small on purpose (a conformal map's
  // limbs: 43% of the faces under 2 epsilon on a four-limbed blob, 194
  // opening steps against none).
  {
    const VectorXd det = face_triple_products(start, F);
    for (Index f = 0; f < F.rows(); ++f)
      if (det[f] > 2 * kRoundoff) barrier.epsilon = std::min(barrier.epsilon, 0.5 * det[f]);
    // ...but not below the floor: faces under it are opened.
    barrier.epsilon = std::max(barrier.epsilon, o.min_epsilon * mean_det);
  }
  // The barrier scaled per face to its target's size: a fine B under a
  // squeezed part of A's map must get as small as its target there, which a
  // barrier sized for the mean face does not let it (measured: a 70k-face
  // bunny onto its 6k-face copy, distortion 0.51 at the targets, 1.77 after
  // the path with one weight, mean 0.2 degrees off its targets).
  {
    const VectorXd target_det = face_triple_products(target, F);
    const double mean = std::max(target_det.mean(), 1e-300);
    barrier.face_weights.resize(F.rows());
    for (Index f = 0; f < F.rows(); ++f)
      barrier.face_weights[f] = std::clamp(target_det[f] / mean, 1e-6, 1.0);
  }
  barrier.mu_end = o.mu_ratio * barrier.mu_start;
  barrier.max_steps = o.max_steps;
  if (o.max_steps > 0 && (!result.start_from_target || o.relax_untangled)) {
    const spherical::SphereBarrierResult solved = spherical::sphere_map_barrier(F, pull, start, barrier, ProgressWindow(progress, 0.3, 1.0));
    result.positions = solved.positions;
    result.barrier_steps = solved.steps;
  } else {
    result.positions = start;
  }
  result.epsilon = barrier.epsilon;
  const VectorXd det = face_triple_products(result.positions, F);
  result.min_triple = det.minCoeff();
  result.objective = (pull.array() * result.positions.array()).sum();
  PM_REQUIRE(result.min_triple > 0, ComputeError, "pinned_sphere_map: ", (det.array() <= 0).count(),
             " faces left folded");
  if (progress) progress->report(1.0, "pinned sphere map");
  result.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
  return result;
}

}  // namespace paramorph::morph
