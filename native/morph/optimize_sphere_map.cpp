#include "morph/optimize_sphere_map.h"

#include <IpIpoptApplication.hpp>
#include <IpTNLP.hpp>

#include <chrono>
#include <cmath>
#include <exception>

#include <Eigen/Geometry>
#include <Eigen/SVD>

#include "common/best_rotation.h"
#include "common/errors.h"
#include "mesh/validate.h"
#include "morph/radial_projection.h"
#include "param/spherical/sphere_map_barrier.h"
#include "morph/sphere_map_nlp.h"

namespace paramorph::morph {

namespace {

/// Triple products of unit vectors above -kRoundoff are not folds (rounding).
constexpr double kRoundoff = 1e-13;

using Ipopt::Index;  // NOLINT: Ipopt's own integer type in the adapter below
using Ipopt::Number;

/// The Ipopt adapter: structure from SphereMapNlp, values at Ipopt's points;
/// evaluations at a folded point are refused (Ipopt then shortens the step).
class SphereMapTnlp : public Ipopt::TNLP {
 public:
  /// multipliers: Ipopt's lambda (#V sphere rows, then #F faces) for a warm
  /// start, or empty.
  SphereMapTnlp(const SphereMapNlp& nlp, const MatrixX3d& start, const VectorXd& multipliers,
                double epsilon, int max_iterations, ProgressWindow progress)
      : nlp_(nlp), start_(start), multipliers_(multipliers), epsilon_(epsilon),
        max_iterations_(max_iterations), progress_(progress) {}

  bool get_nlp_info(Index& n, Index& m, Index& nnz_jac, Index& nnz_hess,
                    IndexStyleEnum& style) override {
    n = nlp_.num_variables();
    m = nlp_.num_constraints();
    nnz_jac = nlp_.jacobian_nonzeros();
    nnz_hess = nlp_.hessian_nonzeros();
    style = TNLP::C_STYLE;
    return true;
  }

  bool get_bounds_info(Index n, Number* x_l, Number* x_u, Index m, Number* g_l,
                       Number* g_u) override {
    std::fill(x_l, x_l + n, -2e19);
    std::fill(x_u, x_u + n, 2e19);
    const Index vertices = Index(start_.rows());
    std::fill(g_l, g_l + vertices, 1.0);
    std::fill(g_u, g_u + vertices, 1.0);
    std::fill(g_l + vertices, g_l + m, epsilon_);
    std::fill(g_u + vertices, g_u + m, 2e19);
    return true;
  }

  bool get_starting_point(Index n, bool init_x, Number* x, bool init_z, Number* z_l, Number* z_u,
                          Index m, bool init_lambda, Number* lambda) override {
    if ((init_z || init_lambda) && multipliers_.size() != m) return false;
    if (init_z) {  // no variable has bounds: these multipliers are unused
      std::fill(z_l, z_l + n, 0.0);
      std::fill(z_u, z_u + n, 0.0);
    }
    if (init_lambda) std::copy(multipliers_.data(), multipliers_.data() + m, lambda);
    for (Index v = 0; v < Index(start_.rows()); ++v)
      for (int d = 0; d < 3; ++d) x[3 * v + d] = start_(v, d);
    return init_x;
  }

  bool eval_f(Index, const Number* x, bool, Number& f) override {
    if (!fold_free(x)) return false;
    f = nlp_.objective(x);
    return true;
  }
  bool eval_grad_f(Index, const Number* x, bool, Number* grad) override {
    nlp_.objective_gradient(x, grad);
    return true;
  }
  bool eval_g(Index, const Number* x, bool, Index, Number* g) override {
    if (!fold_free(x)) return false;
    nlp_.constraints(x, g);
    return true;
  }
  bool eval_jac_g(Index, const Number* x, bool, Index, Index, Index* rows, Index* cols,
                  Number* values) override {
    if (values == nullptr) {
      std::copy(nlp_.jacobian_rows().begin(), nlp_.jacobian_rows().end(), rows);
      std::copy(nlp_.jacobian_cols().begin(), nlp_.jacobian_cols().end(), cols);
    } else {
      nlp_.jacobian_values(x, values);
    }
    return true;
  }
  bool eval_h(Index, const Number* x, bool, Number sigma, Index, const Number* lambda, bool,
              Index, Index* rows, Index* cols, Number* values) override {
    if (values == nullptr) {
      std::copy(nlp_.hessian_rows().begin(), nlp_.hessian_rows().end(), rows);
      std::copy(nlp_.hessian_cols().begin(), nlp_.hessian_cols().end(), cols);
    } else {
      nlp_.hessian_values(x, sigma, lambda, values);
    }
    return true;
  }

  bool intermediate_callback(Ipopt::AlgorithmMode, Index iteration, Number, Number, Number,
                             Number, Number, Number, Number, Number, Index,
                             const Ipopt::IpoptData*, Ipopt::IpoptCalculatedQuantities*) override {
    iterations_ = iteration;
    try {
      progress_.report(std::min(0.99, double(iteration) / max_iterations_), "optimize sphere map");
    } catch (const Cancelled&) {
      cancelled_ = true;  // never throw through Ipopt
      return false;
    }
    return true;
  }

  void finalize_solution(Ipopt::SolverReturn, Index n, const Number* x, const Number*,
                         const Number*, Index, const Number*, const Number*, Number,
                         const Ipopt::IpoptData*, Ipopt::IpoptCalculatedQuantities*) override {
    solution_.assign(x, x + n);
  }

  const std::vector<double>& solution() const { return solution_; }
  int iterations() const { return iterations_; }
  bool cancelled() const { return cancelled_; }

 private:
  bool fold_free(const Number* x) const { return nlp_.min_triple(x) > -kRoundoff; }

  const SphereMapNlp& nlp_;
  const MatrixX3d& start_;
  const VectorXd& multipliers_;
  double epsilon_;
  int max_iterations_;
  ProgressWindow progress_;
  std::vector<double> solution_;
  int iterations_ = 0;
  bool cancelled_ = false;
};

std::string status_name(Ipopt::ApplicationReturnStatus status) {
  switch (status) {
    case Ipopt::Solve_Succeeded: return "Solve_Succeeded";
    case Ipopt::Solved_To_Acceptable_Level: return "Solved_To_Acceptable_Level";
    case Ipopt::Infeasible_Problem_Detected: return "Infeasible_Problem_Detected";
    case Ipopt::Search_Direction_Becomes_Too_Small: return "Search_Direction_Becomes_Too_Small";
    case Ipopt::Diverging_Iterates: return "Diverging_Iterates";
    case Ipopt::User_Requested_Stop: return "User_Requested_Stop";
    case Ipopt::Feasible_Point_Found: return "Feasible_Point_Found";
    case Ipopt::Maximum_Iterations_Exceeded: return "Maximum_Iterations_Exceeded";
    case Ipopt::Restoration_Failed: return "Restoration_Failed";
    case Ipopt::Error_In_Step_Computation: return "Error_In_Step_Computation";
    case Ipopt::Maximum_CpuTime_Exceeded: return "Maximum_CpuTime_Exceeded";
    default: return "Ipopt status " + std::to_string(int(status));
  }
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
  VectorXd weights = VectorXd::Ones(V.rows());
  if (o.weights) {
    weights = *o.weights;
    PM_REQUIRE(weights.size() == V.rows() && weights.allFinite() && (weights.array() >= 0).all() &&
                   weights.sum() > 0,
               InvalidInputError, "weights must be ", V.rows(),
               " finite non-negative numbers, one per vertex, not all 0");
  }
  MatrixX3d start = sphere.rowwise().normalized();
  const VectorXd start_det = face_triple_products(start, F);
  // Long protrusions squeeze a conformal map's faces to triple products of
  // the order of rounding (1e-17); those count as degenerate, not folded.
  std::vector<paramorph::Index> folded;
  for (paramorph::Index f = 0; f < F.rows(); ++f)
    if (!(start_det[f] > -kRoundoff)) folded.push_back(f);
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
  if (start_det.minCoeff() > kRoundoff) result.epsilon = std::min(result.epsilon, 0.5 * start_det.minCoeff());
  SphereMapNlp nlp(mesh, pull);
  result.start_objective = -nlp.objective(start.data());
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
  spherical::SphereBarrierResult barrier;
  VectorXd multipliers;
  if (o.warm_start) {
    const double pull_scale = pull.rowwise().norm().mean();
    spherical::SphereBarrierOptions barrier_options;
    barrier_options.epsilon = result.epsilon;
    barrier_options.mu_start = mean_det * pull_scale;
    barrier_options.mu_end = 1e-4 * barrier_options.mu_start;
    barrier = spherical::sphere_map_barrier(F, pull, start, barrier_options, ProgressWindow(progress, 0.0, 0.6));
    start = barrier.positions;
    result.barrier_steps = barrier.steps;
  }
  const bool warm = barrier.rounds > 0;  // on the barrier's path: Ipopt starts from it
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

  result.positions = start;
  if (warm && !barrier.centred) {
    // The path's last round stopped at its step cap, away from the centre:
    // Ipopt did not finish from such points within polish_iterations
    // (tentacle_sphere 0.9k-62.7k faces, the closed bunny: every run ended
    // Maximum_Iterations_Exceeded and took about as long as the barrier).
    // The barrier's point stands: every face above epsilon.
    result.status = "Barrier_Point";
  } else {
    Ipopt::SmartPtr<Ipopt::IpoptApplication> app = IpoptApplicationFactory();
    app->Options()->SetIntegerValue("print_level", 0);
    app->Options()->SetStringValue("sb", "yes");
    // From the barrier's path (every face above epsilon) Ipopt only polishes.
    const bool polish = warm;
    const int ipopt_iterations = polish ? std::min(o.max_iterations, o.polish_iterations) : o.max_iterations;
    app->Options()->SetIntegerValue("max_iter", ipopt_iterations);
    app->Options()->SetNumericValue("tol", o.tol);
    app->Options()->SetStringValue("linear_solver", "mumps");
    // Measured on spot (5.9k faces), cold: the monotone barrier converges in
    // 100 iterations where the adaptive one, lowering mu early, cuts its steps
    // at folds and has not converged after 300. Per iteration on 5.8k faces:
    // METIS ordering 0.14 s, Ipopt's automatic choice 0.25 s, PORD 0.19 s;
    // MUMPS's default 1000% workspace over-allocation costs a third more than
    // 5% (Ipopt grows it on demand).
    app->Options()->SetStringValue("mu_strategy", "monotone");
    app->Options()->SetIntegerValue("mumps_pivot_order", 5);
    app->Options()->SetIntegerValue("mumps_mem_percent", 5);
    if (warm) {
      // Ipopt's default pushes (1e-3, absolute) would move every slack far
      // from triple products of 1e-8..1e-3 and undo the warm start.
      app->Options()->SetStringValue("warm_start_init_point", "yes");
      app->Options()->SetNumericValue("mu_init", barrier.mu);
      app->Options()->SetNumericValue("warm_start_slack_bound_push", 1e-3 * result.epsilon);
      app->Options()->SetNumericValue("warm_start_slack_bound_frac", 1e-3);
      app->Options()->SetNumericValue("warm_start_mult_bound_push", 1e-3 * barrier.mu);
    }
    PM_REQUIRE(app->Initialize() == Ipopt::Solve_Succeeded, ComputeError, "Ipopt did not initialise");
    Ipopt::SmartPtr<SphereMapTnlp> problem = new SphereMapTnlp(
        nlp, start, multipliers, result.epsilon, ipopt_iterations,
        ProgressWindow(progress, warm ? 0.6 : 0.0, 1.0));
    const Ipopt::ApplicationReturnStatus status = app->OptimizeTNLP(problem);
    if (problem->cancelled()) throw Cancelled();
    result.status = status_name(status);
    result.iterations = problem->iterations();

    if (!problem->solution().empty()) {
      MatrixX3d solved = Eigen::Map<const MatrixX3d>(problem->solution().data(), V.rows(), 3);
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
      if (solved_det.minCoeff() > -kRoundoff &&
          at_or_below_zero(solved_det) <= at_or_below_zero(face_triple_products(start, F)) && no_worse)
        result.positions = solved;
    }
  }
  const VectorXd det = face_triple_products(result.positions, F);
  result.min_triple = det.minCoeff();
  result.flipped = paramorph::Index((det.array() <= 0).count());
  result.objective = -nlp.objective(result.positions.data());
  if (progress) progress->report(1.0, "optimize sphere map");
  result.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
  return result;
}

}  // namespace paramorph::morph
