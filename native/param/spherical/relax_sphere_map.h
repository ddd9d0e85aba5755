// Isometric relaxation of a sphere map where it is poor: a map read off a
// coarser one and untangled is good almost everywhere, but where the model
// turns against the coarse faces (a tail's tip, an ear) it can keep faces a
// sixth of the sphere long and a hair thin, which any later motion turns
// over. The faces whose isometric energy is far above the map's usual, with
// a few rings round them, are relaxed alone by isometric_sphere_map with
// their rim fixed: the cost is the region's, not the model's.
#pragma once

#include <vector>

#include "mesh/types.h"

namespace paramorph::spherical {

struct RelaxPoorOptions {
  double threshold = 30;  ///< poor: energy ratio above this times the area-weighted median face's
  int rings = 3;          ///< rings of faces round the poor ones that move with them
  int max_steps = 30;     ///< isometric Newton steps of the region
};

struct RelaxPoorResult {
  Index poor_faces = 0;    ///< faces found poor
  Index region_faces = 0;  ///< faces relaxed (the poor ones and their rings)
  int steps = 0;           ///< Newton steps taken
  double worst_before = 0, worst_after = 0;  ///< largest energy ratio of the poor faces
  bool skipped = false;  ///< a face of the region is flat or turned over to rounding: nothing was moved
};

/// V, F: the model; X: #V by 3 unit vectors, fold-free, modified in place;
/// fixed: #V flags (pins: never moved), may be empty.
RelaxPoorResult relax_poor_regions(const MatrixX3d& V, const MatrixX3i& F, MatrixX3d& X,
                                   const std::vector<char>& fixed, const RelaxPoorOptions& options = {});

}  // namespace paramorph::spherical
