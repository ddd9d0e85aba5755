// A fold-free sphere map that gives every part of the model a share of the
// sphere close to its share of the surface, computed coarse to fine: the
// model is simplified (mesh/simplify) to a few hundred faces, where its
// conformal sphere map (3.3) does not squeeze limbs to rounding; that map is
// relaxed to the isometric sphere map (isometric_sphere_map); each finer
// level is read off the coarser one (map_through_proxy), untangled where the
// finer surface turns against the coarser faces (untangle_sphere_map) and
// relaxed again.
//
// Why (issue 16): the morph needs maps of both models that neither squeeze
// limbs (a horse's legs reach triple products of 1e-17 in the conformal
// map, which the conformal solver's own start cannot lift without folds at
// 20k faces, and the overlay cannot resolve) nor depend on the pose (the
// thesis' radial projection does), computed in seconds.
#pragma once

#include <vector>

#include "common/progress.h"
#include "mesh/types.h"
#include "param/spherical/isometric_sphere_map.h"

namespace paramorph::spherical {

struct BalancedSphereOptions {
  Index coarsest_faces = 600;  ///< the coarsest level starts from its conformal map
  double level_ratio = 8;      ///< faces of a level over those of the next coarser one
  IsometricSphereOptions isometric;
};

struct BalancedSphereResult {
  MatrixX3d positions;              ///< #V by 3 unit vectors, fold-free
  std::vector<Index> level_faces;   ///< faces per level, coarsest first (the model last)
  int steps = 0;                    ///< isometric Newton steps over all levels
  double energy = 0;                ///< isometric energy over its minimum at the model's level
};

/// V, F: a closed genus-0 mesh without degenerate faces (validated; the
/// MeshError subclasses otherwise). Raises ComputeError when a level cannot
/// be untangled, Cancelled through `progress`.
BalancedSphereResult balanced_sphere_map(const MatrixX3d& V, const MatrixX3i& F,
                                         const BalancedSphereOptions& options = {},
                                         Progress* progress = nullptr);

}  // namespace paramorph::spherical
