// A step of a mesh's vertices that turns no face over: the fit's rounds
// (morph/fit_to_surface.cpp) and the evening-out of its second start
// (morph/even_out_areas.cpp) both move every vertex at once and must leave
// each face facing the way it did.
#pragma once

#include "mesh/types.h"

namespace paramorph {

/// from: #V by 3 positions of mesh F (#F by 3); from_normals: #F by 3,
/// face_normal(from, F, f) for each face (the callers have them already);
/// move: #V by 3 proposed displacements. Each vertex takes a share s_v of its move, starting at 1:
/// while a face would turn over (its normal's dot product with its normal
/// at `from` <= 0; faces of zero area at `from` are not checked), the
/// shares of its three corners are halved, and after `halvings` halvings
/// set to 0 (those vertices stay). Returns from + s .* move; `shares` (if
/// given) receives s (#V), so a caller can tell a step in which no vertex
/// moved (all zero).
MatrixX3d step_without_turning(const MatrixX3d& from, const MatrixX3d& from_normals, const MatrixX3d& move,
                               const MatrixX3i& F, int halvings, VectorXd* shares = nullptr);

}  // namespace paramorph
