// ε-continuation untangling, the fallback behind Algorithm 2.
#include <gtest/gtest.h>

#include <random>

#include "param/planar/untangle.h"
#include "param/planar/untangle_continuation.h"
#include "test_meshes.h"

using namespace paramorph;
using namespace paramorph::planar;

namespace {
struct Patch {
  MatrixX3d V;
  MatrixX3i F;
  MatrixX2d uv;
  std::vector<char> fixed;
};

/// The bumpy grid mapped by its projection, boundary fixed, then the interior
/// scrambled by up to `cells` grid cells and a few interior vertices pinned too.
Patch scrambled(int n, double cells) {
  auto [V, F] = test_meshes::bumpy_grid(n);
  Patch p{V, F, V.leftCols(2), std::vector<char>(V.rows(), 0)};
  for (Index v = 0; v < V.rows(); ++v) {
    const double x = V(v, 0), y = V(v, 1);
    p.fixed[v] = x == 0.0 || y == 0.0 || x == 1.0 || y == 1.0 || v % 29 == 0;
  }
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> jitter(-cells / n, cells / n);
  for (Index v = 0; v < V.rows(); ++v)
    if (!p.fixed[v]) p.uv.row(v) += Eigen::RowVector2d(jitter(rng), jitter(rng));
  return p;
}
}  // namespace

TEST(UntangleContinuation, UnfoldsWithoutSliversAndKeepsFixedVertices) {
  Patch p = scrambled(30, 3.0);  // a fold-free solution exists: the projection
  ASSERT_GT(folded_faces(p.F, p.uv).size(), 100u);
  const MatrixX2d before = p.uv;
  const IsometricFactors factors = isometric_factors(p.V, p.F);
  const ContinuationResult r = untangle_continuation(factors, p.F, p.uv, p.fixed);
  EXPECT_EQ(r.folded, 0) << r.rounds << " rounds";
  EXPECT_TRUE(folded_faces(p.F, p.uv).empty());
  // No slivers: the barrier energy is finite and of moderate size.
  EXPECT_LT(isometric_energy(factors, p.F, p.uv), 1e3 * factors.area.sum());
  for (Index v = 0; v < p.uv.rows(); ++v)
    if (p.fixed[v]) EXPECT_EQ(p.uv.row(v), before.row(v)) << v;
}

TEST(UntangleContinuation, AFoldFreeMapWithoutSliversIsLeftAlone) {
  auto [V, F] = test_meshes::bumpy_grid(10);
  MatrixX2d uv = V.leftCols(2);
  const MatrixX2d before = uv;
  const ContinuationResult r =
      untangle_continuation(isometric_factors(V, F), F, uv, std::vector<char>(V.rows(), 0));
  EXPECT_EQ(r.rounds, 0);
  EXPECT_EQ(uv, before);
}

TEST(UntangleContinuation, AnImpossiblePinSetEndsWithItsFoldsCounted) {
  // A pinned interior vertex placed outside the fixed boundary square cannot
  // be reached without folds; the budget runs out and the count is honest.
  auto [V, F] = test_meshes::bumpy_grid(8);
  MatrixX2d uv = V.leftCols(2);
  std::vector<char> fixed(V.rows(), 0);
  for (Index v = 0; v < V.rows(); ++v)
    fixed[v] = V(v, 0) == 0.0 || V(v, 1) == 0.0 || V(v, 0) == 1.0 || V(v, 1) == 1.0;
  const Index center = 4 * 9 + 4;
  fixed[center] = 1;
  uv.row(center) << 1.5, 0.5;
  ContinuationOptions o;
  o.max_rounds = 10;
  const Index folded_before = Index(folded_faces(F, uv).size());
  const ContinuationResult r = untangle_continuation(isometric_factors(V, F), F, uv, fixed, o);
  EXPECT_GT(r.folded, 0);
  EXPECT_LE(r.folded, folded_before);  // the best map seen, never a worse one
  EXPECT_EQ(r.folded, Index(folded_faces(F, uv).size()));
  EXPECT_EQ(uv.row(center), Eigen::RowVector2d(1.5, 0.5));
}

TEST(UntangleContinuation, UnfoldsAMapWhoseScaleSpansOrdersOfMagnitude) {
  // u = x³ squeezes the strip near x = 0 by up to 1e4 (like the ear of a
  // curved patch mapped flat); vertices scrambled there by a few of their
  // local cells fold. One ε for all faces lets such a region fold further;
  // the local reference scale of the untangler does not.
  const int n = 30;
  auto [V, F] = test_meshes::bumpy_grid(n);
  MatrixX2d uv(V.rows(), 2);
  std::vector<char> fixed(V.rows(), 0);
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> jitter(-1.0, 1.0);
  for (Index v = 0; v < V.rows(); ++v) {
    const double x = V(v, 0), y = V(v, 1);
    uv.row(v) << x * x * x, y;
    fixed[v] = x == 0.0 || y == 0.0 || x == 1.0 || y == 1.0 || v % 31 == 0;
  }
  const MatrixX2d before = uv;
  for (Index v = 0; v < V.rows(); ++v) {
    const double x = V(v, 0);
    if (fixed[v] || x > 0.4) continue;
    const double cell_u = 3.0 * x * x / n, cell_v = 1.0 / n;
    uv.row(v) += Eigen::RowVector2d(3.0 * cell_u * jitter(rng), 1.5 * cell_v * jitter(rng));
  }
  ASSERT_TRUE(folded_faces(F, before).empty());
  ASSERT_GT(folded_faces(F, uv).size(), 20u);
  const ContinuationResult r = untangle_continuation(isometric_factors(V, F), F, uv, fixed);
  EXPECT_EQ(r.folded, 0) << r.rounds << " rounds, " << r.iterations << " iterations";
  EXPECT_TRUE(folded_faces(F, uv).empty());
  for (Index v = 0; v < V.rows(); ++v)
    if (fixed[v]) EXPECT_EQ(uv.row(v), before.row(v)) << v;
}
