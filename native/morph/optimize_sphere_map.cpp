#include "morph/optimize_sphere_map.h"

#include <chrono>
#include <cmath>
#include <exception>

#include <Eigen/Geometry>
#include <Eigen/SVD>

#include "common/best_rotation.h"
#include "common/errors.h"
#include "mesh/validate.h"
#include "morph/ipopt_polish.h"
#include "morph/radial_projection.h"
#include "param/spherical/sphere_map_barrier.h"
#include "morph/sphere_map_nlp.h"

namespace paramorph::morph {

namespace {

/// Decades of mu the barrier path descends when it is the whole solve (no
/// Ipopt). The path's point is within about mu x #F of the optimum in the
/// objective (each face's log term), so 8 decades from mu ~ the mean triple
/// product leave a gap ~1e-7 of #V; tests/bench/morph.py measures it against Ipopt.
constexpr double kBarrierOnlyDecades = 8.0;

/// The sphere's rows as unit vectors, whatever their length: a map given on a
/// sphere of radius 1e200 or 1e-200 is the same map. Eigen's normalized()
/// squares the coordinates, which overflows to a zero row at 1e200 (then a
/// barrier on all-zero triple products failed as a ComputeError) and
/// underflows at 1e-200; stableNorm() scales first. A row of zeros has no
/// direction: InvalidInputError naming it.
MatrixX3d unit_directions(const MatrixX3d& sphere) {
  MatrixX3d unit(sphere.rows(), 3);
  std::vector<paramorph::Index> pointless;
  for (paramorph::Index v = 0; v < sphere.rows(); ++v) {
    const double length = sphere.row(v).stableNorm();
    if (length > 0 && std::isfinite(length))
      unit.row(v) = sphere.row(v) / length;
    else
      pointless.push_back(v);
  }
  PM_REQUIRE(pointless.empty(), InvalidInputError, "sphere rows ", format_indices(pointless),
             " are zero: each vertex needs a direction from the sphere's centre");
  return unit;
}

}  // namespace

VectorXd face_triple_products(const MatrixX3d& X, const MatrixX3i& F) {
  VectorXd det(F.rows());
  for (paramorph::Index f = 0; f < F.rows(); ++f)
    det[f] = X.row(F(f, 0)).dot(X.row(F(f, 1)).cross(X.row(F(f, 2))));
  return det;
}

OptimizeSphereResult optimize_sphere_map(const MatrixX3d& V, const MatrixX3i& F,
                                         const MatrixX3d& sphere,
                                         const OptimizeSphereOptions& o, Progress* progress) {
  const auto started = std::chrono::steady_clock::now();
  validate_arrays(V, F);
  const TriMesh mesh(V, F);
  require_closed_genus0(validate(mesh));
  PM_REQUIRE(sphere.rows() == V.rows() && sphere.allFinite(), InvalidInputError,
             "sphere must be a finite (", V.rows(), ", 3) array, one point per vertex");
  PM_REQUIRE(std::isfinite(o.epsilon) && o.epsilon > 0 && o.epsilon < 1, InvalidInputError,
             "epsilon is a share of the mean face triple product in (0, 1), got ", o.epsilon);
  PM_REQUIRE(o.max_iterations > 0 && o.polish_iterations > 0 && std::isfinite(o.tol) && o.tol > 0,
             InvalidInputError, "max_iterations, polish_iterations and tol must be positive");
  PM_REQUIRE(o.solver != SphereSolver::Ipopt || ipopt_available(), InvalidInputError,
             "solver \"ipopt\" asked for, but this build of paramorph has no Ipopt (CMake option "
             "PARAMORPH_WITH_IPOPT; the released wheel leaves it out): use \"barrier\" or \"auto\"");
  PM_REQUIRE(o.warm_start || o.solver != SphereSolver::Barrier, InvalidInputError,
             "warm_start = false runs Ipopt alone; the barrier solver always follows its path");
  PM_REQUIRE(o.max_barrier_steps > 0, InvalidInputError, "max_barrier_steps must be positive");
  VectorXd weights = VectorXd::Ones(V.rows());
  if (o.weights) {
    weights = *o.weights;
    PM_REQUIRE(weights.size() == V.rows() && weights.allFinite() && (weights.array() >= 0).all() &&
                   weights.sum() > 0,
               InvalidInputError, "weights must be ", V.rows(),
               " finite non-negative numbers, one per vertex, not all 0");
  }
  // The maximiser does not change with a positive scale of the weights, but
  // the barrier's mu and Ipopt's tolerances are set for weights near 1:
  // weights of 1e200 left the feasible set. Solve with the largest at 1 and
  // report the objectives in the caller's scale.
  const double weight_scale = weights.maxCoeff();
  weights /= weight_scale;
  MatrixX3d start = unit_directions(sphere);
  const VectorXd start_det = face_triple_products(start, F);
  // Long protrusions squeeze a conformal map's faces to triple products of
  // the order of rounding (1e-17); those count as degenerate, not folded.
  std::vector<paramorph::Index> folded;
  for (paramorph::Index f = 0; f < F.rows(); ++f)
    if (!(start_det[f] > -kTripleRoundoff)) folded.push_back(f);
  PM_REQUIRE(folded.empty(), InvalidInputError, "the start map folds ", folded.size(),
             " faces (", format_indices(folded), "): give a fold-free sphere map");

  MatrixX3d target;
  if (o.target) {
    target = *o.target;
    PM_REQUIRE(target.rows() == V.rows() && target.allFinite(), InvalidInputError,
               "target must be a finite (", V.rows(), ", 3) array");
  } else {
    target = radial_projection(V, F);
  }
  for (paramorph::Index v = 0; v < target.rows(); ++v) {
    const double length = target.row(v).norm();
    target.row(v) = length > 0 ? (target.row(v) / length).eval() : start.row(v);
  }
  // The objective sum_i w_i t_i . v_i: what both stages see is the weighted
  // target p_i = w_i t_i.
  const MatrixX3d pull = weights.asDiagonal() * target;

  // A sphere map is defined up to a rotation; turn the start to face the
  // targets best (weighted Kabsch) so the solvers do not spend their
  // iterations rotating. A rotation keeps every triple product.
  start = start * best_rotation(start, pull);  // the weights are in pull

  OptimizeSphereResult result;
  // The bound: a share of the mean triple product, but never above half the
  // start's smallest positive one, so a clean start is strictly feasible; a
  // start with degenerate faces begins infeasible there and the solvers open them.
  const double mean_det = start_det.mean();
  result.epsilon = o.epsilon * mean_det;
  if (start_det.minCoeff() > kTripleRoundoff) result.epsilon = std::min(result.epsilon, 0.5 * start_det.minCoeff());
  SphereMapNlp nlp(mesh, pull);
  result.start_objective = -weight_scale * nlp.objective(start.data());
  if (progress) progress->report(0.0, "optimize sphere map");

  // Warm start (sphere_map_barrier): the log-barrier path from mu = mean
  // triple product x mean pull (the barrier's push on a typical face about
  // matching the pull on its corners) down 4 decades, then Ipopt from there
  // with its multipliers. Measured on spot (5.9k faces): 52 Newton steps
  // (1.5 s) and 4 Ipopt iterations (0.5 s) against 100 cold Ipopt iterations
  // (8 s); stopping the path a decade earlier left Ipopt 21-24 iterations
  // (3.2 s), starting it 1 or 2 decades higher changed little (56, 91 steps).
  // A start with faces squeezed to rounding is opened first (see
  // sphere_map_barrier); if the barrier's steps run out before its path
  // begins, Ipopt starts cold from the point reached, with all its iterations.
  // Without Ipopt (solver Barrier, or a build without it) the path goes on
  // down kBarrierOnlyDecades and its end is the result (see the option).
  const bool use_ipopt = o.solver == SphereSolver::Ipopt || (o.solver == SphereSolver::Auto && ipopt_available());
  spherical::SphereBarrierResult barrier;
  VectorXd multipliers;
  if (!use_ipopt || o.warm_start) {
    const double pull_scale = pull.rowwise().norm().mean();
    spherical::SphereBarrierOptions barrier_options;
    barrier_options.epsilon = result.epsilon;
    barrier_options.mu_start = mean_det * pull_scale;
    barrier_options.mu_end = (use_ipopt ? 1e-4 : std::pow(10.0, -kBarrierOnlyDecades)) * barrier_options.mu_start;
    if (!use_ipopt) barrier_options.max_steps = o.max_barrier_steps;
    barrier = spherical::sphere_map_barrier(F, pull, start, barrier_options,
                                            ProgressWindow(progress, 0.0, use_ipopt ? 0.6 : 1.0));
    start = barrier.positions;
    result.barrier_steps = barrier.steps;
    if (!use_ipopt)
      result.status = barrier.rounds == 0 ? "Barrier_Opening" : barrier.centred ? "Barrier_Converged" : "Barrier_Point";
  }
  const bool warm = use_ipopt && barrier.rounds > 0;  // on the barrier's path: Ipopt starts from it
  if (warm) {
    // Ipopt's multipliers on the barrier's central path: y_f = -mu / (det_f - b_f)
    // for the faces and, from the radial part of stationarity,
    // lambda_i = (p_i . v_i - sum_f y_f det_f) / 2 for the spheres.
    const paramorph::Index n = paramorph::Index(V.rows()), m = paramorph::Index(F.rows());
    multipliers.setZero(n + m);
    const VectorXd det = face_triple_products(start, F);
    for (paramorph::Index v = 0; v < n; ++v) multipliers[v] = 0.5 * pull.row(v).dot(start.row(v));
    for (paramorph::Index f = 0; f < m; ++f) {
      const double y = -barrier.mu / (det[f] - barrier.bounds[f]);
      multipliers[n + f] = y;
      for (int k = 0; k < 3; ++k) multipliers[F(f, k)] -= 0.5 * y * det[f];
    }
  }

  result.positions = start;  // without Ipopt, the barrier's end is the result
  if (use_ipopt && warm && !barrier.centred) {
    // The path's last round stopped at its step cap, away from the centre:
    // Ipopt did not finish from such points within polish_iterations
    // (tentacle_sphere 0.9k-62.7k faces, the closed bunny: every run ended
    // Maximum_Iterations_Exceeded and took about as long as the barrier).
    // The barrier's point stands: every face above epsilon.
    result.status = "Barrier_Point";
  } else if (use_ipopt) {
    // From the barrier's path (every face above epsilon) Ipopt only polishes.
    const bool polish = warm;
    IpoptPolishOptions ipopt;
    ipopt.epsilon = result.epsilon;
    ipopt.max_iterations = polish ? std::min(o.max_iterations, o.polish_iterations) : o.max_iterations;
    ipopt.tol = o.tol;
    ipopt.warm = warm;
    ipopt.barrier_mu = barrier.mu;
    const IpoptPolishResult run =
        ipopt_polish(nlp, start, multipliers, ipopt, ProgressWindow(progress, warm ? 0.6 : 0.0, 1.0));
    result.status = run.status;
    result.iterations = run.iterations;
    result.used_ipopt = true;

    if (!run.solution.empty()) {
      MatrixX3d solved = Eigen::Map<const MatrixX3d>(run.solution.data(), V.rows(), 3);
      solved.rowwise().normalize();  // on the sphere to rounding, exactly
      // Ipopt's last point replaces the start only if it leaves no more faces at
      // or below 0 than the start had: a failed run (e.g. Restoration_Failed on
      // a 51k-face Suzanne) can end with a face at -1e-14..0, which the barrier's
      // strictly feasible point does not have.
      const VectorXd solved_det = face_triple_products(solved, F);
      const auto at_or_below_zero = [](const VectorXd& d) { return (d.array() <= 0).count(); };
      // After a polish, also no worse than the barrier's point, which has every
      // face above epsilon: Ipopt may stop early (iteration cap, failure) below
      // where it began, or with faces under epsilon by its own absolute
      // tolerance (a 51k-face Suzanne: 0.38 epsilon after 15 iterations).
      const bool no_worse = !polish || (nlp.objective(solved.data()) <= nlp.objective(start.data()) &&
                                        solved_det.minCoeff() >= 0.9 * result.epsilon);
      if (solved_det.minCoeff() > -kTripleRoundoff &&
          at_or_below_zero(solved_det) <= at_or_below_zero(face_triple_products(start, F)) && no_worse)
        result.positions = solved;
    }
  }
  const VectorXd det = face_triple_products(result.positions, F);
  result.min_triple = det.minCoeff();
  result.flipped = paramorph::Index((det.array() <= 0).count());
  result.objective = -weight_scale * nlp.objective(result.positions.data());
  if (progress) progress->report(1.0, "optimize sphere map");
  result.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
  return result;
}

}  // namespace paramorph::morph
