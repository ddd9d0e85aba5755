// The patch of the target around where a feature lands, and its
// parameterization (thesis 5.2: "we project the feature boundary on the base
// surface and use the corresponding (s,t) parameterization coordinates";
// DESIGN.md §4.5 step 2).
//
// The patch: every face with a vertex within a path radius of the anchor
// along mesh edges (Dijkstra), grown until the map holds a disc of `radius`
// around the anchor (edge paths overestimate distances). It must be a disc. Its map: the free-boundary
// least-squares conformal map (planar::lscm_map), moved so the anchor is at
// uv = 0, the map's scale there is 1 and the reference direction (projected
// onto the surface at the anchor) points along +u, with +v turning towards it
// counter-clockwise seen from the surface's outside (n = e_u x e_v). A
// conformal map keeps shapes, and near the anchor sizes: the pasted feature
// is placed by it, not stretched by it.
#pragma once

#include <Eigen/Core>

#include "mesh/tri_mesh.h"

namespace paramorph::paste {

struct TargetPatch {
  VectorXi faces;          ///< the patch's faces, indices into the target's F
  VectorXi vertices;       ///< its vertices, indices into the target's V (local vertex k is vertices[k])
  MatrixX3i local_faces;   ///< #faces by 3, local vertex numbers, the target's orientation
  MatrixX2d uv;            ///< per local vertex, the normalised conformal map
  Index anchor_face = -1;  ///< target face holding the anchor
  Eigen::Vector3d anchor_bary = Eigen::Vector3d::Zero();
  Eigen::Vector3d anchor_point = Eigen::Vector3d::Zero();
  Eigen::Vector3d normal = Eigen::Vector3d::Zero();   ///< unit surface normal at the anchor (outside)
  Eigen::Vector3d tangent = Eigen::Vector3d::Zero();  ///< unit surface direction that maps to +u
  /// Smallest distance in uv from the anchor to the patch's boundary (>= the
  /// radius asked for): a disc of this radius around uv = 0 lies inside.
  double reach = 0;
};

/// target: a valid manifold triangle mesh (faces counter-clockwise seen from
/// outside). anchor_face, anchor_bary: where the anchor is (barycentric
/// coordinates, >= 0, summing to 1). reference: any direction not along the
/// normal (world X is tried next, then Y). radius > 0, in the target's units.
/// Throws TargetTooSmallError when the patch would be the whole target, is
/// not a disc (it wraps around a handle or a thin part) or cannot hold the
/// disc, InvalidInputError for bad arguments.
TargetPatch target_patch(const TriMesh& target, Index anchor_face, const Eigen::Vector3d& anchor_bary,
                         const Eigen::Vector3d& reference, double radius);

}  // namespace paramorph::paste
