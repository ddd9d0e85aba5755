// A fold-free sphere map of model B whose pinned vertices lie exactly on
// given points (the morph's hard pins: vertex b_k of B on A's map position
// of its partner a_k; DESIGN.md §4.4, issue 16). The thesis bends B's map
// towards A's features by a weighted term ((4.12)); weights leave pins off by
// whatever the other terms pull (measured: 0.21 rad at weight 100), so here
// the pins are constraints:
//
//   1. the targets (where every vertex of B would like to be: B's radial
//      projection, or a correspondence carried onto A's map) are moved onto
//      the pins: nudged locally round each pin where they already nearly
//      meet them, else turned to fit them (Kabsch; one pin: the shortest
//      rotation) and warped (sphere_warp) so their pinned rows are the pins;
//   2. the start map is turned to face the targets and flowed by the same
//      kind of warp until its pinned vertices are on the pins: every step is
//      checked, halved where a face would fold, and where the steps stall
//      the free vertices are relaxed first (the barrier below with the pins
//      where they have got to) — so every accepted map is fold-free;
//   3. the log-barrier path of sphere_map_barrier with the pinned vertices
//      fixed brings every free vertex as close to its target as the fold
//      bounds (epsilon) allow: maximize sum_i w_i t_i . v_i, |v_i| = 1,
//      det(v_a, v_b, v_c) >= epsilon.
//
// The pinned rows of the result are copies of the pins (bit for bit), and
// every face's triple product is positive.
#pragma once

#include <functional>
#include <optional>
#include <vector>

#include "common/progress.h"
#include "mesh/types.h"
#include "param/spherical/untangle_sphere_map.h"

namespace paramorph::morph {

struct PinnedSphereOptions {
  /// Fold bound of the barrier, a share of the start's mean face triple
  /// product (as OptimizeSphereOptions::epsilon).
  double epsilon = 0.05;
  /// The bound is lowered to half the start's smallest face where that is
  /// smaller, but never below this share of the mean: faces under it are
  /// opened (0: never).
  double min_epsilon = 0;
  /// #V unit targets; B's radial projection from its area-weighted centroid
  /// when absent. Turned and warped to the pins (step 1).
  std::optional<MatrixX3d> target;
  /// #V non-negative weights of the targets (all 1 when absent).
  std::optional<VectorXd> weights;
  /// Barrier weight at the end of the path, relative to its start: smaller
  /// brings the free vertices closer to their targets for more Newton steps.
  double mu_ratio = 1e-3;
  int max_steps = 120;       ///< Newton steps of the path's rounds at most
  int warp_steps = 16;       ///< steps of the targets' warp (step 1)
  /// Targets folding at most this share of the faces are the start
  /// themselves (untangled by the barrier) instead of the flowed `sphere`.
  double max_target_folds = 0.05;
  /// Targets that miss no pin by more than this (chord) are nudged onto the
  /// pins locally instead of warped globally (step 1).
  double local_nudge = 0.05;
  /// Run the barrier path (step 3) also when the untangled targets are the
  /// start; false: the untangled targets are the map, and the path runs only
  /// after the flow.
  bool relax_untangled = true;
  /// A fold-free start computed only where the targets cannot be untangled
  /// (then used instead of the `sphere` argument, which may then be anything).
  std::function<MatrixX3d()> fallback_start;
};

struct PinnedSphereResult {
  MatrixX3d positions;          ///< #V by 3 unit vectors, fold-free, pinned rows = the pins
  MatrixX3d target;             ///< the targets after step 1 (pinned rows on the pins to rounding)
  Eigen::Matrix3d rotation;     ///< step 1's turn of the targets (rows: t R)
  /// Step 2 started from the targets, untangled (they folded little), not
  /// from the flowed `sphere`.
  bool start_from_target = false;
  spherical::SphereUntangleResult untangle;  ///< the targets' untangling, when tried
  int flow_steps = 0;           ///< accepted steps of the start's flow (step 2)
  int flow_rejected = 0;        ///< flow steps halved because a face would fold
  int flow_relaxations = 0;     ///< times the free vertices were relaxed where the flow stalled
  int barrier_steps = 0;        ///< Newton steps of step 3
  double epsilon = 0;           ///< the absolute fold bound used
  double min_triple = 0;        ///< smallest face triple product of the result
  double objective = 0;         ///< sum_i w_i t_i . v_i at the end
  double seconds = 0;
};

/// V, F: closed genus-0 mesh B (checked); sphere: a fold-free sphere map of
/// it (checked like optimize_sphere_map's); pinned: distinct vertices of B;
/// pins: one unit vector per pinned vertex (distinct points; renormalised).
/// Raises InvalidInputError for shapes, ranges, non-finite values;
/// ConstraintError naming the pins where a vertex is pinned twice, two pins
/// share a point, the pins' order on the sphere is the mirror image of
/// their order on B (no orientation-preserving map honours it), or the flow
/// cannot bring them home without folding; Cancelled.
PinnedSphereResult pinned_sphere_map(const MatrixX3d& V, const MatrixX3i& F, const MatrixX3d& sphere,
                                     const std::vector<Index>& pinned, const MatrixX3d& pins,
                                     const PinnedSphereOptions& options = {},
                                     Progress* progress = nullptr);

}  // namespace paramorph::morph
