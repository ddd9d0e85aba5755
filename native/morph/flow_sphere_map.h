// A fold-free sphere map carried by the smooth flow that takes some points
// to others (morph/sphere_warp), step by step, every step checked: where a
// step would turn a face over, the map round it is smoothed (fold-free) and
// the step tried again, then halved. Pinned vertices ride on their points
// exactly, so they end exactly where their points go.
//
// The morph (issue 16) uses it twice for B's map: first a short flow takes
// the chosen candidate's map, read through B's proxy (untangled, relaxed),
// the last stretch onto the exact pins and pairs; where that stalls, B's own
// balanced map is carried the whole way, pins, pairs and a registration's
// samples as the points. Given `model`, a stalled flow relaxes the poorly
// shaped regions (relax_poor_regions) and goes on, a few times at most.
#pragma once

#include <utility>
#include <vector>

#include "common/progress.h"
#include "mesh/types.h"

namespace paramorph::morph {

struct SphereFlowOptions {
  double first_step = 1.0 / 16;  ///< share of the way of the first step
  double smallest_step = 1.0 / 4096;  ///< below this the flow stalls
  /// Where a step would turn faces over, the map round them is smoothed
  /// (smooth_sphere_map) and the step tried again, this many times before
  /// it is halved.
  int repairs_per_step = 6;
  /// The model (#V by 3) when known: where the flow stalls, the map's poor
  /// regions (faces far from isometric, as the squeezed ones are) are
  /// relaxed by isometric Newton steps with the pinned vertices fixed
  /// (relax_poor_regions), and the flow goes on, at most this many times.
  const MatrixX3d* model = nullptr;
  int relaxations = 3;
};

struct SphereFlowResult {
  MatrixX3d positions;   ///< fold-free; pinned rows exactly on their points
  double reached = 0;    ///< share of the way travelled (1: all the way)
  int steps = 0;         ///< accepted steps
  int halved = 0;        ///< steps halved because a face would fold
  int repairs = 0;       ///< smoothings round faces a step would fold
  int relaxations = 0;   ///< isometric relaxations where the flow stalled
  /// When stalled: the points nearest the faces the smallest step would
  /// fold, nearest first (at most 4).
  std::vector<Index> blocking;
};

/// F: faces; X: #V by 3 unit vectors, fold-free (triple products > -1e-13);
/// from, to: #k by 3 unit vectors (distinct rows of `from`); pinned: (vertex,
/// row of from/to) pairs, the vertex put on its point at every step
/// (exactly on `to` at the end). Raises InvalidInputError for shapes and
/// ranges, Cancelled.
SphereFlowResult flow_sphere_map(const MatrixX3i& F, const MatrixX3d& X, const MatrixX3d& from, const MatrixX3d& to,
                                 const std::vector<std::pair<Index, Index>>& pinned,
                                 const SphereFlowOptions& options = {}, ProgressWindow progress = {});

}  // namespace paramorph::morph
