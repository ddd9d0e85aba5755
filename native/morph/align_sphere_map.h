// Feature-aligned sphere map of the second model (thesis 4.5, (4.12);
// DESIGN.md §4.4 step 2): move B's optimized sphere map so that its feature
// points land on the sphere positions of the features of A they are paired
// with, keeping B's map fold-free.
//
//   1. rotate: the rotation that best turns B's paired points onto their
//      targets (weighted Kabsch; identity with fewer than 3 pairs);
//   2. warp: a smooth displacement field on the sphere (Gaussian RBF
//      interpolation of the residual pair offsets) bends every target of B
//      with its features, so the neighbours of a feature follow it instead
//      of squeezing against it;
//   3. optimize (optimize_sphere_map): maximize sum_i w_i t_i . v_i — the
//      warped targets with weight 1 and, at the paired vertices, the pair
//      targets with `feature_weight` (the thesis' (4.12) sum of dot
//      products of the pairs) — subject to |v_i| = 1 (4.9) and the fold
//      constraints (4.10).
//
// The thesis keeps B's arc lengths instead ((4.13): v_a . v_b fixed on every
// edge). Fixing every edge of a triangulated sphere leaves only rotations
// (Cauchy's rigidity theorem): the features could not move past step 1. The
// fold constraints keep the map valid and let it bend; measured in
// tests/bench/morph.py (arc-length row of the "align" benchmark).
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "common/progress.h"
#include "mesh/types.h"
#include "morph/optimize_sphere_map.h"

namespace paramorph::morph {

struct AlignSphereOptions {
  double epsilon = 0.05;       ///< fold bound, as in OptimizeSphereOptions
  int max_iterations = 200;
  double tol = 1e-6;
  SphereSolver solver = SphereSolver::Auto;  ///< as in OptimizeSphereOptions
  /// Objective weight of a paired vertex's target relative to an unpaired
  /// vertex's (each pair also carries its own weight, e.g. pins higher).
  double feature_weight = 50.0;
  /// Width of the warp's Gaussian kernel, in radians on the unit sphere;
  /// 0 picks 1.5 x the mean distance between a pair and its nearest other pair
  /// (clamped to [0.2, 1.2]).
  double warp_width = 0.0;
  /// #V unit targets of B before the warp; B's radial projection from its
  /// centroid (as in optimize_sphere_map) when absent.
  std::optional<MatrixX3d> target;
};

struct AlignSphereResult {
  MatrixX3d positions;          ///< #V by 3 unit vectors, fold-free
  Eigen::Matrix3d rotation;     ///< step 1, applied to B's targets
  /// Mean and largest angle (radians) between a paired vertex and its
  /// target: after the rotation alone, and at the end.
  double mean_error_rotated = 0, mean_error = 0, max_error = 0;
  OptimizeSphereResult solve;   ///< the Ipopt run (iterations, status, flipped, seconds)
};

/// V, F: closed genus-0 mesh B; sphere: a fold-free sphere map of it;
/// vertices: the paired vertices of B (repeats allowed: their targets are
/// summed by weight); targets: one unit vector per pair (where its partner
/// of A is on A's map); weights: one positive weight per pair (empty: 1).
/// Raises InvalidInputError for mismatched or out-of-range pairs, the mesh
/// errors of optimize_sphere_map, Cancelled.
AlignSphereResult align_sphere_map(const MatrixX3d& V, const MatrixX3i& F, const MatrixX3d& sphere,
                                   const std::vector<Index>& vertices, const MatrixX3d& targets,
                                   const VectorXd& weights = {}, const AlignSphereOptions& options = {},
                                   Progress* progress = nullptr);

}  // namespace paramorph::morph
