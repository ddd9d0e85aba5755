#include "param/planar/untangle_continuation.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "common/parallel.h"
#include "param/planar/lbfgs.h"
#include "param/planar/untangle.h"

namespace paramorph::planar {

namespace {

constexpr double kTheta = 1.0 / 128.0;
constexpr double kMaxAspectRatio = 10.0;
constexpr double kSmallestEpsilon = 1e-9;  ///< in units of the local det scale
constexpr double kSmallestScale = 1e-12;   ///< floor of a face's UV / 3D area
constexpr int kScaleSmoothingPasses = 10;
/// ε shrinks at least this fast when the smallest det is negative (the
/// paper's 0.1 needs 3x the rounds on a 50k-face bunny patch and did not
/// untangle more in our tests).
constexpr double kMinimumSigma = 0.5;

/// (D + sqrt(ε² + D²)) / 2, written without cancellation for D < 0.
double chi(double d, double eps) {
  const double root = std::sqrt(eps * eps + d * d);
  return d > 0 ? 0.5 * (d + root) : 0.5 * eps * eps / (root - d);
}

/// Longest edge × perimeter / (4√3 area) of a triangle with the given angle
/// cotangents at two corners: 1 for an equilateral one.
double aspect_ratio(double cot_alpha, double cot_beta) {
  const double a = std::atan2(1.0, cot_alpha), b = std::atan2(1.0, cot_beta);
  const double s[3] = {std::sin(a), std::sin(b), std::sin(a + b)};  // ∝ opposite sides
  const double product = s[0] * s[1] * s[2];
  if (!(product > 0)) return std::numeric_limits<double>::infinity();
  return std::max({s[0], s[1], s[2]}) * (s[0] + s[1] + s[2]) / (2.0 * std::sqrt(3.0) * product);
}

/// The untangler's per-face reference: the 3D triangle, or an equilateral one
/// of its area when it is badly shaped; then scaled to the start's local UV
/// scale, so det S is about 1 on every face of a fold-free solution.
///
/// Why local: a map of a curved patch squeezes some regions by orders of
/// magnitude (an ear of a bunny), and ε, one number for all faces, treats
/// every face with det below it as free to invert. Measured against the 3D
/// area, ε = 1 lets whole squeezed regions fold (90 folds became 1600 on a
/// 50k-face bunny patch). The scale is the start's |UV area| / 3D area per
/// face, smoothed in log space so folded faces take their neighbours' scale.
IsometricFactors untangling_reference(const IsometricFactors& factors, const MatrixX3i& F,
                                      const MatrixX2d& uv) {
  const Index m = Index(F.rows()), n = Index(uv.rows());
  IsometricFactors ref = factors;
  const double cot60 = 1.0 / std::sqrt(3.0);
  VectorXd log_scale(m);
  for (Index f = 0; f < m; ++f) {
    const double p = factors.factors(f, 0);
    if (aspect_ratio(factors.factors(f, 1) / p, factors.factors(f, 2) / p) > kMaxAspectRatio) {
      const double lambda = 1.0 / std::sqrt(2.0 * factors.area[f] * 2.0 * cot60);
      ref.factors.row(f) << lambda, lambda * cot60, lambda * cot60;
    }
    const Eigen::Vector2d e1 = uv.row(F(f, 1)) - uv.row(F(f, 0));
    const Eigen::Vector2d e2 = uv.row(F(f, 2)) - uv.row(F(f, 0));
    const double uv_area = 0.5 * std::abs(e1.x() * e2.y() - e1.y() * e2.x());
    log_scale[f] = std::log(std::max(uv_area, kSmallestScale * factors.area[f]) / factors.area[f]);
  }
  // Smoothing: face -> mean over its corners' vertices of their faces' mean.
  VectorXd vertex_sum(n), vertex_count(n);
  for (int pass = 0; pass < kScaleSmoothingPasses; ++pass) {
    vertex_sum.setZero();
    vertex_count.setZero();
    for (Index f = 0; f < m; ++f)
      for (int k = 0; k < 3; ++k) vertex_sum[F(f, k)] += log_scale[f], vertex_count[F(f, k)] += 1.0;
    for (Index f = 0; f < m; ++f) {
      double sum = 0.0;
      for (int k = 0; k < 3; ++k) sum += vertex_sum[F(f, k)] / vertex_count[F(f, k)];
      log_scale[f] = sum / 3.0;
    }
  }
  // det S = UV area / reference area, so the factors scale by 1/sqrt(scale).
  for (Index f = 0; f < m; ++f) ref.factors.row(f) *= std::exp(-0.5 * log_scale[f]);
  return ref;
}

struct DetStats {
  double lowest = std::numeric_limits<double>::infinity();
  Index folded = 0;
};

/// Shape matrix S of face f (isometric_energy.h).
Eigen::Matrix2d shape(const IsometricFactors& ref, const MatrixX3i& F, const MatrixX2d& uv,
                      Index f) {
  return shape_matrix(ref.factors(f, 0), ref.factors(f, 1), ref.factors(f, 2), uv.row(F(f, 0)),
                      uv.row(F(f, 1)), uv.row(F(f, 2)));
}

DetStats det_stats(const IsometricFactors& ref, const MatrixX3i& F, const MatrixX2d& uv) {
  double lowest = std::numeric_limits<double>::infinity();
  Index folded = 0;
#pragma omp parallel for schedule(static) reduction(min : lowest) reduction(+ : folded) if (worth_parallel(Index(F.rows())))
  for (Index f = 0; f < Index(F.rows()); ++f) {
    const double d = shape(ref, F, uv, f).determinant();
    lowest = std::min(lowest, d);
    folded += d <= 0.0;
  }
  return {lowest, folded};
}

/// E_ε on every face, in parallel; corner gradients into a face buffer, then
/// summed per vertex in a fixed order.
class RegularisedEnergy {
 public:
  RegularisedEnergy(const IsometricFactors& ref, const MatrixX3i& F)
      : ref_(ref), F_(F), face_energy_(F.rows()), corner_gradient_(3 * F.rows(), 2) {}

  double operator()(const MatrixX2d& uv, double eps, MatrixX2d* gradient) {
    const Index m = Index(F_.rows());
#pragma omp parallel for schedule(static) if (worth_parallel(m))
    for (Index f = 0; f < m; ++f) {
      const Eigen::Matrix2d S = shape(ref_, F_, uv, f);
      const double d = S.determinant(), c = chi(d, eps), w = ref_.area[f];
      const double numerator = (1.0 - kTheta) * S.squaredNorm() + kTheta * (d * d + 1.0);
      face_energy_[f] = w * numerator / c;
      if (!gradient) continue;
      const double dchi = 0.5 * (1.0 + d / std::sqrt(eps * eps + d * d));
      Eigen::Matrix2d cof;
      cof << S(1, 1), -S(1, 0), -S(0, 1), S(0, 0);
      const Eigen::Matrix2d dS =
          w * ((1.0 - kTheta) * 2.0 * S / c + (kTheta * 2.0 * d / c - numerator * dchi / (c * c)) * cof);
      const double p = ref_.factors(f, 0), q = ref_.factors(f, 1), r = ref_.factors(f, 2);
      const Eigen::Vector2d g1 = p * dS.col(0) - q * dS.col(1), g2 = (q + r) * dS.col(1);
      corner_gradient_.row(3 * f) = -(g1 + g2).transpose();
      corner_gradient_.row(3 * f + 1) = g1.transpose();
      corner_gradient_.row(3 * f + 2) = g2.transpose();
    }
    double total = 0.0;
    for (Index f = 0; f < m; ++f) total += face_energy_[f];
    if (gradient) {
      gradient->setZero(uv.rows(), 2);
      for (Index f = 0; f < m; ++f)
        for (int k = 0; k < 3; ++k) gradient->row(F_(f, k)) += corner_gradient_.row(3 * f + k);
    }
    return total;
  }

 private:
  const IsometricFactors& ref_;
  const MatrixX3i& F_;
  VectorXd face_energy_;
  MatrixX2d corner_gradient_;
};

}  // namespace

ContinuationResult untangle_continuation(const IsometricFactors& factors, const MatrixX3i& F,
                                         MatrixX2d& uv, const std::vector<char>& fixed,
                                         const ContinuationOptions& o, ProgressWindow progress,
                                         const LbfgsPreconditioner& preconditioner) {
  ContinuationResult result;
  std::vector<Index> free;
  for (Index v = 0; v < Index(uv.rows()); ++v)
    if (!fixed[v]) free.push_back(v);
  const Index nf = Index(free.size());
  const IsometricFactors ref = untangling_reference(factors, F, uv);
  DetStats best = det_stats(ref, F, uv);
  result.folded = best.folded;
  if (nf == 0 || (best.folded == 0 && best.lowest >= o.min_relative_det)) return result;

  MatrixX2d full = uv, grad;
  auto scatter = [&](const VectorXd& x) {
    for (Index i = 0; i < nf; ++i) full.row(free[i]) << x[2 * i], x[2 * i + 1];
  };
  VectorXd x(2 * nf);
  for (Index i = 0; i < nf; ++i) x.segment<2>(2 * i) = uv.row(free[i]).transpose();
  const StepBound unbounded = [](const VectorXd&, const VectorXd&) {
    return std::numeric_limits<double>::infinity();
  };
  RegularisedEnergy regularised(ref, F);
  // dets are ~1 after the scaling, so ε = 1 starts smooth. (ε from the
  // smallest det, -30 on that bunny patch, folded 3000 faces in round 0.)
  double eps = 1.0;
  int extra_rounds = 0;
  double previous = regularised(full, eps, nullptr);
  for (; result.rounds < o.max_rounds && result.iterations < o.max_iterations; ++result.rounds) {
    const EnergyFunction energy = [&](const VectorXd& y, VectorXd* g) {
      scatter(y);
      const double e = regularised(full, eps, g ? &grad : nullptr);
      if (g) {
        g->resize(2 * nf);
        for (Index i = 0; i < nf; ++i) g->segment<2>(2 * i) = grad.row(free[i]).transpose();
      }
      return e;
    };
    LbfgsOptions lo;
    lo.max_iterations = std::min(o.iterations_per_round, o.max_iterations - result.iterations);
    lo.energy_tol = 1e-5;  // rounds need not converge: ε moves on
    lo.energy_window = 5;
    const LbfgsResult lr = minimize_lbfgs(energy, unbounded, x, lo, {}, preconditioner);
    result.iterations += lr.iterations;
    scatter(x);
    const double current = lr.energy_history.back();
    const DetStats now = det_stats(ref, F, full);
    if (now.folded < best.folded || (now.folded == best.folded && now.lowest > best.lowest)) {
      best = now;
      uv = full;
    }
    progress.report(std::max(double(result.rounds + 1) / o.max_rounds,
                             double(result.iterations) / o.max_iterations),
                    "untangle");
    // Fold-free is enough once no face is a sliver: a det near 0 would leave
    // the barrier optimisation that follows with steps of 1e-14.
    if (now.folded == 0 && (now.lowest >= o.min_relative_det || ++extra_rounds > o.extra_rounds))
      break;
    // Their ε update: shrink towards the smallest det at the pace the energy falls.
    const double sigma = std::max(1.0 - current / previous, kMinimumSigma);
    const double mu = (1.0 - sigma) * chi(now.lowest, eps);
    eps = now.lowest < mu ? std::max(kSmallestEpsilon, 2.0 * std::sqrt(mu * (mu - now.lowest)))
                          : kSmallestEpsilon;
    previous = regularised(full, eps, nullptr);
  }
  result.folded = best.folded;
  return result;
}

}  // namespace paramorph::planar
