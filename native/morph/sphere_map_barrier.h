// Log-barrier warm start of the optimized sphere map (thesis 4.3.3, (4.8)-(4.10);
// DESIGN.md §4.4 step 1): the same problem with the fold bounds (4.10) moved
// into the objective as a log barrier and the sphere (4.9) kept exactly,
//
//   minimize  E(v) = -sum_i p_i . v_i - mu sum_f log(det(v_a, v_b, v_c) - b_f),  |v_i| = 1,
//
// followed down a short path of mu by Newton steps in each vertex's tangent
// plane. Every accepted step keeps every face above its bound, so every
// iterate is fold-free (a primal barrier, where Ipopt's slacks let the faces
// themselves cross during a step). The result is a point near Ipopt's central
// path at the last mu, from where optimize_sphere_map lets Ipopt finish.
//
// Why (measured on spot, 2,930 vertices): Ipopt from the raw start spends its
// first 20–60 iterations on steps cut back to 1e-6..1e-11 because its linear
// model lets small faces fold, then ~80 more with inertia corrections.
#pragma once

#include "common/progress.h"
#include "mesh/types.h"

namespace paramorph::morph {

struct SphereBarrierOptions {
  double epsilon = 0;      ///< the absolute bound of (4.10)
  double mu_start = 0;     ///< first barrier weight (absolute)
  double mu_end = 0;       ///< last barrier weight: the path stops after the round at mu_end
  double mu_factor = 0.1;  ///< mu shrinks by this factor per round
  int max_steps = 300;     ///< Newton steps over all rounds
};

struct SphereBarrierResult {
  MatrixX3d positions;  ///< #V by 3 unit vectors, every face above its bound
  /// Per face, the barrier's bound b_f: epsilon, or lower where the start
  /// was tighter (half its triple product, or just below 0 for faces squeezed
  /// to rounding); raised towards epsilon after each round as faces open.
  VectorXd bounds;
  double mu = 0;  ///< the barrier weight of the last round
  int steps = 0;  ///< Newton steps taken
  /// Newton systems factored, shifted retries included (one per step and one
  /// per round's final centring test when no system needs a shift).
  int factorizations = 0;
  int rounds = 0;  ///< values of mu visited
};

/// F: #F by 3 faces; pull: #V by 3, p_i = w_i t_i (weighted targets);
/// start: #V by 3 unit vectors, every face's triple product > -1e-13.
SphereBarrierResult sphere_map_barrier(const MatrixX3i& F, const MatrixX3d& pull,
                                       const MatrixX3d& start, const SphereBarrierOptions& options,
                                       ProgressWindow progress = {});

/// E at the points X (any non-zero rows, used as given, not normalised) for
/// the bounds b and weight mu; +inf where a face is at or below its bound.
/// Fills *gradient (#V by 3, Euclidean) when not null. The Newton steps
/// minimise this; exposed for the finite-difference test.
double sphere_barrier_energy(const MatrixX3i& F, const MatrixX3d& pull, const VectorXd& bounds,
                             double mu, const MatrixX3d& X, MatrixX3d* gradient = nullptr);

}  // namespace paramorph::morph
