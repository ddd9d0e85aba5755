#include "morph/ipopt_polish.h"

#include "common/errors.h"
#include "common/library_locks.h"

#ifdef PARAMORPH_HAVE_IPOPT
#include <IpIpoptApplication.hpp>
#include <IpTNLP.hpp>

#include <algorithm>
#include <mutex>

namespace paramorph::morph {

namespace {

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
  bool fold_free(const Number* x) const { return nlp_.min_triple(x) > -kTripleRoundoff; }

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

bool ipopt_available() { return true; }

IpoptPolishResult ipopt_polish(const SphereMapNlp& nlp, const MatrixX3d& start, const VectorXd& multipliers,
                               const IpoptPolishOptions& o, ProgressWindow progress) {
  // The sequential MUMPS behind Ipopt keeps global state: two runs at once
  // (two Python threads, the GIL released) crashed the process. One at a
  // time, and none beside a CHOLMOD factorisation: both reach BLAS.
  const std::lock_guard<std::mutex> lock(blas_lock());
  Ipopt::SmartPtr<Ipopt::IpoptApplication> app = IpoptApplicationFactory();
  app->Options()->SetIntegerValue("print_level", 0);
  app->Options()->SetStringValue("sb", "yes");
  app->Options()->SetIntegerValue("max_iter", o.max_iterations);
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
  if (o.warm) {
    // Ipopt's default pushes (1e-3, absolute) would move every slack far
    // from triple products of 1e-8..1e-3 and undo the warm start.
    app->Options()->SetStringValue("warm_start_init_point", "yes");
    app->Options()->SetNumericValue("mu_init", o.barrier_mu);
    app->Options()->SetNumericValue("warm_start_slack_bound_push", 1e-3 * o.epsilon);
    app->Options()->SetNumericValue("warm_start_slack_bound_frac", 1e-3);
    app->Options()->SetNumericValue("warm_start_mult_bound_push", 1e-3 * o.barrier_mu);
  }
  PM_REQUIRE(app->Initialize() == Ipopt::Solve_Succeeded, ComputeError, "Ipopt did not initialise");
  Ipopt::SmartPtr<SphereMapTnlp> problem =
      new SphereMapTnlp(nlp, start, multipliers, o.epsilon, o.max_iterations, progress);
  const Ipopt::ApplicationReturnStatus status = app->OptimizeTNLP(problem);
  if (problem->cancelled()) throw Cancelled();
  IpoptPolishResult result;
  result.status = status_name(status);
  result.iterations = problem->iterations();
  result.solution = problem->solution();
  return result;

}

}  // namespace paramorph::morph

#else  // built without Ipopt

namespace paramorph::morph {

bool ipopt_available() { return false; }

IpoptPolishResult ipopt_polish(const SphereMapNlp&, const MatrixX3d&, const VectorXd&, const IpoptPolishOptions&,
                               ProgressWindow) {
  throw InvalidInputError(
      "this build of paramorph has no Ipopt (CMake option PARAMORPH_WITH_IPOPT): use solver \"barrier\" or \"auto\"");
}

}  // namespace paramorph::morph

#endif
