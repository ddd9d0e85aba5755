// Feature pairs for the morph (thesis 4.5; DESIGN.md §4.4 step 2): B
// registered onto A in 3D from the feature match's normalisation, then the
// feature points of one kind that are mutually nearest after registration.
// One function for what Preview Matches shows and what the morph uses, so the
// pairs an artist edits are the pairs the morph would have made.
#pragma once

#include <array>
#include <optional>
#include <vector>

#include "common/progress.h"
#include "features/match_features.h"
#include "mesh/types.h"
#include "mesh/closest_points.h"
#include "morph/register_surfaces.h"

namespace paramorph::morph {

/// B onto A (register_surfaces), started from the objects' own placement
/// (first: it wins ties) and from the match's rotation, both centred and
/// scaled by the match's normalisation.
Registration register_matched(const MatrixX3d& VA, const MatrixX3i& FA, const MatrixX3d& VB,
                              const MatrixX3i& FB, const features::FeatureMatch& match,
                              const RegisterOptions& options = {}, Progress* progress = nullptr);

struct RegisteredPairs {
  std::vector<std::array<Index, 2>> pairs;  ///< (vertex of A, vertex of B)
  std::vector<double> scores;               ///< distance after registration, share of A's diagonal
};

/// The match's feature points of one kind that are mutually nearest once B
/// is moved by `registration`, closer than pair_distance x A's bounding-box
/// diagonal (pair_nearest_points).
RegisteredPairs registered_pairs(const MatrixX3d& VA, const MatrixX3d& VB,
                                 const features::FeatureMatch& match, const Registration& registration,
                                 double pair_distance);

/// Share of B's area whose faces, carried onto A by `on_a` (the closest
/// points of A to the registered B's vertices), come out inverted against
/// A's face normals. A registration that squeezes a part of B onto a part of
/// A that is not its counterpart (a tentacle onto a head: the closest-point
/// cost is small, the carried map folds) shows here; a faithful one gives
/// about 0.
double carried_fold_share(const MatrixX3d& VA, const MatrixX3i& FA, const MatrixX3d& VB,
                          const MatrixX3i& FB, const ClosestPoints& on_a);

struct MorphPairs {
  features::FeatureMatch match;
  /// When registered and the registration carried B onto A faithfully
  /// (fold share at most max_fold_share).
  std::optional<Registration> registration;
  ClosestPoints on_a;          ///< with `registration`: closest points of A to the registered B
  double fold_share = 0;       ///< carried_fold_share of the registration tried (0 when none)
  RegisteredPairs pairs;  ///< registered_pairs, or the match's own point pairs when not registered
};

/// match_features, then (with `register_surfaces`) register_matched; the
/// registration is kept when its carried_fold_share is at most
/// max_fold_share, and then the pairs are registered_pairs: what morph()
/// does for its pairs, for a preview.
MorphPairs morph_pairs(const MatrixX3d& VA, const MatrixX3i& FA, const MatrixX3d& VB, const MatrixX3i& FB,
                       const features::MatchOptions& match_options, bool register_surfaces,
                       const RegisterOptions& register_options, double pair_distance,
                       double max_fold_share, Progress* progress = nullptr);

}  // namespace paramorph::morph
