// Log-barrier warm start of the optimized sphere map (thesis 4.3.3, (4.8)-(4.10);
// DESIGN.md §4.4 step 1): the same problem with the fold bounds (4.10) moved
// into the objective as a log barrier and the sphere (4.9) kept exactly,
//
//   minimize  E(v) = -sum_i p_i . v_i - mu sum_f log(det(v_a, v_b, v_c) - b_f),  |v_i| = 1,
//
// followed down a short path of mu by Newton steps in each vertex's tangent
// plane, after an opening phase for faces the start squeezes to rounding
// (their bounds start just below 0; they are pushed above 2 epsilon with
// growing weights before the path, whose bounds are then all epsilon).
// Every accepted step keeps every face above its bound, so every
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

namespace paramorph::spherical {

struct SphereBarrierOptions {
  double epsilon = 0;      ///< the absolute bound of (4.10)
  double mu_start = 0;     ///< first barrier weight (absolute)
  double mu_end = 0;       ///< last barrier weight: the path stops after the round at mu_end
  double mu_factor = 0.1;  ///< mu shrinks by this factor per round
  int max_steps = 300;     ///< Newton steps over all rounds
  /// Newton steps per round at most. Near a round's centre the steps can creep
  /// (the projected face Hessians overstate the curvature along slow modes):
  /// tentacle_sphere(3) spent 250 full steps of one round each lowering E by
  /// ~1e-5 of itself. The next round and Ipopt do not need an exact centre.
  int max_round_steps = 20;
};

struct SphereBarrierResult {
  MatrixX3d positions;  ///< #V by 3 unit vectors, every face above its bound
  /// Per face, the barrier's bound b_f: epsilon once every face is open (the
  /// path runs at epsilon); lower only when the steps ran out while opening.
  VectorXd bounds;
  double mu = 0;  ///< the barrier weight of the last round
  int opening_rounds = 0;  ///< rounds opening faces under 2 epsilon (0: the start was above it)
  int steps = 0;  ///< Newton steps taken
  /// Newton systems factored, shifted retries included (one per step and one
  /// per round's final centring test when no system needs a shift).
  int factorizations = 0;
  int rounds = 0;  ///< values of mu visited on the path (0: the steps ran out while opening)
  /// The last round ended within ~mu of its minimum (not at a step cap).
  bool centred = false;
};

/// F: #F by 3 faces; pull: #V by 3, p_i = w_i t_i (weighted targets);
/// start: #V by 3 unit vectors, every face's triple product > -1e-13.
SphereBarrierResult sphere_map_barrier(const MatrixX3i& F, const MatrixX3d& pull,
                                       const MatrixX3d& start, const SphereBarrierOptions& options,
                                       ProgressWindow progress = {});

/// E at the points X (any non-zero rows, used as given, not normalised) for
/// the bounds b and the per-face weights mu; +inf where a face is at or below its bound.
/// Fills *gradient (#V by 3, Euclidean) when not null. The Newton steps
/// minimise this; exposed for the finite-difference test.
double sphere_barrier_energy(const MatrixX3i& F, const MatrixX3d& pull, const VectorXd& bounds,
                             const VectorXd& mu, const MatrixX3d& X, MatrixX3d* gradient = nullptr);

}  // namespace paramorph::spherical
