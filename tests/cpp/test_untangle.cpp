// Algorithm 2: untangling with fixed vertices.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "param/planar/untangle.h"
#include "test_meshes.h"

using namespace paramorph;
using namespace paramorph::planar;

namespace {
/// Unit-square grid, boundary flagged fixed.
void grid(int n, MatrixX2d& uv, MatrixX3i& F, std::vector<char>& fixed) {
  uv.resize((n + 1) * (n + 1), 2);
  fixed.assign(uv.rows(), 0);
  for (int i = 0; i <= n; ++i)
    for (int j = 0; j <= n; ++j) {
      uv.row(i * (n + 1) + j) << double(i) / n, double(j) / n;
      fixed[i * (n + 1) + j] = (i == 0 || j == 0 || i == n || j == n);
    }
  F = test_meshes::grid_faces(n);
}
}  // namespace

class UntangleGrid : public ::testing::TestWithParam<int> {};

TEST_P(UntangleGrid, UnfoldsAScrambledInteriorWithTheBoundaryFixed) {
  MatrixX2d uv;
  MatrixX3i F;
  std::vector<char> fixed;
  const int n = GetParam();
  grid(n, uv, F, fixed);
  ASSERT_TRUE(folded_faces(F, uv).empty());
  const MatrixX2d original = uv;
  // Scramble the interior by up to 1.5 grid cells: many faces fold.
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> jitter(-1.5 / n, 1.5 / n);
  for (Index v = 0; v < uv.rows(); ++v)
    if (!fixed[v]) uv.row(v) += Eigen::RowVector2d(jitter(rng), jitter(rng));
  ASSERT_GT(folded_faces(F, uv).size(), 10u);
  const UntangleResult r = untangle(F, uv, fixed);
  EXPECT_EQ(r.folded, 0) << r.iterations << " iterations";
  EXPECT_TRUE(folded_faces(F, uv).empty());
  for (Index v = 0; v < uv.rows(); ++v)
    if (fixed[v]) {
      EXPECT_EQ(uv.row(v), original.row(v));
    }
}

INSTANTIATE_TEST_SUITE_P(Sizes, UntangleGrid, ::testing::Values(10, 40));

TEST(Untangle, AnImpossibleConfigurationReportsItsFolds) {
  // Fixed vertices that force an inversion: a triangle whose three corners are
  // pinned clockwise cannot be untangled.
  MatrixX2d uv(3, 2);
  uv << 0, 0, 0, 1, 1, 0;  // clockwise
  MatrixX3i F(1, 3);
  F << 0, 1, 2;
  const UntangleResult r = untangle(F, uv, {1, 1, 1});
  EXPECT_EQ(r.folded, 1);
}
