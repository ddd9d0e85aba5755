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

double isometric_energy(const IsometricFactors& factors, const MatrixX3i& F, const MatrixX2d& uv,
                        MatrixX2d* gradient) {
  const Index m = Index(F.rows());
  if (gradient) gradient->setZero(uv.rows(), 2);
  double total = 0.0;
  bool inverted = false;
  for (Index f = 0; f < m && !inverted; ++f) {
    const double p = factors.factors(f, 0), q = factors.factors(f, 1), r = factors.factors(f, 2);
    const Eigen::Vector2d u0 = uv.row(F(f, 0)), u1 = uv.row(F(f, 1)), u2 = uv.row(F(f, 2));
    const Eigen::Vector2d e1 = u1 - u0, e2 = u2 - u0;
    Eigen::Matrix2d S;
    S.col(0) = p * e1;
    S.col(1) = (q + r) * e2 - q * e1;
    const double det = S.determinant();
    if (!(det > 0.0)) {
      inverted = true;
      break;
    }
    const double frob = S.squaredNorm();
    const double w = factors.area[f];
    total += w * frob * (1.0 + 1.0 / (det * det));
    if (gradient) {
      // dη/dS = 2S(1 + det⁻²) - 2|S|² det⁻³ cof(S); dS/de via S = [e1 e2] B.
      Eigen::Matrix2d cof;
      cof << S(1, 1), -S(1, 0), -S(0, 1), S(0, 0);
      const Eigen::Matrix2d dS = w * (2.0 * (1.0 + 1.0 / (det * det)) * S -
                                      2.0 * frob / (det * det * det) * cof);
      // S = [e1 e2] B with B = [[p, -q], [0, q + r]] ⇒ dE/d[e1 e2] = dS Bᵀ.
      const Eigen::Vector2d g1 = p * dS.col(0) - q * dS.col(1);
      const Eigen::Vector2d g2 = (q + r) * dS.col(1);
      gradient->row(F(f, 1)) += g1.transpose();
      gradient->row(F(f, 2)) += g2.transpose();
      gradient->row(F(f, 0)) -= (g1 + g2).transpose();
    }
  }
  return inverted ? kInfinity : total;
}

double max_feasible_step(const MatrixX3i& F, const MatrixX2d& uv, const MatrixX2d& d) {
  double best = kInfinity;
  for (Index f = 0; f < Index(F.rows()); ++f) {
    const Eigen::Vector2d e1 = uv.row(F(f, 1)) - uv.row(F(f, 0));
    const Eigen::Vector2d e2 = uv.row(F(f, 2)) - uv.row(F(f, 0));
    const Eigen::Vector2d f1 = d.row(F(f, 1)) - d.row(F(f, 0));
    const Eigen::Vector2d f2 = d.row(F(f, 2)) - d.row(F(f, 0));
    // det(e1 + t f1, e2 + t f2) = c + b t + a t².
    const double c = cross2(e1, e2);
    const double b = cross2(e1, f2) + cross2(f1, e2);
    const double a = cross2(f1, f2);
    best = std::min(best, first_positive_root(a, b, c));
  }
  return best;
}

}  // namespace paramorph::planar
