// Feature regions (features/feature_regions) and feature points
// (features/feature_points), thesis 4.5, Defs. 4.1 and 4.2.
#include <gtest/gtest.h>

#include <set>

#include "common/errors.h"
#include "features/concavity.h"
#include "features/feature_points.h"
#include "features/feature_regions.h"
#include "test_meshes.h"

using namespace paramorph;
using namespace paramorph::features;

namespace {

/// The icosphere blown onto the cube [-1, 1]^3 (x / max|x|): six flat sides
/// meeting at 90 degree creases.
std::pair<MatrixX3d, MatrixX3i> cube_from_sphere(int levels) {
  auto [V, F] = test_meshes::icosphere(levels);
  for (Index v = 0; v < V.rows(); ++v) V.row(v) /= V.row(v).cwiseAbs().maxCoeff();
  return {V, F};
}

/// The unit icosphere with a smooth dimple of the given depth around +z.
std::pair<MatrixX3d, MatrixX3i> dimpled_sphere(double depth) {
  auto [V, F] = test_meshes::icosphere(4);
  for (Index v = 0; v < V.rows(); ++v) {
    const double t = std::max(0.0, (V(v, 2) - 0.8) / 0.2);  // 0 at the rim, 1 at the pole
    V.row(v) *= 1.0 - depth * t * t * (3 - 2 * t);
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
  auto [V, F] = cube_from_sphere(4);
  const Segmentation s = feature_regions(V, F);
  EXPECT_EQ(s.regions(), 6);
  std::set<Index> sides;
  for (int axis = 0; axis < 3; ++axis)
    for (double sign : {-1.0, 1.0}) {
      Eigen::Vector3d d = Eigen::Vector3d::Zero();
      d[axis] = sign;
      // The side's centre: the vertex farthest along d among those near the axis.
      sides.insert(region_of_vertex(F, s, farthest_along(V, d + 0.01 * Eigen::Vector3d(1, 2, 3))));
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
  const Index bottom = farthest_along(V, {0, 0, 1});  // the pole moved in; still the top-most vertex
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
  FeatureRegionOptions o;
  o.normal_angle = 0.0;
  EXPECT_THROW(feature_regions(V, F, o), InvalidInputError);
  o = {};
  o.concavity = VectorXd::Zero(3);
  EXPECT_THROW(feature_regions(V, F, o), InvalidInputError);
  MatrixX3i degenerate = F;
  degenerate(5, 1) = degenerate(5, 0);
  EXPECT_THROW(feature_regions(V, degenerate), DegenerateFaceError);
  EXPECT_THROW(feature_points(V, F, VectorXi::Zero(2), VectorXd::Zero(V.rows())), InvalidInputError);
}
