#include "param/planar/untangle_continuation.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "param/planar/lbfgs.h"
#include "param/planar/untangle.h"

namespace paramorph::planar {

namespace {

constexpr double kTheta = 1.0 / 128.0;

double chi(double d, double eps) { return 0.5 * (d + std::sqrt(eps * eps + d * d)); }

/// Shape matrix S of face f and its determinant.
Eigen::Matrix2d shape(const IsometricFactors& factors, const MatrixX3i& F, const MatrixX2d& uv,
                      Index f) {
  const double p = factors.factors(f, 0), q = factors.factors(f, 1), r = factors.factors(f, 2);
  const Eigen::Vector2d e1 = uv.row(F(f, 1)) - uv.row(F(f, 0));
  const Eigen::Vector2d e2 = uv.row(F(f, 2)) - uv.row(F(f, 0));
  Eigen::Matrix2d S;
  S.col(0) = p * e1;
  S.col(1) = (q + r) * e2 - q * e1;
  return S;
}

double min_det(const IsometricFactors& factors, const MatrixX3i& F, const MatrixX2d& uv) {
  double lowest = std::numeric_limits<double>::infinity();
  for (Index f = 0; f < Index(F.rows()); ++f) lowest = std::min(lowest, shape(factors, F, uv, f).determinant());
  return lowest;
}

/// E_ε and, when asked, its gradient (#V by 2).
double regularised_energy(const IsometricFactors& factors, const MatrixX3i& F, const MatrixX2d& uv,
                          double eps, MatrixX2d* gradient) {
  if (gradient) gradient->setZero(uv.rows(), 2);
  double total = 0.0;
  for (Index f = 0; f < Index(F.rows()); ++f) {
    const Eigen::Matrix2d S = shape(factors, F, uv, f);
    const double d = S.determinant(), c = chi(d, eps), w = factors.area[f];
    const double frob = S.squaredNorm();
    total += w * ((1.0 - kTheta) * frob + kTheta * (d * d + 1.0)) / c;
    if (!gradient) continue;
    const double dchi = 0.5 * (1.0 + d / std::sqrt(eps * eps + d * d));
    Eigen::Matrix2d cof;
    cof << S(1, 1), -S(1, 0), -S(0, 1), S(0, 0);
    const double numerator = (1.0 - kTheta) * frob + kTheta * (d * d + 1.0);
    const Eigen::Matrix2d dS =
        w * ((1.0 - kTheta) * 2.0 * S / c + (kTheta * 2.0 * d / c - numerator * dchi / (c * c)) * cof);
    const double p = factors.factors(f, 0), q = factors.factors(f, 1), r = factors.factors(f, 2);
    const Eigen::Vector2d g1 = p * dS.col(0) - q * dS.col(1);
    const Eigen::Vector2d g2 = (q + r) * dS.col(1);
    gradient->row(F(f, 1)) += g1.transpose();
    gradient->row(F(f, 2)) += g2.transpose();
    gradient->row(F(f, 0)) -= (g1 + g2).transpose();
  }
  return total;
}

}  // namespace

ContinuationResult untangle_continuation(const IsometricFactors& factors, const MatrixX3i& F,
                                         MatrixX2d& uv, const std::vector<char>& fixed,
                                         const ContinuationOptions& o, ProgressWindow progress) {
  ContinuationResult result;
  std::vector<Index> free;
  for (Index v = 0; v < Index(uv.rows()); ++v)
    if (!fixed[v]) free.push_back(v);
  const Index nf = Index(free.size());
  // The shape matrices are scale-dependent; ε starts at the scale of a
  // typical |det S| so the first round is a smooth problem.
  double typical = 0.0;
  for (Index f = 0; f < Index(F.rows()); ++f) typical += std::abs(shape(factors, F, uv, f).determinant());
  typical /= std::max<Index>(1, Index(F.rows()));
  result.folded = Index(folded_faces(F, uv).size());
  if (nf == 0 || (result.folded == 0 && min_det(factors, F, uv) >= o.min_relative_det * typical))
    return result;
  double eps = typical;
  MatrixX2d full = uv, grad;
  auto scatter = [&](const VectorXd& x) {
    for (Index i = 0; i < nf; ++i) full.row(free[i]) << x[2 * i], x[2 * i + 1];
  };
  VectorXd x(2 * nf);
  for (Index i = 0; i < nf; ++i) x.segment<2>(2 * i) = uv.row(free[i]).transpose();
  const StepBound unbounded = [](const VectorXd&, const VectorXd&) {
    return std::numeric_limits<double>::infinity();
  };
  scatter(x);
  int extra_rounds = 0;
  double previous = regularised_energy(factors, F, full, eps, nullptr);
  for (; result.rounds < o.max_rounds; ++result.rounds) {
    const EnergyFunction energy = [&](const VectorXd& y, VectorXd* g) {
      scatter(y);
      const double e = regularised_energy(factors, F, full, eps, g ? &grad : nullptr);
      if (g) {
        g->resize(2 * nf);
        for (Index i = 0; i < nf; ++i) g->segment<2>(2 * i) = grad.row(free[i]).transpose();
      }
      return e;
    };
    LbfgsOptions lo;
    lo.max_iterations = o.iterations_per_round;
    lo.energy_tol = 1e-9;
    const LbfgsResult lr = minimize_lbfgs(energy, unbounded, x, lo);
    result.iterations += lr.iterations;
    scatter(x);
    const double current = lr.energy_history.back();
    const double lowest = min_det(factors, F, full);
    result.folded = Index(folded_faces(F, full).size());
    progress.report(double(result.rounds + 1) / o.max_rounds, "untangle");
    // Fold-free is enough once no face is a sliver: a det near 0 would leave
    // the barrier optimisation that follows with steps of 1e-14.
    if (result.folded == 0 && lowest > 0.0 &&
        (lowest >= o.min_relative_det * typical || ++extra_rounds > o.extra_rounds))
      break;
    // Their ε update: shrink towards the smallest det at the pace the energy falls.
    const double sigma = std::max(1.0 - current / previous, 0.1);
    const double mu = (1.0 - sigma) * chi(lowest, eps);
    eps = lowest < mu ? 2.0 * std::sqrt(mu * (mu - lowest)) : 1e-12 * typical;
    previous = regularised_energy(factors, F, full, eps, nullptr);
  }
  uv = full;
  result.folded = Index(folded_faces(F, uv).size());
  return result;
}

}  // namespace paramorph::planar
