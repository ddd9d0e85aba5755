// Polynomial point-to-plane ICP of B onto A (morph/register_surfaces.h).
#include "morph/register_surfaces.h"

#include <algorithm>
#include <cmath>

#include <Eigen/Cholesky>
#include <Eigen/Geometry>

#include "common/errors.h"
#include "mesh/closest_points.h"

namespace paramorph::morph {

namespace {

/// Monomials of degree <= `degree` of the rows of Y (normalised coordinates).
Eigen::MatrixXd basis(const MatrixX3d& Y, int degree) {
  Eigen::MatrixXd P(Y.rows(), PolynomialWarp::basis_size(degree));
  for (Index i = 0; i < Index(Y.rows()); ++i) {
    const double x = Y(i, 0), y = Y(i, 1), z = Y(i, 2);
    P(i, 0) = 1.0, P(i, 1) = x, P(i, 2) = y, P(i, 3) = z;
    if (degree >= 2) P.row(i).segment(4, 6) << x * x, y * y, z * z, x * y, y * z, z * x;
    if (degree >= 3)
      P.row(i).segment(10, 10) << x * x * x, y * y * y, z * z * z, x * x * y, x * x * z, y * y * x,
          y * y * z, z * z * x, z * z * y, x * y * z;
  }
  return P;
}

/// Per vertex, a third of the area of its faces.
VectorXd vertex_areas(const MatrixX3d& V, const MatrixX3i& F) {
  VectorXd area = VectorXd::Zero(V.rows());
  for (Index f = 0; f < Index(F.rows()); ++f) {
    const Eigen::RowVector3d a = V.row(F(f, 0)), b = V.row(F(f, 1)), c = V.row(F(f, 2));
    const double third = (b - a).cross(c - a).norm() / 6.0;
    for (int k = 0; k < 3; ++k) area[F(f, k)] += third;
  }
  return area;
}

/// Truncated area-weighted mean distance of T(VB) from A, share of the diagonal.
double cost_of(const ClosestPointTree& tree, const PolynomialWarp& T, const MatrixX3d& VB,
               const VectorXd& area, double diagonal, double cap) {
  const ClosestPoints c = tree.query(T(VB));
  return (c.distance.array() / diagonal).min(cap).matrix().dot(area) / area.sum();
}

}  // namespace

int PolynomialWarp::basis_size(int degree) { return degree >= 3 ? 20 : degree == 2 ? 10 : 4; }

PolynomialWarp PolynomialWarp::similarity(const Eigen::RowVector3d& centre, double scale,
                                          const Eigen::Matrix3d& rotation,
                                          const Eigen::RowVector3d& to_centre, double to_scale) {
  PolynomialWarp T;
  T.centre = centre;
  T.scale = scale;
  T.degree = 1;
  T.coefficients = Eigen::MatrixXd::Zero(4, 3);
  T.coefficients.row(0) = to_centre;
  // Row vectors: y = to_centre + to_scale * x' R^T for x' = (x - centre) / scale.
  T.coefficients.bottomRows(3) = to_scale * rotation.transpose();
  return T;
}

MatrixX3d PolynomialWarp::operator()(const MatrixX3d& X) const {
  const MatrixX3d Y = (X.rowwise() - centre) / scale;
  return basis(Y, degree) * coefficients;
}

Registration register_surfaces(const MatrixX3d& VA, const MatrixX3i& FA, const MatrixX3d& VB,
                               const MatrixX3i& FB, const std::vector<PolynomialWarp>& starts,
                               const RegisterOptions& o, Progress* progress) {
  PM_REQUIRE(!starts.empty(), InvalidInputError, "register_surfaces needs a start");
  PM_REQUIRE(o.max_degree >= 1 && o.max_degree <= 3, InvalidInputError, "max_degree is 1, 2 or 3, got ",
             o.max_degree);
  PM_REQUIRE(o.iterations >= 1, InvalidInputError, "iterations must be >= 1");
  PM_REQUIRE(std::isfinite(o.max_distance) && o.max_distance > 0 && std::isfinite(o.damping) &&
                 o.damping >= 0, InvalidInputError, "max_distance must be > 0 and damping >= 0");
  for (const PolynomialWarp& s : starts)
    PM_REQUIRE(s.degree >= 1 && s.degree <= o.max_degree &&
                   s.coefficients.rows() == PolynomialWarp::basis_size(s.degree) &&
                   s.coefficients.cols() == 3 && s.coefficients.allFinite() && s.scale > 0,
               InvalidInputError, "a start warp is malformed");
  const ClosestPointTree tree(VA, FA);
  const double diagonal = (VA.colwise().maxCoeff() - VA.colwise().minCoeff()).norm();
  const VectorXd area = vertex_areas(VB, FB);
  const double total = std::max(area.sum(), 1e-300);

  // One start refined by ICP from its degree up to `to_degree`.
  const double rounds = double((starts.size() + o.max_degree - 1) * o.iterations);
  int round = 0;
  auto refine = [&](PolynomialWarp T, int to_degree) {
    const MatrixX3d Y = (VB.rowwise() - T.centre) / T.scale;
    ClosestPoints c;
    bool hinted = false;
    for (int degree = T.degree; degree <= to_degree; ++degree) {
      // Raise the degree: the new monomials start at zero.
      const int k = PolynomialWarp::basis_size(degree);
      Eigen::MatrixXd C = Eigen::MatrixXd::Zero(k, 3);
      C.topRows(T.coefficients.rows()) = T.coefficients;
      T.degree = degree;
      T.coefficients = C;
      const Eigen::MatrixXd P = basis(Y, degree);
      for (int it = 0; it < o.iterations; ++it, ++round) {
        if (progress) progress->report(double(round) / rounds, "register");
        c = tree.query(P * T.coefficients, hinted ? &c : nullptr);
        hinted = true;
        // Rows sqrt(w) [n_x phi, n_y phi, n_z phi] . vec(C) = sqrt(w) n . closest.
        Eigen::MatrixXd D = Eigen::MatrixXd::Zero(VB.rows(), 3 * k);
        Eigen::VectorXd r = Eigen::VectorXd::Zero(VB.rows());
        for (Index i = 0; i < Index(VB.rows()); ++i) {
          if (c.distance[i] > o.max_distance * diagonal) continue;
          const auto f = FA.row(c.face[i]);
          Eigen::RowVector3d n = (VA.row(f[1]) - VA.row(f[0])).cross(VA.row(f[2]) - VA.row(f[0]));
          if (!(n.norm() > 0)) continue;
          n.normalize();
          const double s = std::sqrt(area[i] / total);
          for (int a = 0; a < 3; ++a) D.row(i).segment(a * k, k) = s * n[a] * P.row(i);
          r[i] = s * n.dot(c.points.row(i));
        }
        // D^T D as a rank update (the lower triangle, which ldlt() reads): a
        // general product of this size (n by 60) is split between OpenMP
        // threads by Eigen, a parallel region per iteration, which on a busy
        // machine doubled a small morph's time (common/parallel.h).
        Eigen::MatrixXd M = Eigen::MatrixXd::Zero(3 * k, 3 * k);
        M.selfadjointView<Eigen::Lower>().rankUpdate(D.transpose());
        Eigen::VectorXd rhs = D.transpose() * r;
        // Damping towards the current T: the planes leave sliding along them free.
        const double lambda = o.damping * M.trace() / double(3 * k) + 1e-12;
        Eigen::VectorXd current(3 * k);
        for (int a = 0; a < 3; ++a) current.segment(a * k, k) = T.coefficients.col(a);
        M.diagonal().array() += lambda;
        rhs += lambda * current;
        const Eigen::VectorXd x = M.ldlt().solve(rhs);
        if (!x.allFinite()) break;
        for (int a = 0; a < 3; ++a) T.coefficients.col(a) = x.segment(a * k, k);
      }
    }
    return T;
  };

  // Every start at its own degree (affine for a similarity); the first wins
  // unless another is clearly better; the winner alone goes on to max_degree.
  Registration out;
  std::vector<PolynomialWarp> fitted;
  for (const PolynomialWarp& start : starts) {
    fitted.push_back(refine(start, start.degree));
    out.start_costs.push_back(cost_of(tree, fitted.back(), VB, area, diagonal, o.max_distance));
  }
  out.start = 0;
  for (std::size_t s = 1; s < fitted.size(); ++s)
    if (out.start_costs[s] < 0.95 * out.start_costs[0] && out.start_costs[s] < out.start_costs[out.start])
      out.start = s;
  PolynomialWarp best = fitted[out.start];
  if (best.degree < o.max_degree) {
    // Continue from the next degree (refine re-runs the current one first otherwise).
    const int k = PolynomialWarp::basis_size(best.degree + 1);
    Eigen::MatrixXd C = Eigen::MatrixXd::Zero(k, 3);
    C.topRows(best.coefficients.rows()) = best.coefficients;
    best.degree += 1;
    best.coefficients = C;
    best = refine(best, o.max_degree);
  }
  out.warp = best;
  out.cost = cost_of(tree, best, VB, area, diagonal, o.max_distance);
  if (progress) progress->report(1.0, "register");
  return out;
}

}  // namespace paramorph::morph
