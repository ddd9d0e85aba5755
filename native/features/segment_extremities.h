// Segmentation into extremities by the area stretch of a spherical map
// (thesis 3.5.1, Defs. 3.1 and 3.2; DESIGN.md §4.3).
//
// A conformal sphere map shrinks protruding parts (limbs, ears) into small
// regions of the sphere, so their area stretch A (surface share / sphere
// share, per vertex) is high. Seed candidates are the vertices where A is a
// local maximum or minimum over their 1-ring; regions grow from them in
// descending order of A, vertex by vertex in order of closeness to the
// seed's stretch, while |log A(v) - log A(seed)| <= threshold (log, so the
// threshold means the same on a finger as on the torso). A candidate taken
// by an earlier region seeds nothing; vertices no region reached seed new
// regions in the same order, so every vertex and every face is labelled.
// Faces take the label most of their corners have.
#pragma once

#include <optional>

#include "common/progress.h"
#include "features/segmentation.h"

namespace paramorph::features {

struct ExtremityOptions {
  double threshold = 0.7;  ///< largest |log A(v) - log A(seed)| inside a region
  /// #V by 3 unit vectors of a fold-free sphere map; computed (conformal
  /// weights) when absent, which needs a closed genus-0 mesh.
  std::optional<MatrixX3d> sphere;
};

/// Validates the mesh (closed genus 0 when the sphere is computed; any
/// manifold mesh with a matching sphere otherwise) and raises the matching
/// MeshError / InvalidInputError.
Segmentation segment_extremities(const MatrixX3d& V, const MatrixX3i& F,
                                 const ExtremityOptions& options = {},
                                 Progress* progress = nullptr);

/// The region growing alone, on given per-vertex stretch values (> 0).
Segmentation grow_stretch_regions(const TriMesh& mesh, const VectorXd& stretch, double threshold);

}  // namespace paramorph::features
