// The tips of a segmentation's extremities (thesis 3.5.1: limbs, head,
// tail, ears found by segment_extremities): the peaks of the distance along
// the surface from the body, each standing at least `prominence` above where
// it meets a higher one (the join-tree sweep of features/peak_regions), so a
// head carries its muzzle and, if they stand out, its horns and ears. These
// are the points an animator would pin first (hooves, muzzle, tail tip), and
// the automatic correspondence of a morph pairs them (morph/correspondence).
#pragma once

#include <vector>

#include "features/segmentation.h"

namespace paramorph::features {

struct ExtremityTips {
  Index body = -1;               ///< the body: the region of largest area
  std::vector<Index> vertices;   ///< the tips, farthest from the body first
  std::vector<Index> regions;    ///< each tip's extremity (region of the segmentation)
  std::vector<double> lengths;   ///< edge-path distance from the body to the tip
};

/// V, F: the mesh that `segmentation` labels (every face); prominence: in
/// the units of V, how far a peak must rise above where it meets a higher
/// one (0: one tip per extremity, its farthest vertex). No tips when there
/// is one region.
ExtremityTips extremity_tips(const MatrixX3d& V, const MatrixX3i& F, const Segmentation& segmentation,
                             double prominence = 0);

}  // namespace paramorph::features
