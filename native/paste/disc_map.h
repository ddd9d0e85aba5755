// A fold-free planar map of the target's disc under a pasted feature (thesis
// ch. 2 and 5.2; DESIGN.md §4.5): the paste's parameterization of the target
// where the discrete exponential map (paste/exponential_map.h) folds.
//
// The disc (paste/disc_region.h) is mapped by the project's constrained
// isometric solver (param/planar/isometric_map.h) with a free boundary,
// started from Tutte's map (boundary on a circle by arc length, clamped
// cotangent weights: positive, so the start is an embedding, Floater 1997);
// the solver's barrier keeps every step fold-free while it brings lengths
// and areas towards the surface's, so distances from the anchor follow the
// surface. The map is then moved so the anchor point lands on the origin and
// turned (and scaled, uniformly about the anchor) to agree with the
// exponential map near the anchor, where that is still fold-free: the
// least-squares similarity onto its coordinates at the `reference` vertices.
// So the anchor's frame means the same in both maps (rotation turns the
// feature the same way) and the feature keeps its size: the isometric
// map's scale is an average over the whole disc, and on a strongly curved
// one (a hemisphere) it differs from geodesic distance at the anchor by
// several percent, which a feature's slopes show. With fewer than 3 reference
// vertices the map is only turned, to fit the anchor face's corners and
// their neighbours laid in the anchor's tangent plane at full length, as the
// exponential map seeds them. Never reflected: a face counter-clockwise seen
// along the target's normal is counter-clockwise in the map.
#pragma once

#include <Eigen/Core>
#include <utility>
#include <vector>

#include "mesh/tri_mesh.h"
#include "paste/disc_region.h"

namespace paramorph::paste {

struct DiscMapOptions {
  /// At most this many L-BFGS iterations of the isometric solver after the
  /// Tutte start (0: the Tutte map, scaled to the disc's area, as it is).
  /// Measured on a scan-like disc of 3k faces: the Tutte start has L2
  /// stretch rms 0.177 and area ratios 0.09-2.9; 10 iterations 0.096 and
  /// 0.49-1.9, the same as converged (23 iterations) to 3 digits.
  int iterations = 12;
  double tol = 1e-4;  ///< relative energy decrease over 10 iterations at which it stops earlier
};

struct DiscMap {
  std::vector<Eigen::Vector2d> q;  ///< #V: coordinates of the disc's vertices (0 elsewhere), mesh units
  int iterations = 0;              ///< solver iterations used
  double scale = 1;                ///< the factor of the fit to the reference (1 without one)
};

/// mesh: the target; region: a disc from grow_disc_region; anchor_face and
/// bary: where the anchor lies (barycentric in the face); tangent, normal:
/// orthonormal, the anchor's frame. reference: vertices near the anchor with
/// the coordinates the map should agree with there (the exponential map,
/// where it is fold-free), in the mesh's units; may be empty.
DiscMap disc_map(const TriMesh& mesh, const DiscRegion& region, Index anchor_face, const Eigen::Vector3d& bary,
                 const Eigen::Vector3d& tangent, const Eigen::Vector3d& normal,
                 const std::vector<std::pair<Index, Eigen::Vector2d>>& reference, const DiscMapOptions& options = {});

}  // namespace paramorph::paste
