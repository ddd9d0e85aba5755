// Untangling a planar map with fixed vertices (thesis 2.3.3, Algorithm 2).
//
// Every free vertex moves along the summed area gradients of its inverted
// (or nearly degenerate) triangles — each the opposite edge rotated by 90° —
// plus the shear correction of Fig. 2.10 weighted by (2.26), all vertices at
// once; δ halves whenever the total |area| stops decreasing (such a step is
// undone). Fixed vertices (hard pins, a fixed boundary) never move.
#pragma once

#include <vector>

#include "common/progress.h"
#include "mesh/types.h"

namespace paramorph::planar {

struct UntangleOptions {
  int max_iterations = 10000;
  double min_delta = 1e-12;      ///< stop when δ falls below
  /// β of (2.26) relative to the mean |det| of the faces: triangles with
  /// det <= β are pushed open and sheared back towards their opposite edge.
  double relative_min_area = 1e-3;
};

struct UntangleResult {
  int iterations = 0;
  Index folded = 0;  ///< faces with det <= 0 at the end
};

/// uv: #V by 2, modified in place. fixed: #V flags (1 = never moves).
UntangleResult untangle(const MatrixX3i& F, MatrixX2d& uv, const std::vector<char>& fixed,
                        const UntangleOptions& options = {}, ProgressWindow progress = {});

/// Faces with det(A) <= 0 (inverted or degenerate), ascending.
std::vector<Index> folded_faces(const MatrixX3i& F, const MatrixX2d& uv);

}  // namespace paramorph::planar
