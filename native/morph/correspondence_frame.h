// The frame a morph's correspondence is computed in (issue 16): each model
// turned outward, centred on its area-weighted centroid and scaled to unit
// area, so that an inside-out file (faces wound inwards), a model ten times
// smaller or far from the origin is matched like any other. The morph itself
// (the in-betweens) still uses the models as they are placed.
//
// Both models are also turned by one rotation taken from A's shape (issue
// 29): its principal axes, each signed by the skew of the surface along it.
// Every step after (simplification, maps, tips, registrations) then sees
// the same numbers however the scene is turned, while what the user placed
// side by side stays side by side.
#pragma once

#include "mesh/types.h"

namespace paramorph::morph {

struct CorrespondenceFrame {
  bool inside_out = false;     ///< the faces were wound inwards (negative enclosed volume)
  Eigen::RowVector3d centre = Eigen::RowVector3d::Zero();  ///< area-weighted centroid
  double scale = 1.0;          ///< square root of the surface area
  MatrixX3d V;                 ///< (V - centre) / scale
  MatrixX3i F;                 ///< the faces, each reversed when inside_out
};

/// V, F: a closed, consistently oriented mesh (its enclosed volume decides
/// the orientation; not checked here) with positive area.
CorrespondenceFrame correspondence_frame(const MatrixX3d& V, const MatrixX3i& F);

/// A rotation taken from the shape alone (rows: the area-weighted principal
/// axes of the surface, largest spread first, signed so the surface's third
/// moment along the two most skewed is positive, det +1): for V turned by
/// any rotation Q it is this one times Q^T, up to rounding, except for
/// shapes with equal spreads or no skew, whose frame no shape can fix.
/// V, F: positive area.
Eigen::Matrix3d shape_rotation(const MatrixX3d& V, const MatrixX3i& F);

}  // namespace paramorph::morph
