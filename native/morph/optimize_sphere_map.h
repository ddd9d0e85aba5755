// Optimized spherical parameterization for morphing (thesis 4.3.3; DESIGN.md
// §4.4): starting from a fold-free sphere map, move every vertex as close as
// the fold constraints allow to its radial projection v_i^0 (the mesh seen
// from its centroid), so convex, structurally important parts keep their
// place and the distortion goes to the concave areas.
//
//   maximize   sum_i v_i^0 . v_i                       (4.8: "keep them close")
//   subject to |v_i|^2 = 1                             (4.9)
//              det(v_a, v_b, v_c) >= epsilon per face  (4.10)
//
// (4.10) lists three constraints per face; for a triangle they are one and the
// same scalar triple product, so one per face is kept (repeats would make the
// constraint Jacobian rank-deficient). Solved by param/spherical/sphere_map_barrier
// (the same problem with the bounds as a log barrier, followed down a path of
// mu by Newton steps on the spheres, after opening any faces the start
// squeezes to rounding; every accepted step keeps every face above its
// bound), then, where the build has Ipopt (morph/ipopt_polish: interior
// point, MUMPS, exact sparse derivatives; folded points refused), polished by
// Ipopt from a short path's end; without Ipopt the path goes on to a small mu.
// The start matters: morph/optimization_start picks the conformal map or,
// where that squeezes long parts, the thesis' relaxed radial projection.
#pragma once

#include <optional>
#include <string>

#include "common/progress.h"
#include "mesh/types.h"

namespace paramorph::morph {

/// Who finishes the solve (see optimize_sphere_map).
enum class SphereSolver {
  Auto,     ///< Ipopt where this build has it (ipopt_available()), else Barrier
  Barrier,  ///< the log-barrier path alone, followed down 8 decades of mu
  Ipopt,    ///< Ipopt's polish (InvalidInputError in a build without Ipopt)
};

struct OptimizeSphereOptions {
  /// Lower bound of each face's triple product, as a share of the mean
  /// triple product of the start (resolution-free); lowered to half the
  /// start's smallest when the start is tighter, so the start is feasible.
  double epsilon = 0.05;
  int max_iterations = 200;
  /// Ipopt iterations allowed after the barrier warm start (also capped by
  /// max_iterations). Warm-started runs converge in 3-10 (spot, 20k-face
  /// meshes); where Ipopt cannot finish from there (a 51k-face Suzanne:
  /// Restoration_Failed after 112 iterations, 380 s, objective no better than
  /// the barrier's, which was within 1e-4 relative of the bound n), the
  /// barrier's point is kept (status says Ipopt's outcome).
  int polish_iterations = 15;
  /// Start Ipopt from the log-barrier path (sphere_map_barrier); false:
  /// Ipopt alone from the start, as in the thesis (for comparison: spot 100
  /// iterations, 8 s).
  bool warm_start = true;
  SphereSolver solver = SphereSolver::Auto;
  /// Newton steps of the barrier path when it is the whole solve.
  int max_barrier_steps = 600;
  double tol = 1e-6;  ///< Ipopt's convergence tolerance (the thesis used 1e-6)
  /// #V by 3 unit targets v_i^0; the radial projection from the area-weighted
  /// centroid when absent.
  std::optional<MatrixX3d> target;
  /// #V non-negative per-vertex weights w_i (not all 0): the objective becomes
  /// sum_i w_i t_i . v_i (thesis (4.12) weighs feature points this way); all 1
  /// when absent. The pre-rotation to the targets uses them too.
  std::optional<VectorXd> weights;
};

struct OptimizeSphereResult {
  MatrixX3d positions;        ///< #V by 3 unit vectors, fold-free
  int iterations = 0;         ///< Ipopt's iterations (0 when Ipopt was not run)
  bool used_ipopt = false;    ///< Ipopt ran (solver Ipopt, or Auto in a build with Ipopt)
  int barrier_steps = 0;      ///< Newton steps of the log-barrier warm start (0: Ipopt alone)
  double objective = 0;       ///< sum_i w_i v_i^0 . v_i at the end (sum_i w_i at best)
  double start_objective = 0;
  double epsilon = 0;         ///< the absolute bound used
  double min_triple = 0;      ///< smallest face triple product at the end (>= epsilon to Ipopt's tolerance)
  Index flipped = 0;          ///< faces with a triple product <= 0 (0 on success)
  /// Ipopt's return status, e.g. "Solve_Succeeded"; "Barrier_Point" where the
  /// barrier path's last round stopped at its step cap and its point (every
  /// face above epsilon) is returned without Ipopt; without Ipopt also
  /// "Barrier_Converged" (the path's last round centred) or
  /// "Barrier_Opening" (the steps ran out while opening squeezed faces: fold-
  /// free, but some faces below epsilon).
  std::string status;
  double seconds = 0;
};

/// V, F: a closed genus-0 mesh (checked); sphere: #V by 3 points of a
/// fold-free map of it on a sphere about the origin of any radius (each row
/// is normalised; a zero row raises InvalidInputError), e.g.
/// sphere_map(V, F).positions; checked: raises
/// InvalidInputError naming the folded faces; faces squeezed to a triple
/// product within rounding of 0 are accepted and opened up to epsilon).
/// Raises Cancelled when the progress callback asks to stop.
OptimizeSphereResult optimize_sphere_map(const MatrixX3d& V, const MatrixX3i& F,
                                         const MatrixX3d& sphere,
                                         const OptimizeSphereOptions& options = {},
                                         Progress* progress = nullptr);

/// Triple product det(v_a, v_b, v_c) of every face (its orientation on the sphere).
VectorXd face_triple_products(const MatrixX3d& X, const MatrixX3i& F);

}  // namespace paramorph::morph
