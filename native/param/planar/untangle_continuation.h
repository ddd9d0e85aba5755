// Untangling by ε-continuation, the fallback when Algorithm 2 (untangle.h)
// stalls with folds left or leaves slivers (det S near 0) that would stall the
// barrier optimisation (beyond the thesis; Garanzha et al., "Foldover-free
// maps in 50 lines of code", 2021). A map that is fold-free without slivers
// is returned unchanged.
//
// The barrier of the isometric energy is replaced by a regularised one that
// is finite for inverted faces: with D = det S and χ(D, ε) = (D + sqrt(ε² + D²))/2,
//   E_ε = Σ area_f [(1 - θ) |S|²/χ + θ (D² + 1)/χ],
// S the face's shape matrix (isometric_energy.h), θ = 1/128. For ε → 0, E_ε
// tends to a barrier that blocks inversion; for ε > 0 inverted faces are
// merely expensive. Each round minimises E_ε with L-BFGS (fixed vertices
// never move), then shrinks ε from the smallest det (their update rule), until
// no face is inverted or the budget is spent.
#pragma once

#include <vector>

#include "common/progress.h"
#include "param/planar/isometric_energy.h"

namespace paramorph::planar {

struct ContinuationOptions {
  int max_rounds = 60;
  int iterations_per_round = 60;  ///< L-BFGS steps per ε
  /// Once fold-free, go on (at most extra_rounds) while the smallest det is
  /// below min_relative_det times the mean |det| of the start.
  double min_relative_det = 1e-3;
  int extra_rounds = 5;
};

struct ContinuationResult {
  int rounds = 0;
  int iterations = 0;  ///< L-BFGS steps over all rounds
  Index folded = 0;    ///< faces with det <= 0 at the end
};

/// uv: #V by 2, modified in place; fixed: #V flags (1 = never moves).
ContinuationResult untangle_continuation(const IsometricFactors& factors, const MatrixX3i& F,
                                         MatrixX2d& uv, const std::vector<char>& fixed,
                                         const ContinuationOptions& options = {},
                                         ProgressWindow progress = {});

}  // namespace paramorph::planar
