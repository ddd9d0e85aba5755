// Feature points: local extrema of the concavity intensity inside feature
// regions (thesis 4.5, Def. 4.2; DESIGN.md §4.3). They summarise the
// concave and convex parts of an object and are paired between two meshes
// after their regions are matched (morphing, ch. 4).
//
// A concave point is a vertex whose intensity I is positive and highest in
// its 1-ring (the bottom of a pocket). On the convex hull I is zero over
// whole patches, so among hull vertices the extremum is taken on the
// distance from the mesh centroid (the tip of a nose or a boss): a convex
// point is a hull vertex farther out than every hull neighbour. Ties go to
// the lower index. Within each region, points closer than `spacing` to a
// more extreme point of the same kind are dropped.
#pragma once

#include <vector>

#include "mesh/tri_mesh.h"

namespace paramorph::features {

struct FeaturePointOptions {
  /// Smallest distance between two points of one kind in one region, as a
  /// share of the bounding-box diagonal.
  double spacing = 0.05;
};

struct FeaturePoints {
  std::vector<Index> vertices;  ///< the feature points, most extreme first within each region
  std::vector<Index> regions;   ///< per point, the region of the faces around it (majority)
  std::vector<int> kinds;       ///< per point, +1 concave (a pocket's bottom), -1 convex (a tip)
};

/// V, F: the mesh; face_labels: #F regions (e.g. Segmentation::face_labels);
/// concavity: #V intensities (Def. 4.1, e.g. from features::concavity).
FeaturePoints feature_points(const MatrixX3d& V, const MatrixX3i& F, const VectorXi& face_labels,
                             const VectorXd& concavity, const FeaturePointOptions& options = {});

}  // namespace paramorph::features
