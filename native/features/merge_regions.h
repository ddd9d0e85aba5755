// Smaller-regions-merge-first (thesis 4.5; DESIGN.md §4.3): segmentations
// by region growing leave slivers and specks along region borders and on
// noise; they are merged into the neighbour they resemble most, smallest
// first, until every region covers at least a given share of the surface.
#pragma once

#include "features/segmentation.h"

namespace paramorph::features {

/// Merges, smallest first, every region whose area is below `min_area` into
/// the adjacent region with the nearest descriptor (Euclidean distance
/// between rows; a merged region's descriptor is the area-weighted mean).
/// `descriptor` is #regions by d (any d >= 1). A region with no neighbour
/// (the only region of its connected component) stays. The absorbing
/// region keeps its seed; regions are renumbered 0.. in their old order and
/// area, centroid and adjacency are recomputed.
void merge_small_regions(const TriMesh& mesh, Segmentation& segmentation, Eigen::MatrixXd descriptor,
                         double min_area);

/// Area-weighted mean of a per-face quantity (#F by d) over each region.
Eigen::MatrixXd region_means(const TriMesh& mesh, const Segmentation& segmentation,
                      const Eigen::MatrixXd& face_values);

}  // namespace paramorph::features
