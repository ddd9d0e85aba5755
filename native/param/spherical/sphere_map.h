// Fold-free spherical parameterization of a closed genus-0 mesh
// (thesis ch. 3, 3.3.1 and 4.3.2; DESIGN.md §4.2).
//
//   1. validate (closed, connected, manifold, genus 0, no degenerate faces);
//   2. reorder vertices for memory locality;
//   3. fold-free start: stereographic lift of a Tutte embedding of the mesh
//      punctured at one vertex (or the thesis' centroid relaxation), repaired
//      by relaxation if the lift folds a face, then Möbius-balanced;
//   4. outer loop: saddle-point solve in the tangent planes (x_i · u_i = 1),
//      renormalise (Proposition 3.1: the spring energy cannot increase), stop
//      when the relative energy decrease falls below `outer_tol`, after
//      `max_outer_iterations`, or before a step that would fold a face.
#pragma once

#include <string>
#include <vector>

#include "common/progress.h"
#include "compute/device.h"
#include "mesh/types.h"
#include "param/spherical/saddle_point.h"
#include "param/spherical/spring_graph.h"

namespace paramorph::spherical {

enum class InitialMap { Auto, Stereographic, Relaxation, Progressive };
InitialMap parse_initial_map(const std::string& name);

struct SphereMapOptions {
  Weights weights = Weights::Conformal;
  InnerSolver solver = InnerSolver::Pcg;
  compute::Backend backend = compute::Backend::Auto;
  InitialMap init = InitialMap::Auto;
  double tol = 1e-7;                ///< relative residual of every saddle-point solve
  int max_iterations = 200000;      ///< inner iterations per saddle-point solve
  int max_outer_iterations = 4;     ///< the thesis reports 2–4 (at most 2 after a progressive start)
  double outer_tol = 1e-3;          ///< stop when (E_prev - E) / E_prev < outer_tol
  int check_every = 50;             ///< Jacobi: sweeps between residual tests
  double omega = 0.9;               ///< Jacobi damping
  int max_relaxation_sweeps = 20000;
  bool reorder = true;              ///< renumber vertices for locality while solving
  /// init Auto: keep a Tutte start squeezed to rounding (replaced only when
  /// it folds), and take outer steps unless they fold, as before issue 28.
  /// For the thesis' area-stretch features (segment_extremities,
  /// shape_signature), whose thresholds were measured on that map: a limb
  /// squeezed to 1e-17 reads as an extremity either way.
  bool keep_squeezed_start = false;
};

struct SphereMapResult {
  MatrixX3d positions;               ///< #V by 3 unit vectors, input vertex order
  Index flipped = 0;                 ///< faces with orientation <= 0
  /// Relative residual of the last accepted saddle-point solve; 1 when no
  /// outer step was taken (the start is returned unsolved).
  double residual = 1.0;
  int outer_iterations = 0;
  int inner_iterations = 0;          ///< summed over outer iterations
  std::vector<int> inner_per_outer;
  std::vector<double> energy_history;  ///< spring energy of the start and after each outer step
  bool energy_increased = false;     ///< a step raised the energy (then it was rejected)
  /// "converged", "max_outer_iterations", "fold", "energy", or "inner_stalled"
  /// (the energy stopped falling but the last solve did not reach tol: Jacobi
  /// on a mesh it does not converge on; fold-free all the same).
  std::string stop_reason;
  int relaxation_sweeps = 0;         ///< centroid-relaxation sweeps spent on the start
  /// The start used: "stereographic" (Tutte), "progressive" (built fold-free
  /// coarse to fine) or "relaxation" (the thesis' radial projection).
  std::string initial_map;
  /// Faces of the Tutte start with triple products within rounding of 0
  /// (<= 1e-13); with init "auto", any sends it to the progressive start.
  Index squeezed_start = 0;
  /// Outer steps cut short so that no face folds or reaches rounding.
  int partial_steps = 0;
  VectorXd area_stretch;             ///< #V, Def. 3.1
  std::string weights, solver, backend, device, backend_note;
  double seconds = 0.0;
  std::vector<std::pair<std::string, double>> timings;  ///< per stage, seconds
};

/// V: #V by 3, F: #F by 3 (counter-clockwise seen from outside). Throws a
/// MeshError subclass for invalid meshes, Cancelled when `progress` says so.
SphereMapResult sphere_map(const MatrixX3d& V, const MatrixX3i& F,
                           const SphereMapOptions& options = {}, Progress* progress = nullptr);

}  // namespace paramorph::spherical
