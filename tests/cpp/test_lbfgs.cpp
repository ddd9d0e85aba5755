// L-BFGS with the feasibility-bounded strong-Wolfe line search (param/planar/lbfgs).
#include <gtest/gtest.h>

#include <Eigen/SparseCholesky>
#include <cmath>

#include "param/planar/isometric_energy.h"
#include "param/planar/lbfgs.h"
#include "test_meshes.h"

using namespace paramorph;
using namespace paramorph::planar;

namespace {
const StepBound kUnbounded = [](const VectorXd&, const VectorXd&) {
  return std::numeric_limits<double>::infinity();
};

const EnergyFunction rosenbrock = [](const VectorXd& x, VectorXd* g) {
  const double a = 1 - x[0], b = x[1] - x[0] * x[0];
  if (g) {
    g->resize(2);
    *g << -2 * a - 400 * x[0] * b, 200 * b;
  }
  return a * a + 100 * b * b;
};

bool non_increasing(const std::vector<double>& h) {
  for (std::size_t k = 1; k < h.size(); ++k)
    if (h[k] > h[k - 1]) return false;
  return true;
}
}  // namespace

TEST(Lbfgs, MinimisesRosenbrock) {
  VectorXd x(2);
  x << -1.2, 1.0;
  LbfgsOptions o;
  o.gradient_tol = 1e-10;
  const LbfgsResult r = minimize_lbfgs(rosenbrock, kUnbounded, x, o);
  EXPECT_EQ(r.stop_reason, "gradient");
  EXPECT_NEAR(x[0], 1.0, 1e-6);
  EXPECT_NEAR(x[1], 1.0, 1e-6);
  EXPECT_TRUE(non_increasing(r.energy_history));
  EXPECT_LT(r.iterations, 100);
}

TEST(Lbfgs, BarrierIteratesStayFeasible) {
  // Σ (x_i - c_i)² - μ Σ log x_i, half the targets outside the domain x > 0:
  // from x = 3 the first steps aim past the boundary; the bound keeps every
  // iterate strictly inside.
  const int n = 20;
  VectorXd c(n);
  for (int i = 0; i < n; ++i) c[i] = (i % 2 ? -1.0 : 2.0) * (1 + 0.1 * i);
  const double mu = 0.5;
  int infeasible_evaluations = 0;
  const EnergyFunction f = [&](const VectorXd& x, VectorXd* g) {
    if ((x.array() <= 0).any()) {
      ++infeasible_evaluations;
      return std::numeric_limits<double>::infinity();
    }
    if (g) *g = 2 * (x - c) - mu * x.cwiseInverse();
    return (x - c).squaredNorm() - mu * x.array().log().sum();
  };
  const StepBound bound = [](const VectorXd& x, const VectorXd& d) {
    double t = std::numeric_limits<double>::infinity();
    for (Index i = 0; i < x.size(); ++i)
      if (d[i] < 0) t = std::min(t, -x[i] / d[i]);
    return t;
  };
  VectorXd x = VectorXd::Constant(n, 3.0);
  LbfgsOptions o;
  o.energy_tol = 0.0;  // converge on the gradient alone
  const LbfgsResult r = minimize_lbfgs(f, bound, x, o);
  EXPECT_EQ(r.stop_reason, "gradient") << r.iterations;
  EXPECT_EQ(infeasible_evaluations, 0);
  EXPECT_GT(x.minCoeff(), 0.0);
  EXPECT_TRUE(non_increasing(r.energy_history));
  for (int i = 0; i < n; ++i) {  // stationarity: x = (c + sqrt(c² + 2μ)) / 2
    const double expected = 0.5 * (c[i] + std::sqrt(c[i] * c[i] + 2 * mu));
    EXPECT_NEAR(x[i], expected, 1e-6 * std::max(1.0, expected)) << i;
  }
}

TEST(Lbfgs, IsometricEnergyOfAPinnedPatchDecreasesWithoutFolds) {
  // A bumpy height-field patch, boundary pinned at its projection, interior free.
  const int n = 12;
  MatrixX3d V((n + 1) * (n + 1), 3);
  MatrixX3i F;
  std::vector<Index> free_vertices;
  for (int i = 0; i <= n; ++i)
    for (int j = 0; j <= n; ++j) {
      const double x = double(i) / n, y = double(j) / n;
      V.row(i * (n + 1) + j) << x, y, 0.4 * std::sin(4 * x) * std::sin(3 * y);
      if (i > 0 && i < n && j > 0 && j < n) free_vertices.push_back(i * (n + 1) + j);
    }
  F = test_meshes::grid_faces(n);
  const IsometricFactors factors = isometric_factors(V, F);
  MatrixX2d uv = V.leftCols(2);
  const MatrixX2d pinned = uv;
  auto scatter = [&](const VectorXd& x) {
    MatrixX2d full = pinned;
    for (std::size_t i = 0; i < free_vertices.size(); ++i) full.row(free_vertices[i]) << x[2 * i], x[2 * i + 1];
    return full;
  };
  const EnergyFunction energy = [&](const VectorXd& x, VectorXd* g) {
    MatrixX2d grad;
    const double e = isometric_energy(factors, F, scatter(x), g ? &grad : nullptr);
    if (g && std::isfinite(e)) {
      g->resize(x.size());
      for (std::size_t i = 0; i < free_vertices.size(); ++i)
        g->segment<2>(2 * i) = grad.row(free_vertices[i]).transpose();
    }
    return e;
  };
  const StepBound bound = [&](const VectorXd& x, const VectorXd& d) {
    MatrixX2d dir = MatrixX2d::Zero(pinned.rows(), 2);
    for (std::size_t i = 0; i < free_vertices.size(); ++i) dir.row(free_vertices[i]) << d[2 * i], d[2 * i + 1];
    return max_feasible_step(F, scatter(x), dir);
  };
  VectorXd x(2 * free_vertices.size());
  for (std::size_t i = 0; i < free_vertices.size(); ++i)
    x.segment<2>(2 * i) = pinned.row(free_vertices[i]).transpose();
  VectorXd g0;
  const double e0 = energy(x, &g0);
  LbfgsOptions o;
  o.max_iterations = 300;
  const LbfgsResult r = minimize_lbfgs(energy, bound, x, o);
  VectorXd g1;
  const double e1 = energy(x, &g1);
  EXPECT_TRUE(std::isfinite(e1));  // no face inverted
  EXPECT_LT(e1, e0);
  EXPECT_LT(g1.norm(), 1e-3 * g0.norm());
  EXPECT_TRUE(non_increasing(r.energy_history));
  EXPECT_EQ(r.energy_history.size(), std::size_t(r.iterations) + 1);
}

TEST(Lbfgs, HessianShapedPreconditionerRemovesIllConditioning) {
  // ½ xᵀAx - bᵀx with A the 1D Laplacian (+ a small shift): condition number
  // ~1e5, so plain L-BFGS needs hundreds of steps; with H0 shaped by P = 2A
  // (right shape, wrong scale: the pair scaling must fix it) it needs ~1.
  const int n = 400;
  Eigen::SparseMatrix<double> A(n, n);
  std::vector<Eigen::Triplet<double>> t;
  for (int i = 0; i < n; ++i) {
    t.emplace_back(i, i, 2.0 + 1e-4);
    if (i > 0) t.emplace_back(i, i - 1, -1.0), t.emplace_back(i - 1, i, -1.0);
  }
  A.setFromTriplets(t.begin(), t.end());
  const VectorXd b = VectorXd::LinSpaced(n, -1.0, 1.0).array().sin();
  const EnergyFunction f = [&](const VectorXd& x, VectorXd* g) {
    const VectorXd Ax = A * x;
    if (g) *g = Ax - b;
    return 0.5 * x.dot(Ax) - b.dot(x);
  };
  Eigen::SimplicialLLT<Eigen::SparseMatrix<double>> llt(2.0 * A);
  const LbfgsPreconditioner shaped{[&](VectorXd& q) { q = llt.solve(q); },
                                   [&](const VectorXd& s) { return 2.0 * s.dot(A * s); }};
  LbfgsOptions o;
  o.energy_tol = 0.0;
  o.gradient_tol = 1e-9;
  o.max_iterations = 2000;
  VectorXd x_plain = VectorXd::Zero(n), x_shaped = VectorXd::Zero(n);
  const LbfgsResult plain = minimize_lbfgs(f, kUnbounded, x_plain, o);
  const LbfgsResult preconditioned = minimize_lbfgs(f, kUnbounded, x_shaped, o, {}, shaped);
  EXPECT_EQ(preconditioned.stop_reason, "gradient");
  EXPECT_LE(preconditioned.iterations, 5);
  EXPECT_GT(plain.iterations, 20 * preconditioned.iterations);
  const VectorXd exact = Eigen::SimplicialLLT<Eigen::SparseMatrix<double>>(A).solve(b);
  EXPECT_LT((x_shaped - exact).norm(), 1e-6 * exact.norm());
  EXPECT_TRUE(non_increasing(preconditioned.energy_history));
}

TEST(Lbfgs, GradientReferenceReplacesTheStartingGradient) {
  // Far out on Rosenbrock's valley |g0| is ~1e7: relative to it the
  // gradient test passes long before the minimum; relative to a reference
  // of the problem's own scale it does not.
  LbfgsOptions o;
  o.gradient_tol = 1e-6;
  o.energy_tol = 0.0;
  o.max_iterations = 5000;
  VectorXd relative(2), referenced(2), g(2);
  relative << -30.0, 1.0;
  referenced = relative;
  rosenbrock(relative, &g);
  ASSERT_GT(g.norm(), 1e6);
  const LbfgsResult a = minimize_lbfgs(rosenbrock, kUnbounded, relative, o);
  o.gradient_reference = 1.0;
  const LbfgsResult b = minimize_lbfgs(rosenbrock, kUnbounded, referenced, o);
  EXPECT_EQ(a.stop_reason, "gradient");
  EXPECT_EQ(b.stop_reason, "gradient");
  rosenbrock(referenced, &g);
  EXPECT_LE(g.norm(), 1e-6);
  EXPECT_NEAR(referenced[0], 1.0, 1e-5);
  EXPECT_GT(b.iterations, a.iterations);
}
