// A kept topology's faces evened out along its own surface, the start of
// the fit's second run (issue 31; not in the thesis; morph/fit_to_surface.h).
// The correspondence puts A's vertices on B as densely as A's own mesh has
// them: a decimated source (the lion on the horned cow: its median face a
// quarter of the mean, its largest fifty times) leaves
// parts of B under a few large faces (3 of the lion's vertices within 5 %
// of the diagonal under the horned cow's head, against 391 of the cow's),
// and no pull of the fit slides vertices that far along B. Each pass moves
// every free vertex by `step` of the way to the area-weighted centroid of
// its faces' centroids, within its own tangent plane (a large face draws
// its corners in, so the faces tend to equal areas); where a move would turn
// a face over, that face's corners move half as far, up to 12 times, then
// not at all. The fit's rounds then draw the vertices back onto B.
// Measured: the lion onto the horned cow 3.65 -> 1.86 %.
#pragma once

#include <vector>

#include "mesh/types.h"

namespace paramorph::morph {

/// X, F: A's mesh (#V by 3, #F by 3). movable[v]: whether vertex v may move
/// (held ones stay exactly). passes >= 0, step in (0, 1]. Returns the moved
/// vertices (#V by 3). Its work is O(passes #F).
MatrixX3d even_out_areas(const MatrixX3d& X, const MatrixX3i& F, const std::vector<char>& movable, int passes,
                         double step);

}  // namespace paramorph::morph
