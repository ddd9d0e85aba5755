// Constrained isometric planar parameterization (thesis ch. 2; DESIGN.md §4.1).
//
//   1. validate: an open, connected, manifold genus-0 surface (one or more
//      boundary loops) without degenerate faces;
//   2. start: Tutte on a circle, a free-boundary LSCM map, or the caller's;
//      hard pins are then placed exactly and are not unknowns;
//   3. untangle (Algorithm 2) with the pins fixed if the start folds, then,
//      if it stalls, ε-continuation (untangle_continuation.h); if folds
//      remain, ConstraintError (or the best map when allow_folds);
//   4. L-BFGS on the isometric energy (2.19) + soft-pin penalty, each step
//      bounded by the first inversion, so the map stays fold-free.
//
// The energy, gradient and step bound run on IsometricKernels (C++ or
// OpenCL, 2.3.2); starts, untangling and the Laplacian solve of L-BFGS's H0
// run on the host.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "common/progress.h"
#include "compute/device.h"
#include "mesh/types.h"
#include "param/planar/lbfgs.h"

namespace paramorph::planar {

enum class PlanarInit { Auto, Tutte, Free, Given };
PlanarInit parse_planar_init(const std::string& name);

struct PlanarMapOptions {
  PlanarInit init = PlanarInit::Auto;
  std::optional<MatrixX2d> initial_uv;  ///< with PlanarInit::Given
  std::vector<Index> pinned;            ///< hard pins: vertex indices
  MatrixX2d pinned_uv;                  ///< their exact positions
  std::vector<Index> soft;              ///< soft pins
  MatrixX2d soft_uv;
  double soft_weight = 100.0;
  int max_iterations = 1000;
  /// Converged when the energy fell by less than tol (relative) over the
  /// last 10 iterations, or the gradient norm by a factor 1e-3 · tol.
  double tol = 1e-6;
  bool allow_folds = false;
  compute::Backend backend = compute::Backend::Auto;
};

/// Distortion of the final map after scaling its area to the 3D area, as in
/// thesis Tables 2.1–2.4 (σ1 ≥ σ2 the singular values of each face's map,
/// means weighted by 3D area): area_min/max of σ1σ2 and area_rms the rms of
/// σ1σ2 - 1; angular the mean of σ1/σ2 - 1; l2_min/max of Sander's
/// L2 = sqrt((σ1²+σ2²)/2) and l2_rms the rms of L2 - 1 (the tables' rms are
/// deviations from 1: L2(rms) 0.06 with L2 in [0.72, 1.39]);
/// symmetric_dirichlet the mean of σ1²+σ2²+σ1⁻²+σ2⁻² (4 for an isometry).
struct PlanarMetrics {
  double area_min = 0, area_max = 0, area_rms = 0, angular = 0;
  double l2_min = 0, l2_max = 0, l2_rms = 0, symmetric_dirichlet = 0;
};

struct PlanarMapResult {
  MatrixX2d uv;
  Index flipped = 0;
  int iterations = 0, energy_evaluations = 0, gradient_evaluations = 0;
  int untangle_iterations = 0;
  std::vector<double> energy_history;
  std::string stop_reason, init;
  std::string backend, device, backend_note;  ///< what ran; why "auto" fell back
  PlanarMetrics metrics;
  double seconds = 0.0;
};

PlanarMapResult isometric_map(const MatrixX3d& V, const MatrixX3i& F,
                              const PlanarMapOptions& options = {}, Progress* progress = nullptr);

/// The metrics above for any map (inverted faces count with their |det|).
PlanarMetrics planar_metrics(const MatrixX3d& V, const MatrixX3i& F, const MatrixX2d& uv);

}  // namespace paramorph::planar
