// paste/fill_between_loops and paste/plane_polygon: the seam of a carried
// feature (issue 32) between a hole in the target and the feature's boundary.
#include <gtest/gtest.h>

#include <cmath>

#include "paste/fill_between_loops.h"
#include "paste/plane_polygon.h"

using namespace paramorph;
using namespace paramorph::paste;

namespace {

/// k points on a circle of radius r, turned by phase, counter-clockwise.
std::vector<Eigen::Vector2d> circle(int k, double r, double phase = 0.0) {
  std::vector<Eigen::Vector2d> out;
  for (int i = 0; i < k; ++i) {
    const double a = phase + 2 * M_PI * i / k;
    out.emplace_back(r * std::cos(a), r * std::sin(a));
  }
  return out;
}

/// Points and segments of loops given one after another.
struct Loops {
  std::vector<Eigen::Vector2d> points;
  std::vector<std::array<Index, 2>> segments;
  void add(const std::vector<Eigen::Vector2d>& loop) {
    const Index first = Index(points.size());
    for (std::size_t k = 0; k < loop.size(); ++k) {
      points.push_back(loop[k]);
      segments.push_back({first + Index(k), first + Index((k + 1) % loop.size())});
    }
  }
};

double polygon_area(const std::vector<Eigen::Vector2d>& loop) {
  double area = 0;
  for (std::size_t k = 0; k < loop.size(); ++k) area += 0.5 * plane_cross(loop[k], loop[(k + 1) % loop.size()]);
  return area;
}

}  // namespace

TEST(FillBetweenLoops, FillsTheRingBetweenACoarseHoleAndAFineBoundaryExactly) {
  const auto hole = circle(9, 1.0, 0.1), boundary = circle(40, 0.6);
  Loops loops;
  loops.add(hole);
  loops.add(boundary);
  const auto faces = fill_between_loops(loops.points, loops.segments);
  ASSERT_TRUE(faces.has_value());
  double area = 0;
  std::vector<int> used(loops.points.size(), 0);
  for (Index r = 0; r < faces->rows(); ++r) {
    const Eigen::Vector2d a = loops.points[(*faces)(r, 0)], b = loops.points[(*faces)(r, 1)],
                          c = loops.points[(*faces)(r, 2)];
    const double signed_area = 0.5 * plane_cross(b - a, c - a);
    EXPECT_GT(signed_area, 0) << "face " << r << " is not counter-clockwise";
    area += signed_area;
    for (int k = 0; k < 3; ++k) used[(*faces)(r, k)] = 1;
  }
  // The ring exactly (no face inside the boundary, none outside the hole),
  // every point used, and a ring of n points takes n triangles.
  EXPECT_NEAR(area, polygon_area(hole) - polygon_area(boundary), 1e-12);
  EXPECT_EQ(std::count(used.begin(), used.end(), 1), Index(used.size()));
  EXPECT_EQ(faces->rows(), Index(hole.size() + boundary.size()));
}

TEST(FillBetweenLoops, AnIslandInsideTheInnerLoopIsFilledAgain) {
  Loops loops;
  loops.add(circle(8, 1.0));
  loops.add(circle(8, 0.6, 0.2));
  loops.add(circle(5, 0.2));
  const auto faces = fill_between_loops(loops.points, loops.segments);
  ASSERT_TRUE(faces.has_value());
  double area = 0;
  for (Index r = 0; r < faces->rows(); ++r)
    area += 0.5 * plane_cross(loops.points[(*faces)(r, 1)] - loops.points[(*faces)(r, 0)],
                              loops.points[(*faces)(r, 2)] - loops.points[(*faces)(r, 0)]);
  EXPECT_NEAR(area, polygon_area(circle(8, 1.0)) - polygon_area(circle(8, 0.6, 0.2)) + polygon_area(circle(5, 0.2)),
              1e-12);
}

TEST(FillBetweenLoops, CrossingLoopsOrARepeatedPointAreRefused) {
  Loops crossing;
  crossing.add(circle(6, 1.0));
  std::vector<Eigen::Vector2d> off = circle(6, 0.8);
  for (auto& p : off) p.x() += 0.5;  // pokes out through the first loop
  crossing.add(off);
  EXPECT_FALSE(fill_between_loops(crossing.points, crossing.segments).has_value());

  Loops repeated;
  repeated.add(circle(6, 1.0));
  repeated.add({Eigen::Vector2d(1.0, 0.0), Eigen::Vector2d(0.2, 0.1), Eigen::Vector2d(0.1, 0.2)});
  EXPECT_FALSE(fill_between_loops(repeated.points, repeated.segments).has_value());
}

TEST(PlanePolygon, InsideNearAndCrossingTests) {
  const auto square = std::vector<Eigen::Vector2d>{{0, 0}, {1, 0}, {1, 1}, {0, 1}};
  EXPECT_TRUE(inside_or_near(square, {0.5, 0.5}, 0.0));
  EXPECT_FALSE(inside_or_near(square, {1.5, 0.5}, 0.0));
  EXPECT_TRUE(inside_or_near(square, {1.0 + 1e-9, 0.5}, 1e-6));  // near the boundary counts
  EXPECT_FALSE(inside_or_near(square, {1.0 + 1e-3, 0.5}, 1e-6));
  EXPECT_TRUE(segments_meet({0, 0}, {1, 1}, {0, 1}, {1, 0}));
  EXPECT_TRUE(segments_meet({0, 0}, {1, 0}, {1, 0}, {2, 1}));  // touching
  EXPECT_FALSE(segments_meet({0, 0}, {1, 0}, {0, 1}, {1, 1}));
  EXPECT_FALSE(self_crossing(square));
  const auto bow_tie = std::vector<Eigen::Vector2d>{{0, 0}, {1, 1}, {1, 0}, {0, 1}};
  EXPECT_TRUE(self_crossing(bow_tie));
}
