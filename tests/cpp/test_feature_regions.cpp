// Feature regions (features/feature_regions) and feature points
// (features/feature_points), thesis 4.5, Defs. 4.1 and 4.2.
#include <gtest/gtest.h>

#include <array>
#include <map>
#include <set>

#include <Eigen/Geometry>

#include "common/errors.h"
#include "features/concavity.h"
#include "features/feature_points.h"
#include "features/feature_regions.h"
#include "test_meshes.h"

using namespace paramorph;
using namespace paramorph::features;

namespace {

/// The cube [-1, 1]^3, each side an n by n grid of squares split into two
/// triangles, sides sharing their edge vertices: 90 degree creases on edges.
std::pair<MatrixX3d, MatrixX3i> grid_cube(int n) {
  std::map<std::array<long, 3>, Index> index;
  std::vector<Eigen::Vector3d> points;
  std::vector<Eigen::Vector3i> faces;
  auto vertex = [&](const Eigen::Vector3d& p) {
    const std::array<long, 3> key{std::lround(p.x() * n), std::lround(p.y() * n), std::lround(p.z() * n)};
    auto [it, added] = index.emplace(key, Index(points.size()));
    if (added) points.push_back(p);
    return it->second;
  };
  for (int axis = 0; axis < 3; ++axis)
    for (double sign : {-1.0, 1.0}) {
      Eigen::Vector3d normal = Eigen::Vector3d::Zero(), u = Eigen::Vector3d::Zero();
      normal[axis] = sign;
      u[(axis + 1) % 3] = 1.0;
      const Eigen::Vector3d v = normal.cross(u);  // u x v = normal: counter-clockwise outside
      for (int i = 0; i < n; ++i)
        for (int j = 0; j < n; ++j) {
          auto at = [&](int a, int b) {
            return vertex(normal + (2.0 * a / n - 1) * u + (2.0 * b / n - 1) * v);
          };
          const Index p00 = at(i, j), p10 = at(i + 1, j), p11 = at(i + 1, j + 1), p01 = at(i, j + 1);
          faces.push_back({p00, p10, p11});
          faces.push_back({p00, p11, p01});
        }
    }
  MatrixX3d V(points.size(), 3);
  MatrixX3i F(faces.size(), 3);
  for (std::size_t i = 0; i < points.size(); ++i) V.row(i) = points[i].transpose();
  for (std::size_t i = 0; i < faces.size(); ++i) F.row(i) = faces[i].transpose().cast<Index>();
  return {V, F};
}

/// The unit icosphere with a conical pit of the given depth pushed down (-z)
/// around the +z pole, deepest at the pole.
std::pair<MatrixX3d, MatrixX3i> dimpled_sphere(double depth) {
  auto [V, F] = test_meshes::icosphere(4);
  for (Index v = 0; v < V.rows(); ++v) {
    const double t = std::max(0.0, (V(v, 2) - 0.8) / 0.2);  // 0 at the rim, 1 at the pole
    V(v, 2) -= depth * t;
  }
  return {V, F};
}

Index region_of_vertex(const MatrixX3i& F, const Segmentation& s, Index v) {
  for (Index f = 0; f < F.rows(); ++f)
    for (int k = 0; k < 3; ++k)
      if (F(f, k) == v) return s.face_labels[f];
  return -1;
}

Index farthest_along(const MatrixX3d& V, const Eigen::Vector3d& d) {
  Index i = 0;
  (V * d).maxCoeff(&i);
  return i;
}

}  // namespace

TEST(FeatureRegions, TheSixSidesOfACubeAreSixRegions) {
  auto [V, F] = grid_cube(8);
  const Segmentation s = feature_regions(V, F);
  EXPECT_EQ(s.regions(), 6);
  std::set<Index> sides;
  for (int axis = 0; axis < 3; ++axis)
    for (double sign : {-1.0, 1.0}) {
      Eigen::Vector3d d = Eigen::Vector3d::Zero();
      d[axis] = sign;
      Index centre = 0;  // of the side facing d
      (V.rowwise() - d.transpose()).rowwise().norm().minCoeff(&centre);
      sides.insert(region_of_vertex(F, s, centre));
    }
  EXPECT_EQ(sides.size(), 6u);
  for (Index r = 0; r < s.regions(); ++r) EXPECT_NEAR(s.area[r], 4.0, 0.4) << r;
}

TEST(FeatureRegions, ADimpleIsAPocketRegionWithAConcavePointAtItsBottom) {
  auto [V, F] = dimpled_sphere(0.3);
  const VectorXd intensity = concavity(V, F);
  FeatureRegionOptions o;
  o.concavity = intensity;
  const Segmentation s = feature_regions(V, F, o);
  ASSERT_EQ(s.regions(), 2);
  Index bottom = 0;  // the pole, moved in to z = 0.7
  (V.rowwise() - Eigen::RowVector3d(0, 0, 0.7)).rowwise().norm().minCoeff(&bottom);
  const Index pocket = region_of_vertex(F, s, bottom);
  EXPECT_NE(pocket, region_of_vertex(F, s, farthest_along(V, {0, 0, -1})));
  EXPECT_LT(s.area[pocket], 0.2 * s.area.sum());

  const FeaturePoints points = feature_points(V, F, s.face_labels, intensity);
  int concave = 0;
  for (std::size_t i = 0; i < points.vertices.size(); ++i) {
    EXPECT_EQ(points.regions[i], region_of_vertex(F, s, points.vertices[i]));
    if (points.kinds[i] > 0) {
      ++concave;
      EXPECT_EQ(points.vertices[i], bottom);
      EXPECT_EQ(points.regions[i], pocket);
    }
  }
  EXPECT_EQ(concave, 1);
}

TEST(FeatureRegions, ShallowDimpleBelowTheThresholdIsNoRegion) {
  auto [V, F] = dimpled_sphere(0.01);
  EXPECT_EQ(feature_regions(V, F).regions(), 1);
}

TEST(FeaturePoints, ConvexTipsOfAnOctahedronLikeBlobArePoints) {
  // A sphere pulled into six cones along the axes: the six tips are hull
  // vertices farther out than every hull neighbour.
  auto [V, F] = test_meshes::icosphere(3);
  for (Index v = 0; v < V.rows(); ++v) {
    const double peak = V.row(v).cwiseAbs().maxCoeff();
    V.row(v) *= 1.0 + 0.8 * std::pow(peak, 8);
  }
  const VectorXi one_region = VectorXi::Zero(F.rows());
  const FeaturePoints points = feature_points(V, F, one_region, concavity(V, F));
  std::vector<Index> convex;
  for (std::size_t i = 0; i < points.vertices.size(); ++i)
    if (points.kinds[i] < 0) convex.push_back(points.vertices[i]);
  ASSERT_GE(convex.size(), 6u);
  // The six most extreme convex points come first, and they are the tips.
  const std::set<Index> tips(convex.begin(), convex.begin() + 6);
  for (int axis = 0; axis < 3; ++axis)
    for (double sign : {-1.0, 1.0}) {
      Eigen::Vector3d d = Eigen::Vector3d::Zero();
      d[axis] = sign;
      EXPECT_TRUE(tips.count(farthest_along(V, d))) << "tip along axis " << axis << " sign " << sign;
    }
}

TEST(FeatureRegions, BadInputRaisesTheMatchingError) {
  auto [V, F] = dimpled_sphere(0.3);
  FeatureRegionOptions flat_angle;
  flat_angle.normal_angle = 0.0;
  EXPECT_THROW(feature_regions(V, F, flat_angle), InvalidInputError);
  FeatureRegionOptions short_concavity;
  short_concavity.concavity = VectorXd::Zero(3);
  EXPECT_THROW(feature_regions(V, F, short_concavity), InvalidInputError);
  MatrixX3i degenerate = F;
  degenerate(5, 1) = degenerate(5, 0);
  EXPECT_THROW(feature_regions(V, degenerate), DegenerateFaceError);
  EXPECT_THROW(feature_points(V, F, VectorXi::Zero(2), VectorXd::Zero(V.rows())), InvalidInputError);
}
