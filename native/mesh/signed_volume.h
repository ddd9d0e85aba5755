// The volume a closed mesh encloses, signed by its orientation: how an
// inside-out file (faces wound inwards, as some exporters write them) is told
// from a good one.
#pragma once

#include "mesh/types.h"

namespace paramorph {

/// Sum over faces of det(a, b, c) / 6: positive when the faces of a closed
/// mesh are wound counter-clockwise seen from outside. Meaningless for an
/// open mesh.
double signed_volume(const MatrixX3d& V, const MatrixX3i& F);

}  // namespace paramorph
