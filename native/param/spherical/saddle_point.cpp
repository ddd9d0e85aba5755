#include "param/spherical/saddle_point.h"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>

#include "common/cholesky_solve_rows.h"
#include "common/errors.h"

namespace paramorph::spherical {

InnerSolver parse_inner_solver(const std::string& name) {
  if (name == "auto" || name == "pcg") return InnerSolver::Pcg;
  if (name == "jacobi") return InnerSolver::Jacobi;
  if (name == "cholesky") return InnerSolver::Cholesky;
  throw InvalidInputError("solver must be \"auto\", \"pcg\", \"jacobi\" or \"cholesky\", got \"" +
                          name + "\"");
}

std::string to_string(InnerSolver solver) {
  switch (solver) {
    case InnerSolver::Pcg: return "pcg";
    case InnerSolver::Jacobi: return "jacobi";
    case InnerSolver::Cholesky: return "cholesky";
  }
  return "?";
}

namespace {

/// What a solve's residual is measured against: its start r0, but never less
/// than roundoff over n unit vectors divided by tol. A start that is already
/// the solution (a symmetric mesh whose Tutte map is the optimum) has r0 at
/// roundoff; relative to it no solver gets under tol, and Jacobi ran its
/// 200000 sweeps on a 24-face bipyramid and reported a residual of 0.2.
constexpr double kRoundoffResidualPerVertex = 1e-12;

double residual_reference(double r0, Index n, double tol) {
  return std::max(r0, kRoundoffResidualPerVertex * std::sqrt(double(std::max<Index>(n, 1))) / tol);
}

/// Jacobi gives up when `kStallChecks` residual tests in a row brought no
/// tenth off the best residual: the projected iteration does not converge on
/// some meshes (high-valence poles over short rings), so more sweeps only burn time.
constexpr int kStallChecks = 20;

}  // namespace

struct TangentPlaneSolver::Factorizations {
  // Cholesky solver: reduced 2n system, pattern analysed once.
  std::unique_ptr<Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>>> reduced;
  bool reduced_analysed = false;
};

TangentPlaneSolver::TangentPlaneSolver(const SpringGraph& graph, InnerSolver kind,
                                       SphereKernels& kernels,
                                       std::shared_ptr<const PuncturedLaplacian> laplacian)
    : graph_(graph),
      kind_(kind),
      kernels_(kernels),
      laplacian_(std::move(laplacian)),
      factors_(std::make_unique<Factorizations>()) {
  PM_REQUIRE(kind != InnerSolver::Pcg || (laplacian_ && laplacian_->factor), InvalidInputError,
             "the PCG solver needs the factored punctured Laplacian");
}

TangentPlaneSolver::~TangentPlaneSolver() = default;

InnerResult TangentPlaneSolver::solve(const MatrixX3d& x, MatrixX3d& u, const InnerOptions& o,
                                      ProgressWindow p) {
  switch (kind_) {
    case InnerSolver::Jacobi: return solve_jacobi(x, u, o, p);
    case InnerSolver::Pcg: return solve_pcg(x, u, o, p);
    case InnerSolver::Cholesky: return solve_cholesky(x, u, o);
  }
  return {};
}

InnerResult TangentPlaneSolver::solve_jacobi(const MatrixX3d& x, MatrixX3d& u,
                                             const InnerOptions& o, ProgressWindow& progress) {
  kernels_.begin_solve(x);
  const double r0 = residual_reference(std::sqrt(kernels_.residual_squared()), graph_.num_vertices(), o.tol);
  InnerResult result;
  result.residual = std::sqrt(kernels_.residual_squared()) / r0;
  result.converged = result.residual <= o.tol;
  double best = result.residual;
  int stalled = 0;
  while (!result.converged && result.iterations < o.max_iterations && stalled < kStallChecks) {
    const int sweeps = std::min(o.check_every, o.max_iterations - result.iterations);
    kernels_.jacobi(sweeps, o.omega);
    result.iterations += sweeps;
    result.residual = std::sqrt(kernels_.residual_squared()) / r0;
    result.converged = result.residual <= o.tol;
    if (result.residual < 0.9 * best) {
      best = result.residual;
      stalled = 0;
    } else {
      ++stalled;
    }
    progress.report(std::log(result.residual) / std::log(o.tol), "jacobi");
  }
  kernels_.read_solution(u);
  return result;
}

namespace {

double dot(const MatrixX3d& a, const MatrixX3d& b) { return (a.array() * b.array()).sum(); }

/// v_i -= (x_i · v_i) x_i: onto the tangent planes.
void project(const MatrixX3d& x, MatrixX3d& v) {
  const VectorXd normal = (x.array() * v.array()).rowwise().sum();  // evaluated before v changes
  v -= normal.asDiagonal() * x;
}

}  // namespace

InnerResult TangentPlaneSolver::solve_pcg(const MatrixX3d& x, MatrixX3d& u, const InnerOptions& o,
                                          ProgressWindow& progress) {
  const Index n = graph_.num_vertices();
  const PuncturedLaplacian& M = *laplacian_;
  const VectorXd inv_degree = graph_.degree.cwiseInverse();
  auto scaled_norm = [&](const MatrixX3d& r) {
    return std::sqrt((inv_degree.asDiagonal() * r).squaredNorm());
  };
  MatrixX3d interior(M.interior_count, 3);
  auto precondition = [&](const MatrixX3d& r, MatrixX3d& z) {
    z.resize(n, 3);
    for (Index v = 0; v < n; ++v) {
      const Index i = M.interior_index[v];
      if (i >= 0)
        interior.row(i) = r.row(v);
      else
        z.row(v) = r.row(v) * inv_degree[v];  // puncture and ring: diagonal
    }
    cholesky_solve_rows<PuncturedLaplacian::Factor, 3>(*M.factor, interior, interior);
    for (Index v = 0; v < n; ++v)
      if (M.interior_index[v] >= 0) z.row(v) = interior.row(M.interior_index[v]);
    project(x, z);
  };

  kernels_.begin_solve(x);
  MatrixX3d t = MatrixX3d::Zero(n, 3), rho, z, p, q;
  kernels_.apply_projected_laplacian(x, rho);
  rho = -rho;  // ρ = b - K t with t = 0
  const double r0 = residual_reference(scaled_norm(rho), n, o.tol);
  InnerResult result;
  result.residual = scaled_norm(rho) / r0;
  result.converged = result.residual <= o.tol;
  if (!result.converged) {
    precondition(rho, z);
    p = z;
    double rz = dot(rho, z);
    while (result.iterations < o.max_iterations) {
      kernels_.apply_projected_laplacian(p, q);
      const double pq = dot(p, q);

      if (!(pq > 0)) break;  // lost positive definiteness to rounding: stop here
      const double alpha = rz / pq;
      t += alpha * p;
      rho -= alpha * q;
      ++result.iterations;
      result.residual = scaled_norm(rho) / r0;
      if (result.residual <= o.tol) {
        result.converged = true;
        break;
      }
      precondition(rho, z);
      const double rz_next = dot(rho, z);
      p = z + (rz_next / rz) * p;
      rz = rz_next;
      // Every iteration (the report itself is throttled): one takes 0.14 s at
      // a million faces.
      progress.report(std::log(result.residual) / std::log(o.tol), "pcg");
    }
  }
  project(x, t);  // keep x_i · u_i = 1 exact despite rounding in the updates
  u = x + t;
  // Report the true residual, not the recursively updated one.
  kernels_.write_solution(u);
  // |Π D⁻¹ L x| = |D⁻¹ ρ₀|, so this is the same relative measure.
  result.residual = std::sqrt(kernels_.residual_squared()) / r0;
  result.converged = result.residual <= o.tol;
  return result;
}

InnerResult TangentPlaneSolver::solve_cholesky(const MatrixX3d& x, MatrixX3d& u,
                                               const InnerOptions& o) {
  const Index n = graph_.num_vertices();
  // Orthonormal tangent frame (t1, t2) per vertex.
  MatrixX3d T1(n, 3), T2(n, 3);
  for (Index i = 0; i < n; ++i) {
    const Eigen::Vector3d xi = x.row(i).transpose();
    const Eigen::Vector3d axis =
        std::abs(xi.z()) < 0.9 ? Eigen::Vector3d::UnitZ() : Eigen::Vector3d::UnitX();
    const Eigen::Vector3d t1 = axis.cross(xi).normalized();
    T1.row(i) = t1.transpose();
    T2.row(i) = xi.cross(t1).transpose();
  }
  std::vector<Eigen::Triplet<double>> triplets;
  triplets.reserve(4 * (graph_.neighbors.size() + n));
  for (Index i = 0; i < n; ++i) {
    triplets.emplace_back(2 * i, 2 * i, graph_.degree[i]);
    triplets.emplace_back(2 * i + 1, 2 * i + 1, graph_.degree[i]);
    for (Index k = graph_.offsets[i]; k < graph_.offsets[i + 1]; ++k) {
      const Index j = graph_.neighbors[k];
      const double w = graph_.weights[k];
      triplets.emplace_back(2 * i, 2 * j, -w * T1.row(i).dot(T1.row(j)));
      triplets.emplace_back(2 * i, 2 * j + 1, -w * T1.row(i).dot(T2.row(j)));
      triplets.emplace_back(2 * i + 1, 2 * j, -w * T2.row(i).dot(T1.row(j)));
      triplets.emplace_back(2 * i + 1, 2 * j + 1, -w * T2.row(i).dot(T2.row(j)));
    }
  }
  Eigen::SparseMatrix<double> K(2 * n, 2 * n);
  K.setFromTriplets(triplets.begin(), triplets.end());
  if (!factors_->reduced) factors_->reduced = std::make_unique<Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>>>();
  auto& solver = *factors_->reduced;
  if (!factors_->reduced_analysed) {
    solver.analyzePattern(K);
    factors_->reduced_analysed = true;
  }
  solver.factorize(K);
  PM_REQUIRE(solver.info() == Eigen::Success, ComputeError,
             "the tangent-plane system factorisation failed");
  MatrixX3d Lx;
  graph_.apply(x, Lx);
  VectorXd rhs(2 * n);
  for (Index i = 0; i < n; ++i) {
    rhs[2 * i] = -T1.row(i).dot(Lx.row(i));
    rhs[2 * i + 1] = -T2.row(i).dot(Lx.row(i));
  }
  const VectorXd s = solver.solve(rhs);
  u.resize(n, 3);
  for (Index i = 0; i < n; ++i) u.row(i) = x.row(i) + s[2 * i] * T1.row(i) + s[2 * i + 1] * T2.row(i);

  kernels_.begin_solve(x);
  const double r0 = residual_reference(std::sqrt(kernels_.residual_squared()), n, o.tol);
  kernels_.write_solution(u);
  InnerResult result;
  result.iterations = 1;
  result.residual = std::sqrt(kernels_.residual_squared()) / r0;
  result.converged = result.residual <= o.tol;
  return result;
}

}  // namespace paramorph::spherical
