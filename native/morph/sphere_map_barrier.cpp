#include "morph/sphere_map_barrier.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <functional>
#include <vector>

#include <Eigen/CholmodSupport>
#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>

#include "common/errors.h"

namespace paramorph::morph {

namespace {

using Vec3 = Eigen::Vector3d;
using Mat3 = Eigen::Matrix3d;
using Mat32 = Eigen::Matrix<double, 3, 2>;
using Mat6 = Eigen::Matrix<double, 6, 6>;
using Vec6 = Eigen::Matrix<double, 6, 1>;
using SparseMatrix = Eigen::SparseMatrix<double>;

constexpr double kInfinity = std::numeric_limits<double>::infinity();
/// Triple products above -kRoundoff are not folds (as in optimize_sphere_map).
constexpr double kRoundoff = 1e-13;

Vec3 row(const MatrixX3d& X, Index v) { return X.row(v).transpose(); }

/// Two orthonormal tangent directions at the unit vector v (columns).
Mat32 tangent_basis(const Vec3& v) {
  const Vec3 axis = std::abs(v.x()) < 0.9 ? Vec3::UnitX() : Vec3::UnitY();
  const Vec3 e1 = (axis - axis.dot(v) * v).normalized();
  Mat32 T;
  T << e1, v.cross(e1);
  return T;
}

/// E(t) with E_pq = sum_r eps_pqr t_r: d^2 det(x0, x1, x2) / dx_k,p dx_{k+1},q = E(x_{k+2}).
Mat3 mixed_block(const Vec3& t) {
  Mat3 E;
  E << 0, t.z(), -t.y(), -t.z(), 0, t.x(), t.y(), -t.x(), 0;
  return E;
}

/// The Newton system's fixed sparsity: lower triangle of the 2#V by 2#V
/// matrix (two tangent coordinates per vertex, coupled along edges), and for
/// every face the slot of each entry of its 6 by 6 block (-1: upper triangle,
/// filled by its mirror).
struct NewtonPattern {
  SparseMatrix A;
  std::vector<Index> face_slot;  ///< 36 per face, row-major over the local 6 by 6
  std::vector<Index> diagonal_slot;  ///< 3 per vertex: (2i,2i), (2i+1,2i), (2i+1,2i+1)

  NewtonPattern(const MatrixX3i& F, Index vertices) {
    const Index faces = Index(F.rows());
    auto global = [&](Index f, int local) { return 2 * F(f, local / 2) + local % 2; };
    std::vector<Eigen::Triplet<double>> entries;
    entries.reserve(std::size_t(faces) * 21 + std::size_t(vertices) * 3);
    for (Index f = 0; f < faces; ++f)
      for (int r = 0; r < 6; ++r)
        for (int c = 0; c < 6; ++c)
          if (global(f, r) >= global(f, c)) entries.emplace_back(global(f, r), global(f, c), 0.0);
    for (Index v = 0; v < vertices; ++v)
      for (auto [r, c] : {std::pair{0, 0}, {1, 0}, {1, 1}}) entries.emplace_back(2 * v + r, 2 * v + c, 0.0);
    A.resize(2 * vertices, 2 * vertices);
    A.setFromTriplets(entries.begin(), entries.end());
    A.makeCompressed();
    auto slot = [&](Index r, Index c) {
      const Index* begin = A.innerIndexPtr() + A.outerIndexPtr()[c];
      const Index* end = A.innerIndexPtr() + A.outerIndexPtr()[c + 1];
      return Index(std::lower_bound(begin, end, r) - A.innerIndexPtr());
    };
    face_slot.resize(std::size_t(faces) * 36);
    for (Index f = 0; f < faces; ++f)
      for (int r = 0; r < 6; ++r)
        for (int c = 0; c < 6; ++c)
          face_slot[36 * std::size_t(f) + 6 * r + c] =
              global(f, r) >= global(f, c) ? slot(global(f, r), global(f, c)) : -1;
    diagonal_slot.resize(std::size_t(vertices) * 3);
    for (Index v = 0; v < vertices; ++v) {
      diagonal_slot[3 * v] = slot(2 * v, 2 * v);
      diagonal_slot[3 * v + 1] = slot(2 * v + 1, 2 * v);
      diagonal_slot[3 * v + 2] = slot(2 * v + 1, 2 * v + 1);
    }
  }
};

/// Unit vectors v_i moved by u_i (#V by 2, tangent coordinates) and projected back.
void move(const MatrixX3d& X, const std::vector<Mat32>& T, const VectorXd& u, double step, MatrixX3d& out) {
  for (Index v = 0; v < Index(X.rows()); ++v)
    out.row(v) = (row(X, v) + step * T[v] * u.segment<2>(2 * v)).normalized().transpose();
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

  NewtonPattern pattern(F, vertices);
  Eigen::CholmodSupernodalLLT<SparseMatrix, Eigen::Lower> llt;
  llt.cholmod().print = 0;  // a singular try is handled (shifted below), not news
  // Fill-reducing ordering: the one of AMD and METIS with the smaller factor
  // (CHOLMOD compares them). pair20k's Suzanne: METIS 1.10M nonzeros and
  // 1.4e8 flops per factorization against AMD's 1.23M and 2.3e8 (58 against
  // 69 ms); spot: AMD's 0.24M against METIS's 0.26M.
  llt.cholmod().nmethods = 2;
  llt.cholmod().method[0].ordering = CHOLMOD_AMD;
  llt.cholmod().method[1].ordering = CHOLMOD_METIS;
  llt.cholmod().postorder = 1;
  llt.analyzePattern(pattern.A);
  double* values = pattern.A.valuePtr();
  const Index nonzeros = Index(pattern.A.nonZeros());
  const Index* outer = pattern.A.outerIndexPtr();
  const Index* inner = pattern.A.innerIndexPtr();

  std::vector<Mat32> T(vertices);
  VectorXd gradient(2 * vertices), step(2 * vertices), scale(2 * vertices), scaled(nonzeros);
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
    std::fill(values, values + nonzeros, 0.0);
#pragma omp parallel for schedule(static)
    for (Index v = 0; v < vertices; ++v) T[v] = tangent_basis(row(X, v));
#pragma omp parallel for schedule(static)
    for (Index f = 0; f < faces; ++f) {
      const double mu = mu_face[f];
      const Vec3 x[3] = {row(X, F(f, 0)), row(X, F(f, 1)), row(X, F(f, 2))};
      const Vec3 g[3] = {x[1].cross(x[2]), x[2].cross(x[0]), x[0].cross(x[1])};
      const double det = x[0].dot(g[0]), gap = det - bounds[f];
      Vec6 gt;
      for (int k = 0; k < 3; ++k) gt.segment<2>(2 * k) = T[F(f, k)].transpose() * g[k];
      face_gradient[f] = (-mu / gap) * gt;
      Mat6 H = (mu / (gap * gap)) * gt * gt.transpose();
      H.diagonal().array() += mu * det / gap;  // -v . dE/dv of the barrier (det is linear in each v)
      for (int k = 0; k < 3; ++k) {
        const int l = (k + 1) % 3;
        const Eigen::Matrix2d block =
            (-mu / gap) * T[F(f, k)].transpose() * mixed_block(x[(k + 2) % 3]) * T[F(f, l)];
        H.block<2, 2>(2 * k, 2 * l) += block;
        H.block<2, 2>(2 * l, 2 * k) += block.transpose();
      }
      // Always indefinite (the triple product's second derivative has
      // eigenvalues of both signs, as the signed area of a plane triangle),
      // so no cheaper positive-definiteness test would skip this.
      const Eigen::SelfAdjointEigenSolver<Mat6> eigen(H);
      face_hessian[f] = eigen.eigenvectors() * eigen.eigenvalues().cwiseMax(0.0).asDiagonal() *
                        eigen.eigenvectors().transpose();
    }
    for (Index v = 0; v < vertices; ++v) {
      const Vec3 p = row(pull, v);
      gradient.segment<2>(2 * v) = -T[v].transpose() * p;
      // -v . dE/dv of the pull: negative where v faces away from its target
      // (concave there, so left out of the convex model).
      const double curvature = std::max(0.0, p.dot(row(X, v)));
      values[pattern.diagonal_slot[3 * v]] += curvature;
      values[pattern.diagonal_slot[3 * v + 2]] += curvature;
    }
    for (Index f = 0; f < faces; ++f) {
      for (int k = 0; k < 3; ++k) gradient.segment<2>(2 * F(f, k)) += face_gradient[f].segment<2>(2 * k);
      const Index* slot = pattern.face_slot.data() + 36 * std::size_t(f);
      const Mat6& H = face_hessian[f];
      for (int k = 0; k < 36; ++k)
        if (slot[k] >= 0) values[slot[k]] += H(k / 6, k % 6);
    }
  };

  // Newton step: symmetric diagonal scaling first (squeezed faces put
  // 1/gap^2 ~ 1e26 beside entries of 1). The system is positive
  // semi-definite by construction; a diagonal shift is only the fallback
  // for a singular one (e.g. a vertex whose pull and faces all vanish).
  auto newton_step = [&]() {
    for (Index c = 0; c < 2 * vertices; ++c)
      scale[c] = values[outer[c]] != 0 ? 1.0 / std::sqrt(std::abs(values[outer[c]])) : 1.0;
    for (Index c = 0; c < 2 * vertices; ++c)
      for (Index k = outer[c]; k < outer[c + 1]; ++k) values[k] *= scale[c] * scale[inner[k]];
    std::copy(values, values + nonzeros, scaled.data());
    for (double tau = 0;;) {
      if (tau > 0) {
        std::copy(scaled.data(), scaled.data() + nonzeros, values);
        for (Index c = 0; c < 2 * vertices; ++c) values[outer[c]] += tau;
      }
      llt.factorize(pattern.A);
      ++result.factorizations;
      if (llt.info() == Eigen::Success) break;
      PM_REQUIRE(tau < 1e8, ComputeError, "sphere_map_barrier: no positive definite Newton system");
      tau = tau == 0 ? 1e-10 : 8 * tau;
    }
    step = -scale.cwiseProduct(llt.solve(scale.cwiseProduct(gradient)));
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
      newton_step();
      const double decrement = -gradient.dot(step);  // squared Newton decrement
      if (decrement <= 2.0 * tolerance) return true;
      // Backtracking (Armijo); a step that crosses a bound has E = +inf.
      double t = 1.0, next = kInfinity;
      for (int k = 0; k < 60; ++k, t *= 0.5) {
        move(X, T, step, t, trial);
        next = sphere_barrier_energy(F, pull, bounds, weight, trial);
        if (next <= energy - 1e-4 * t * decrement) break;
      }
      if (!(next <= energy - 1e-4 * t * decrement)) return true;  // centred to rounding
      // A face far below where the barrier wants it only doubles its gap per
      // full Newton step: try longer steps along the same direction while
      // they keep lowering E (spot: 52 steps instead of 60).
      if (t == 1.0) {
        for (double longer = 2.0; longer <= 1024.0; longer *= 2.0) {
          move(X, T, step, longer, longer_trial);
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

}  // namespace paramorph::morph
