// Pasting a feature onto a target mesh, interactively (thesis 5.2; DESIGN.md
// §4.5 steps 2 and 3).
//
// PLACEMENT. The anchor is snapped to the closest point p of the target; n is
// the target's (vertex-normal interpolated) normal there; the feature's u axis
// is the target's object X projected onto the tangent plane (Y when X is
// within 25 degrees of n), turned by `rotation` about n. The feature keeps its
// form: it is placed rigidly, scaled by `scale`, with its frame (paste/
// feature.h) on (p + lift n; t, n x t, n):
//   x_world = p + lift n + scale [t, n x t, n] x_frame,
// lift chosen so that the feature's boundary sits on the target on average
// (along n), so the base deforms as little as it can.
//
// THE PARAMETERIZATIONS. Target vertices get feature-plane coordinates q
// from the discrete exponential map around p in the frame (t, n x t),
// divided by scale (paste/exponential_map.h); the feature gets its own from
// the same map around its origin on its base (its base map where that origin
// is off the base, an annulus). Built alike, the two agree: a feature cut
// from a curved surface fits a like one at its own size.
// Where the surface turns too much under the feature, the exponential map
// folds (a scan's noise and bumps, a cartoon's ears: it overlaps itself
// beyond a ridge). If any face within the rim is turned over in it, or the
// faces within the rim do not form a disc up to holes of the target, the
// target is instead parameterized by a fold-free disc map: the region within
// about 1.25 rims (edge-path distance) grown as a topological disc (paste/
// disc_region.h) and flattened by the isometric solver from a Tutte start
// (paste/disc_map.h), placed so the anchor and its frame mean what they mean
// in the exponential map (so rotation and scale do too). It refuses only
// where the surface within the rim is not a disc (a handle, a hole, a part
// thinner than the feature it would wrap around) or the feature reaches the
// target's boundary. Both maps are computed per placement (a few ms), so an
// update equals a fresh session.
//
// BASE DEFORMATION (5.1, 5.2; keep form). The feature's boundary must meet
// the target: an RBF over the feature plane moves the target around it, with
// moving control points at the feature's boundary (value: the placed boundary
// point minus the target's point with the same q) and stationary ones on the
// rim |q| = blend_radius * (the feature's radius in that plane) (value 0).
// The control points are fixed in the feature plane whatever the placement,
// so the system is LU-factored once per session and every update
// back-substitutes. Target vertices inside the rim move by the RBF; those
// outside are untouched.
//
// DETAIL. Target faces that the feature's disc (|q| <= its radius) touches
// are refined with OpenSubdiv (paste/refine_region.h: Loop, uniform, to
// `subdivision_level`, or automatically to the level whose edges match the
// feature's scaled edge length), stitched to their neighbours without cracks
// or T-junctions. Every output vertex whose q lies in the feature's domain
// takes the feature's point there: keep form, the placed feature itself
// (its vertices interpolated at q, read from a lookup grid built once per
// session, exactly along the domain's boundary); follow surface, the Loop
// limit position plus the feature's vector displacement map in the limit
// surface's frame (PasteFit).
//
// A FEATURE CARRIED AS ITS OWN MESH (Feature::carried: a trunk, a horn with
// its root, a limb; with PasteFit::KeepForm). A long protrusion squeezed into
// its base's plane would need the target refined far past level 6 to be
// resampled, so its own triangles are pasted instead: placed as above, the
// target bent around its boundary by the same RBF, the target's faces that
// the boundary (in the feature plane) encloses, crosses or touches cut away,
// and the ring between the hole and the boundary filled with triangles that
// use only their vertices (paste/fill_between_loops.h). New vertices: the
// feature's, in its order; new faces: the seam, then the feature's own. The
// target's vertices inside the hole stay in V, used by no face. FollowSurface
// resamples a carried feature through its base map as any other.
#pragma once

#include <Eigen/Core>
#include <memory>
#include <string>

#include "common/progress.h"
#include "mesh/types.h"
#include "paste/feature.h"
#include "paste/rbf_interpolator.h"

namespace paramorph::paste {

/// How the feature meets the target.
enum class PasteFit {
  /// The feature keeps its form (placed rigidly); an RBF bends the target
  /// around it to meet its boundary (5.1, 5.2). For parts, bosses, ears.
  KeepForm,
  /// The feature's displacement map is laid over the target's Loop limit
  /// surface in that surface's frame: the detail follows the target's
  /// curvature and the target does not move around it (blend_radius and
  /// basis play no part). For skin detail, engraving, texture-like relief.
  FollowSurface,
};

/// "keep_form" | "follow_surface" -> PasteFit; InvalidInputError otherwise.
PasteFit parse_paste_fit(const std::string& name);

/// How the target under the feature is parameterized (see THE
/// PARAMETERIZATIONS above).
enum class TargetMap {
  /// The exponential map where it is fold-free over the region within the
  /// rim and that region is a disc (up to holes of the target); else the
  /// disc map. The default.
  Auto,
  /// Only the exponential map; TargetTooSmallError where it folds under the
  /// feature (the behaviour before the disc map).
  Exponential,
  /// Always the disc map (paste/disc_map.h).
  Disc,
};

/// "auto" | "exponential" | "disc" -> TargetMap; InvalidInputError otherwise.
TargetMap parse_target_map(const std::string& name);

struct PasteOptions {
  Eigen::Vector3d anchor = Eigen::Vector3d::Zero();  ///< target coordinates; snapped to the surface
  double rotation = 0.0;      ///< radians about the normal
  double scale = 1.0;         ///< > 0, uniform factor on the feature's size
  double blend_radius = 2.0;  ///< > 1.1: the influence rim, in feature radii
  int subdivision_level = -1; ///< -1: automatic; else 0..6
  RbfBasis basis = RbfBasis::Polyharmonic;
  PasteFit fit = PasteFit::KeepForm;
  TargetMap target_map = TargetMap::Auto;
};

struct PasteStats {
  int level = 0;                  ///< subdivision level used
  Index anchor_face = -1;         ///< target face holding the snapped anchor
  Index refined_faces = 0;        ///< target faces refined under the feature (carried: cut under its root)
  Index replaced_faces = 0;       ///< target faces not kept as they were (refined + stitched)
  Index moved_vertices = 0;       ///< target vertices moved (blend and feature)
  Index feature_vertices = 0;     ///< output vertices placed on the feature
  Index control_points = 0;       ///< RBF control points (moving + stationary)
  double lift = 0.0;              ///< keep form: the feature's offset along the normal (see PLACEMENT)
  double feature_radius = 0.0;    ///< the feature's extent from the anchor, target units (max |q| of its boundary x scale)
  double influence_radius = 0.0;  ///< blend_radius x feature_radius: beyond it nothing moves
  bool disc_map = false;          ///< the target's coordinates came from the disc map (else the exponential map)
  Index disc_faces = 0;           ///< the disc map's faces (0 with the exponential map)
  int disc_iterations = 0;        ///< the isometric solver's iterations for the disc map
  double map_seconds = 0.0;       ///< of update_seconds: the target's parameterization (step 2)
  double setup_seconds = 0.0;     ///< the constructor's one-off work
  double update_seconds = 0.0;    ///< the last placement
};

class PasteSession {
 public:
  /// V: #V by 3, F: #F by 3 (0-based, counter-clockwise seen from outside):
  /// a manifold triangle mesh, open or closed. feature: from extract_feature
  /// (or Feature::from_arrays). Builds everything placement-independent
  /// (topology and OpenSubdiv refiner, closest-point tree, the feature's
  /// lookup grid, the RBF factorization) and places the feature as `options`
  /// says. Throws InvalidInputError (bad arrays or options), NonManifoldError,
  /// DegenerateFaceError, TargetTooSmallError (see update), Cancelled.
  PasteSession(const MatrixX3d& V, const MatrixX3i& F, Feature feature, const PasteOptions& options,
               Progress* progress = nullptr);
  ~PasteSession();
  PasteSession(PasteSession&&) noexcept;
  PasteSession& operator=(PasteSession&&) noexcept;

  /// Moves, turns or scales the feature: the same result as a new session
  /// with these values. Throws TargetTooSmallError when the feature does not
  /// fit there (its disc reaches the target's boundary, the surface within
  /// the rim is not a disc, or the target ends within the blend radius); the
  /// session then keeps its previous placement and result. InvalidInputError for a non-finite anchor or rotation, or a
  /// scale <= 0.
  void update(const Eigen::Vector3d& anchor, double rotation, double scale);

  /// The pasted mesh: the target's vertices first, in order (those within
  /// the rim moved), then new ones; the target's untouched faces first, in
  /// order, then the new faces, whose indices new_faces() lists.
  const MatrixX3d& V() const;
  const MatrixX3i& F() const;
  const VectorXi& new_faces() const;
  /// Indices into the input F of the faces replaced (ascending).
  const VectorXi& replaced_faces() const;
  /// Per new face: the input face it lies in (one of replaced_faces()).
  const VectorXi& new_face_parents() const;

  const PasteOptions& options() const;     ///< the current placement and settings
  const Eigen::Vector3d& anchor_point() const;  ///< the snapped anchor
  const Eigen::Vector3d& normal() const;        ///< the unit normal there
  const PasteStats& stats() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace paramorph::paste
