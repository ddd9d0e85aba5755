// Segmentation into extremities by the area stretch of a spherical map
// (thesis 3.5.1, Defs. 3.1 and 3.2; DESIGN.md §4.3).
//
// A conformal sphere map shrinks protruding parts (limbs, ears) into small
// regions of the sphere, so their area stretch A (surface share / sphere
// share, per vertex) is high and rises towards the tip. The body's level is
// the median of log A over the sphere (where extremities weigh almost
// nothing); the surface more than `threshold` above it is split into
// extremities by the join-tree sweep of features/peak_regions.h, seeded at
// the local maxima of A (Def. 3.2) in descending order, and the rest is the
// body. The threshold is on log A, so it means the same on a finger as on
// the torso. Regions smaller than `min_area` are then merged into their
// neighbour of the nearest mean log A, smallest first (4.5).
#pragma once

#include <optional>

#include "common/progress.h"
#include "features/segmentation.h"

namespace paramorph::features {

struct ExtremityOptions {
  /// Variation of log A a region must span to stand on its own (1.5 = a
  /// factor 4.5 of stretch between its seed and where it meets another region).
  double threshold = 1.5;
  /// Regions below this share of the surface area are merged away (0 keeps all).
  double min_area = 0.01;
  /// #V by 3 unit vectors of a fold-free sphere map; computed (conformal
  /// weights) when absent, which needs a closed genus-0 mesh.
  std::optional<MatrixX3d> sphere;
};

/// Validates the mesh (closed genus 0 when the sphere is computed; any
/// manifold mesh with a matching sphere otherwise) and raises the matching
/// MeshError / InvalidInputError. Every face is labelled.
Segmentation segment_extremities(const MatrixX3d& V, const MatrixX3i& F,
                                 const ExtremityOptions& options = {},
                                 Progress* progress = nullptr);

/// The region growing alone, on given per-vertex stretch values (> 0);
/// min_area is a share of the surface area as in ExtremityOptions.
Segmentation grow_stretch_regions(const TriMesh& mesh, const VectorXd& stretch, double threshold,
                                  double min_area = 0.0);

}  // namespace paramorph::features
