// Ways to pair the extremity tips of two models (issue 16: legs with legs,
// head with head, tail with tail): every ordered pair of tips of A with
// every ordered pair of B fixes a rotation of B's sphere map onto A's (the
// two-point Kabsch fit), and under it each tip of B goes with the tip of A
// it is mutually nearest to, if within max_angle. The distinct assignments
// are ranked by how many tips they pair, then by their mean angle. Only
// rotations are tried, so no assignment asks for a mirror image; which of
// them is right is for the correspondence score to decide
// (morph/correspondence).
#pragma once

#include <array>
#include <vector>

#include "mesh/types.h"

namespace paramorph::morph {

struct TipAssignment {
  std::vector<std::array<Index, 2>> pairs;  ///< (row of tips_a, row of tips_b), ascending
  double mean_angle = 0;                    ///< radians between paired tips under the rotation
};

/// tips_a, tips_b: the tips' points on the two sphere maps (unit vectors).
/// Assignments of at least two pairs, the best first, at most max_count.
std::vector<TipAssignment> tip_assignments(const MatrixX3d& tips_a, const MatrixX3d& tips_b, double max_angle,
                                           std::size_t max_count);

}  // namespace paramorph::morph
