// A kept topology fitted to the target's surface (issue 31; not in the
// thesis, whose morph ends on the merged mesh). Keep Source's Topology puts
// A's vertices at their corresponding points on B; A's larger triangles then
// cut across B's curves, and B's thinner parts (legs, a tail, a muzzle) are
// spanned by a few stretched triangles. Rounds of a two-sided fit (a
// symmetric ICP) move the vertices so that the two surfaces lie close both
// ways:
//   1. samples of A's faces (corners and points inside) are drawn to their
//      closest points on B, weighted by their face's share of A's area; a
//      face over 4 times the median area (one drawn out over a horn) is
//      sampled as finely as a median face, the largest first within a
//      budget of as many samples again, so its whole span is drawn onto B
//      and its distance is measured, not only its corners';
//   2. B's vertices are drawn to their closest points on A (held to the face
//      and barycentric point found), weighted by their share of B's area,
//      where that face and B's normal there agree (never across a thin gap
//      to the other side);
//   3. where part of B starts unreached (twice as far from A as A is from
//      B: a horn or a tail the source has nothing for), or is so after 10
//      rounds none of which came closer than the start, the farther side's
//      far samples are weighted up each round, towards the largest distance
//      rather than the mean;
//   4. each round's displacement is smooth: its graph Laplacian over A's
//      edges is penalised with a weight that falls each round (stiff first,
//      so large moves stay coherent; soft last, for the fine fit);
//   5. the held vertices (pins, matched feature tips) stay exactly where they
//      are; where a step would turn a face over (its normal against the one
//      before the step) the step of that face's corners is halved, only
//      there (one tight spot does not hold the whole mesh back), and after
//      12 halvings they stay where they are for the round.
// After the schedule's rounds, softer rounds go on while they still come
// closer (up to twice as many). Where they end farther than 2 % of B's
// diagonal, the rounds run again from A's faces evened out along its own
// surface (morph/even_out_areas.h: a decimated source's vertices then reach
// what its large faces spanned), on a schedule twice as long (its rounds
// reach an unreached horn only once the smoothness has decayed far). The round with the smallest sampled
// two-sided distance is kept, so the fit never ends farther from B than it
// started; then its pleats are smoothed along B within that distance
// (morph/smooth_pleats.h). Every weight is a share of an area: a turn, scale or shift of
// both meshes gives the same answer, moved with them.
#pragma once

#include "common/progress.h"
#include "mesh/types.h"

namespace paramorph::morph {

struct FitToSurfaceOptions {
  /// Rounds of the schedule (the softer late ones still gain: no early
  /// stop within them).
  int rounds = 150;
  /// Then rounds go on, softer still, while the last `patience` of them
  /// came closer, up to twice `rounds` in all: where the schedule ended
  /// short of a horn (the lion onto the horned cow placed otherwise: 3.8 %
  /// after 150 rounds, 3.0 % after 300) it goes on; where it had settled it
  /// stops within `patience`. 0: the schedule alone.
  int patience = 20;
  /// Weight of the displacement's smoothness against the distance terms in
  /// the first round; each later round multiplies it by stiffness_decay.
  /// 1 rather than 0.3: a part drawn out to a horn moves as a whole for
  /// longer (the cat onto the horned cow 3.6 -> 1.8 %).
  double stiffness = 1.0;
  double stiffness_decay = 0.95;
  /// Where the rounds end farther than 2 % of B's diagonal, they run again
  /// from A's faces evened out by this many passes, each moving a vertex
  /// this share of the way to its faces' area-weighted centroid
  /// (morph/even_out_areas.h), and the closer end is kept: a decimated
  /// source's vertices reach the parts of B its large faces spanned (the
  /// lion onto the horned cow 3.65 -> 1.86 %). That run's schedule is
  /// 2 * rounds (then on while it comes closer, up to 4 * rounds): from
  /// the lion's correspondence moved by 1e-7 of the diagonal it ends at
  /// 6.9 % after 150 rounds, 1.8 % after 300. Only then: spot onto the
  /// horned cow ends at 1.66 % from X, 3.06 % from its faces evened. 0: never.
  int even_out_passes = 30;
  double even_out_step = 0.5;
  /// After the rounds, up to this many passes smooth the pleats (faces folded over on B)
  /// along B's surface, never ending farther from B (morph/smooth_pleats.h).
  /// 0: none.
  int smooth_pleats = 20;
};

struct FitToSurface {
  MatrixX3d positions;           ///< #V by 3: the fitted vertices
  int rounds = 0;                ///< rounds that stepped (the schedule's and any after; both runs' when it ran again)
  double distance_before = 0.0;  ///< sampled two-sided distance (largest over the samples) at the start
  double distance_after = 0.0;   ///< the same for `positions`
  /// Share of A's faces whose normal points against B's at the closest
  /// point to their centre (pleats and wrinkles the distance does not see),
  /// at the start and for `positions`.
  double facing_away_before = 0.0, facing_away_after = 0.0;
  Index pleat_moves = 0;         ///< vertex moves the pleat smoothing kept (all passes)
};

/// X, F: A's mesh as it lies on B (#V by 3, #F by 3); VB, FB: the target B.
/// held: vertices of A that do not move. InvalidInputError for malformed
/// arrays, a held index out of range, rounds < 0, patience < 0,
/// even_out_passes < 0, even_out_step outside (0, 1], smooth_pleats < 0, a negative
/// or non-finite stiffness or a decay outside (0, 1]. progress: 0..1 over
/// the rounds; cancel throws Cancelled.
FitToSurface fit_to_surface(const MatrixX3d& X, const MatrixX3i& F, const MatrixX3d& VB, const MatrixX3i& FB,
                            const VectorXi& held, const FitToSurfaceOptions& options = {},
                            Progress* progress = nullptr);

}  // namespace paramorph::morph
