// morph/tip_path_pairs: tips paired by the paths from each model's core out
// to them, each model measured in its own spread (issue 29).
#include <gtest/gtest.h>

#include "common/errors.h"
#include "morph/tip_path_pairs.h"

using namespace paramorph;

namespace {

/// Points on three axes through a core at the origin: a "long" model along
/// x, and the paths out to the ends of +x (a tail), -x (a head) and -y (a
/// leg), in the given order.
struct Star {
  MatrixX3d V;
  VectorXd area;
  features::ProtrusionTips tips;
};

Star star(double length, double height, const std::vector<int>& order) {
  Star s;
  s.V.resize(7, 3);
  s.V << 0, 0, 0,                    // core
      length / 2, 0, 0, length, 0, 0,   // +x
      -length / 2, 0, 0, -length, 0, 0, // -x
      0, -height / 2, 0, 0, -height, 0; // -y
  s.area = VectorXd::Ones(7);
  s.tips.core = 0;
  const std::vector<std::vector<Index>> paths{{0, 1, 2}, {0, 3, 4}, {0, 5, 6}};
  for (const int k : order) {
    s.tips.vertices.push_back(paths[std::size_t(k)].back());
    s.tips.paths.push_back(paths[std::size_t(k)]);
  }
  return s;
}

}  // namespace

TEST(TipPathPairs, PairsTipsByWhereTheirPathsGoWhateverTheirLengths) {
  // B is twice as long and half as tall, its tips listed in another order:
  // in each model's own spread the paths nearly agree end for end.
  const Star a = star(1.0, 0.6, {0, 1, 2}), b = star(2.0, 0.3, {2, 0, 1});
  const std::vector<morph::TipPathPair> pairs = morph::tip_path_pairs(a.V, a.area, a.tips, b.V, b.area, b.tips, 5, 10.0);
  ASSERT_EQ(pairs.size(), 3u);
  for (const auto& pair : pairs) {
    EXPECT_EQ(pair.a, pair.b) << "tip " << pair.a << " of A paired with " << pair.b << " of B";
    EXPECT_LT(pair.cost, 0.75);
  }
  for (std::size_t k = 1; k < pairs.size(); ++k) EXPECT_LE(pairs[k - 1].cost, pairs[k].cost);  // cheapest first
}

TEST(TipPathPairs, ATurnedModelPairsByWhereItsTipsAreNotByTheirOrder) {
  const Star a = star(1.0, 0.6, {0, 1, 2});
  // B turned half round about y: its "head" path now runs to +x.
  Star b = star(1.0, 0.6, {0, 1, 2});
  b.V.col(0) *= -1;
  b.V.col(2) *= -1;
  const auto pairs = morph::tip_path_pairs(a.V, a.area, a.tips, b.V, b.area, b.tips, 5, 10.0);
  ASSERT_EQ(pairs.size(), 3u);
  for (const auto& pair : pairs) {
    EXPECT_EQ(b.V.row(pair.b), a.V.row(pair.a));
    EXPECT_NEAR(pair.cost, 0.0, 1e-12);
  }
}

TEST(TipPathPairs, DropsPairsCostlierThanTheLimit) {
  const Star a = star(1.0, 0.6, {0, 1, 2});
  // B's third limb points sideways (+z) instead of down.
  Star b = star(1.0, 0.6, {0, 1, 2});
  b.V.row(5) << 0, 0, 0.3;
  b.V.row(6) << 0, 0, 0.6;
  const auto loose = morph::tip_path_pairs(a.V, a.area, a.tips, b.V, b.area, b.tips, 5, 10.0);
  ASSERT_EQ(loose.size(), 3u);
  EXPECT_EQ(loose.back().a, 6);  // the sideways limb costs the most
  const double limit = 0.5 * (loose[1].cost + loose[2].cost);
  const auto tight = morph::tip_path_pairs(a.V, a.area, a.tips, b.V, b.area, b.tips, 5, limit);
  ASSERT_EQ(tight.size(), 2u);
  for (const auto& pair : tight) EXPECT_EQ(pair.a, pair.b);
}

TEST(TipPathPairs, RefusesTooFewSamplesAndMismatchedAreas) {
  const Star a = star(1.0, 0.6, {0, 1, 2});
  EXPECT_THROW(morph::tip_path_pairs(a.V, a.area, a.tips, a.V, a.area, a.tips, 1, 1.0), InvalidInputError);
  EXPECT_THROW(morph::tip_path_pairs(a.V, VectorXd::Ones(3), a.tips, a.V, a.area, a.tips, 5, 1.0), InvalidInputError);
  EXPECT_TRUE(morph::tip_path_pairs(a.V, a.area, {}, a.V, a.area, a.tips, 5, 1.0).empty());
}

TEST(TipPathPairs, TheMirrorOutweighsPathsThatCannotTellTwoTipsApart) {
  // B's -x and -y paths both run out to the lower left, so either pairing
  // of them costs nearly the same; A's -x tip is alone under the
  // mirror (a muzzle) and its -y tip one of a pair (an ear); on B it is the
  // other way round. With the mirror term the lonely tips pair.
  const Star a = star(1.0, 1.0, {0, 1, 2});
  Star b = star(1.0, 1.0, {0, 1, 2});
  b.V.row(3) << -0.45, -0.2, 0;
  b.V.row(4) << -0.75, -0.6, 0;
  b.V.row(5) << -0.2, -0.45, 0;
  b.V.row(6) << -0.6, -0.75, 0;
  VectorXd alone_a(3), alone_b(3);
  alone_a << 1, 1, 0;
  alone_b << 1, 0, 1;
  const auto plain = morph::tip_path_pairs(a.V, a.area, a.tips, b.V, b.area, b.tips, 5, 10.0);
  ASSERT_EQ(plain.size(), 3u);
  for (const auto& pair : plain) EXPECT_EQ(pair.a, pair.b);
  const auto mirrored = morph::tip_path_pairs(a.V, a.area, a.tips, b.V, b.area, b.tips, 5, 10.0, alone_a, alone_b, 2.0);
  ASSERT_EQ(mirrored.size(), 3u);
  for (const auto& pair : mirrored) {
    if (pair.a == 2) EXPECT_EQ(pair.b, 2);  // +x: the tail either way
    if (pair.a == 4) EXPECT_EQ(pair.b, 6);
    if (pair.a == 6) EXPECT_EQ(pair.b, 4);
  }
  EXPECT_THROW(morph::tip_path_pairs(a.V, a.area, a.tips, b.V, b.area, b.tips, 5, 10.0, alone_a, VectorXd(), 1.0),
               InvalidInputError);
  EXPECT_THROW(morph::tip_path_pairs(a.V, a.area, a.tips, b.V, b.area, b.tips, 5, 10.0, alone_a, alone_b, -1.0),
               InvalidInputError);
}
