#include "param/spherical/sphere_map.h"

#include <chrono>
#include <cmath>
#include <limits>

#include "common/errors.h"
#include "common/report_while.h"
#include "compute/select_backend.h"
#include "mesh/reorder.h"
#include "mesh/tri_mesh.h"
#include "mesh/validate.h"
#include "param/spherical/initial_map.h"
#include "param/spherical/progressive_sphere_map.h"
#include "param/spherical/sphere_kernels.h"
#include "param/spherical/sphere_quality.h"

namespace paramorph::spherical {

InitialMap parse_initial_map(const std::string& name) {
  if (name == "auto") return InitialMap::Auto;
  if (name == "stereographic") return InitialMap::Stereographic;
  if (name == "relaxation") return InitialMap::Relaxation;
  if (name == "progressive") return InitialMap::Progressive;
  throw InvalidInputError("init must be \"auto\", \"stereographic\", \"relaxation\" or \"progressive\", got \"" +
                          name + "\"");
}

namespace {

class StageClock {
 public:
  explicit StageClock(std::vector<std::pair<std::string, double>>& out) : out_(out) {}
  void mark(const std::string& stage) {
    const auto now = std::chrono::steady_clock::now();
    out_.emplace_back(stage, std::chrono::duration<double>(now - last_).count());
    last_ = now;
  }

 private:
  std::vector<std::pair<std::string, double>>& out_;
  std::chrono::steady_clock::time_point last_ = std::chrono::steady_clock::now();
};

void normalize_rows(MatrixX3d& X) { X.rowwise().normalize(); }

/// Triple products at or below this are within rounding of 0 (unit
/// vectors: about 1e-16 absolute error), the project's threshold
/// (kTripleRoundoff, sphere_map_barrier's kRoundoff).
constexpr double kSqueezedTriple = 1e-13;
/// Under init auto, the thesis' relaxation repairs a folded start for at
/// most this many sweeps x faces (20,000 sweeps up to 5k faces, 1,000 at
/// 100k: about a second) before the progressive start takes over.
constexpr double kRepairFaceSweeps = 1e8;
/// Partial outer steps keep every face this far clear.
constexpr double kClearTriple = 1e-12;

double min_triple(const MatrixX3d& X, const MatrixX3i& F) {
  double smallest = std::numeric_limits<double>::infinity();
  for (Index f = 0; f < F.rows(); ++f)
    smallest = std::min(smallest, X.row(F(f, 0)).dot(X.row(F(f, 1)).cross(X.row(F(f, 2)))));
  return smallest;
}

Index squeezed_faces(const MatrixX3d& X, const MatrixX3i& F) {
  Index count = 0;
  for (Index f = 0; f < F.rows(); ++f)
    count += X.row(F(f, 0)).dot(X.row(F(f, 1)).cross(X.row(F(f, 2)))) <= kSqueezedTriple;
  return count;
}

}  // namespace

SphereMapResult sphere_map(const MatrixX3d& V_in, const MatrixX3i& F_in,
                           const SphereMapOptions& options, Progress* progress) {
  const auto start = std::chrono::steady_clock::now();
  SphereMapResult result;
  StageClock clock(result.timings);
  PM_REQUIRE(std::isfinite(options.tol) && options.tol > 0 && std::isfinite(options.outer_tol) &&
                 options.outer_tol >= 0 && options.max_iterations > 0 && options.max_outer_iterations >= 0 &&
                 options.check_every > 0 && options.omega > 0 && options.omega < 1,
             InvalidInputError,
             "need a finite tol > 0, a finite outer_tol >= 0, max_iterations > 0, max_outer_iterations >= 0, "
             "check_every > 0 and 0 < omega < 1 (got tol ", options.tol, ", outer_tol ", options.outer_tol,
             ", omega ", options.omega, ")");
  if (progress) progress->report(0.0, "validate");

  validate_arrays(V_in, F_in);
  TriMesh mesh(V_in, F_in);
  require_closed_genus0(validate(mesh));  // on the input numbering, so errors name input indices
  clock.mark("validate");
  // Reports between the setup steps too (each up to a second on 100k faces),
  // so Esc acts within half a second (issue 20).
  if (progress) progress->report(0.01, "reorder");

  // Locality: solve on a renumbered copy, map back at the end.
  Reordering order;
  if (options.reorder) {
    order = locality_order(V_in, F_in);
    mesh = TriMesh(order.apply_to_vertices(V_in), order.apply_to_faces(F_in));
  }
  clock.mark("reorder");
  if (progress) progress->report(0.02, "setup");

  // Shared, so a factorisation left running by a cancel still has them.
  const auto shared_mesh = std::make_shared<const TriMesh>(mesh);
  const auto shared_graph =
      std::make_shared<const SpringGraph>(build_spring_graph(mesh, edge_weights(mesh, options.weights)));
  const SpringGraph& graph = *shared_graph;
  // The factorisation cannot report (11 s at a million faces): it runs
  // beside a thread that does, and a cancel returns at once.
  auto factor = [&](const std::shared_ptr<const SpringGraph>& weights) {
    return report_while([shared_mesh, weights] { return factor_punctured_laplacian(*shared_mesh, *weights); },
                        progress, 0.05, "factor the Laplacian");
  };
  auto kernels = compute::select_backend(
      options.backend, [&] { return make_cpu_kernels(graph, mesh.F()); },
      [&](std::string& why) { return make_opencl_kernels(graph, mesh.F(), why); },
      result.backend_note);
  result.backend = kernels->backend();
  result.device = kernels->device();
  result.weights = to_string(options.weights);
  result.solver = to_string(options.solver);
  clock.mark("setup");
  if (progress) progress->report(0.05, "initial map");

  // Fold-free start. One factorisation serves the Tutte start and the PCG
  // preconditioner.
  std::shared_ptr<const PuncturedLaplacian> laplacian;
  const bool tutte = options.init == InitialMap::Auto || options.init == InitialMap::Stereographic;
  if (tutte || options.solver == InnerSolver::Pcg) laplacian = factor(shared_graph);
  clock.mark("factor");
  if (progress) progress->report(0.05, "initial map");
  MatrixX3d X;
  bool progressive = options.init == InitialMap::Progressive;
  if (tutte) {
    X = stereographic_tutte_map(mesh, graph, *laplacian);
    // Judged balanced, as the outer loop gets it: the lift alone leaves
    // faces far from the puncture small (the bunny: 9 within rounding before
    // Möbius balancing, none after).
    if (kernels->count_flipped(X) == 0) mobius_center(X, mesh.F(), vertex_areas(mesh));
    result.squeezed_start = squeezed_faces(X, mesh.F());
    // The Tutte start is fold-free only in exact arithmetic: long limbs
    // shrink geometrically to rounding (20% of a cat's faces at 1e-18), and
    // a face turned over by rounding cannot be relaxed back out in time (a
    // dancer: 295 faces after 40,000 sweeps). auto then builds the start
    // that is valid by construction.
    progressive = options.init == InitialMap::Auto && !options.keep_squeezed_start && result.squeezed_start > 0;
  }
  if (options.init == InitialMap::Relaxation) X = radial_projection(mesh);
  if (!progressive && kernels->count_flipped(X) > 0) {
    // The thesis' repair: centroid relaxation, then (cotangent weights can
    // fold the Tutte start beyond repair; uniform ones cannot, in the plane)
    // a start from uniform weights. Under auto it gets a bounded number of
    // sweeps (sweeps x faces; a 84k-face elephant spent 13-17 s here), then
    // the progressive start takes over.
    const bool automatic = options.init == InitialMap::Auto;
    const int sweeps = automatic ? int(std::min<double>(options.max_relaxation_sweeps,
                                                        kRepairFaceSweeps / double(mesh.num_faces())))
                                 : options.max_relaxation_sweeps;
    result.relaxation_sweeps = centroid_relaxation(mesh, X, sweeps, 10, ProgressWindow(progress, 0.05, 0.1));
    if (kernels->count_flipped(X) > 0 && options.weights != Weights::Barycentric &&
        options.init != InitialMap::Relaxation) {
      const auto uniform =
          std::make_shared<const SpringGraph>(build_spring_graph(mesh, edge_weights(mesh, Weights::Barycentric)));
      X = stereographic_tutte_map(mesh, *uniform, *factor(uniform));
      if (kernels->count_flipped(X) > 0)
        result.relaxation_sweeps += centroid_relaxation(mesh, X, sweeps, 10, ProgressWindow(progress, 0.05, 0.1));
    }
    const Index start_folds = kernels->count_flipped(X);
    PM_REQUIRE(start_folds == 0 || automatic, ComputeError, "could not build a fold-free start: ", start_folds,
               " faces still folded after ", result.relaxation_sweeps,
               " relaxation sweeps (init=\"auto\" or \"progressive\" builds one that is fold-free by construction)");
    progressive = start_folds > 0;
  }
  double start_done = 0.1;
  if (progressive) {
    X = progressive_sphere_map(mesh, {}, ProgressWindow(progress, 0.05, 0.45)).positions;
    result.initial_map = "progressive";
    start_done = 0.5;
  } else {
    result.initial_map = options.init == InitialMap::Relaxation ? "relaxation" : "stereographic";
  }
  if (progress) progress->report(start_done - 0.01, "initial map");
  mobius_center(X, mesh.F(), vertex_areas(mesh));
  clock.mark("initial map");

  // Outer loop (3.3.1).
  TangentPlaneSolver inner(graph, options.solver, *kernels, laplacian);
  InnerOptions inner_options;
  // After the progressive start the steps go towards a conformal map the
  // limbs keep out of reach (all were cut short on the real characters), so
  // two steps solved to 1e-2 do what there is to do. Measured (area-weighted
  // quasi-conformal distortion, 0 / 2 / 4 steps): cat 4.17 / 2.98 / 3.58,
  // dancer 7.47 / 6.42 / 6.32, horned cow 4.07 / 3.27 / 3.17, a 112k-face
  // star 20.96 / 20.06 / 20.01 in 1.4 / 2.5 / 3.9 s; solved to 1e-2 instead
  // of 1e-3, the same distortion to 2-3 digits, the star in 2.3 s.
  inner_options.tol = progressive ? std::max(options.tol, 1e-2) : options.tol;
  const int outer_iterations = progressive ? std::min(options.max_outer_iterations, 2) : options.max_outer_iterations;
  inner_options.max_iterations = options.max_iterations;
  inner_options.check_every = options.check_every;
  inner_options.omega = options.omega;
  double energy = kernels->energy(X);
  result.energy_history.push_back(energy);
  result.stop_reason = "max_outer_iterations";
  MatrixX3d U;
  for (int outer = 0; outer < outer_iterations; ++outer) {
    const double span = 0.95 - start_done;
    const double lo = start_done + span * outer / outer_iterations;
    const double hi = start_done + span * (outer + 1) / outer_iterations;
    if (progress) progress->report(lo, "outer iteration " + std::to_string(outer + 1));
    const InnerResult step = inner.solve(X, U, inner_options, ProgressWindow(progress, lo, hi));
    normalize_rows(U);
    const bool folds = kernels->count_flipped(U) > 0;
    if (folds && options.keep_squeezed_start) {
      result.stop_reason = "fold";
      break;
    }
    if (folds || (!options.keep_squeezed_start && squeezed_faces(U, mesh.F()) > squeezed_faces(X, mesh.F()))) {
      // A step that folds or squeezes faces to rounding (towards a
      // conformal map that long limbs make unrepresentable): part of it,
      // as far as every face stays kClearTriple clear of rounding.
      // (Measured: cutting the step back vertex by vertex instead, only
      // where faces would squeeze, raised the energy and moved less.)
      const double clear = std::min(kClearTriple, 0.5 * min_triple(X, mesh.F()));
      bool partial = false;
      for (double t = 0.5; t >= 1.0 / 64 && !partial; t *= 0.5) {
        MatrixX3d Y = X + t * (U - X);
        normalize_rows(Y);
        if (min_triple(Y, mesh.F()) > clear) {
          U.swap(Y);
          partial = true;
        }
      }
      if (!partial) {
        result.stop_reason = "fold";
        break;
      }
      result.partial_steps += 1;
    }
    const double next_energy = kernels->energy(U);
    // Proposition 3.1: |u_i| >= 1, so renormalising cannot raise the energy,
    // and the solve itself lowers it; a rise means the solve went wrong.
    if (next_energy > energy * (1.0 + 1e-12)) {
      result.energy_increased = true;
      result.stop_reason = "energy";
      break;
    }
    X.swap(U);
    result.outer_iterations += 1;
    result.inner_iterations += step.iterations;
    result.inner_per_outer.push_back(step.iterations);
    result.residual = step.residual;
    result.energy_history.push_back(next_energy);
    const double decrease = (energy - next_energy) / energy;
    energy = next_energy;
    if (decrease < options.outer_tol) {
      // "converged" only when the last solve met tol; a stalled one (Jacobi
      // on a mesh it does not converge on) says so.
      result.stop_reason = step.converged ? "converged" : "inner_stalled";
      break;
    }
  }
  clock.mark("outer loop");

  result.flipped = Index(flipped_faces(X, mesh.F()).size());
  result.area_stretch = area_stretch(mesh, X);
  if (options.reorder) {
    result.positions = order.restore_vertices(X);
    result.area_stretch = order.restore_vector(result.area_stretch);
  } else {
    result.positions = std::move(X);
  }
  clock.mark("finish");
  result.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  if (progress) progress->report(1.0, "done");
  return result;
}

}  // namespace paramorph::spherical
