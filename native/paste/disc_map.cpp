// Fold-free map of the disc under a feature (paste/disc_map.h).
#include "paste/disc_map.h"

#include <Eigen/Geometry>
#include <Eigen/SparseCholesky>
#include <cmath>
#include <complex>

#include "common/errors.h"
#include "mesh/cotangent_weights.h"
#include "param/planar/initial_maps.h"
#include "param/planar/isometric_energy.h"
#include "param/planar/isometric_kernels.h"
#include "param/planar/isometric_map.h"
#include "param/planar/laplacian_preconditioner.h"
#include "param/planar/lbfgs.h"

namespace paramorph::paste {

namespace {

/// Tutte's map (param/planar/initial_maps.h's tutte_map, with the weights
/// given): the disc's one boundary loop on the unit circle by arc length,
/// the rest the weighted average of its neighbours.
MatrixX2d tutte(const TriMesh& disc, const VectorXd& weights) {
  const std::vector<Index>& loop = disc.boundary_loops().front();
  const MatrixX3d& V = disc.V();
  std::vector<double> cumulative{0.0};
  for (std::size_t k = 0; k < loop.size(); ++k)
    cumulative.push_back(cumulative.back() + (V.row(loop[(k + 1) % loop.size()]) - V.row(loop[k])).norm());
  MatrixX2d X = MatrixX2d::Zero(disc.num_vertices(), 2);
  std::vector<char> pinned(std::size_t(disc.num_vertices()), 0);
  for (std::size_t k = 0; k < loop.size(); ++k) {
    const double angle = 2.0 * M_PI * cumulative[k] / cumulative.back();
    X.row(loop[k]) << std::cos(angle), std::sin(angle);
    pinned[loop[k]] = 1;
  }
  return planar::harmonic_fill(disc, weights, pinned, std::move(X));
}

/// L-BFGS's H0 shaped by the disc's Laplacian, as planar::LaplacianPreconditioner
/// does it with nothing pinned (clamped cotangent weights, a hair of shift so it is
/// definite), but ordered by AMD: for a few thousand vertices METIS's ordering took
/// longer than the factorization itself (measured 3-10 ms against 1-2.5 ms).
class SmallLaplacian {
 public:
  SmallLaplacian(const TriMesh& disc, const VectorXd& weights) {
    const planar::FreeVertices all = planar::free_vertices(std::vector<char>(std::size_t(disc.num_vertices()), 0));
    lower_ = planar::free_laplacian(disc, weights, all);
    const double shift = 1e-8 * lower_.diagonal().sum() / double(std::max<Index>(1, lower_.rows()));
    for (Index r = 0; r < lower_.rows(); ++r) lower_.coeffRef(r, r) += shift;
    llt_.compute(lower_);
    PM_REQUIRE(llt_.info() == Eigen::Success, TargetTooSmallError,
               "the surface under the feature could not be flattened (degenerate faces there); move the feature");
  }
  planar::LbfgsPreconditioner hooks() const {
    using Interleaved = Eigen::Map<Eigen::Matrix<double, Eigen::Dynamic, 2, Eigen::RowMajor>>;
    return {[this](VectorXd& x) {
              Interleaved X(x.data(), x.size() / 2, 2);
              const Eigen::MatrixX2d solved = llt_.solve(Eigen::MatrixX2d(X));
              X = solved;
            },
            [this](const VectorXd& s) {
              const Eigen::MatrixX2d S = Interleaved(const_cast<double*>(s.data()), s.size() / 2, 2);
              const Eigen::MatrixX2d PS = lower_.selfadjointView<Eigen::Lower>() * S;
              return (S.array() * PS.array()).sum();
            }};
  }

 private:
  Eigen::SparseMatrix<double> lower_;
  Eigen::SimplicialLLT<Eigen::SparseMatrix<double>, Eigen::Lower, Eigen::AMDOrdering<int>> llt_;
};

}  // namespace

DiscMap disc_map(const TriMesh& mesh, const DiscRegion& region, Index anchor_face, const Eigen::Vector3d& bary,
                 const Eigen::Vector3d& tangent, const Eigen::Vector3d& normal,
                 const std::vector<std::pair<Index, Eigen::Vector2d>>& reference, const DiscMapOptions& options) {
  const MatrixX3d& V = mesh.V();
  const MatrixX3i& F = mesh.F();
  const Index nv = Index(region.vertices.size()), nf = Index(region.faces.size());
  std::vector<Index> slot(std::size_t(mesh.num_vertices()), -1);
  MatrixX3d sub_V(nv, 3);
  for (Index i = 0; i < nv; ++i) slot[region.vertices[i]] = i, sub_V.row(i) = V.row(region.vertices[i]);
  MatrixX3i sub_F(nf, 3);
  for (Index k = 0; k < nf; ++k)
    for (int c = 0; c < 3; ++c) sub_F(k, c) = slot[F(region.faces[k], c)];

  // Tutte's embedding, scaled to the disc's area, then the isometric solver
  // (thesis ch. 2) as param/planar/isometric_map.h runs it for a free
  // boundary: L-BFGS shaped by the Laplacian, every step bounded by the first
  // inversion. The region is a disc by construction and has no degenerate
  // face (the session checked the target), so isometric_map's validation
  // and its quality report are left out: they cost as much as the solve.
  const TriMesh disc(sub_V, sub_F);
  const VectorXd weights = clamped_cotangent_weights(disc);
  MatrixX2d uv = tutte(disc, weights);
  const planar::IsometricFactors factors = planar::isometric_factors(sub_V, sub_F);
  {
    double area = 0;
    for (Index k = 0; k < nf; ++k) {
      const Eigen::Vector2d e1 = uv.row(sub_F(k, 1)) - uv.row(sub_F(k, 0));
      const Eigen::Vector2d e2 = uv.row(sub_F(k, 2)) - uv.row(sub_F(k, 0));
      area += 0.5 * std::abs(e1.x() * e2.y() - e1.y() * e2.x());
    }
    uv *= std::sqrt(factors.area.sum() / area);
  }
  const auto folds = [&](const MatrixX2d& map) {
    for (Index k = 0; k < nf; ++k) {
      const Eigen::Vector2d e1 = map.row(sub_F(k, 1)) - map.row(sub_F(k, 0));
      const Eigen::Vector2d e2 = map.row(sub_F(k, 2)) - map.row(sub_F(k, 0));
      if (!(e1.x() * e2.y() - e1.y() * e2.x() > 0)) return true;
    }
    return false;
  };
  DiscMap out;
  if (folds(uv)) {
    // Round-off on slivers can fold Tutte's map: the full solver untangles it.
    planar::PlanarMapOptions o;
    o.init = planar::PlanarInit::Given;
    o.initial_uv = uv;
    o.backend = compute::Backend::Cpu;
    o.max_iterations = options.iterations;
    o.tol = options.tol;
    o.allow_folds = true;
    const planar::PlanarMapResult map = planar::isometric_map(sub_V, sub_F, o);
    uv = map.uv;
    out.iterations = map.iterations;
  } else if (options.iterations > 0) {
    const auto kernels = planar::make_cpu_isometric_kernels(disc, factors);
    MatrixX2d full = uv, grad, direction = MatrixX2d::Zero(nv, 2);
    const auto scatter = [&](const VectorXd& x) {
      for (Index i = 0; i < nv; ++i) full.row(i) << x[2 * i], x[2 * i + 1];
    };
    const planar::EnergyFunction energy = [&](const VectorXd& x, VectorXd* g) {
      scatter(x);
      const double e = kernels->energy(full, g ? &grad : nullptr);
      if (g && std::isfinite(e)) {
        g->resize(2 * nv);
        for (Index i = 0; i < nv; ++i) g->segment<2>(2 * i) = grad.row(i).transpose();
      }
      return e;
    };
    const planar::StepBound bound = [&](const VectorXd& x, const VectorXd& d) {
      scatter(x);
      for (Index i = 0; i < nv; ++i) direction.row(i) << d[2 * i], d[2 * i + 1];
      return kernels->max_feasible_step(full, direction);
    };
    VectorXd x(2 * nv);
    for (Index i = 0; i < nv; ++i) x.segment<2>(2 * i) = uv.row(i).transpose();
    double mean_edge = 0;
    const MatrixX2i& E = disc.edges();
    for (Index e = 0; e < Index(E.rows()); ++e) mean_edge += (sub_V.row(E(e, 0)) - sub_V.row(E(e, 1))).norm();
    mean_edge /= double(std::max<Index>(1, Index(E.rows())));
    planar::LbfgsOptions lo;  // as isometric_map sets them
    lo.max_iterations = options.iterations;
    lo.energy_tol = options.tol;
    lo.energy_window = 10;
    lo.gradient_tol = 1e-3 * options.tol;
    lo.gradient_reference = factors.area.sum() / (mean_edge * std::sqrt(double(nv)));
    const SmallLaplacian laplacian(disc, weights);
    const planar::LbfgsResult result = planar::minimize_lbfgs(energy, bound, x, lo, {}, laplacian.hooks());
    scatter(x);
    uv = full;
    out.iterations = result.iterations;
  }
  PM_REQUIRE(!folds(uv), TargetTooSmallError,
             "the surface under the feature could not be flattened without folds; move the feature or make it "
             "smaller");

  // Placement: the anchor to the origin, its frame onto (u, v).
  Eigen::Vector2d origin = Eigen::Vector2d::Zero();
  for (int c = 0; c < 3; ++c) origin += bary(c) * uv.row(slot[F(anchor_face, c)]).transpose();
  const Eigen::Vector3d anchor = bary(0) * V.row(F(anchor_face, 0)).transpose() +
                                 bary(1) * V.row(F(anchor_face, 1)).transpose() +
                                 bary(2) * V.row(F(anchor_face, 2)).transpose();
  // The similarity z -> c z (complex c) that best fits the map's offsets
  // from the anchor (a) onto the reference's (b): c = sum conj(a) b / sum |a|^2.
  std::complex<double> cross_sum = 0;
  double spread = 0;
  Index fitted = 0;
  const auto pair = [&](const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
    cross_sum += std::conj(std::complex<double>(a.x(), a.y())) * std::complex<double>(b.x(), b.y());
    spread += a.squaredNorm();
  };
  for (const auto& [v, b] : reference)
    if (slot[v] >= 0) pair(uv.row(slot[v]).transpose() - origin, b), ++fitted;
  if (fitted < 3 || !(spread > 0) || !(std::abs(cross_sum) > 0)) {
    // Turn only: the anchor ring laid in the tangent plane at full length.
    cross_sum = 0, spread = 0;
    const Eigen::Vector3d bitangent = normal.cross(tangent);
    const Csr& ring = mesh.vertex_neighbors();
    std::vector<char> used(std::size_t(mesh.num_vertices()), 0);
    const auto fit = [&](Index v) {
      if (used[v] || slot[v] < 0) return;
      used[v] = 1;
      const Eigen::Vector3d offset = V.row(v).transpose() - anchor;
      const Eigen::Vector2d in_plane(tangent.dot(offset), bitangent.dot(offset));
      if (in_plane.norm() > 0) pair(uv.row(slot[v]).transpose() - origin, in_plane * (offset.norm() / in_plane.norm()));
    };
    for (int c = 0; c < 3; ++c) {
      const Index v = F(anchor_face, c);
      fit(v);
      for (Index j = ring.begin(v); j < ring.end(v); ++j) fit(ring.items[j]);
    }
    cross_sum /= std::abs(cross_sum);
  } else {
    cross_sum /= spread;
  }
  PM_REQUIRE(std::isfinite(std::abs(cross_sum)) && std::abs(cross_sum) > 0, TargetTooSmallError,
             "the surface under the feature could not be flattened (degenerate faces there); move the feature");
  out.scale = std::abs(cross_sum);
  Eigen::Matrix2d turn;
  turn << cross_sum.real(), -cross_sum.imag(), cross_sum.imag(), cross_sum.real();

  out.q.assign(std::size_t(mesh.num_vertices()), Eigen::Vector2d::Zero());
  for (Index i = 0; i < nv; ++i) out.q[region.vertices[i]] = turn * (uv.row(i).transpose() - origin);
  return out;
}

}  // namespace paramorph::paste
