// Feature matching (thesis 4.5): min_cost_assignment, region_graph and
// match_features (features/min_cost_assignment.h, region_graph.h,
// match_features.h).
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <numeric>
#include <random>

#include "common/errors.h"
#include "features/match_features.h"
#include "features/min_cost_assignment.h"
#include "features/region_graph.h"
#include "test_meshes.h"

using namespace paramorph;
using namespace paramorph::features;

namespace {

/// The least total cost over all one-to-one assignments, by trying them all.
double brute_force_min(const Eigen::MatrixXd& cost) {
  const bool rows_fewer = cost.rows() <= cost.cols();
  const Eigen::MatrixXd c = rows_fewer ? cost : Eigen::MatrixXd(cost.transpose());
  std::vector<int> columns(c.cols());
  std::iota(columns.begin(), columns.end(), 0);
  double best = std::numeric_limits<double>::infinity();
  do {  // the first c.rows() entries of each permutation
    double total = 0;
    for (Eigen::Index i = 0; i < c.rows(); ++i) total += c(i, columns[i]);
    best = std::min(best, total);
  } while (std::next_permutation(columns.begin(), columns.end()));
  return best;
}

/// A unit sphere (the directions of V) pushed out into three bumps and in
/// into two pits of different sizes at irregular places, then stretched:
/// the radius depends on the direction only, so two samplings of the sphere
/// give the same surface (as tests/native/meshes.bumps_and_pits).
MatrixX3d bumps_and_pits(const MatrixX3d& sphere) {
  struct Feature {
    Eigen::Vector3d direction;
    double width, height;
  };
  const Feature features[] = {{{0.2, 0.3, 1.0}, 0.35, 0.45},
                              {{1.0, -0.2, 0.1}, 0.30, 0.35},
                              {{-0.6, 0.8, -0.3}, 0.40, -0.30},
                              {{0.1, -1.0, -0.5}, 0.30, -0.25},
                              {{-0.8, -0.4, 0.5}, 0.25, 0.30}};
  MatrixX3d V(sphere.rows(), 3);
  for (Index i = 0; i < Index(sphere.rows()); ++i) {
    const Eigen::Vector3d p = sphere.row(i).transpose().normalized();
    double r = 1.0;
    for (const Feature& f : features) {
      const double angle = std::acos(std::clamp(p.dot(f.direction.normalized()), -1.0, 1.0));
      r += f.height * std::exp(-std::pow(angle / f.width, 2));
    }
    V.row(i) = (r * p.cwiseProduct(Eigen::Vector3d(1.0, 1.2, 0.9))).transpose();
  }
  return V;
}

Eigen::Matrix3d turn(double degrees, const Eigen::Vector3d& axis) {
  return Eigen::AngleAxisd(degrees * M_PI / 180.0, axis.normalized()).toRotationMatrix();
}

double diagonal(const MatrixX3d& V) {
  return (V.colwise().maxCoeff() - V.colwise().minCoeff()).norm();
}

/// Segmentation of a box into its six sides (by the faces' normals).
Segmentation box_sides(const MatrixX3d& V, const MatrixX3i& F) {
  Segmentation s;
  s.face_labels.resize(F.rows());
  s.seeds.assign(6, -1);
  for (Index f = 0; f < Index(F.rows()); ++f) {
    const Eigen::Vector3d a = V.row(F(f, 0)), b = V.row(F(f, 1)), c = V.row(F(f, 2));
    const Eigen::Vector3d n = (b - a).cross(c - a);
    Eigen::Index axis;
    n.cwiseAbs().maxCoeff(&axis);
    const Index side = Index(2 * axis + (n[axis] > 0));
    s.face_labels[f] = side;
    s.seeds[side] = F(f, 0);
  }
  summarise_regions(TriMesh(V, F), s);
  return s;
}

}  // namespace

TEST(MinCostAssignment, FindsTheLeastTotalOverAllAssignments) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> value(0.0, 10.0);
  for (int n = 1; n <= 6; ++n)
    for (int m = 1; m <= 6; ++m) {
      Eigen::MatrixXd cost(n, m);
      for (int i = 0; i < n; ++i)
        for (int j = 0; j < m; ++j) cost(i, j) = std::round(value(rng));  // ties on purpose
      const std::vector<Index> partner = min_cost_assignment(cost);
      ASSERT_EQ(partner.size(), std::size_t(n));
      double total = 0;
      std::vector<Index> used;
      for (int i = 0; i < n; ++i) {
        if (partner[i] < 0) continue;
        ASSERT_LT(partner[i], m);
        used.push_back(partner[i]);
        total += cost(i, partner[i]);
      }
      EXPECT_EQ(used.size(), std::size_t(std::min(n, m))) << n << "x" << m;
      std::sort(used.begin(), used.end());
      EXPECT_EQ(std::unique(used.begin(), used.end()), used.end()) << "a column used twice";
      EXPECT_NEAR(total, brute_force_min(cost), 1e-9) << n << "x" << m;
      EXPECT_EQ(min_cost_assignment(cost), partner) << "not deterministic";
    }
  EXPECT_TRUE(min_cost_assignment(Eigen::MatrixXd(0, 3)).empty());
  EXPECT_EQ(min_cost_assignment(Eigen::MatrixXd(2, 0)), (std::vector<Index>{-1, -1}));
  Eigen::MatrixXd bad = Eigen::MatrixXd::Ones(2, 2);
  bad(1, 0) = std::numeric_limits<double>::quiet_NaN();
  EXPECT_THROW(min_cost_assignment(bad), InvalidInputError);
}

TEST(RegionGraph, BoxSidesHaveExactGeodesicsAndTheLongEdgesAreDropped) {
  // Half extents (1, 2, 4): between the centres of two adjacent sides the
  // geodesic runs across their shared edge, the sum of the two half extents
  // along it: x-y 3, x-z 5, y-z 6; exact along the grid lines.
  const auto [V, F] = test_meshes::box_grid(8, Eigen::Vector3d(1, 2, 4));
  const Segmentation s = box_sides(V, F);
  ASSERT_EQ(s.regions(), 6);
  ASSERT_EQ(s.adjacency.size(), 12u);
  auto expected = [](Index a, Index b) {
    const int x = std::min(a / 2, b / 2), y = std::max(a / 2, b / 2);
    return x == 0 ? (y == 1 ? 3.0 : 5.0) : 6.0;
  };
  const RegionGraph full = region_graph(V, F, s);
  EXPECT_TRUE(full.dropped.empty());
  ASSERT_EQ(full.edges.size(), 12u);
  for (std::size_t k = 0; k < full.edges.size(); ++k)
    EXPECT_NEAR(full.lengths[k], expected(full.edges[k].first, full.edges[k].second), 1e-12);
  for (Index r = 0; r < 6; ++r) {
    EXPECT_EQ(full.degree[r], 4);
    EXPECT_NEAR((V.row(full.anchors[r]) - s.centroid.row(r)).norm(), 0.0, 1e-12)
        << "anchor at the centre";
  }

  // Median 5; factor 1.1 drops the four y-z edges (6), which are the shortest
  // edge of neither side (y's is 3, z's is 5).
  RegionGraphOptions o;
  o.long_edge_factor = 1.1;
  const RegionGraph reduced = region_graph(V, F, s, o);
  ASSERT_EQ(reduced.dropped.size(), 4u);
  for (std::size_t k = 0; k < 4; ++k) {
    EXPECT_EQ(reduced.dropped[k].first / 2 + reduced.dropped[k].second / 2, 3) << "a y-z edge";
    EXPECT_NEAR(reduced.dropped_lengths[k], 6.0, 1e-12);
  }
  for (Index r = 0; r < 6; ++r) EXPECT_EQ(reduced.degree[r], r / 2 == 0 ? 4 : 2) << r;
  EXPECT_EQ(reduced.edges.size() + reduced.dropped.size(), 12u);

  // A tiny factor keeps only each side's shortest edges: nobody is isolated.
  o.long_edge_factor = 1e-6;
  for (int d : region_graph(V, F, s, o).degree) EXPECT_GE(d, 1);

  o.long_edge_factor = 0.0;
  EXPECT_THROW(region_graph(V, F, s, o), InvalidInputError);
  Segmentation wrong = s;
  wrong.face_labels[0] = 6;
  EXPECT_THROW(region_graph(V, F, wrong), InvalidInputError);
  EXPECT_THROW(region_graph(V, MatrixX3i(F.topRows(F.rows() - 1)), s), InvalidInputError);
}

TEST(MatchFeatures, ResampledTurnedScaledMovedCopyMatchesUnderTheKnownTransform) {
  const auto [S, F] = test_meshes::icosphere(4);
  const MatrixX3d VA = bumps_and_pits(S);
  // B: the same surface sampled at other directions (the sphere turned
  // before the bumps are applied), then turned by Q, scaled and moved.
  const MatrixX3d S2 = S * turn(17, {1, 2, 3}).transpose();
  const MatrixX3d B0 = bumps_and_pits(S2);
  const Eigen::Matrix3d Q = turn(130, {-1, 0.5, 2});
  const Eigen::RowVector3d shift(4, -2, 7);
  const MatrixX3d VB = ((3.0 * B0) * Q.transpose()).rowwise() + shift;

  const FeatureMatch m = match_features(VA, F, VB, F);
  const Eigen::Matrix3d& R = m.rotation;
  EXPECT_LT((R * R.transpose() - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff(), 1e-12);
  EXPECT_NEAR(R.determinant(), 1.0, 1e-12);
  EXPECT_LT((R * Q - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff(), 0.02) << R * Q;

  const double d = diagonal(VA);
  ASSERT_GE(m.region_pairs.size(), 4u);
  ASSERT_EQ(m.region_scores.size(), m.region_pairs.size());
  for (const auto& [i, j] : m.region_pairs) {
    const Eigen::RowVector3d back = (m.regions_b.centroid.row(j) - shift) * Q / 3.0;
    EXPECT_LT((m.regions_a.centroid.row(i) - back).norm() / d, 0.01) << i << " - " << j;
  }
  // Every point pair lies at one place of the surface (within 5% of the
  // diagonal: the samplings differ), and most points are paired.
  ASSERT_EQ(m.point_scores.size(), m.point_pairs.size());
  for (std::size_t k = 0; k < m.point_pairs.size(); ++k) {
    const auto [a, b] = m.point_pairs[k];
    EXPECT_LT((VA.row(a) - B0.row(b)).norm() / d, 0.05) << a << " - " << b;
    EXPECT_LE(m.point_scores[k], 0.05);
  }
  const std::size_t fewer = std::min(m.points_a.vertices.size(), m.points_b.vertices.size());
  EXPECT_GE(m.point_pairs.size(), 3 * fewer / 4) << fewer;

  // Deterministic.
  const FeatureMatch again = match_features(VA, F, VB, F);
  EXPECT_EQ(again.region_pairs, m.region_pairs);
  EXPECT_EQ(again.point_pairs, m.point_pairs);
  EXPECT_EQ(again.region_scores, m.region_scores);
  EXPECT_TRUE(again.rotation == m.rotation);
}

TEST(MatchFeatures, DifferentShapesGiveAValidResult) {
  const auto [VA, FA] = test_meshes::box_grid(6, Eigen::Vector3d(1, 1.5, 2));
  const auto [S, FB] = test_meshes::icosphere(3);
  const FeatureMatch m = match_features(VA, FA, bumps_and_pits(S), FB);
  EXPECT_NEAR(m.rotation.determinant(), 1.0, 1e-12);
  for (std::size_t k = 0; k < m.region_pairs.size(); ++k) {
    EXPECT_LT(m.region_pairs[k][0], m.regions_a.regions());
    EXPECT_LT(m.region_pairs[k][1], m.regions_b.regions());
    EXPECT_LT(m.region_scores[k], MatchOptions{}.max_region_score);
  }
}

TEST(MatchFeatures, ErrorsAreTypedNameTheMeshAndCancelStops) {
  const auto [S, F] = test_meshes::icosphere(2);
  const MatrixX3d V = bumps_and_pits(S);
  MatrixX3d degenerate = V;
  degenerate.row(F(3, 0)) = degenerate.row(F(3, 1));  // face 3 has no area
  try {
    match_features(V, F, degenerate, F);
    FAIL() << "no error";
  } catch (const DegenerateFaceError& e) {
    EXPECT_NE(std::string(e.what()).find("mesh B"), std::string::npos) << e.what();
  }
  MatrixX3i out_of_range = F;
  out_of_range(0, 0) = Index(V.rows());
  try {
    match_features(V, out_of_range, V, F);
    FAIL() << "no error";
  } catch (const InvalidInputError& e) {
    EXPECT_NE(std::string(e.what()).find("mesh A"), std::string::npos) << e.what();
  }
  MatchOptions o;
  o.alignment_nodes = 0;
  EXPECT_THROW(match_features(V, F, V, F, o), InvalidInputError);
  o = {};
  o.regions.concavity = VectorXd::Zero(V.rows());
  EXPECT_THROW(match_features(V, F, V, F, o), InvalidInputError);

  // Every stage reported in order, each mesh's named; a false answer stops.
  std::vector<std::pair<double, std::string>> seen;
  Progress record(
      [&](double f, const std::string& stage) { return seen.emplace_back(f, stage), true; }, 0.0);
  match_features(V, F, V, F, {}, &record);
  ASSERT_GE(seen.size(), 6u);
  EXPECT_EQ(seen.front().first, 0.0);
  EXPECT_EQ(seen.back().first, 1.0);
  for (std::size_t k = 1; k < seen.size(); ++k)
    EXPECT_GE(seen[k].first, seen[k - 1].first) << seen[k].second;
  for (const char* name : {"mesh A: ", "mesh B: "})
    EXPECT_TRUE(std::any_of(seen.begin(), seen.end(), [&](const auto& s) {
      return s.second.find(name) == 0;
    })) << name;
  int calls = 0;
  Progress stop([&](double, const std::string&) { return ++calls < 3; }, 0.0);
  EXPECT_THROW(match_features(V, F, V, F, {}, &stop), Cancelled);
  EXPECT_EQ(calls, 3);
}
