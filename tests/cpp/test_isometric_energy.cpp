// The planar isometric energy (thesis 2.19) and the exact largest fold-free step.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <random>

#include "param/planar/isometric_energy.h"
#include "test_meshes.h"

using namespace paramorph;
using namespace paramorph::planar;

namespace {

/// A small bumpy disc-like patch: a grid in 3D with a height field.
void bumpy_patch(int n, MatrixX3d& V, MatrixX3i& F) {
  V.resize((n + 1) * (n + 1), 3);
  for (int i = 0; i <= n; ++i)
    for (int j = 0; j <= n; ++j) {
      const double x = double(i) / n, y = double(j) / n + 0.3 * x * x;
      V.row(i * (n + 1) + j) << x, y, 0.2 * std::sin(3 * x) * std::cos(2 * y);
    }
  F = test_meshes::grid_faces(n);
}

/// Each 3D triangle laid flat on its own (a disconnected, exactly isometric map).
void isometric_layout(const MatrixX3d& V, const MatrixX3i& F, MatrixX2d& uv, MatrixX3i& G) {
  uv.resize(3 * F.rows(), 2);
  G.resize(F.rows(), 3);
  for (Index f = 0; f < F.rows(); ++f) {
    const Eigen::Vector3d v0 = V.row(F(f, 0)), v1 = V.row(F(f, 1)), v2 = V.row(F(f, 2));
    const Eigen::Vector3d x = (v1 - v0).normalized();
    const Eigen::Vector3d y = (v1 - v0).cross(v2 - v0).cross(v1 - v0).normalized();
    uv.row(3 * f) << 0.0, 0.0;
    uv.row(3 * f + 1) << (v1 - v0).norm(), 0.0;
    uv.row(3 * f + 2) << (v2 - v0).dot(x), (v2 - v0).dot(y);
    G.row(f) << 3 * f, 3 * f + 1, 3 * f + 2;
  }
}

}  // namespace

TEST(IsometricEnergy, IsometryCostsFourPerUnitAreaWithZeroGradient) {
  MatrixX3d V;
  MatrixX3i F, G;
  bumpy_patch(6, V, F);
  MatrixX2d uv;
  isometric_layout(V, F, uv, G);
  const IsometricFactors factors = isometric_factors(V, F);
  MatrixX2d grad;
  const double energy = isometric_energy(factors, G, uv, &grad);
  EXPECT_NEAR(energy, 4.0 * factors.area.sum(), 1e-10);
  EXPECT_LT(grad.cwiseAbs().maxCoeff(), 1e-9);
  // Rigid motions change nothing; a uniform scale raises the energy.
  const Eigen::Matrix2d R = Eigen::Rotation2Dd(0.7).toRotationMatrix();
  MatrixX2d moved = (uv * R.transpose()).rowwise() + Eigen::RowVector2d(3.0, -1.0);
  EXPECT_NEAR(isometric_energy(factors, G, moved), energy, 1e-10);
  EXPECT_GT(isometric_energy(factors, G, 1.2 * uv), energy);
}

TEST(IsometricEnergy, GradientMatchesFiniteDifferences) {
  MatrixX3d V;
  MatrixX3i F;
  bumpy_patch(4, V, F);
  const IsometricFactors factors = isometric_factors(V, F);
  MatrixX2d uv(V.rows(), 2);
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> jitter(-0.02, 0.02);
  for (Index i = 0; i < V.rows(); ++i) uv.row(i) << 1.3 * V(i, 0) + jitter(rng), 0.8 * V(i, 1) + jitter(rng);
  MatrixX2d grad;
  ASSERT_TRUE(std::isfinite(isometric_energy(factors, F, uv, &grad)));
  const double h = 1e-6;
  for (Index i = 0; i < uv.rows(); i += 3)
    for (int c = 0; c < 2; ++c) {
      MatrixX2d plus = uv, minus = uv;
      plus(i, c) += h;
      minus(i, c) -= h;
      const double fd = (isometric_energy(factors, F, plus) - isometric_energy(factors, F, minus)) / (2 * h);
      EXPECT_NEAR(grad(i, c), fd, 1e-6 * std::max(1.0, std::abs(fd))) << "vertex " << i << " coord " << c;
    }
}

TEST(IsometricEnergy, InvertedFaceIsInfinite) {
  MatrixX3d V;
  MatrixX3i F;
  bumpy_patch(2, V, F);
  const IsometricFactors factors = isometric_factors(V, F);
  MatrixX2d uv = V.leftCols(2);
  EXPECT_TRUE(std::isfinite(isometric_energy(factors, F, uv)));
  uv.col(0) = -uv.col(0);  // mirror: every face inverted
  EXPECT_TRUE(std::isinf(isometric_energy(factors, F, uv)));
}

TEST(MaxFeasibleStep, StopsExactlyWhereTheFirstFaceInverts) {
  MatrixX3d V;
  MatrixX3i F;
  bumpy_patch(3, V, F);
  const MatrixX2d uv = V.leftCols(2);
  MatrixX2d d = MatrixX2d::Zero(uv.rows(), 2);
  d.row(5) << 1.0, 0.7;  // drag one interior vertex across its neighbours
  const double t = max_feasible_step(F, uv, d);
  ASSERT_TRUE(std::isfinite(t));
  auto min_det = [&](double s) {
    const MatrixX2d x = uv + s * d;
    double lo = std::numeric_limits<double>::infinity();
    for (Index f = 0; f < F.rows(); ++f) {
      const Eigen::Vector2d e1 = x.row(F(f, 1)) - x.row(F(f, 0)), e2 = x.row(F(f, 2)) - x.row(F(f, 0));
      lo = std::min(lo, e1.x() * e2.y() - e1.y() * e2.x());
    }
    return lo;
  };
  EXPECT_GT(min_det(0.999 * t), 0.0);
  EXPECT_LT(min_det(1.001 * t), 0.0);
  EXPECT_NEAR(min_det(t), 0.0, 1e-12);
  // A rigid translation never inverts anything.
  EXPECT_TRUE(std::isinf(max_feasible_step(F, uv, MatrixX2d::Ones(uv.rows(), 2))));
}
