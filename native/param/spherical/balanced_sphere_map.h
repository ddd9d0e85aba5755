// A fold-free sphere map that gives every part of the model a share of the
// sphere close to its share of the surface: the progressive embedding
// (progressive_sphere_map: collapsed to a tetrahedron, the vertices put back
// one at a time inside their rings, relaxed towards the isometric energy
// level by level; valid at every insertion), then polished by Newton steps
// on the isometric energy of the whole model (isometric_sphere_map).
//
// Why (issue 16): the morph needs maps of both models that neither squeeze
// limbs (a horse's legs reach triple products of 1e-17 in the conformal
// map, which the overlay cannot resolve) nor depend on the pose (the thesis'
// radial projection does). Why this way (issue 28): the map used to be read
// level by level off a coarser one and untangled afterwards, which failed on
// 5 of 11 real characters (a dancer, a woman in a skirt, a horned cow ...):
// faces stayed folded where a finer level turned against a coarser one. The
// progressive embedding cannot fail that way, and it is within 0.5-14% of
// the isometric minimum before any Newton step (measured on the models in
// ../shared/models), so the polish is short.
#pragma once

#include "common/progress.h"
#include "mesh/types.h"
#include "param/spherical/isometric_sphere_map.h"
#include "param/spherical/progressive_sphere_map.h"

namespace paramorph::spherical {

struct BalancedSphereOptions {
  BalancedSphereOptions() { isometric.max_steps = 100; }
  /// The fold-free start. (More relaxation per level gives a lower start,
  /// e.g. the dancer 4.82 -> 4.50 of its minimum with 5 times the sweeps,
  /// but the same end after the polish, for up to 0.7 s more at 70k faces.)
  ProgressiveSphereOptions progressive;
  /// The polish: max_steps Newton steps at most, fewer on large models.
  IsometricSphereOptions isometric;
  /// The polish takes at most polish_face_steps / faces Newton steps (each
  /// factors the whole model's system: about 0.3 s at 100k faces), so a
  /// 3k-face proxy gets all max_steps and 100k faces three.
  double polish_face_steps = 300000;
};

struct BalancedSphereResult {
  MatrixX3d positions;       ///< #V by 3 unit vectors, fold-free
  int levels = 0;            ///< relaxation checkpoints of the progressive start
  int steps = 0;             ///< isometric Newton steps of the polish
  double start_energy = 0;   ///< isometric energy over its minimum after the progressive start
  double energy = 0;         ///< and at the end
};

/// V, F: a closed genus-0 mesh without degenerate faces (validated; the
/// MeshError subclasses otherwise). Cancelled through `progress`.
BalancedSphereResult balanced_sphere_map(const MatrixX3d& V, const MatrixX3i& F,
                                         const BalancedSphereOptions& options = {},
                                         Progress* progress = nullptr);

}  // namespace paramorph::spherical
