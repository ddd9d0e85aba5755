// How far one surface is from another (issue 17: the source's own topology
// sampled on the target, against the target): one-sided distances sampled at
// the vertices, edge midpoints and face centroids, through closest points
// on the other surface (CGAL AABB tree, mesh/closest_points.h).
#pragma once

#include "common/progress.h"
#include "mesh/types.h"

namespace paramorph {

struct SurfaceDistance {
  double a_to_b = 0, b_to_a = 0;            ///< largest distance from a sample of one to the other
  double mean_a_to_b = 0, mean_b_to_a = 0;  ///< mean over the samples
  /// The Hausdorff distance (sampled): max(a_to_b, b_to_a).
  double hausdorff() const { return a_to_b > b_to_a ? a_to_b : b_to_a; }
};

/// VA, FA and VB, FB: triangle meshes (each with a face of non-zero area).
/// InvalidInputError for malformed arrays. progress: 0..1 over the queries
/// (a 370k-face mesh takes seconds); cancel throws Cancelled.
SurfaceDistance surface_distance(const MatrixX3d& VA, const MatrixX3i& FA, const MatrixX3d& VB, const MatrixX3i& FB,
                                 Progress* progress = nullptr);

}  // namespace paramorph
