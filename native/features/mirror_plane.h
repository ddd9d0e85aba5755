// A shape's mirror plane (issue 29): the plane a left-right symmetric body
// (an animal, a person, a car) reflects onto itself, found from the shape
// alone, so it turns with the model. Each of the three principal planes
// through the centroid is refined by reflecting the surface, taking each
// vertex's closest point on it as its mirror partner and fitting the plane
// that best swaps the pairs; the one that maps the surface closest onto
// itself wins.
//
// What it is for: tips that are their own mirror image (a muzzle, a tail, a
// trunk) and tips that come in mirrored twins (feet, ears, horns) are
// different things, whatever way they point (morph/tip_path_pairs). A
// grazing cow's muzzle points down and its ears forward-up like a cat's
// muzzle; only the ears have twins.
#pragma once

#include <vector>

#include "mesh/types.h"

namespace paramorph::features {

struct MirrorPlane {
  Eigen::RowVector3d normal = Eigen::RowVector3d::UnitX();  ///< unit
  double offset = 0;          ///< the plane is {x : x . normal = offset}
  double mean_distance = 0;   ///< area-weighted mean distance from the reflected surface to the surface
};

/// V, F: a mesh with positive area (a proxy of a few thousand faces: one
/// closest-point query of every vertex per iteration); area: per vertex, the
/// weights (e.g. a third of the incident faces' areas). iterations >= 1 per
/// principal plane. Raises InvalidInputError for mismatched sizes or no area.
MirrorPlane mirror_plane(const MatrixX3d& V, const MatrixX3i& F, const VectorXd& area, int iterations = 10);

/// How alone each point is under the mirror (0 to 1): its own distance to
/// its reflection against the distance from its reflection to the nearest
/// other point. About 1 for a point on the plane or without a twin, about 0
/// for one of a mirrored pair; a single point is 1.
VectorXd mirror_loneliness(const MatrixX3d& points, const MirrorPlane& plane);

}  // namespace paramorph::features
