// Radial projection of a mesh onto the unit sphere from its area-weighted
// centroid (thesis 4.3.3: the v_i^0 the optimized map stays close to).
#pragma once

#include "mesh/types.h"

namespace paramorph::morph {

/// #V by 3 unit vectors (V_i - c) / |V_i - c|, c the area-weighted centroid
/// of the faces; a vertex at c itself gets (0, 0, 1).
MatrixX3d radial_projection(const MatrixX3d& V, const MatrixX3i& F);

}  // namespace paramorph::morph
