// Regions of a per-vertex level by a join-tree sweep from the peaks (thesis
// 3.5.1 and 4.5; DESIGN.md §4.3): the region growing shared by the
// extremity segmentation (level = log area stretch) and the feature regions
// (level = concavity intensity).
//
// Vertices more than `threshold` above `base` are swept from the top,
// starting a region at each seed candidate (a local maximum, Def. 3.2) and
// joining every other vertex to the region of its higher neighbours, as
// water would recede from the peaks. Where growing regions meet, a region
// whose level has fallen by at least `threshold` since its seed (a limb, a
// deep pocket) stops; one that varied less (a bump) is absorbed, and the
// surface further down continues as one region (a palm below the fingers).
// The rest of the surface is one region per connected part, grown from its
// lowest vertex (a local minimum). O(n log n).
#pragma once

#include "features/segmentation.h"

namespace paramorph::features {

/// level: #V finite values; threshold > 0. Faces take the region most of
/// their corners have (three different: the corner closest in level to its
/// region's seed); regions left with no face are dropped and a region in
/// several edge-connected pieces becomes one region per piece (seeded at its
/// highest vertex). Area, centroid and adjacency are filled in.
Segmentation peak_regions(const TriMesh& mesh, const VectorXd& level, double base,
                          double threshold);

}  // namespace paramorph::features
