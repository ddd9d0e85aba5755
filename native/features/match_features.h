// Automatic feature matching between two meshes (thesis 4.5, Fig. 4.8;
// DESIGN.md §4.3, §4.4 step 2): feature regions and feature points of both
// meshes, their reduced region graphs, a rotation aligning them, region
// pairs by the similarity (4.11) and feature point pairs.
//
// The two meshes may differ in position, scale, orientation and
// triangulation. What is done, in order:
//  1. Per mesh: concavity (Def. 4.1), feature_regions, feature_points and
//     region_graph. The thresholds that are shares of "the bounding-box
//     diagonal" are taken of the box in the mesh's principal axes
//     (area-weighted second moments), so turning a mesh does not change
//     what is found (for a mesh already aligned with its principal axes
//     this is its ordinary bounding box).
//  2. Normalisation: each mesh's area-weighted centroid moves to the origin
//     and it is scaled to unit RMS radius (area-weighted root mean square
//     distance of its surface from the centroid). Region centroids c, areas
//     a (shares of the mesh's area) and degrees d (in the reduced graphs,
//     counted as at least 1) enter the score (4.11):
//        s_ij = |c_i - R c_j| max(a_i, a_j) / min(a_i, a_j) max(d_i, d_j) / min(d_i, d_j),
//     lower is better, in units of the RMS radius.
//  3. Rotation R (B onto A). The thesis matches the two highest-degree
//     nodes and aligns; one direction pair leaves a twist, so a candidate
//     comes from two correspondences: a top region i of A with a top region
//     j of B (the `alignment_nodes` regions of highest degree, ties: larger
//     area first), and i' with j', each a neighbour in the reduced graph or
//     another top region; R best turns (c_j, c_j') onto (c_i, c_i')
//     (orthogonal Procrustes about the origin, det +1). Pairs of
//     correspondences whose rigid invariants (|c|, |c - c'|) differ by
//     more than max_region_score are skipped. A candidate's cost is the least
//     total of min(s_ij, max_region_score) over a one-to-one pairing
//     (min_cost_assignment). The 8 cheapest, the 24 rotations taking B's
//     principal axes onto A's (any order and direction: they cover shapes
//     whose graphs are stars around a central region, whose centroid gives
//     no direction) and the identity (artists usually model in one
//     orientation) are refined by ICP on the region centroids (Procrustes on
//     the pairs below the cap weighted by the smaller area share, pair
//     again, while the cost falls; also coarse to fine from 4 and 2 times
//     the cap, so a rough start still has pairs). The cheapest wins; the
//     identity-started one wins unless another is cheaper by more than 5
//     per cent (a symmetric object keeps the pose it was modelled in).
//  4. Region pairs: the one-to-one pairing under R, without pairs scoring
//     max_region_score or more, nor pairs scoring more than
//     outlier_factor times the median pair score (and more than a tenth of
//     max_region_score, so near-perfect matches do not make good ones
//     outliers).
//  5. Point pairs: for each region pair (i, j), B is turned by R and moved so
//     c_j lands on c_i; points of one kind (concave/convex) in the two
//     regions (a point counts in every region among its faces, so a corner
//     on a border is found from either side) are candidates when they lie
//     within max_point_distance (share of A's bounding-box diagonal) of
//     each other; a pair is kept when each is the other's nearest candidate.
// Deterministic: fixed tie-breaks throughout, no order-dependent parallel sums.
#pragma once

#include <Eigen/Core>
#include <array>
#include <vector>

#include "common/progress.h"
#include "features/feature_points.h"
#include "features/feature_regions.h"
#include "features/region_graph.h"

namespace paramorph::features {

struct MatchOptions {
  /// Segmentation of each mesh. `regions.concavity` must be left empty: the
  /// concavity of each mesh is computed here.
  FeatureRegionOptions regions;
  /// Feature points of each mesh.
  FeaturePointOptions points;
  /// Region graphs and their reduction.
  RegionGraphOptions graph;
  /// How many highest-degree regions of each mesh anchor rotation candidates (>= 1).
  int alignment_nodes = 6;
  /// Pairs scoring this or more (4.11, units of the RMS radius) are never made.
  double max_region_score = 0.5;
  /// Pairs scoring more than this many times the median pair score are dropped.
  double outlier_factor = 4.0;
  /// Largest distance of a point pair after centroid alignment, as a share of
  /// A's bounding-box diagonal.
  double max_point_distance = 0.05;
};

struct FeatureMatch {
  Segmentation regions_a, regions_b;  ///< feature regions of A and B (in their own coordinates)
  FeaturePoints points_a, points_b;   ///< feature points of A and B
  RegionGraph graph_a, graph_b;       ///< reduced region graphs
  /// Normalisation: x' = (x - centre) / scale (area-weighted centroid, RMS radius).
  Eigen::Vector3d centre_a = Eigen::Vector3d::Zero(), centre_b = Eigen::Vector3d::Zero();
  double scale_a = 1.0, scale_b = 1.0;
  /// Turns B (centred, scale-normalised) onto A: a point x of B lands at
  /// centre_a + scale_a * rotation * (x - centre_b) / scale_b in A's frame.
  Eigen::Matrix3d rotation = Eigen::Matrix3d::Identity();
  /// (region of A, region of B), sorted by A's region; s_ij of (4.11), lower = better.
  std::vector<std::array<Index, 2>> region_pairs;
  std::vector<double> region_scores;
  /// (vertex of A, vertex of B), sorted by A's vertex; their distance after
  /// centroid alignment as a share of A's bounding-box diagonal.
  std::vector<std::array<Index, 2>> point_pairs;
  std::vector<double> point_scores;
};

/// VA, FA and VB, FB: two manifold triangle meshes with volume (#V by 3
/// positions, #F by 3 vertex indices, 0-based); open or closed, any genus.
/// progress: coarse stages; returning false throws Cancelled.
/// Throws (with "mesh A: " / "mesh B: " in the message) DegenerateFaceError,
/// NonManifoldError, InvalidInputError (malformed arrays, a flat mesh,
/// bad options), and Cancelled.
FeatureMatch match_features(const MatrixX3d& VA, const MatrixX3i& FA, const MatrixX3d& VB,
                            const MatrixX3i& FB, const MatchOptions& options = {},
                            Progress* progress = nullptr);

}  // namespace paramorph::features
