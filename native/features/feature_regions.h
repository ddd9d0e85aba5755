// Feature regions by concavity and normal variation (thesis 4.5, Def. 4.1;
// DESIGN.md §4.3).
//
// The concavity intensity I(v) (distance to the convex hull) separates the
// soft features: pockets (eye sockets, the gap between ribs) are where I
// rises more than `concavity_threshold` above the hull, split by the
// join-tree sweep of features/peak_regions.h so that two pockets that meet
// stay two regions. Rapid variations of the surface normal separate the
// hard features: regions never grow across an edge whose dihedral angle
// exceeds `normal_angle` (the rim of a boss, the sides of a rib). Pieces of
// one plane (a CAD part's flat side, cut by the concavity sweep) are joined
// again; then small regions are merged into the most similar neighbour
// (mean normal and mean concavity), smallest first.
#pragma once

#include <optional>

#include "common/progress.h"
#include "features/segmentation.h"

namespace paramorph::features {

struct FeatureRegionOptions {
  /// Largest angle (degrees) between the normals of two faces sharing an
  /// edge inside one region.
  double normal_angle = 40.0;
  /// Depth below the convex hull, as a share of the bounding-box diagonal,
  /// that a pocket must reach to be a region of its own.
  double concavity_threshold = 0.02;
  /// Regions below this share of the surface area are merged away (0 keeps all).
  double min_area = 0.005;
  /// #V concavity intensities (Def. 4.1) when already known; computed otherwise.
  std::optional<VectorXd> concavity;
};

/// Any manifold triangle mesh (open or closed, any genus); validates it and
/// raises the matching MeshError / InvalidInputError. Every face is labelled.
Segmentation feature_regions(const MatrixX3d& V, const MatrixX3i& F,
                             const FeatureRegionOptions& options = {},
                             Progress* progress = nullptr);

/// The region growing alone, on a mesh and its per-vertex concavity.
Segmentation grow_feature_regions(const TriMesh& mesh, const VectorXd& concavity,
                                  const FeatureRegionOptions& options);

}  // namespace paramorph::features
