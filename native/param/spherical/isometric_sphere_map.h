// A sphere map that is as close to an isometry as the sphere allows: the
// symmetric Dirichlet (isometric) energy of thesis ch. 2 (2.19: the map of
// every 3D triangle onto its chord triangle on the sphere, the model scaled
// to the sphere's area), minimised by Newton steps in the tangent planes
// from a fold-free start. The energy is infinite for a degenerate face, and
// a step that would turn a face over is cut back, so every iterate is
// fold-free.
//
// Why (issue 16): a conformal sphere map (3.3) shrinks a long limb
// exponentially in its length over its girth (a horse's legs: triple
// products of 1e-17, at rounding), which neither a correspondence nor the
// overlay can resolve, and it matches limbs of different proportions badly.
// The isometric energy is intrinsic like the conformal one (a re-posed model
// gets the same map up to a rotation), but gives every part a share of the
// sphere close to its share of the surface (Praun & Hoppe 2003 minimise a
// similar stretch for the same reason).
#pragma once

#include <vector>

#include "common/progress.h"
#include "mesh/types.h"

namespace paramorph::spherical {

struct IsometricSphereOptions {
  /// Newton steps at most. From a coarser level's map 20-40 steps bring the
  /// energy within 0.5% of where 160 do (a 3k-face horse: 4.19 after 20,
  /// 4.186 after 40, 4.18 after 80); the rest creeps.
  int max_steps = 40;
  /// Stop when the squared Newton decrement falls under tol x the energy.
  double tol = 1e-5;
  /// Vertices that do not move (the rim of a region relaxed alone).
  std::vector<Index> fixed;
  /// Sphere area per unit of model area; 0: 4 pi over the mesh's own area
  /// (a region relaxed alone gives its whole model's).
  double area_scale = 0;
};

struct IsometricSphereResult {
  MatrixX3d positions;      ///< #V by 3 unit vectors, every face positively oriented
  int steps = 0;            ///< Newton steps taken
  int factorizations = 0;
  /// Energy over its isometric minimum (1 for an isometry; the sphere
  /// forces more for any other shape), at the start and the end.
  double start_energy = 0, energy = 0;
  bool converged = false;   ///< the decrement test ended it (not the step cap)
};

/// Per-face isometric energy of the sphere map X and, when `gradient` is
/// not null, its Euclidean gradient (#V by 3); +inf where a face is turned
/// over or degenerate. rest: per face the three cotangents of its scaled 3D
/// triangle and its scaled area (isometric_sphere_rest). Exposed for the
/// derivative test.
struct IsometricSphereRest {
  Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor> cotangents;  ///< per face and corner
  VectorXd area;  ///< per face, its 3D area scaled so the areas sum to 4 pi
};
IsometricSphereRest isometric_sphere_rest(const MatrixX3d& V, const MatrixX3i& F, double area_scale = 0);
double isometric_sphere_energy(const IsometricSphereRest& rest, const MatrixX3i& F, const MatrixX3d& X,
                               MatrixX3d* gradient = nullptr);

/// Per face, its isometric energy over its minimum (1 for an isometric
/// face, +inf for one turned over or degenerate).
VectorXd isometric_face_ratios(const IsometricSphereRest& rest, const MatrixX3i& F, const MatrixX3d& X);

/// V, F: a closed genus-0 mesh without degenerate faces (not checked here);
/// start: #V by 3 unit vectors, every face's triple product > 0 (checked:
/// InvalidInputError). Raises Cancelled through `progress`.
IsometricSphereResult isometric_sphere_map(const MatrixX3d& V, const MatrixX3i& F, const MatrixX3d& start,
                                           const IsometricSphereOptions& options = {},
                                           ProgressWindow progress = {});

}  // namespace paramorph::spherical
