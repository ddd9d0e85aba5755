#include "param/planar/isometric_energy.h"

#include <Eigen/Dense>
#include <cmath>
#include <limits>

namespace paramorph::planar {

namespace {
constexpr double kInfinity = std::numeric_limits<double>::infinity();

double cross2(const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
  return a.x() * b.y() - a.y() * b.x();
}

/// Smallest positive root of a t² + b t + c (c > 0 at t = 0), +inf if none.
double first_positive_root(double a, double b, double c) {
  const double scale = std::max({std::abs(a), std::abs(b), std::abs(c)});
  if (scale == 0.0) return kInfinity;
  if (std::abs(a) <= 1e-14 * scale) {  // linear
    return b < 0.0 ? -c / b : kInfinity;
  }
  const double disc = b * b - 4.0 * a * c;
  if (disc < 0.0) return kInfinity;
  // Stable pair of roots: q = -(b + sign(b) sqrt(disc)) / 2, roots q/a and c/q.
  const double q = -0.5 * (b + std::copysign(std::sqrt(disc), b));
  double best = kInfinity;
  for (double t : {q / a, q != 0.0 ? c / q : kInfinity})
    if (t > 0.0 && t < best) best = t;
  return best;
}
}  // namespace

IsometricFactors isometric_factors(const MatrixX3d& V, const MatrixX3i& F) {
  const Index m = Index(F.rows());
  IsometricFactors out;
  out.factors.resize(m, 3);
  out.area.resize(m);
  for (Index f = 0; f < m; ++f) {
    const Eigen::Vector3d v0 = V.row(F(f, 0)), v1 = V.row(F(f, 1)), v2 = V.row(F(f, 2));
    const double twice_area = (v1 - v0).cross(v2 - v0).norm();
    // cot of the angle at a corner = dot / |cross| of its two edges.
    const double cot_alpha = (v1 - v0).dot(v2 - v0) / twice_area;
    const double cot_beta = (v0 - v1).dot(v2 - v1) / twice_area;
    const double lambda = 1.0 / std::sqrt(twice_area * (cot_alpha + cot_beta));
    out.factors.row(f) << lambda, lambda * cot_alpha, lambda * cot_beta;
    out.area[f] = 0.5 * twice_area;
  }
  return out;
}

double face_first_inversion(const Eigen::Vector2d& u0, const Eigen::Vector2d& u1,
                            const Eigen::Vector2d& u2, const Eigen::Vector2d& d0,
                            const Eigen::Vector2d& d1, const Eigen::Vector2d& d2) {
  const Eigen::Vector2d e1 = u1 - u0, e2 = u2 - u0, f1 = d1 - d0, f2 = d2 - d0;
  // det(e1 + t f1, e2 + t f2) = c + b t + a t².
  const double c = cross2(e1, e2);
  const double b = cross2(e1, f2) + cross2(f1, e2);
  const double a = cross2(f1, f2);
  return first_positive_root(a, b, c);
}

double isometric_energy(const IsometricFactors& factors, const MatrixX3i& F, const MatrixX2d& uv,
                        MatrixX2d* gradient) {
  if (gradient) gradient->setZero(uv.rows(), 2);
  double total = 0.0;
  Eigen::Vector2d g[3];
  for (Index f = 0; f < Index(F.rows()); ++f) {
    const double e = face_isometric_energy(factors.factors(f, 0), factors.factors(f, 1),
                                           factors.factors(f, 2), factors.area[f], uv.row(F(f, 0)),
                                           uv.row(F(f, 1)), uv.row(F(f, 2)), gradient ? g : nullptr);
    if (!std::isfinite(e)) return kInfinity;
    total += e;
    if (gradient)
      for (int k = 0; k < 3; ++k) gradient->row(F(f, k)) += g[k].transpose();
  }
  return total;
}

double max_feasible_step(const MatrixX3i& F, const MatrixX2d& uv, const MatrixX2d& d) {
  double best = kInfinity;
  for (Index f = 0; f < Index(F.rows()); ++f)
    best = std::min(best, face_first_inversion(uv.row(F(f, 0)), uv.row(F(f, 1)), uv.row(F(f, 2)),
                                               d.row(F(f, 0)), d.row(F(f, 1)), d.row(F(f, 2))));
  return best;
}

}  // namespace paramorph::planar
