#include "param/spherical/sphere_map_barrier.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <functional>
#include <vector>

#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>

#include "common/errors.h"
#include "common/parallel.h"
#include "param/spherical/tangent_newton.h"

namespace paramorph::spherical {

namespace {

using Vec3 = Eigen::Vector3d;
using Mat3 = Eigen::Matrix3d;



constexpr double kInfinity = std::numeric_limits<double>::infinity();
/// Triple products above -kRoundoff are not folds (as in optimize_sphere_map).
constexpr double kRoundoff = 1e-13;

Vec3 row(const MatrixX3d& X, Index v) { return X.row(v).transpose(); }

/// E(t) with E_pq = sum_r eps_pqr t_r: d^2 det(x0, x1, x2) / dx_k,p dx_{k+1},q = E(x_{k+2}).
Mat3 mixed_block(const Vec3& t) {
  Mat3 E;
  E << 0, t.z(), -t.y(), -t.z(), 0, t.x(), t.y(), -t.x(), 0;
  return E;
}

}  // namespace

double sphere_barrier_energy(const MatrixX3i& F, const MatrixX3d& pull, const VectorXd& bounds,
                             const VectorXd& mu, const MatrixX3d& X, MatrixX3d* gradient) {
  double energy = -(pull.array() * X.array()).sum();
  if (gradient) *gradient = -pull;
  for (Index f = 0; f < Index(F.rows()); ++f) {
    const Vec3 a = row(X, F(f, 0)), b = row(X, F(f, 1)), c = row(X, F(f, 2));
    const double gap = a.dot(b.cross(c)) - bounds[f];
    if (!(gap > 0)) return kInfinity;
    energy -= mu[f] * std::log(gap);
    if (gradient) {
      const double s = -mu[f] / gap;
      gradient->row(F(f, 0)) += s * b.cross(c).transpose();
      gradient->row(F(f, 1)) += s * c.cross(a).transpose();
      gradient->row(F(f, 2)) += s * a.cross(b).transpose();
    }
  }
  return energy;
}

SphereBarrierResult sphere_map_barrier(const MatrixX3i& F, const MatrixX3d& pull,
                                       const MatrixX3d& start, const SphereBarrierOptions& o,
                                       ProgressWindow progress) {
  const Index vertices = Index(start.rows()), faces = Index(F.rows());
  PM_REQUIRE(pull.rows() == vertices && o.epsilon > 0 && o.mu_end > 0 && o.mu_start >= o.mu_end &&
                 o.mu_factor > 0 && o.mu_factor < 1 && o.max_steps > 0,
             InvalidInputError, "sphere_map_barrier: inconsistent arguments");
  SphereBarrierResult result;
  result.positions = start;
  MatrixX3d& X = result.positions;
  VectorXd& bounds = result.bounds;
  auto triple = [&](const MatrixX3d& Y, Index f) {
    return row(Y, F(f, 0)).dot(row(Y, F(f, 1)).cross(row(Y, F(f, 2))));
  };
  bounds.resize(faces);
  for (Index f = 0; f < faces; ++f) {
    const double det = triple(X, f);
    PM_REQUIRE(det > -kRoundoff, InvalidInputError, "sphere_map_barrier: the start folds face ", f);
    // A bound within rounding of the triple product would be crossed by the
    // rounding of the next step alone: faces squeezed that far get -kRoundoff.
    bounds[f] = det > 2 * kRoundoff ? std::min(o.epsilon, 0.5 * det) : -kRoundoff;
  }

  TangentNewton newton(F, vertices);
  VectorXd step(2 * vertices);
  MatrixX3d trial(vertices, 3), longer_trial(vertices, 3);

  // Gradient and Hessian of E in the tangent coordinates u
  // (v_i <- normalise(v_i + T_i u_i)): T^T (d^2 E) T - diag(v_i . dE/dv_i).
  // Every term is made positive semi-definite (each face's 6 by 6 block
  // projected, the pull's diagonal clamped at 0), so the Newton system is
  // factored at the first try. Measured against projecting only the faces
  // whose rank-one barrier term does not dominate and shifting the diagonal
  // until the sum is positive definite (a tau tracked from step to step):
  // on pair20k's Suzanne (20k faces) 80 steps and 86 factorizations instead
  // of 98 and 172, on its octopus 68 and 74 instead of 104 and 181 (each
  // factorization ~50 ms, a third of them failed tries); the shift also
  // turned the first rounds' steps into near-gradient steps (tau up to 0.67
  // of the scaled diagonal). On spot it takes 64 steps and 10 Ipopt
  // iterations instead of 52 and 4 (same objective to 2e-7).
  // The faces are independent, so the blocks are computed in parallel and
  // then added to the shared matrix in order (deterministic sums).
  std::vector<Mat6> face_hessian(faces);
  std::vector<Vec6> face_gradient(faces);
  auto assemble = [&](const VectorXd& mu_face) {
    newton.begin(X);
#pragma omp parallel for schedule(static) if (worth_parallel(faces))
    for (Index f = 0; f < faces; ++f) {
      const double mu = mu_face[f];
      const Vec3 x[3] = {row(X, F(f, 0)), row(X, F(f, 1)), row(X, F(f, 2))};
      const Vec3 g[3] = {x[1].cross(x[2]), x[2].cross(x[0]), x[0].cross(x[1])};
      const double det = x[0].dot(g[0]), gap = det - bounds[f];
      Vec6 gt;
      for (int k = 0; k < 3; ++k) gt.segment<2>(2 * k) = newton.basis(F(f, k)).transpose() * g[k];
      face_gradient[f] = (-mu / gap) * gt;
      Mat6 H = (mu / (gap * gap)) * gt * gt.transpose();
      H.diagonal().array() += mu * det / gap;  // -v . dE/dv of the barrier (det is linear in each v)
      for (int k = 0; k < 3; ++k) {
        const int l = (k + 1) % 3;
        const Eigen::Matrix2d block =
            (-mu / gap) * newton.basis(F(f, k)).transpose() * mixed_block(x[(k + 2) % 3]) * newton.basis(F(f, l));
        H.block<2, 2>(2 * k, 2 * l) += block;
        H.block<2, 2>(2 * l, 2 * k) += block.transpose();
      }
      // Always indefinite (the triple product's second derivative has
      // eigenvalues of both signs, as the signed area of a plane triangle),
      // so no cheaper positive-definiteness test would skip this.
      face_hessian[f] = project_psd(H);
    }
    for (Index v = 0; v < vertices; ++v) {
      const Vec3 p = row(pull, v);
      // -v . dE/dv of the pull: negative where v faces away from its target
      // (concave there, so left out of the convex model).
      const double curvature = std::max(0.0, p.dot(row(X, v)));
      newton.add_vertex(v, -newton.basis(v).transpose() * p, curvature * Eigen::Matrix2d::Identity());
    }
    for (Index f = 0; f < faces; ++f) newton.add_face(f, face_gradient[f], face_hessian[f]);
  };

  // Newton steps on E for the per-face weights `weight` until the squared
  // Newton decrement is at most 2 * tolerance (within ~tolerance of the
  // minimum), `done()` holds, or the round's or the path's steps run out.
  VectorXd weight(faces);
  // Returns whether the decrement test ended it (centred).
  auto centre = [&](double tolerance, const std::function<double(int)>& progress_at,
                    const std::function<bool()>& done) {
    double energy = sphere_barrier_energy(F, pull, bounds, weight, X);
    PM_REQUIRE(std::isfinite(energy), ComputeError, "sphere_map_barrier: left the feasible set");
    for (int inner_step = 0; inner_step < o.max_round_steps && result.steps < o.max_steps; ++inner_step) {
      assemble(weight);
      step = newton.solve();
      result.factorizations = newton.factorizations();
      const double decrement = -newton.gradient().dot(step);  // squared Newton decrement
      if (decrement <= 2.0 * tolerance) return true;
      // Backtracking (Armijo); a step that crosses a bound has E = +inf.
      double t = 1.0, next = kInfinity;
      for (int k = 0; k < 60; ++k, t *= 0.5) {
        newton.move(X, step, t, trial);
        next = sphere_barrier_energy(F, pull, bounds, weight, trial);
        if (next <= energy - 1e-4 * t * decrement) break;
      }
      if (!(next <= energy - 1e-4 * t * decrement)) return true;  // centred to rounding
      // A face far below where the barrier wants it only doubles its gap per
      // full Newton step: try longer steps along the same direction while
      // they keep lowering E (spot: 52 steps instead of 60).
      if (t == 1.0) {
        for (double longer = 2.0; longer <= 1024.0; longer *= 2.0) {
          newton.move(X, step, longer, longer_trial);
          const double further = sphere_barrier_energy(F, pull, bounds, weight, longer_trial);
          if (!(further < next)) break;
          trial.swap(longer_trial);
          next = further;
        }
      }
      X.swap(trial);
      energy = next;
      ++result.steps;
      progress.report(progress_at(inner_step), "optimize sphere map: barrier");
      if (done()) break;
    }
    return false;
  };

  // Opening, for a start with faces squeezed to rounding (a conformal map of
  // long protrusions: triple products of 1e-17, vertices that coincide):
  // their bounds start just below 0 and they are pushed open, with the pull
  // on, until every face is above 2 epsilon. Each round, the faces still
  // under it get 10 times the barrier weight and a bound raised to half
  // their triple product. Measured on tentacle_sphere(4) (18.7k faces, 12.7k
  // of them squeezed): open in 133 steps, optimized in 34 s, where Ipopt
  // from the squeezed start had not converged after 400 s.
  auto all_open = [&] {
    for (Index f = 0; f < faces; ++f)
      if (!(triple(X, f) > 2 * o.epsilon)) return false;
    return true;
  };
  for (Index f = 0; f < faces; ++f) weight[f] = triple(X, f) > 2 * o.epsilon ? o.mu_start : 10 * o.mu_start;
  while (!all_open()) {
    if (result.steps >= o.max_steps) return result;  // not open: result.rounds == 0
    ++result.opening_rounds;
    centre(o.mu_start, [](int) { return 0.0; }, all_open);
    for (Index f = 0; f < faces; ++f) {
      const double det = triple(X, f);
      if (det > 2 * o.epsilon) continue;
      if (det > 2 * kRoundoff) bounds[f] = std::min(o.epsilon, std::max(bounds[f], 0.5 * det));
      weight[f] *= 10;
    }
  }
  bounds.setConstant(o.epsilon);

  // The path: mu_start * mu_factor^k down to mu_end, the last one mu_end
  // itself. Counted up front: comparing a product of rounded factors with
  // mu_end added one more round (one Newton system) at mu_end * (1 - 1e-16).
  const int rounds =
      1 + std::max(0, int(std::ceil(std::log(o.mu_start / o.mu_end) / -std::log(o.mu_factor) - 1e-9)));
  double mu = o.mu_start;
  for (int round = 0; round < rounds && result.steps < o.max_steps; ++round) {
    if (round == rounds - 1) mu = o.mu_end;
    result.rounds = round + 1;
    weight.setConstant(mu);
    result.centred =
        centre(mu, [&](int k) { return (round + std::min(1.0, k / 10.0)) / rounds; }, [] { return false; });
    result.mu = mu;
    mu *= o.mu_factor;
  }
  return result;
}

}  // namespace paramorph::spherical
