// Cotangent edge weights with every corner angle clamped (thesis 3.2.1):
// w_e = Σ over the faces of e of ½ cot(clamp(angle opposite e)). Clamping to
// [lo, hi] ⊂ (0°, 90°) keeps every weight positive, which the Tutte/Floater
// embedding guarantee and Proposition 3.1 need.
#pragma once

#include "mesh/tri_mesh.h"

namespace paramorph {

/// #E weights aligned with mesh.edges(); a boundary edge gets its one face's half.
VectorXd clamped_cotangent_weights(const TriMesh& mesh, double min_angle_degrees = 5.0,
                                   double max_angle_degrees = 85.0);

}  // namespace paramorph
