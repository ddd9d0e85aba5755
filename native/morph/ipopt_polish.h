// Ipopt's interior point (MUMPS) on the optimized sphere map's program
// (morph/sphere_map_nlp, thesis 4.3.3), the polish optimize_sphere_map may
// finish with. Compiled with Ipopt only where the build finds it and
// PARAMORPH_WITH_IPOPT allows (source builds): Ipopt's EPL and the GPL do
// not mix in one distributed work, so the released wheel is built without
// it, and optimize_sphere_map then follows its log-barrier path to the end.
#pragma once

#include <string>
#include <vector>

#include "common/progress.h"
#include "mesh/types.h"
#include "morph/sphere_map_nlp.h"

namespace paramorph::morph {

/// Whether this build has Ipopt (false: ipopt_polish raises InvalidInputError).
bool ipopt_available();

struct IpoptPolishOptions {
  double epsilon = 0;      ///< the absolute triple-product bound (4.10)
  int max_iterations = 0;
  double tol = 1e-6;       ///< Ipopt's convergence tolerance
  /// Start from a point on the barrier's central path at barrier_mu, with
  /// `multipliers` (#V sphere rows, then #F faces); false: a cold start.
  bool warm = false;
  double barrier_mu = 0;
};

struct IpoptPolishResult {
  std::vector<double> solution;  ///< Ipopt's last point, 3 #V stacked coordinates (empty if none)
  std::string status;            ///< Ipopt's return status, e.g. "Solve_Succeeded"
  int iterations = 0;
};

/// Runs Ipopt on `nlp` from `start` (#V by 3), one call at a time in the
/// process (MUMPS is not thread-safe; concurrent callers wait). Points with a folded face are
/// refused to Ipopt, so every iterate it accepts is fold-free. Raises
/// Cancelled when the progress callback asks to stop, InvalidInputError in a
/// build without Ipopt.
IpoptPolishResult ipopt_polish(const SphereMapNlp& nlp, const MatrixX3d& start, const VectorXd& multipliers,
                               const IpoptPolishOptions& options, ProgressWindow progress = {});

}  // namespace paramorph::morph
