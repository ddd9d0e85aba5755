// Feature point pairs after registration (thesis 4.5, (4.12) needs pairs;
// DESIGN.md §4.4 step 2): once B is registered onto A in 3D
// (register_surfaces), a feature point of A and one of B of the same kind
// (concave / convex) are paired when each is the other's nearest and they
// are closer than a bound. Unlike pairing after region-centroid alignment,
// this sees the whole registered surface, so a tip is not left unpaired
// because its region's centroid moved, and the many near-equivalent points
// of a concave ring around a bump only pair where they actually meet.
#pragma once

#include <array>
#include <vector>

#include "mesh/types.h"

namespace paramorph::morph {

struct PointPairs {
  std::vector<std::array<Index, 2>> pairs;  ///< (row of PA, row of PB), ascending by PA's row
  std::vector<double> distances;            ///< per pair, |PA - PB|
};

/// PA, kinds_a: A's feature points and their kinds; PB, kinds_b: B's, in A's
/// frame (registered); max_distance: largest distance of a pair.
/// Ties: the lower row. Raises InvalidInputError for mismatched sizes.
PointPairs pair_nearest_points(const MatrixX3d& PA, const std::vector<int>& kinds_a,
                               const MatrixX3d& PB, const std::vector<int>& kinds_b,
                               double max_distance);

}  // namespace paramorph::morph
