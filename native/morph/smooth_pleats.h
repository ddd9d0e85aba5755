// Pleats of a kept topology smoothed out along the target's surface
// (issue 31; not in the thesis). After morph/fit_to_surface's rounds, some of
// A's faces lie folded over on B: their normal points against B's beneath
// them (a pleat, a wrinkle), where neighbouring vertices were drawn past
// each other. The two-sided distance does not see them; the shading does.
// Each pass moves the vertices of those faces (and one ring around them) a
// half umbrella step in B's tangent plane and back onto B; a move is kept
// only where it stays on the same sheet of B (the snap is short, B's normal
// does not turn, the move is within the ring). The fit's distances are the
// bound, each side's own (a move may not let B's samples drift farther from
// A up to A's farthest sample): where a pass takes one past its bound, the
// moved vertices around the farthest sample go back and stay; if none moved
// there, the pass goes back and the smoothing ends. Measured on the real
// pairs (models/; README, "Morph: a kept topology fitted to the target"):
// the faces against the target fall 5.8 -> 2.6 % (Suzanne onto the cow),
// 16.8 -> 8.0 % (the cow onto the horned cow), the Hausdorff distance as it
// was within 0.03 % of the diagonal.
#pragma once

#include <functional>
#include <vector>

#include "common/progress.h"
#include "mesh/closest_points.h"
#include "mesh/types.h"

namespace paramorph::morph {

/// A's faces (P, F) whose normal points against B's at the closest point to
/// their centre. source_side: +1 when A's faces turn outward (its signed
/// volume >= 0), else -1; B's are taken as they are.
std::vector<char> faces_facing_away(const MatrixX3d& P, const MatrixX3i& F, const ClosestPointTree& target,
                                    const MatrixX3d& VB, const MatrixX3i& FB, double source_side);

/// The fit's sampled distances for A as placed: how far past its bound the
/// farther side is (`over`: the largest of each side's largest distance over
/// that side's bound; 1 at the bound), that distance, and a point where it is
/// (on either surface).
struct Farthest {
  double over = 0.0;
  double distance = 0.0;
  Eigen::RowVector3d where = Eigen::RowVector3d::Zero();
};

struct SmoothedPleats {
  int passes = 0;   ///< passes that kept a move
  Index moves = 0;  ///< vertex moves kept, over all passes
};

/// Up to `passes` passes over P (A's vertices on B) in place. target: B's
/// tree; target_normals: B's vertex normals (#VB by 3). fixed: vertices
/// that never move (held ones, those by the farthest samples); it grows as
/// vertices go back. farthest(P): the fit's distance measure against its
/// bounds; no pass ends past them (over > 1). A pass's work is
/// O(#F log #FB) plus the measure. progress: reported (at 0.99, the fit's
/// end) each pass; cancel throws Cancelled.
SmoothedPleats smooth_pleats(MatrixX3d& P, const MatrixX3i& F, const ClosestPointTree& target, const MatrixX3d& VB,
                             const MatrixX3i& FB, const MatrixX3d& target_normals, double source_side,
                             std::vector<char>& fixed,
                             const std::function<Farthest(const MatrixX3d&)>& farthest, int passes,
                             Progress* progress = nullptr);

}  // namespace paramorph::morph
