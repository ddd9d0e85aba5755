// Separate parts of a character riding along its morphing body (issue 31;
// not in the thesis, whose morph takes one genus-0 surface): eyes, teeth,
// buttons, a lid. The body is morphed; each other part is carried, keeping
// its own shape, by the motion of the patch of body around where it sits:
//
//   1. a part rides along when it sits on or near the body (its gap at most
//      its own size or attach_share of the body's diagonal); at rest, its closest points on the body and the body vertices
//      grown from them across the body's edges while within patch_scale
//      times the part's size of their centre (at least min_patch vertices)
//      make its patch, weighted by a Gaussian of that distance;
//   2. at any shape of the body, the weighted similarity (rotation, uniform
//      scale, translation: Kabsch with Umeyama's scale) taking the patch from
//      rest to now moves the part rigidly;
//   3. the part may not sink deeper into the body than it sat at rest (eyes
//      in their sockets sit partly inside): its deepest vertex is measured by
//      closest points and angle-weighted pseudonormals (inside where the
//      offset points against the normal of the face, edge or vertex it is
//      closest to, exact for a closed, outward mesh), and the part is pushed
//      out along the patch's normal until it sits no deeper.
#pragma once

#include <vector>

#include "mesh/types.h"

namespace paramorph::morph {

struct RideAlongOptions {
  /// The patch reaches this many times the part's size (its largest
  /// distance from its centre, or its gap to the body if larger) from the
  /// centre of its closest points on the body.
  double patch_scale = 1.5;
  /// The fewest body vertices a patch holds (grown ring by ring past the reach).
  Index min_patch = 12;
  /// A part rides along when its gap to the body is at most its own size or
  /// this share of the body's diagonal, whichever is larger; a part farther
  /// off (another object in the same mesh) stays where it was.
  double attach_share = 0.1;
};

/// Where each part's vertices are at one shape of the body.
struct CarriedParts {
  MatrixX3d positions;  ///< #P by 3, the parts' vertices in the rows given
  VectorXd pushed;      ///< per part: how far it was pushed out of the body (0: not)
};

/// Solver object: attach once, carry at every key (`at`).
class PartRider {
 public:
  /// body_V, body_F: the body at rest, a closed mesh facing outward.
  /// part_V: #P by 3, every part vertex at rest; part_of: #P labels in
  /// [0, #parts) saying which part each vertex belongs to (every label used).
  /// InvalidInputError for malformed arrays, labels out of range or unused,
  /// or a body with no face of non-zero area.
  PartRider(const MatrixX3d& body_V, const MatrixX3i& body_F, const MatrixX3d& part_V, const VectorXi& part_of,
            const RideAlongOptions& options = {});

  /// The parts carried by the body at `body_now` (#body_V by 3, the same
  /// faces). At body_now == the rest shape, the parts are where they were.
  CarriedParts at(const MatrixX3d& body_now) const;

  Index parts() const { return Index(patches_.size()); }
  /// Per part, the body vertices of its patch (ascending).
  const std::vector<std::vector<Index>>& patches() const { return patches_; }
  /// Per part, how deep its deepest vertex sat inside the body at rest (0:
  /// outside or touching).
  const VectorXd& rest_depth() const { return rest_depth_; }
  /// Per part, its gap to the body at rest (0: touching or inside).
  const VectorXd& rest_gap() const { return rest_gap_; }
  /// Per part, whether it rides along (else `at` leaves it where it was).
  const std::vector<bool>& riding() const { return riding_; }

 private:
  MatrixX3d body_rest_;
  MatrixX3i body_F_;
  MatrixX3d part_rest_;
  std::vector<std::vector<Index>> members_;  ///< per part, its rows of part_rest_
  std::vector<std::vector<Index>> patches_;
  std::vector<VectorXd> weights_;  ///< per part, one weight per patch vertex
  VectorXd rest_depth_, rest_gap_;
  std::vector<bool> riding_;
};

/// Per query point, its signed distance to the closed, outward mesh (V, F):
/// negative inside. Through closest points and angle-weighted pseudonormals
/// (Baerentzen and Aanaes 2005).
VectorXd signed_distance(const MatrixX3d& V, const MatrixX3i& F, const MatrixX3d& points);

}  // namespace paramorph::morph
