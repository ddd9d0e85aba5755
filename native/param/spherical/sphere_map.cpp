#include "param/spherical/sphere_map.h"

#include <chrono>
#include <cmath>

#include "common/errors.h"
#include "compute/select_backend.h"
#include "mesh/reorder.h"
#include "mesh/tri_mesh.h"
#include "mesh/validate.h"
#include "param/spherical/initial_map.h"
#include "param/spherical/sphere_kernels.h"
#include "param/spherical/sphere_quality.h"

namespace paramorph::spherical {

InitialMap parse_initial_map(const std::string& name) {
  if (name == "auto") return InitialMap::Auto;
  if (name == "stereographic") return InitialMap::Stereographic;
  if (name == "relaxation") return InitialMap::Relaxation;
  throw InvalidInputError("init must be \"auto\", \"stereographic\" or \"relaxation\", got \"" +
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

  const SpringGraph graph = build_spring_graph(mesh, edge_weights(mesh, options.weights));
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

  // Fold-free start.
  // One factorisation serves the Tutte start and the PCG preconditioner.
  std::shared_ptr<const PuncturedLaplacian> laplacian;
  if (options.init != InitialMap::Relaxation || options.solver == InnerSolver::Pcg)
    laplacian = factor_punctured_laplacian(mesh, graph);
  clock.mark("factor");
  if (progress) progress->report(0.05, "initial map");
  MatrixX3d X;
  if (options.init == InitialMap::Relaxation)
    X = radial_projection(mesh);
  else
    X = stereographic_tutte_map(mesh, graph, *laplacian);
  if (kernels->count_flipped(X) > 0)
    result.relaxation_sweeps =
        centroid_relaxation(mesh, X, options.max_relaxation_sweeps, 10,
                            ProgressWindow(progress, 0.05, 0.1));
  if (kernels->count_flipped(X) > 0 && options.weights != Weights::Barycentric &&
      options.init != InitialMap::Relaxation) {
    // Negative cotangent weights (long thin triangles, e.g. coarse limbs) can
    // fold the Tutte start beyond repair; uniform weights cannot fold it in
    // the plane (Tutte's theorem), so start from those instead.
    const SpringGraph uniform = build_spring_graph(mesh, edge_weights(mesh, Weights::Barycentric));
    X = stereographic_tutte_map(mesh, uniform, *factor_punctured_laplacian(mesh, uniform));
    if (kernels->count_flipped(X) > 0)
      result.relaxation_sweeps +=
          centroid_relaxation(mesh, X, options.max_relaxation_sweeps, 10,
                              ProgressWindow(progress, 0.05, 0.1));
  }
  const Index start_folds = kernels->count_flipped(X);
  PM_REQUIRE(start_folds == 0, ComputeError, "could not build a fold-free start: ", start_folds,
             " faces still folded after ", result.relaxation_sweeps, " relaxation sweeps");
  if (progress) progress->report(0.09, "initial map");
  mobius_center(X, mesh.F(), vertex_areas(mesh));
  clock.mark("initial map");

  // Outer loop (3.3.1).
  TangentPlaneSolver inner(graph, options.solver, *kernels, laplacian);
  InnerOptions inner_options;
  inner_options.tol = options.tol;
  inner_options.max_iterations = options.max_iterations;
  inner_options.check_every = options.check_every;
  inner_options.omega = options.omega;
  double energy = kernels->energy(X);
  result.energy_history.push_back(energy);
  result.stop_reason = "max_outer_iterations";
  MatrixX3d U;
  for (int outer = 0; outer < options.max_outer_iterations; ++outer) {
    const double lo = 0.1 + 0.85 * outer / options.max_outer_iterations;
    const double hi = 0.1 + 0.85 * (outer + 1) / options.max_outer_iterations;
    if (progress) progress->report(lo, "outer iteration " + std::to_string(outer + 1));
    const InnerResult step = inner.solve(X, U, inner_options, ProgressWindow(progress, lo, hi));
    normalize_rows(U);
    if (kernels->count_flipped(U) > 0) {
      result.stop_reason = "fold";
      break;
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
