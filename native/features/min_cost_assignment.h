// Minimum-cost one-to-one assignment (the Hungarian method with potentials,
// Kuhn-Munkres / Jonker-Volgenant form) for feature-region pairing (thesis
// 4.5: regions of one mesh paired with regions of the other by the score
// (4.11)). None of the project's libraries offers one; region counts are
// small (tens), so the dense O(n² m) version is enough.
#pragma once

#include <Eigen/Core>
#include <vector>

#include "mesh/types.h"

namespace paramorph::features {

/// cost: n by m, finite. Pairs min(n, m) rows with distinct columns so the
/// summed cost is least. Returns n entries: the column of each row, or -1 for
/// the rows left out when n > m. Deterministic (ties go the same way on every
/// run). Throws InvalidInputError for a non-finite cost.
std::vector<Index> min_cost_assignment(const Eigen::MatrixXd& cost);

}  // namespace paramorph::features
