// L-BFGS for barrier energies (thesis 2.3.1–2.3.2; DESIGN.md §4.1).
//
// Two-loop recursion with m pairs and H0 = γ I, γ = sᵀy / yᵀy. The line
// search never evaluates past the first inversion: the caller supplies the
// largest feasible step along a direction (for the isometric energy, the
// smallest positive root of det(A(x + t d)) = 0 over faces), the full step is
// taken when it is feasible and meets the strong Wolfe conditions, else the
// minimiser is bracketed inside the feasible interval and refined by
// safeguarded (Brent-style) interpolation.
#pragma once

#include <functional>
#include <string>
#include <vector>

#include "common/progress.h"
#include "mesh/types.h"

namespace paramorph::planar {

struct LbfgsOptions {
  int memory = 7;                 ///< stored (s, y) pairs, 5–10 in the thesis
  int max_iterations = 1000;
  /// Stop when |g| <= gradient_tol * reference, the reference being
  /// gradient_reference when > 0, else max(1, |g0|). A caller that knows its
  /// energy's scale should give it: |g0| of a bad start can be 1e6 times
  /// the gradient of a good map, and relative to it the test passes early.
  double gradient_tol = 1e-8;
  double gradient_reference = 0.0;
  /// Stop when the energy fell by less than energy_tol (relative) over the
  /// last energy_window steps: one step alone can be short (a line search
  /// that had to stop before an inversion) without the descent being over.
  double energy_tol = 1e-12;
  int energy_window = 1;
  double wolfe_c1 = 1e-4;         ///< sufficient decrease
  double wolfe_c2 = 0.9;          ///< curvature (strong Wolfe)
  double feasible_fraction = 0.95;  ///< steps stay below this fraction of the first inversion
  int max_line_search_evaluations = 30;
};

struct LbfgsResult {
  int iterations = 0;
  int energy_evaluations = 0;
  int gradient_evaluations = 0;
  std::vector<double> energy_history;  ///< the start and every accepted step
  std::string stop_reason;             ///< "gradient", "energy", "max_iterations", "line_search"
};

/// energy(x, grad): value at x (+inf where infeasible); fills *grad when not null.
using EnergyFunction = std::function<double(const VectorXd& x, VectorXd* grad)>;
/// max_step(x, d): largest t with x + s d feasible for all s in [0, t) (+inf if unbounded).
using StepBound = std::function<double(const VectorXd& x, const VectorXd& d)>;

/// Shape of the initial inverse Hessian H0 = (sᵀPs / sᵀy) P⁻¹ of the two-loop
/// recursion, for an SPD P that resembles the Hessian (e.g. a mesh Laplacian).
/// apply(q) overwrites q with P⁻¹q; quadratic(s) returns sᵀPs. Empty: H0 = γ I.
struct LbfgsPreconditioner {
  std::function<void(VectorXd&)> apply;
  std::function<double(const VectorXd&)> quadratic;
};

/// Minimises from a feasible x (finite energy), in place. Every iterate stays feasible.
LbfgsResult minimize_lbfgs(const EnergyFunction& energy, const StepBound& max_step, VectorXd& x,
                           const LbfgsOptions& options = {}, ProgressWindow progress = {},
                           const LbfgsPreconditioner& preconditioner = {});

}  // namespace paramorph::planar
