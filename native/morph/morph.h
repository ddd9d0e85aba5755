// Feature-based morphing between two genus-0 meshes of different topology
// (thesis ch. 4, Fig. 4.3 and 4.8; DESIGN.md §4.4):
//
//   1. sphere-map both meshes (sphere_map, 4.3.2) and optimize A's map for
//      morphing (optimize_sphere_map, 4.3.3);
//   2. match feature regions and feature points (match_features, 4.5);
//      user pins join the automatic pairs and win over them;
//   3. with features: register B onto A in 3D (register_surfaces: polynomial
//      point-to-plane ICP from the match's similarity and from the objects'
//      own placement); B's targets are A's map at the closest points of A
//      to the registered B, and the pairs are the mutually nearest feature
//      points after registration (registered_pairs) — unless the carried map
//      folds (shapes too unlike for a 3D fit: max_fold_share), then B's
//      radial projection and the match's pairs;
//   4. optimize B's map towards its targets (its own radial projection
//      without features) and A's paired features (align_sphere_map,
//      (4.12) with the fold constraints);
//   5. overlay the two maps into one merged topology (overlay, 4.4);
//   6. every merged vertex's position on A and on B from its barycentric
//      coordinates: the source and target of a linear morph (4.4).
#pragma once

#include <array>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "common/progress.h"
#include "features/match_features.h"
#include "mesh/types.h"
#include "morph/align_sphere_map.h"
#include "morph/optimize_sphere_map.h"
#include "morph/register_surfaces.h"
#include "morph/spherical_overlay.h"

namespace paramorph::morph {

struct MorphOptions {
  /// Match features automatically (4.5); off: B's map only faces A's by
  /// the radial projections (the objects' own placement) and the pins.
  bool features = true;
  /// Replaces the automatic pairs when given (e.g. edited in a preview):
  /// (vertex of A, vertex of B).
  std::optional<std::vector<std::array<Index, 2>>> pairs;
  /// User pins (vertex of A, vertex of B): always used, weighted above the
  /// automatic pairs, and an automatic pair that shares a vertex with a pin
  /// or lies within `pin_radius` of one on either map is dropped.
  std::vector<std::array<Index, 2>> pins;
  double pin_weight = 4.0;     ///< pin weight relative to an automatic pair
  double pin_radius = 0.15;    ///< radians on the sphere
  double epsilon = 0.05;       ///< fold bound of both optimized maps
  int max_iterations = 200;
  features::MatchOptions match;
  /// With features: register B onto A in 3D and take B's targets and (unless
  /// `pairs` are given) the pairs from the registration (step 3). Off: B's
  /// radial projection turned by the match's rotation, and the match's
  /// pairs after region-centroid alignment.
  bool register_surfaces = true;
  RegisterOptions registration;
  /// Largest distance of a feature pair after registration, as a share of
  /// A's bounding-box diagonal.
  double pair_distance = 0.03;
  /// The registration is used only when at most this share of B's area
  /// comes out folded when carried onto A (carried_fold_share): otherwise
  /// the shapes are too unlike for a 3D fit (a head into an octopus) and B's
  /// targets are its radial projection, the pairs the match's own.
  double max_fold_share = 0.01;
  /// Width (radians) of align_sphere_map's warp when the targets come from
  /// the registration and align.warp_width is 0: the targets already follow
  /// the features, the warp only spreads the pairs' small offsets (about a
  /// vertex spacing: feature points are vertices of two tessellations).
  double registered_warp_width = 0.1;
  AlignSphereOptions align;    ///< epsilon / max_iterations taken from above
  OverlayOptions overlay;
  /// Fold-free sphere maps of A / B already at hand (e.g. the add-on's
  /// cache); computed when absent.
  std::optional<MatrixX3d> sphere_a, sphere_b;
};

struct Morph {
  MergedTopology merged;      ///< merged faces, vertices on the sphere, barycentrics
  MatrixX3d source, target;   ///< #M by 3: each merged vertex on A and on B
  /// The pairs used, (vertex of A, vertex of B), pins first.
  std::vector<std::array<Index, 2>> pairs;
  std::vector<bool> pair_is_pin;
  std::vector<double> pair_scores;  ///< automatic pairs: match_features' score; pins: 0
  MatrixX3d sphere_a, sphere_b;     ///< the two maps that were overlaid
  std::optional<features::FeatureMatch> match;  ///< when features were matched
  std::optional<Registration> registration;      ///< when B's registration onto A was used
  double registration_fold_share = 0;            ///< carried_fold_share of the registration tried
  double mean_pair_error = 0;   ///< mean angle (radians) between paired points on the two maps
  std::vector<std::pair<std::string, double>> timings;  ///< per stage, seconds
};

/// VA, FA / VB, FB: closed genus-0 meshes (the MeshError subclasses
/// otherwise, naming which of the two); pins and pairs are checked
/// (InvalidInputError). Raises Cancelled when `progress` says so.
Morph morph(const MatrixX3d& VA, const MatrixX3i& FA, const MatrixX3d& VB, const MatrixX3i& FB,
            const MorphOptions& options = {}, Progress* progress = nullptr);

/// Per-corner values of A (side 0) or B (side 1) — UVs, colours: rows
/// 3f + c for corner c of face f — carried to the merged faces through the
/// corner barycentric coordinates: rows 3k + c of the result.
Eigen::MatrixXd carry_corner_values(const MergedTopology& merged, int side,
                                    const Eigen::MatrixXd& corner_values);

}  // namespace paramorph::morph
