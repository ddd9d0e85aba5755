// Untangling a sphere map that folds in a few small places (a morph's
// correspondence carried through two sphere maps folds only where B's faces
// straddle kinks of the carrying map: 781 faces in 271 clusters of a
// 70k-face bunny). Each cluster of folded faces is cut out with a few rings
// of faces around it, laid flat by the gnomonic projection (great circles
// become straight lines, so a face keeps its orientation), untangled with
// the patch's boundary and the pinned vertices fixed by the planar
// untanglers (thesis Algorithm 2, then the epsilon-continuation of
// param/planar, with the model's own triangles as the shapes to keep), and
// put back. Where that fails, the patch grows by a ring and is tried again.
//
// A log barrier cannot start from a folded map, and its own opening rounds
// untangle slowly (measured on the bunny above: 781 folded faces to 696
// after 300 Newton steps).
#pragma once

#include <vector>

#include "mesh/types.h"

namespace paramorph::spherical {

struct SphereUntangleOptions {
  int first_rings = 2;   ///< rings of faces around a cluster in its first patch
  int max_rings = 10;    ///< give up on a cluster past this
  /// A patch must lie within this angle (radians) of its centre: the
  /// gnomonic projection stretches towards the horizon.
  double max_patch_angle = 1.2;
};

struct SphereUntangleResult {
  Index folded_before = 0;  ///< faces with a triple product <= 0 at the start
  Index folded = 0;         ///< at the end (0 on success)
  int patches = 0;          ///< patches untangled
  int largest_rings = 0;    ///< rings of the widest patch that was needed
};

/// V, F: the model (its triangles are the shapes the untangling keeps);
/// X: #V by 3 unit vectors, modified in place; fixed: #V flags (pins: never
/// moved). Faces with all corners fixed are left as they are.
SphereUntangleResult untangle_sphere_map(const MatrixX3d& V, const MatrixX3i& F, MatrixX3d& X,
                                         const std::vector<char>& fixed,
                                         const SphereUntangleOptions& options = {});

}  // namespace paramorph::spherical
