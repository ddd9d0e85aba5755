// Morphing between two genus-0 meshes of different topology (thesis ch. 4,
// Fig. 4.3 and 4.8; DESIGN.md §4.4; issue 16):
//
//   1. each model is put in its correspondence frame: turned outward if its
//      file is inside-out, centred and scaled to unit area
//      (correspondence_frame); the interpolation (step 5) uses the models as
//      they are placed;
//   2. the correspondence (morph/correspondence): on proxies of a few
//      thousand faces with balanced sphere maps, candidates (none, pairings
//      of extremity tips, 3D registrations, the thesis' feature points) are
//      scored by the distortion of the correspondence they make, and the
//      best is used; the user's pins hold in every candidate;
//   3. A's sphere map is its proxy's map read at every vertex (untangled
//      where the model turns against the proxy's faces, poor regions
//      relaxed); B's map is the winner's map of B's proxy read the same way,
//      then carried by a short checked flow (flow_sphere_map) the last
//      stretch onto the exact points: its pinned vertices ride on their
//      points, so the pinned vertex of A lands exactly on its partner of B
//      at t = 1. Where that flow stalls, B's own map is carried the whole
//      way instead; where that stalls too, the next best candidate is tried;
//   4. the two maps are overlaid into one merged topology (overlay, 4.4);
//   5. every merged vertex's position on A and on B from its barycentric
//      coordinates: the source and target of the morph (4.4); then the merged
//      mesh is welded (weld_merged: short edges collapsed where both ends
//      stay within 1e-6 of the diagonal, slivers flipped inside their cells).
#pragma once

#include <array>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "common/progress.h"
#include "mesh/types.h"
#include "morph/correspondence.h"
#include "morph/spherical_overlay.h"
#include "morph/weld_merged.h"

namespace paramorph::morph {

struct MorphOptions {
  /// Automatic correspondence (step 2); off: only the pins, the given
  /// `pairs` if any, and the models' placement decide.
  bool automatic = true;
  /// Pairs to use instead of the automatic candidates (e.g. edited in a
  /// preview): (vertex of A, vertex of B), hard like the pins.
  std::optional<std::vector<std::array<Index, 2>>> pairs;
  /// User pins (vertex of A, vertex of B): hard constraints, exact on the
  /// maps, so the pinned vertex of A lands on its partner at t = 1.
  std::vector<std::array<Index, 2>> pins;
  CorrespondenceOptions correspondence;
  OverlayOptions overlay;
  /// Weld the merged mesh (weld_merged): short edges collapsed where every
  /// face stays within this share of the diagonal of one face of each input,
  /// slivers flipped inside their cells; 0: off.
  double weld_tolerance = 1e-6;
};

struct Morph {
  MergedTopology merged;      ///< merged faces, vertices on the sphere, barycentrics
  MatrixX3d source, target;   ///< #M by 3: each merged vertex on A and on B, as placed
  /// The pairs that hold exactly, (vertex of A, vertex of B): pins first.
  std::vector<std::array<Index, 2>> pairs;
  std::vector<bool> pair_is_pin;
  std::vector<CorrespondenceCandidate> candidates;  ///< every candidate and its score
  Index chosen = 0;                                 ///< the candidate used
  MatrixX3d sphere_a, sphere_b;  ///< the two maps that were overlaid
  /// A model's file was inside-out: its faces were turned for the
  /// correspondence, and the merged faces face outward.
  bool inside_out_a = false, inside_out_b = false;
  /// Radians B's placement beside A was straightened by its tips for the
  /// correspondence (Correspondence::placement_turn); the output keeps the
  /// models as placed.
  double placement_turn = 0;
  /// Isometric distortion of the final correspondence (map_distortion of B
  /// read on A through the two maps; 0 for an isometry).
  double distortion = 0;
  std::vector<std::pair<std::string, double>> timings;  ///< per stage, seconds
  WeldStats weld;  ///< what welding the merged mesh did (faces before and after, slivers)
  /// What the morph fell back on, in words for a report (e.g. a model's own
  /// sphere map where its proxy's could not be read without folds); empty
  /// when everything went the first way.
  std::vector<std::string> fallbacks;
};

/// VA, FA / VB, FB: closed genus-0 meshes (the MeshError subclasses
/// otherwise, naming which of the two). Pins and pairs: InvalidInputError
/// for vertices out of range, ConstraintError naming the pins where a vertex
/// is pinned twice or the pins are in mirrored order. Raises Cancelled when
/// `progress` says so; nothing is kept then.
Morph morph(const MatrixX3d& VA, const MatrixX3i& FA, const MatrixX3d& VB, const MatrixX3i& FB,
            const MorphOptions& options = {}, Progress* progress = nullptr);

/// The correspondence morph() would choose, for a preview (Preview Matches):
/// the same checks and candidates, without the maps and the overlay. Its
/// pairs are on the models (not the frames').
struct MorphCorrespondence {
  Correspondence correspondence;
  bool inside_out_a = false, inside_out_b = false;
};
MorphCorrespondence morph_correspondence(const MatrixX3d& VA, const MatrixX3i& FA, const MatrixX3d& VB,
                                         const MatrixX3i& FB, const MorphOptions& options = {},
                                         Progress* progress = nullptr);

/// Per-corner values of A (side 0) or B (side 1) — UVs, colours: rows
/// 3f + c for corner c of face f of the input mesh — carried to the merged
/// faces through the corner barycentric coordinates: rows 3k + c of the
/// result. A side whose file was inside-out has its corners' order mended.
Eigen::MatrixXd carry_corner_values(const Morph& morph, int side, const Eigen::MatrixXd& corner_values);

}  // namespace paramorph::morph
