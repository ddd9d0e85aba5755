// extract_feature: cut a feature out of a surface for pasting (thesis 5.2;
// DESIGN.md §4.5 step 1; the lead's paste design).
//
//   1. the selection is checked (paste/selection_patch.h) and the source must
//      be a manifold, consistently oriented, with no degenerate face selected;
//   2. the base surface spans the feature's boundary (paste/base_surface.h);
//   3. the base map: isometric_map of the base with a free boundary, moved so
//      its area centroid is uv = 0 and turned about 0 so e_u there follows
//      the world x axis projected on the base (y where x is within 25° of
//      the normal: a free map's rotation is otherwise arbitrary);
//      A long protrusion's thin-plate base folds (its interior is spread by
//      the protrusion's own weights): its boundary is then laid on its
//      best-fit plane and the interior averaged (a flat base, fold-free);
//   4. the feature map: isometric_map of the feature with every boundary
//      vertex pinned to its base map uv ("we fix the boundary ... on
//      corresponding positions of the base surface parameterization"), so
//      both maps cover the same domain. A long protrusion (a trunk, a horn
//      with its root, a limb) has no fold-free such map, or one too squeezed
//      to resample: it is carried as its own mesh (Feature::carried, Carry)
//      and its map is the base map; then the feature frame at uv = 0 (for
//      an annulus, where uv = 0 lies in the hole: the base's tangent plane at
//      the closest domain point, continued to uv = 0);
//   5. the displacement grid (paste/feature.h states nodes, origin, spacing).
// The work is done on the input translated and scaled to unit mean edge
// length and scaled back, so the result scales with the input.
#pragma once

#include <string>
#include <vector>

#include "common/progress.h"
#include "compute/device.h"
#include "paste/feature.h"

namespace paramorph::paste {

/// Whether the feature is carried as its own mesh (Feature::carried).
enum class Carry {
  /// When its map cannot be pinned to the base's boundary without folds, the
  /// base itself cannot be laid flat as a thin plate, or the base map
  /// squeezes a tenth of the feature's edges over kCarrySqueeze times (a
  /// protrusion's walls: a resampling on the base's plane would need a far
  /// finer refinement than the feature's own mesh to show them). The default.
  Auto,
  Always,  ///< a disc selection, always (a part)
  Never,   ///< never: SelectionTopologyError where Auto would carry it
};

/// "auto" | "always" | "never" -> Carry; InvalidInputError otherwise.
Carry parse_carry(const std::string& name);

/// Auto carries a feature whose base map shortens a tenth of its edges more
/// than this many times: a resampling would need about its square times the
/// feature's own faces (measured, tests/bench/paste_protrusion.py: a muzzle
/// 1.3 to 12, a tube as long as wide 3.2, twice as long 38, a cat's tail
/// within 10 % of the model's diagonal of its tip 50, a leg 20 and more).
constexpr double kCarrySqueeze = 4.0;

struct ExtractFeatureOptions {
  int resolution = 64;  ///< displacement grid nodes per side, 2 to kMaxFeatureResolution
  Carry carry = Carry::Auto;
  compute::Backend backend = compute::Backend::Auto;  ///< of the two isometric_map runs
};

/// V: #V by 3 source positions; F: #F by 3 faces (counter-clockwise seen from
/// outside); feature_faces: indices into F of the feature, any order.
/// Throws InvalidInputError (malformed arrays, selected index out of range or
/// repeated, resolution outside [2, kMaxFeatureResolution]), NonManifoldError / DegenerateFaceError (source),
/// EmptySelectionError, WholeMeshSelectedError, SelectionTopologyError
/// (paste/selection_patch.h), ConstraintError when a map cannot be made
/// fold-free, Cancelled.
Feature extract_feature(const MatrixX3d& V, const MatrixX3i& F, const std::vector<Index>& feature_faces,
                        const ExtractFeatureOptions& options = {}, Progress* progress = nullptr);

}  // namespace paramorph::paste
