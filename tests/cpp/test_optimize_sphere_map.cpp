// The optimized sphere map for morphing (morph/optimize_sphere_map, thesis
// 4.3.3): derivatives against finite differences (Ipopt's problem and the
// barrier warm start's energy), fold-free results, per-vertex weights.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>

#include <Eigen/Geometry>

#include "common/errors.h"
#include "mesh/tri_mesh.h"
#include "morph/ipopt_polish.h"
#include "morph/optimize_sphere_map.h"
#include "param/spherical/sphere_map_barrier.h"
#include "morph/sphere_map_nlp.h"
#include "param/spherical/sphere_map.h"
#include "test_meshes.h"

using namespace paramorph;
using namespace paramorph::morph;
using namespace paramorph::spherical;

namespace {

Eigen::MatrixXd dense(Index rows, Index cols, const std::vector<Index>& r, const std::vector<Index>& c,
                      const std::vector<double>& values) {
  Eigen::MatrixXd M = Eigen::MatrixXd::Zero(rows, cols);
  for (std::size_t k = 0; k < values.size(); ++k) M(r[k], c[k]) += values[k];
  return M;
}

/// A point near a sphere map (not on the sphere), so every term is exercised.
std::vector<double> perturbed(const MatrixX3d& X, double amount, unsigned seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> noise(0.0, amount);
  std::vector<double> x(X.data(), X.data() + X.size());
  for (double& value : x) value = value * 1.1 + noise(rng);
  return x;
}

}  // namespace

TEST(SphereMapNlp, DerivativesMatchFiniteDifferences) {
  auto [V, F] = test_meshes::lumpy_blob(1);
  const TriMesh mesh(V, F);
  const MatrixX3d sphere = spherical::sphere_map(V, F).positions;
  const SphereMapNlp nlp(mesh, V.rowwise().normalized());
  const Index n = nlp.num_variables(), m = nlp.num_constraints();
  std::vector<double> x = perturbed(sphere, 0.05, 7);
  const double h = 1e-6;

  std::vector<double> grad(n);
  nlp.objective_gradient(x.data(), grad.data());
  std::vector<double> jac(nlp.jacobian_nonzeros());
  nlp.jacobian_values(x.data(), jac.data());
  const Eigen::MatrixXd J = dense(m, n, nlp.jacobian_rows(), nlp.jacobian_cols(), jac);

  std::mt19937 rng(3);
  std::uniform_real_distribution<double> uniform(-1.0, 1.0);
  VectorXd lambda(m);
  for (Index k = 0; k < m; ++k) lambda[k] = uniform(rng);
  std::vector<double> hess(nlp.hessian_nonzeros());
  nlp.hessian_values(x.data(), 1.0, lambda.data(), hess.data());
  Eigen::MatrixXd H = dense(n, n, nlp.hessian_rows(), nlp.hessian_cols(), hess);
  for (Index i = 0; i < n; ++i)  // the lower triangle is stored: mirror it
    for (Index j = 0; j < i; ++j) H(j, i) = H(i, j);
  for (std::size_t k = 0; k < hess.size(); ++k) ASSERT_GE(nlp.hessian_rows()[k], nlp.hessian_cols()[k]);

  VectorXd g_plus(m), g_minus(m);
  double worst_grad = 0, worst_jac = 0, worst_hess = 0;
  for (Index j = 0; j < n; ++j) {
    std::vector<double> xp = x, xm = x;
    xp[j] += h;
    xm[j] -= h;
    worst_grad = std::max(worst_grad, std::abs((nlp.objective(xp.data()) - nlp.objective(xm.data())) / (2 * h) - grad[j]));
    nlp.constraints(xp.data(), g_plus.data());
    nlp.constraints(xm.data(), g_minus.data());
    worst_jac = std::max(worst_jac, ((g_plus - g_minus) / (2 * h) - J.col(j)).cwiseAbs().maxCoeff());
    // Column j of the Lagrangian's Hessian: d/dx_j of J(x)^T lambda.
    std::vector<double> jp(jac.size()), jm(jac.size());
    nlp.jacobian_values(xp.data(), jp.data());
    nlp.jacobian_values(xm.data(), jm.data());
    const Eigen::MatrixXd Jp = dense(m, n, nlp.jacobian_rows(), nlp.jacobian_cols(), jp);
    const Eigen::MatrixXd Jm = dense(m, n, nlp.jacobian_rows(), nlp.jacobian_cols(), jm);
    const VectorXd column = (Jp.transpose() * lambda - Jm.transpose() * lambda) / (2 * h);
    worst_hess = std::max(worst_hess, (column - H.col(j)).cwiseAbs().maxCoeff());
  }
  EXPECT_LT(worst_grad, 1e-8);
  EXPECT_LT(worst_jac, 1e-7);
  EXPECT_LT(worst_hess, 1e-6);
}

TEST(OptimizeSphereMap, StaysFoldFreeAndMovesTowardsTheProjection) {
  auto [V, F] = test_meshes::lumpy_blob(2);
  const MatrixX3d sphere = spherical::sphere_map(V, F).positions;
  const OptimizeSphereResult r = optimize_sphere_map(V, F, sphere);
  EXPECT_EQ(r.flipped, 0);
  EXPECT_GE(r.min_triple, r.epsilon * (1 - 1e-4));  // to Ipopt's constraint tolerance
  EXPECT_GT(r.objective, r.start_objective);
  EXPECT_LE(r.objective, double(V.rows()));
  EXPECT_LT((r.positions.rowwise().norm().array() - 1.0).abs().maxCoeff(), 1e-12);
  if (ipopt_available())
    EXPECT_TRUE(r.status == "Solve_Succeeded" || r.status == "Solved_To_Acceptable_Level") << r.status;
  else
    EXPECT_EQ(r.status, "Barrier_Converged");
  EXPECT_EQ(r.used_ipopt, ipopt_available());
}

TEST(OptimizeSphereMap, TheBarrierAloneIsFoldFreeAboveEpsilonAndAtIpoptsOptimum) {
  auto [V, F] = test_meshes::lumpy_blob(2);
  const MatrixX3d sphere = spherical::sphere_map(V, F).positions;
  OptimizeSphereOptions o;
  o.solver = SphereSolver::Barrier;
  const OptimizeSphereResult barrier = optimize_sphere_map(V, F, sphere, o);
  EXPECT_FALSE(barrier.used_ipopt);
  EXPECT_EQ(barrier.iterations, 0);
  EXPECT_EQ(barrier.flipped, 0);
  EXPECT_GE(barrier.min_triple, barrier.epsilon);  // a primal barrier: exactly, no tolerance
  EXPECT_GT(barrier.objective, barrier.start_objective);
  EXPECT_EQ(barrier.status, "Barrier_Converged");
  if (ipopt_available()) {
    o.solver = SphereSolver::Ipopt;
    const OptimizeSphereResult ipopt = optimize_sphere_map(V, F, sphere, o);
    EXPECT_TRUE(ipopt.used_ipopt);
    EXPECT_GE(barrier.objective, ipopt.objective - 1e-6 * ipopt.objective);
  }
  o.solver = SphereSolver::Barrier;
  o.warm_start = false;  // Ipopt alone: not the barrier
  EXPECT_THROW(optimize_sphere_map(V, F, sphere, o), InvalidInputError);
}

TEST(OptimizeSphereMap, IpoptAskedForInABuildWithoutItIsRefused) {
  if (ipopt_available()) GTEST_SKIP() << "this build has Ipopt";
  auto [V, F] = test_meshes::lumpy_blob(1);
  OptimizeSphereOptions o;
  o.solver = SphereSolver::Ipopt;
  EXPECT_THROW(optimize_sphere_map(V, F, spherical::sphere_map(V, F).positions, o), InvalidInputError);
}

TEST(OptimizeSphereMap, PolishIterationsCapIpoptAfterTheWarmStartAndKeepTheBetterPoint) {
  if (!ipopt_available()) GTEST_SKIP() << "this build has no Ipopt";
  auto [V, F] = test_meshes::lumpy_blob(2);
  const MatrixX3d sphere = spherical::sphere_map(V, F).positions;
  const OptimizeSphereResult full = optimize_sphere_map(V, F, sphere);
  OptimizeSphereOptions o;
  o.polish_iterations = 1;
  const OptimizeSphereResult capped = optimize_sphere_map(V, F, sphere, o);
  ASSERT_GT(capped.barrier_steps, 0);  // warm started: the cap applies
  EXPECT_LE(capped.iterations, 1);
  EXPECT_EQ(capped.flipped, 0);
  // The barrier's point already sits near the optimum; Ipopt only polishes.
  EXPECT_GT(capped.objective, capped.start_objective);
  EXPECT_NEAR(capped.objective, full.objective, 1e-3 * full.objective);
  o.polish_iterations = 0;
  EXPECT_THROW(optimize_sphere_map(V, F, sphere, o), InvalidInputError);
  // Without the warm start: Ipopt alone, to the same optimum.
  OptimizeSphereOptions cold;
  cold.warm_start = false;
  const OptimizeSphereResult alone = optimize_sphere_map(V, F, sphere, cold);
  EXPECT_EQ(alone.barrier_steps, 0);
  EXPECT_EQ(alone.flipped, 0);
  EXPECT_NEAR(alone.objective, full.objective, 1e-4 * full.objective);
}

TEST(OptimizeSphereMap, AConvexMeshGoesToItsRadialProjection) {
  auto [V, F] = test_meshes::icosphere(2);
  V.col(0) *= 1.6;  // an ellipsoid: star-shaped, its radial projection folds nothing
  const MatrixX3d sphere = spherical::sphere_map(V, F).positions;
  OptimizeSphereOptions o;
  o.epsilon = 1e-3;
  const OptimizeSphereResult r = optimize_sphere_map(V, F, sphere, o);
  const MatrixX3d projection = V.rowwise().normalized();
  EXPECT_EQ(r.flipped, 0);
  EXPECT_LT((r.positions - projection).rowwise().norm().maxCoeff(), 1e-3) << r.status;
  EXPECT_NEAR(r.objective, double(V.rows()), 1e-3);
}

TEST(OptimizeSphereMap, BadInputAndCancel) {
  auto [V, F] = test_meshes::lumpy_blob(1);
  const MatrixX3d sphere = spherical::sphere_map(V, F).positions;
  MatrixX3d folded = sphere;
  folded.row(F(0, 0)) = -folded.row(F(0, 0));
  EXPECT_THROW(optimize_sphere_map(V, F, folded), InvalidInputError);
  EXPECT_THROW(optimize_sphere_map(V, F, sphere.topRows(3)), InvalidInputError);
  auto [G, FG] = test_meshes::bumpy_grid(4);
  EXPECT_THROW(optimize_sphere_map(G, FG, MatrixX3d::Zero(G.rows(), 3)), NotClosedError);
  Progress stop([](double, const std::string&) { return false; });
  EXPECT_THROW(optimize_sphere_map(V, F, sphere, {}, &stop), Cancelled);
}

TEST(SphereMapBarrier, EnergyGradientMatchesFiniteDifferences) {
  auto [V, F] = test_meshes::lumpy_blob(1);
  const MatrixX3d sphere = spherical::sphere_map(V, F).positions;
  const std::vector<double> x = perturbed(sphere, 0.01, 11);
  const MatrixX3d X = Eigen::Map<const MatrixX3d>(x.data(), V.rows(), 3);
  const VectorXd det = face_triple_products(X, F);
  ASSERT_GT(det.minCoeff(), 0.0);
  const VectorXd bounds = 0.5 * det;  // every face strictly inside, at different gaps
  const MatrixX3d pull = 1.7 * V.rowwise().normalized();
  // Per-face weights, not all equal (faces still opening keep a larger one).
  const VectorXd mu = VectorXd::LinSpaced(F.rows(), 1e-3, 3e-3);
  MatrixX3d gradient;
  const double energy = sphere_barrier_energy(F, pull, bounds, mu, X, &gradient);
  ASSERT_TRUE(std::isfinite(energy));
  const double h = 1e-7;
  double worst = 0, largest = 0;
  for (Index v = 0; v < X.rows(); ++v)
    for (int d = 0; d < 3; ++d) {
      MatrixX3d plus = X, minus = X;
      plus(v, d) += h;
      minus(v, d) -= h;
      const double fd = (sphere_barrier_energy(F, pull, bounds, mu, plus) -
                         sphere_barrier_energy(F, pull, bounds, mu, minus)) / (2 * h);
      worst = std::max(worst, std::abs(fd - gradient(v, d)));
      largest = std::max(largest, std::abs(gradient(v, d)));
    }
  EXPECT_LT(worst, 1e-6 * std::max(1.0, largest));
  // Crossing a bound is infinitely expensive: the line search's feasibility test.
  VectorXd tight = bounds;
  tight[0] = det[0];
  EXPECT_EQ(sphere_barrier_energy(F, pull, tight, mu, X), std::numeric_limits<double>::infinity());
}

TEST(SphereMapBarrier, StaysAboveItsBoundsOnTheSphereAndPullsTowardsTheTargets) {
  auto [V, F] = test_meshes::lumpy_blob(2);
  const MatrixX3d start = spherical::sphere_map(V, F).positions.rowwise().normalized();
  const MatrixX3d pull = V.rowwise().normalized();
  const VectorXd start_det = face_triple_products(start, F);
  SphereBarrierOptions o;
  o.epsilon = 0.05 * start_det.mean();
  o.mu_start = start_det.mean();
  o.mu_end = 1e-3 * o.mu_start;
  const SphereBarrierResult r = sphere_map_barrier(F, pull, start, o);
  EXPECT_GT(r.steps, 0);
  EXPECT_LE(r.mu, o.mu_end * (1 + 1e-12));
  EXPECT_LT((r.positions.rowwise().norm().array() - 1.0).abs().maxCoeff(), 1e-12);
  const VectorXd det = face_triple_products(r.positions, F);
  for (Index f = 0; f < F.rows(); ++f) {
    EXPECT_GT(det[f], r.bounds[f]) << f;
    EXPECT_LE(r.bounds[f], o.epsilon) << f;
    EXPECT_GE(r.bounds[f], std::min(o.epsilon, 0.5 * start_det[f])) << f;  // bounds only rise
  }
  EXPECT_GT((pull.array() * r.positions.array()).sum(), (pull.array() * start.array()).sum());
  // 3 decades at a factor 0.1: mu_start, /10, /100 and mu_end, no more.
  EXPECT_EQ(r.rounds, 4);
  // The Newton systems are positive definite as built: one factorization per
  // step and one per round's last centring test, no shifted retries.
  EXPECT_EQ(r.factorizations, r.steps + r.rounds);
}

TEST(OptimizeSphereMap, AHeavilyWeightedVertexEndsCloserToItsTarget) {
  auto [V, F] = test_meshes::lumpy_blob(2);
  const MatrixX3d sphere = spherical::sphere_map(V, F).positions;
  // Targets: the radial projection turned by 0.3 rad, so the pull fights the
  // fold bounds everywhere and no vertex reaches its target for free.
  const Eigen::Matrix3d turn = Eigen::AngleAxisd(0.3, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  MatrixX3d target = V.rowwise().normalized() * turn;
  for (Index v = 0; v < V.rows(); ++v) target(v, 0) += 0.4 * std::sin(5 * V(v, 1));
  target.rowwise().normalize();
  OptimizeSphereOptions o;
  o.target = target;
  const OptimizeSphereResult plain = optimize_sphere_map(V, F, sphere, o);
  ASSERT_EQ(plain.flipped, 0);
  // The vertex left farthest from its target by the unweighted optimum.
  Index far = 0;
  (plain.positions - target).rowwise().norm().maxCoeff(&far);
  const double plain_distance = (plain.positions.row(far) - target.row(far)).norm();
  ASSERT_GT(plain_distance, 1e-3);
  VectorXd weights = VectorXd::Ones(V.rows());
  weights[far] = 1000.0;
  o.weights = weights;
  const OptimizeSphereResult weighted = optimize_sphere_map(V, F, sphere, o);
  EXPECT_EQ(weighted.flipped, 0);
  EXPECT_LT((weighted.positions.row(far) - target.row(far)).norm(), 0.5 * plain_distance)
      << plain.status << " " << weighted.status;
  EXPECT_GT(weighted.objective, weighted.start_objective);
}

TEST(OptimizeSphereMap, BadWeights) {
  auto [V, F] = test_meshes::lumpy_blob(1);
  const MatrixX3d sphere = spherical::sphere_map(V, F).positions;
  OptimizeSphereOptions o;
  o.weights = VectorXd::Ones(V.rows() - 1);
  EXPECT_THROW(optimize_sphere_map(V, F, sphere, o), InvalidInputError);
  o.weights = VectorXd::Ones(V.rows());
  (*o.weights)[3] = -1;
  EXPECT_THROW(optimize_sphere_map(V, F, sphere, o), InvalidInputError);
  (*o.weights)[3] = std::numeric_limits<double>::quiet_NaN();
  EXPECT_THROW(optimize_sphere_map(V, F, sphere, o), InvalidInputError);
  o.weights = VectorXd::Zero(V.rows());
  EXPECT_THROW(optimize_sphere_map(V, F, sphere, o), InvalidInputError);
}
