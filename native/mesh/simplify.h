// A coarser copy of a mesh with the same topology: CGAL's edge collapse
// (Lindstrom-Turk cost and placement; an edge collapses only where its link
// condition keeps the surface manifold and of the same genus). The morph
// scores its candidate correspondences on such proxies (issue 16: a
// 97k-face model scored on a few thousand faces).
#pragma once

#include "common/progress.h"
#include "mesh/types.h"

namespace paramorph {

struct SimplifiedMesh {
  MatrixX3d V;          ///< #P by 3 proxy vertices (moved by the placement)
  MatrixX3i F;          ///< proxy faces, orientation kept
  VectorXi proxy_of;    ///< #V_in: the proxy vertex each input vertex was collapsed into
};

/// V, F: a closed, manifold, consistently oriented triangle mesh (checked:
/// InvalidInputError); target_faces: stop once this many faces are left (or
/// no edge may collapse). A mesh already that small comes back as it is.
/// progress: 0..1 while edges are collected and collapsed (a 97k-face mesh
/// takes seconds); cancel throws Cancelled.
SimplifiedMesh simplify(const MatrixX3d& V, const MatrixX3i& F, Index target_faces,
                        Progress* progress = nullptr);

}  // namespace paramorph
