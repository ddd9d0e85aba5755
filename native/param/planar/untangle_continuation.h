// Untangling by ε-continuation, the fallback when Algorithm 2 (untangle.h)
// stalls with folds left or leaves slivers (det S near 0) that would stall the
// barrier optimisation (beyond the thesis; Garanzha et al., "Foldover-free
// maps in 50 lines of code", 2021). A map that is fold-free without slivers
// is returned unchanged, and the result never has more folds than the input:
// the best map seen (fewest folds, then largest smallest det) is returned.
//
// The barrier of the isometric energy is replaced by a regularised one that
// is finite for inverted faces: with D = det S and χ(D, ε) = (D + sqrt(ε² + D²))/2,
//   E_ε = Σ area_f [(1 - θ) |S|²/χ + θ (D² + 1)/χ],
// S the face's shape matrix (isometric_energy.h), θ = 1/128. Faces whose
// 3D triangle is badly shaped (aspect ratio > 10) get an equilateral
// reference of the same area, as in the paper: their own shape would make
// the energy stiff for no benefit while untangling. Every reference is then
// scaled to the start's local UV scale (its |UV area| / 3D area, smoothed
// over the mesh), so det ≈ 1 wherever the map is sound and one ε suits
// regions squeezed by orders of magnitude (beyond the paper, which scales
// globally). Rounds are preconditioned L-BFGS. For ε → 0, E_ε tends to
// a barrier that blocks inversion; for ε > 0 inverted faces are merely
// expensive. Each round minimises E_ε with L-BFGS (fixed vertices never
// move), then shrinks ε from the smallest det (their update rule), until no
// face is inverted and no face is a sliver, or the budget is spent.
#pragma once

#include <vector>

#include "common/progress.h"
#include "param/planar/isometric_energy.h"
#include "param/planar/lbfgs.h"

namespace paramorph::planar {

struct ContinuationOptions {
  int max_rounds = 100;
  int iterations_per_round = 300;  ///< L-BFGS steps per ε, at most
  int max_iterations = 6000;       ///< L-BFGS steps over all rounds
  /// Once fold-free, go on (at most extra_rounds) while the smallest det is
  /// below min_relative_det (in units of the local scale).
  double min_relative_det = 1e-3;
  int extra_rounds = 5;
};

struct ContinuationResult {
  int rounds = 0;
  int iterations = 0;  ///< L-BFGS steps over all rounds
  Index folded = 0;    ///< faces with det <= 0 at the end
};

/// uv: #V by 2, modified in place; fixed: #V flags (1 = never moves).
/// preconditioner: H0 of the L-BFGS rounds over the free vertices in
/// ascending order (a LaplacianPreconditioner's; the shape term, which
/// dominates E_ε, has a Laplacian-like Hessian). Empty: plain L-BFGS.
ContinuationResult untangle_continuation(const IsometricFactors& factors, const MatrixX3i& F,
                                         MatrixX2d& uv, const std::vector<char>& fixed,
                                         const ContinuationOptions& options = {},
                                         ProgressWindow progress = {},
                                         const LbfgsPreconditioner& preconditioner = {});

}  // namespace paramorph::planar
