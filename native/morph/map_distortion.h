// How much a morph's correspondence distorts, with no ground truth (issue
// 16: automatic correspondences are scored before one is used): every
// vertex of B is read on A through the two sphere maps (its point on B's map
// located in A's map, then A's barycentric interpolation in 3D), and every
// face of B is compared with its image on A. With both surfaces scaled to
// the same area, a faithful correspondence between like shapes is close to
// an isometry; a leg carried onto a flank, a head onto a tail, or a mirror
// image is stretched, squeezed or turned over.
//
// Per face: the singular values s1, s2 of the linear map from B's triangle
// to its image (in the image's tangent plane, A's interpolated normal), and
// the isometric distortion (ln s1)^2 + (ln s2)^2, capped at `cap`; an image
// turned over against A's normal counts as the cap. The measure is the
// area-weighted mean over B.
#pragma once

#include "mesh/types.h"

namespace paramorph::morph {

struct MapDistortion {
  double mean = 0;           ///< area-weighted mean of the capped per-face distortion
  double folded_share = 0;   ///< share of B's area whose image is turned over
  double capped_share = 0;   ///< share of B's area at the cap (folded ones included)
  VectorXd per_face;         ///< #FB capped distortion per face of B
};

/// VA, FA, sphere_a: model A and a fold-free sphere map of it; VB, FB: model
/// B; sphere_b: #VB points of B on the sphere (any non-zero directions: a
/// fold-free map, or targets that fold). `cap` bounds a face's distortion
/// ((ln 10)^2 x 2 by default: a factor 10 of stretch in both directions).
MapDistortion map_distortion(const MatrixX3d& VA, const MatrixX3i& FA, const MatrixX3d& sphere_a,
                             const MatrixX3d& VB, const MatrixX3i& FB, const MatrixX3d& sphere_b,
                             double cap = 10.6);

/// Where each vertex of B lands on A through the maps (#VB by 3 points of A).
MatrixX3d carry_through_maps(const MatrixX3d& VA, const MatrixX3i& FA, const MatrixX3d& sphere_a,
                             const MatrixX3d& sphere_b);

}  // namespace paramorph::morph
