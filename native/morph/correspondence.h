// The morph's correspondence: which point of A each point of B becomes
// (thesis ch. 4; issue 16), chosen among automatic candidates by a score
// that needs no ground truth.
//
//   1. Proxies: each model (already in its correspondence frame: outward,
//      centred, unit area) is simplified to about `proxy_faces` faces
//      (mesh/simplify) and given a balanced sphere map (isometric, coarse to
//      fine: param/spherical/balanced_sphere_map), turned to face its own
//      model (Kabsch onto its radial directions), so that "no pairs" means
//      "as the models are placed".
//   2. Candidates, each a set of point pairs (vertex of A, vertex of B):
//      - none: no automatic pairs;
//      - extremities: pairings of the tips of segment_extremities (3.5.1;
//        limbs, head, tail) found by tip_assignments;
//      - tip paths: the protrusion tips (local maxima of the average
//        geodesic distance) paired by the paths from each model's core out
//        to them, as placed and from the principal axes (tip_path_pairs);
//      - registration: the proxies registered in 3D (polynomial ICP up to
//        cubic, register_surfaces) from their principal axes (the four proper
//        sign choices) and from their placement; farthest-point samples of
//        B paired with A at their registered closest points shape the map,
//        and the tips mutually nearest afterwards are paired;
//      - features: the thesis' feature points (match_features, 4.5).
//      The user's pins join every candidate; automatic pairs near a pin are
//      dropped.
//   3. Score: B's map is turned (Kabsch on the pairs) and carried by a
//      checked flow (flow_sphere_map) until every pair coincides; every vertex of B's proxy is
//      read on A's proxy through the maps, and the score is the isometric
//      distortion of that correspondence (map_distortion) plus how unlike the
//      smoothed Gaussian curvatures are at corresponding points, raised a
//      little the further it turns B from where it is placed and the farther
//      it puts B's protrusion tips from the partners their paths chose as
//      placed (tip_path_pairs: what a tip is). A candidate
//      whose pairs are in mirrored order is rejected (a map it would fold
//      where the proxy is too coarse for the flow is scored with its folds).
//      The lowest score wins, so an automatic candidate is used only when it
//      beats "none".
//   4. The winner's pairs are carried to the models' own vertices: a tip to
//      the model's own peak of distance from the body it stands for, any
//      other proxy vertex to the model's nearest vertex.
//
// Why proxies and balanced maps: a conformal map squeezes a horse's legs to
// rounding (1e-17), and the thesis' radial projection depends on the pose
// (its correspondence between a model and the same model re-posed distorts
// 50 times more than the balanced maps', measured on a bent four-limbed
// blob); scoring a dozen candidates on 3k-face proxies takes a fraction of a
// second where one full-resolution map of 97k faces took minutes.
#pragma once

#include <array>
#include <limits>
#include <optional>
#include <string>
#include <vector>

#include "common/progress.h"
#include "features/extremity_tips.h"
#include "features/match_features.h"
#include "features/segment_extremities.h"
#include "mesh/types.h"
#include "morph/register_surfaces.h"

namespace paramorph::morph {

struct CorrespondenceOptions {
  Index proxy_faces = 3000;     ///< faces of each proxy (a smaller model is its own proxy)
  bool extremities = true;      ///< extremity-tip candidates
  bool registration = true;     ///< 3D-registration candidates
  bool features = true;         ///< the thesis' feature-point candidate
  std::size_t max_tip_assignments = 12;
  /// How far a tip must stand out along the surface (extremity_tips; units of
  /// the correspondence frame: the model scaled to unit area): a cow's horns
  /// and muzzle are tips of one head.
  double tip_prominence = 0.04;
  /// The farthest tips kept per model: a scan's bumps made 62 tips on one
  /// cow, and pairing every two of them with every two of the other's took
  /// a minute (issue 29); limbs, head, tail and horns are fewer.
  std::size_t max_tips = 12;
  /// Tips paired by the paths from each model's core out to them
  /// (features/protrusion_tips, morph/tip_path_pairs), as placed and from
  /// the principal axes; needs `extremities`.
  bool tip_paths = true;
  /// A protrusion tip is the highest within this distance along edges (units
  /// of the correspondence frame: the model scaled to unit area).
  double protrusion_radius = 0.15;
  int tip_path_samples = 8;  ///< points per path
  /// Tips whose paths differ more than this (root mean square, in each
  /// model's spreads) are not paired: the right pairs of a cat, a lion and a
  /// scanned cow cost 0.4-1.75 (a raised tail against a hanging one the most).
  double tip_path_cost = 2.0;
  /// Added to a tip pair's cost per unit of difference in how alone the two
  /// tips are under their models' mirror planes (features/mirror_plane): a
  /// muzzle or a tail against an ear, a horn or a foot (0 leaves the mirror out).
  double mirror_weight = 0.5;
  /// With 3+ pins: tips whose distances to the pins (as unit vectors) are
  /// closer than this pair (tips_by_pin_distances).
  double pin_distance_match = 0.08;
  double tip_angle = 0.8;       ///< radians: tips farther apart under a candidate rotation are not paired
  /// Tips, and registration samples, farther from their closest partner
  /// than this after a registration are not paired (units of the
  /// correspondence frame: the model scaled to unit area).
  double registered_tip_distance = 0.15;
  /// Points of B's proxy whose registered closest points on A shape a
  /// registration candidate's map.
  std::size_t registration_samples = 40;
  /// Automatic pairs closer than this to a pin, on either model, are dropped
  /// (same units: about three edges of a 3k-face proxy; the pins rule there).
  double pin_radius = 0.02;
  /// Candidates after the best to try when the model's own map cannot meet
  /// the best's pairs without folding (ranked by score).
  int fallbacks = 2;
  /// Weight of the curvature mismatch beside the distortion in the score.
  double curvature_weight = 0.5;
  /// How much the score of a candidate grows as it turns B away from where
  /// it is placed: times 1 + placement_weight x turn / 180 degrees. The
  /// artist's placement counts as evidence: on a featureless blob the
  /// candidates score within 10% of each other, and a half-turned one won
  /// by chance (Suzanne into a blob came out turned round).
  double placement_weight = 0.25;
  /// The largest turn (radians) that straightening B's placement by its
  /// tips may take (a lion turned 20 degrees and tilted 10 beside the
  /// horned cow took about 20); a larger misplacement is taken as placed.
  double max_placement_turn = 0.8;
  /// How much the score grows as the candidate's map puts B's protrusion
  /// tips away from the partners their paths chose as placed: times 1 +
  /// tip_weight x tip_disagreement (0 to 1).
  double tip_weight = 0.5;
  features::ExtremityOptions extremity;
  features::MatchOptions match;
  RegisterOptions registration_options;  ///< ICP, affine up to cubic
};

struct CorrespondenceCandidate {
  std::string kind;      ///< "none", "extremities", "tip paths", "pin distances", "registration", "features" or "given"
  std::string detail;    ///< e.g. "6 tips" or "principal axes, turned 180 deg about x"
  /// The automatic pairs on the proxies (vertex of A's proxy, of B's proxy);
  /// the pins are not listed.
  std::vector<std::array<Index, 2>> proxy_pairs;
  /// (distortion + curvature_weight x curvature_mismatch) x (1 +
  /// placement_weight x turn / pi) x (1 + tip_weight x tip_disagreement):
  /// lower is better; +inf when rejected
  /// before scoring (one rejected later, by the morph, keeps its score).
  double score = std::numeric_limits<double>::infinity();
  /// Mean isometric distortion of the correspondence through the proxies'
  /// maps (map_distortion; 0 for an isometry).
  double distortion = 0;
  /// Mean difference of smoothed Gaussian curvature between each point of B
  /// and where it lands on A, over the curvatures' spread: what distortion
  /// misses (a map sliding along a smooth surface carries a bump beside its
  /// partner and bends little).
  double curvature_mismatch = 0;
  /// Radians B's map is turned from where the models are placed
  /// (straightened: Correspondence::placement_turn).
  double turn = 0;
  /// 0 to 1: how far the map puts B's protrusion tips from the partners
  /// their paths chose as placed (tip_path_pairs), confidence-weighted.
  double tip_disagreement = 0;
  std::string rejected;  ///< why it could not be used: before scoring, or by the morph on the models (empty otherwise)
};

/// A ranked candidate carried to the models: what the morph needs to build
/// its maps from it.
struct Realization {
  Index candidate = 0;  ///< index in Correspondence::candidates
  /// Its automatic pairs on the models (vertex of A, of B), distinct
  /// vertices, none on a pin's.
  std::vector<std::array<Index, 2>> pairs;
  /// Its map of B's proxy with every pin and pair at its exact point.
  MatrixX3d warped_b;
  /// Its turn of B's map where it has no points, and the points besides the
  /// pins and pairs that shape its map (a registration's samples), on A's
  /// proxy map and on B's.
  Eigen::Matrix3d rotation = Eigen::Matrix3d::Identity();
  MatrixX3d shape_a, shape_b;
};

struct Correspondence {
  MatrixX3d proxy_a, proxy_b;        ///< proxy vertices (correspondence frames)
  MatrixX3i proxy_faces_a, proxy_faces_b;
  MatrixX3d map_a, map_b;            ///< balanced sphere maps of the proxies, placed
  std::vector<CorrespondenceCandidate> candidates;
  Index chosen = 0;                  ///< the best candidate
  /// The best candidates carried to the models, best first (at most
  /// 1 + fallbacks, then "none"): the morph uses the first its model's map
  /// can meet.
  std::vector<Realization> ranked;
  /// The best's map of B's proxy: map_b turned and carried so its pairs and
  /// pins lie on their partners of map_a.
  MatrixX3d warped_b;
  /// The best's automatic pairs on the models (vertex of A, of B), without
  /// the pins; distinct vertices.
  std::vector<std::array<Index, 2>> pairs;
  /// Radians B's placement was straightened by its tips before the
  /// candidates (0: taken as placed).
  double placement_turn = 0;
  std::vector<std::pair<std::string, double>> timings;  ///< per stage, seconds
};

/// VA, FA / VB, FB: closed genus-0 models in their correspondence frames
/// (morph/correspondence_frame); pins: (vertex of A, vertex of B), checked by
/// the caller; given: pairs to use instead of the automatic candidates (a
/// preview the user edited). Raises ConstraintError for pins in mirrored
/// order, the mesh errors of the steps, Cancelled.
Correspondence correspondence(const MatrixX3d& VA, const MatrixX3i& FA, const MatrixX3d& VB, const MatrixX3i& FB,
                              const std::vector<std::array<Index, 2>>& pins,
                              const std::optional<std::vector<std::array<Index, 2>>>& given,
                              const CorrespondenceOptions& options = {}, Progress* progress = nullptr);

}  // namespace paramorph::morph
