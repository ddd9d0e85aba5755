#include "param/planar/isometric_map.h"

#include <Eigen/Dense>
#include <chrono>
#include <cmath>
#include <complex>

#include "common/errors.h"
#include "compute/select_backend.h"
#include "mesh/cotangent_weights.h"
#include "mesh/tri_mesh.h"
#include "mesh/validate.h"
#include "param/planar/initial_maps.h"
#include "param/planar/isometric_energy.h"
#include "param/planar/isometric_kernels.h"
#include "param/planar/laplacian_preconditioner.h"
#include "param/planar/untangle.h"
#include "param/planar/untangle_continuation.h"

namespace paramorph::planar {

PlanarInit parse_planar_init(const std::string& name) {
  if (name == "auto") return PlanarInit::Auto;
  if (name == "tutte") return PlanarInit::Tutte;
  if (name == "free") return PlanarInit::Free;
  throw InvalidInputError("init must be \"auto\", \"tutte\", \"free\" or an (n, 2) array, got \"" +
                          name + "\"");
}

namespace {

void require_open_genus0(const MeshReport& r) {
  require_manifold(r);
  PM_REQUIRE(r.degenerate_faces.empty(), DegenerateFaceError, "mesh has ",
             r.degenerate_faces.size(), " degenerate (zero-area) faces: ",
             format_indices(r.degenerate_faces));
  const Index surfaces = r.components - Index(r.isolated_vertices.size());
  PM_REQUIRE(surfaces == 1, DisconnectedError, "mesh has ", surfaces,
             " connected components; map one connected patch at a time");
  PM_REQUIRE(r.isolated_vertices.empty(), DisconnectedError, "mesh has ",
             r.isolated_vertices.size(), " loose vertices that belong to no face (",
             format_indices(r.isolated_vertices), ")");
  PM_REQUIRE(r.boundary_loops > 0, NotOpenError,
             "mesh is closed: a planar map needs a boundary; cut a seam first");
  PM_REQUIRE(r.genus == 0, NotGenusZeroError, "mesh patch has genus ", r.genus,
             " (handles); cut it into a disc (or a disc with holes) first");
}

void check_pins(const std::vector<Index>& pins, const MatrixX2d& targets, Index n,
                const char* what) {
  PM_REQUIRE(Index(targets.rows()) == Index(pins.size()), InvalidInputError, what,
             ": one (u, v) target per pinned vertex expected, got ", targets.rows(), " for ",
             pins.size());
  PM_REQUIRE(targets.allFinite(), InvalidInputError, what, " targets must be finite");
  std::vector<char> seen(n, 0);
  for (Index v : pins) {
    PM_REQUIRE(v >= 0 && v < n, InvalidInputError, what, " index ", v, " is out of range for ",
               n, " vertices");
    PM_REQUIRE(!seen[v], ConstraintError, what, " index ", v, " is given twice");
    seen[v] = 1;
  }
}

/// Rescales a map so its total area equals the surface's (isometry's scale).
void match_area(const MatrixX3i& F, double surface_area, MatrixX2d& uv) {
  double area = 0.0;
  for (Index f = 0; f < Index(F.rows()); ++f) {
    const Eigen::Vector2d e1 = uv.row(F(f, 1)) - uv.row(F(f, 0));
    const Eigen::Vector2d e2 = uv.row(F(f, 2)) - uv.row(F(f, 0));
    area += 0.5 * std::abs(e1.x() * e2.y() - e1.y() * e2.x());
  }
  if (area > 0) uv *= std::sqrt(surface_area / area);
}

/// uv moved by the similarity z -> a z + b (complex a, b) that best fits the
/// pinned rows to their targets in least squares; a translation for one pin.
MatrixX2d fit_similarity(const MatrixX2d& uv, const std::vector<Index>& pins,
                         const MatrixX2d& targets) {
  using C = std::complex<double>;
  const double k = double(pins.size());
  C mean_z = 0, mean_t = 0;
  for (std::size_t i = 0; i < pins.size(); ++i) {
    mean_z += C(uv(pins[i], 0), uv(pins[i], 1)) / k;
    mean_t += C(targets(i, 0), targets(i, 1)) / k;
  }
  C cross = 0;
  double spread = 0;
  for (std::size_t i = 0; i < pins.size(); ++i) {
    const C z = C(uv(pins[i], 0), uv(pins[i], 1)) - mean_z;
    cross += std::conj(z) * (C(targets(i, 0), targets(i, 1)) - mean_t);
    spread += std::norm(z);
  }
  const C a = spread > 0 ? cross / spread : C(1.0);
  MatrixX2d out(uv.rows(), 2);
  for (Index v = 0; v < Index(uv.rows()); ++v) {
    const C w = a * (C(uv(v, 0), uv(v, 1)) - mean_z) + mean_t;
    out.row(v) << w.real(), w.imag();
  }
  return out;
}

}  // namespace

PlanarMetrics planar_metrics(const MatrixX3d& V, const MatrixX3i& F, const MatrixX2d& uv_in) {
  const IsometricFactors factors = isometric_factors(V, F);
  MatrixX2d uv = uv_in;
  match_area(F, factors.area.sum(), uv);
  PlanarMetrics m;
  m.area_min = m.l2_min = std::numeric_limits<double>::infinity();
  double total = 0, area_sq = 0, angular = 0, l2_sq = 0, sd = 0;
  for (Index f = 0; f < Index(F.rows()); ++f) {
    const double p = factors.factors(f, 0), q = factors.factors(f, 1), r = factors.factors(f, 2);
    const Eigen::Matrix2d S =
        shape_matrix(p, q, r, uv.row(F(f, 0)), uv.row(F(f, 1)), uv.row(F(f, 2)));
    const Eigen::Vector2d s = Eigen::JacobiSVD<Eigen::Matrix2d>(S).singularValues();
    const double w = factors.area[f], ratio = s[0] * s[1];
    const double l2 = std::sqrt(0.5 * (s[0] * s[0] + s[1] * s[1]));
    m.area_min = std::min(m.area_min, ratio);
    m.area_max = std::max(m.area_max, ratio);
    m.l2_min = std::min(m.l2_min, l2);
    m.l2_max = std::max(m.l2_max, l2);
    total += w;
    area_sq += w * (ratio - 1.0) * (ratio - 1.0);
    angular += w * (s[1] > 0 ? s[0] / s[1] - 1.0 : std::numeric_limits<double>::infinity());
    l2_sq += w * (l2 - 1.0) * (l2 - 1.0);
    sd += w * (s[0] * s[0] + s[1] * s[1] + 1.0 / (s[0] * s[0]) + 1.0 / (s[1] * s[1]));
  }
  m.area_rms = std::sqrt(area_sq / total);
  m.angular = angular / total;
  m.l2_rms = std::sqrt(l2_sq / total);
  m.symmetric_dirichlet = sd / total;
  return m;
}

PlanarMapResult isometric_map(const MatrixX3d& V, const MatrixX3i& F, const PlanarMapOptions& o,
                              Progress* progress) {
  const auto start = std::chrono::steady_clock::now();
  PM_REQUIRE(o.max_iterations >= 0 && std::isfinite(o.tol) && o.tol >= 0 && std::isfinite(o.soft_weight) &&
                 o.soft_weight >= 0,
             InvalidInputError, "need max_iterations >= 0, a finite tol >= 0 and a finite soft_weight >= 0 (got tol ",
             o.tol, ", soft_weight ", o.soft_weight, ")");
  if (progress) progress->report(0.0, "validate");
  validate_arrays(V, F);
  const TriMesh mesh(V, F);
  require_open_genus0(validate(mesh));
  const Index n = mesh.num_vertices();
  check_pins(o.pinned, o.pinned_uv, n, "pinned");
  check_pins(o.soft, o.soft_uv, n, "soft");

  PlanarMapResult result;
  // Reports between the steps of the start (each a sparse solve or two), so
  // progress and cancel come every fraction of a second on big patches.
  if (progress) progress->report(0.01, "factors");
  const IsometricFactors factors = isometric_factors(V, F);
  const auto kernels = compute::select_backend(
      o.backend, [&] { return make_cpu_isometric_kernels(mesh, factors); },
      [&](std::string& why) { return make_opencl_isometric_kernels(mesh, factors, why); },
      result.backend_note);
  result.backend = kernels->backend();
  result.device = kernels->device();
  const double surface_area = factors.area.sum();

  // Start.
  if (progress) progress->report(0.02, "start map");
  PlanarInit init = o.init;
  if (init == PlanarInit::Auto) init = o.initial_uv ? PlanarInit::Given : PlanarInit::Free;
  MatrixX2d uv;
  if (init == PlanarInit::Given) {
    PM_REQUIRE(o.initial_uv && o.initial_uv->rows() == n && o.initial_uv->allFinite(),
               InvalidInputError, "init array must be a finite (", n, ", 2) array");
    uv = *o.initial_uv;
    result.init = "given";
  } else if (init == PlanarInit::Tutte) {
    uv = tutte_map(mesh);
    result.init = "tutte";
  } else {
    uv = lscm_map(mesh);
    result.init = "free";
  }
  if (init != PlanarInit::Given && o.pinned.empty()) match_area(F, surface_area, uv);
  std::vector<char> fixed(n, 0);
  MatrixX2d targets = MatrixX2d::Zero(n, 2);
  for (std::size_t k = 0; k < o.pinned.size(); ++k) {
    targets.row(o.pinned[k]) = o.pinned_uv.row(k);
    fixed[o.pinned[k]] = 1;
  }
  if (!o.pinned.empty()) {
    if (progress) progress->report(0.03, "pins");
    // Bring the start to the pins: first as a whole (least-squares similarity,
    // so its scale and orientation match theirs), then each pin exactly by
    // the smoothest displacement field. With the whole boundary pinned a
    // computed start is re-solved inside that boundary first (Tutte).
    if (init != PlanarInit::Given) uv = fit_similarity(uv, o.pinned, o.pinned_uv);
    std::vector<char> on_boundary(n, 0);
    bool boundary_pinned = init != PlanarInit::Given;
    for (const auto& loop : mesh.boundary_loops())
      for (Index v : loop) boundary_pinned = boundary_pinned && fixed[v], on_boundary[v] = 1;
    if (boundary_pinned) {
      for (Index v = 0; v < n; ++v)
        if (on_boundary[v]) uv.row(v) = targets.row(v);
      uv = harmonic_fill(mesh, clamped_cotangent_weights(mesh), on_boundary, uv);
      if (progress) progress->report(0.04, "pins");
    }
    uv = blend_pins(mesh, uv, fixed, targets);
  }
  if (progress) progress->report(0.05, "untangle");

  // Untangle (Algorithm 2) when the start folds.
  if (!folded_faces(F, uv).empty()) {
    const UntangleResult u = untangle(F, uv, fixed, {}, ProgressWindow(progress, 0.05, 0.1));
    result.untangle_iterations = u.iterations;
    // Where Algorithm 2 stalled or left slivers: ε-continuation from its result.
    const FreeVertices movable = free_vertices(fixed);
    const LaplacianPreconditioner laplacian(mesh, movable, VectorXd());
    const ContinuationResult c =
        untangle_continuation(factors, F, uv, fixed, {}, ProgressWindow(progress, 0.1, 0.2),
                              movable.vertices.empty() ? LbfgsPreconditioner{}
                                                       : laplacian_lbfgs_preconditioner(laplacian));
    result.untangle_iterations += c.iterations;
    const Index folded = c.folded;
    if (folded > 0) {
      PM_REQUIRE(o.allow_folds, ConstraintError, folded,
                 " faces stay folded after untangling: the pins cannot all be met without "
                 "folds (move them apart, or pass allow_folds=True for the best map)");
      result.uv = uv;
      result.flipped = folded;
      result.stop_reason = "folded";
      result.metrics = planar_metrics(V, F, uv);
      result.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
      return result;
    }
  }

  // Free unknowns: every vertex not hard-pinned.
  const FreeVertices free = free_vertices(fixed);
  const Index nf = Index(free.vertices.size());
  // Soft pins: soft_weight · A_i |uv_i - t_i|² / h², h the mean edge length, so
  // the penalty is an area like the isometric energy.
  const MatrixX2i& E = mesh.edges();
  double mean_edge = 0.0;
  for (Index e = 0; e < Index(E.rows()); ++e) mean_edge += (V.row(E(e, 0)) - V.row(E(e, 1))).norm();
  mean_edge /= std::max<Index>(1, Index(E.rows()));
  VectorXd soft_scale = VectorXd::Zero(n);
  MatrixX2d soft_target = MatrixX2d::Zero(n, 2);
  {
    VectorXd vertex_area = VectorXd::Zero(n);
    for (Index f = 0; f < Index(F.rows()); ++f)
      for (int k = 0; k < 3; ++k) vertex_area[F(f, k)] += factors.area[f] / 3.0;
    for (std::size_t k = 0; k < o.soft.size(); ++k) {
      soft_scale[o.soft[k]] = o.soft_weight * vertex_area[o.soft[k]] / (mean_edge * mean_edge);
      soft_target.row(o.soft[k]) = o.soft_uv.row(k);
    }
  }
  MatrixX2d full = uv, grad;
  auto scatter = [&](const VectorXd& x) {
    for (Index i = 0; i < nf; ++i) full.row(free.vertices[i]) << x[2 * i], x[2 * i + 1];
  };
  const EnergyFunction energy = [&](const VectorXd& x, VectorXd* g) {
    scatter(x);
    double e = kernels->energy(full, g ? &grad : nullptr);
    if (!std::isfinite(e)) return e;
    for (Index k : o.soft) {
      const Eigen::RowVector2d d = full.row(k) - soft_target.row(k);
      e += soft_scale[k] * d.squaredNorm();
      if (g) grad.row(k) += 2.0 * soft_scale[k] * d;
    }
    if (g) {
      g->resize(2 * nf);
      for (Index i = 0; i < nf; ++i) g->segment<2>(2 * i) = grad.row(free.vertices[i]).transpose();
    }
    return e;
  };
  MatrixX2d direction = MatrixX2d::Zero(n, 2);
  const StepBound bound = [&](const VectorXd& x, const VectorXd& d) {
    scatter(x);
    for (Index i = 0; i < nf; ++i) direction.row(free.vertices[i]) << d[2 * i], d[2 * i + 1];
    return kernels->max_feasible_step(full, direction);
  };
  VectorXd x(2 * nf);
  for (Index i = 0; i < nf; ++i) x.segment<2>(2 * i) = uv.row(free.vertices[i]).transpose();
  LbfgsOptions lo;
  lo.max_iterations = o.max_iterations;
  lo.energy_tol = o.tol;
  lo.energy_window = 10;
  lo.gradient_tol = 1e-3 * o.tol;
  // |g| in the energy's own units, not |g0|'s (a squeezed LSCM start of a
  // bunny patch has |g0| ~1e6 times that): the gradient at which moving every
  // free vertex by an edge length would change E by the surface area.
  lo.gradient_reference = surface_area / (mean_edge * std::sqrt(double(std::max<Index>(1, nf))));
  LbfgsResult lr;
  if (nf > 0) {
    VectorXd penalty_diagonal = 2.0 * soft_scale;  // the soft pins' exact Hessian
    const LaplacianPreconditioner laplacian(mesh, free, penalty_diagonal);
    lr = minimize_lbfgs(energy, bound, x, lo, ProgressWindow(progress, 0.2, 1.0),
                        laplacian_lbfgs_preconditioner(laplacian));
  }
  scatter(x);
  result.uv = full;
  result.iterations = lr.iterations;
  result.energy_evaluations = lr.energy_evaluations;
  result.gradient_evaluations = lr.gradient_evaluations;
  result.energy_history = lr.energy_history;
  result.stop_reason = lr.stop_reason;
  result.flipped = Index(folded_faces(F, result.uv).size());
  result.metrics = planar_metrics(V, F, result.uv);
  result.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  if (progress) progress->report(1.0, "done");
  return result;
}

}  // namespace paramorph::planar
