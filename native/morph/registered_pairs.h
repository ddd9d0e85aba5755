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

struct MorphPairs {
  features::FeatureMatch match;
  std::optional<Registration> registration;  ///< when registered
  RegisteredPairs pairs;  ///< registered_pairs, or the match's own point pairs when not registered
};

/// match_features, then (with `register_surfaces`) register_matched and
/// registered_pairs: what morph() does for its pairs, for a preview.
MorphPairs morph_pairs(const MatrixX3d& VA, const MatrixX3i& FA, const MatrixX3d& VB, const MatrixX3i& FB,
                       const features::MatchOptions& match_options, bool register_surfaces,
                       const RegisterOptions& register_options, double pair_distance,
                       Progress* progress = nullptr);

}  // namespace paramorph::morph
