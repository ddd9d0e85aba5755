// Inner solvers of the tangent-plane saddle-point problem (thesis 3.3.1,
// Algorithm 3; DESIGN.md §4.2). All three reach the same saddle point:
//
//  - Jacobi: Algorithm 3, damped Jacobi with per-vertex multipliers; fully
//    parallel, residual tested only every `check_every` sweeps.
//  - Pcg: conjugate gradients on the tangent-plane-projected system
//    Π L Π t = -Π L x (u = x + t), preconditioned by Π M⁻¹ Π where M is the
//    scalar Laplacian with Dirichlet rows at the puncture and its ring (their
//    rows diagonal): the very factorisation that gave the Tutte start, reused
//    by every outer step. The projected operator is the component-wise
//    Laplacian up to a curvature shift, so M captures its mesh-size dependence.
//  - Cholesky: sparse LDLᵀ of the reduced 2#V system in per-vertex tangent
//    frames, pattern analysed once, refactored every outer step.
//
// Residual (all solvers): |Π D⁻¹ L u| / |Π D⁻¹ L x|, the relative reduction of
// the normalised tangential gradient, as in thesis 3.4.
#pragma once

#include <Eigen/Dense>
#include <Eigen/SparseCholesky>
#include <memory>
#include <string>

#include "common/progress.h"
#include "param/spherical/initial_map.h"
#include "param/spherical/sphere_kernels.h"

namespace paramorph::spherical {

enum class InnerSolver { Pcg, Jacobi, Cholesky };
InnerSolver parse_inner_solver(const std::string& name);  ///< "auto" -> Pcg
std::string to_string(InnerSolver solver);

struct InnerOptions {
  double tol = 1e-7;
  int max_iterations = 200000;  ///< per solve
  int check_every = 50;         ///< Jacobi: sweeps between residual tests
  double omega = 0.9;           ///< Jacobi damping, 0 < ω < 1 (Proposition 3.2)
};

struct InnerResult {
  int iterations = 0;
  double residual = 0.0;  ///< relative, as above
  bool converged = false;
};

class TangentPlaneSolver {
 public:
  /// `laplacian` is required by the Pcg solver (its preconditioner).
  TangentPlaneSolver(const SpringGraph& graph, InnerSolver kind, SphereKernels& kernels,
                     std::shared_ptr<const PuncturedLaplacian> laplacian = nullptr);
  ~TangentPlaneSolver();

  /// Solves about the map x (#V by 3 unit vectors); u receives the
  /// unnormalised solution (x_i · u_i = 1).
  InnerResult solve(const MatrixX3d& x, MatrixX3d& u, const InnerOptions& options,
                    ProgressWindow progress = {});

 private:
  InnerResult solve_jacobi(const MatrixX3d& x, MatrixX3d& u, const InnerOptions& o,
                           ProgressWindow& p);
  InnerResult solve_pcg(const MatrixX3d& x, MatrixX3d& u, const InnerOptions& o,
                        ProgressWindow& p);
  InnerResult solve_cholesky(const MatrixX3d& x, MatrixX3d& u, const InnerOptions& o);

  const SpringGraph& graph_;
  InnerSolver kind_;
  SphereKernels& kernels_;
  std::shared_ptr<const PuncturedLaplacian> laplacian_;
  struct Factorizations;
  std::unique_ptr<Factorizations> factors_;
};

}  // namespace paramorph::spherical
