// extract_feature (paste/extract_feature.h, thesis 5.2): selection errors are
// typed, the base of a bump on a plane is the plane, both maps are fold-free
// with one shared boundary, and the grid rebuilds the feature.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numeric>

#include "common/errors.h"
#include "param/planar/untangle.h"
#include "paste/extract_feature.h"
#include "paste/sample_feature.h"
#include "test_meshes.h"

using namespace paramorph;
using namespace paramorph::paste;

namespace {

constexpr double kH = 0.1, kS = 0.3, kR = 0.9;

const test_meshes::BumpGrid& bump() {
  static const test_meshes::BumpGrid g = test_meshes::gaussian_bump_grid(30, kH, kS, kR);
  return g;
}

ExtractFeatureOptions cpu(int resolution) {
  ExtractFeatureOptions o;
  o.resolution = resolution;
  o.backend = compute::Backend::Cpu;
  return o;
}

}  // namespace

TEST(ExtractFeature, SelectionErrorsAreTyped) {
  const auto& g = bump();
  EXPECT_THROW(extract_feature(g.V, g.F, {}), EmptySelectionError);
  std::vector<Index> all(g.F.rows());
  std::iota(all.begin(), all.end(), 0);
  EXPECT_THROW(extract_feature(g.V, g.F, all), WholeMeshSelectedError);
  std::vector<Index> repeated = g.feature;
  repeated.push_back(g.feature.front());
  EXPECT_THROW(extract_feature(g.V, g.F, repeated), InvalidInputError);
  std::vector<Index> out_of_range = g.feature;
  out_of_range.push_back(Index(g.F.rows()));
  EXPECT_THROW(extract_feature(g.V, g.F, out_of_range), InvalidInputError);
  // Two faces far apart: not connected.
  try {
    extract_feature(g.V, g.F, {0, Index(g.F.rows()) - 1});
    FAIL() << "two pieces accepted";
  } catch (const SelectionTopologyError& e) {
    EXPECT_NE(std::string(e.what()).find("is not connected"), std::string::npos) << e.what();
  }
  // The bump minus one interior face: an annulus is fine, minus two apart: 3 loops.
  auto nearest = [&](double x, double y) {  // the feature face whose centroid is nearest (x, y)
    Index best = -1;
    double best_d = 1e300;
    for (Index f : g.feature) {
      const Eigen::RowVector3d c = (g.V.row(g.F(f, 0)) + g.V.row(g.F(f, 1)) + g.V.row(g.F(f, 2))) / 3.0;
      const double d = std::hypot(c.x() - x, c.y() - y);
      if (d < best_d) best_d = d, best = f;
    }
    return best;
  };
  const Index hole_a = nearest(-0.3, 0.0), hole_b = nearest(0.3, 0.0);
  std::vector<Index> holed;
  for (Index f : g.feature)
    if (f != hole_a && f != hole_b) holed.push_back(f);
  try {
    extract_feature(g.V, g.F, holed);
    FAIL() << "three loops accepted";
  } catch (const SelectionTopologyError& e) {
    EXPECT_NE(std::string(e.what()).find("has 3 boundary loops"), std::string::npos) << e.what();
  }
}

TEST(ExtractFeature, PlaneBumpBaseMapsAndRebuild) {
  const auto& g = bump();
  const Feature f = extract_feature(g.V, g.F, g.feature, cpu(48));
  ASSERT_EQ(f.boundary_loops.size(), 1u);
  EXPECT_TRUE(planar::folded_faces(f.F, f.uv).empty());
  EXPECT_TRUE(planar::folded_faces(f.F, f.base_uv).empty());
  for (Index v : f.boundary_loops[0]) EXPECT_EQ(f.uv.row(v), f.base_uv.row(v));
  // Base on the plane z = 0, n = +z; stored positions are the source's.
  EXPECT_GT(f.axes(2, 2), 1 - 1e-9);
  // (The bump's tail at the rim, ~1e-4 h with its slope, is continued by the
  // thin-plate fill: the base leaves the plane by ~2e-3 h.)
  double base_z = 0, stored = 0;
  for (Index i = 0; i < Index(f.V.rows()); ++i) {
    const Eigen::Vector3d base = f.origin + f.axes * f.base_V.row(i).transpose();
    base_z = std::max(base_z, std::abs(base.z()));
    const Eigen::Vector3d x = f.origin + f.axes * f.V.row(i).transpose();
    stored = std::max(stored, (x - g.V.row(f.source_vertices[i]).transpose()).norm());
  }
  EXPECT_LT(base_z, 5e-3 * kH);
  EXPECT_LT(stored, 1e-12);
  // The normal displacement at inside nodes is the bump's height where the
  // feature point lies (mesh interpolation error: 3% of h on this coarse grid).
  MatrixX2d nodes(f.displacement.rows(), 2);
  for (int i = 0; i < f.resolution; ++i)
    for (int j = 0; j < f.resolution; ++j)
      nodes.row(i * f.resolution + j) = f.grid_origin.transpose() + f.grid_spacing * Eigen::RowVector2d(j, i);
  const FeatureSample s = sample_feature(f, nodes);
  int inside = 0;
  double worst_normal = 0, worst_node = 0;
  for (Index q = 0; q < Index(nodes.rows()); ++q) {
    if (!f.mask[q]) continue;
    ++inside;
    const Eigen::Vector3d p = f.origin + f.axes * s.position.row(q).transpose();
    const double r = std::hypot(p.x(), p.y());
    worst_normal = std::max(worst_normal, std::abs(f.displacement(q, 2) - kH * std::exp(-r * r / (kS * kS))));
    worst_node = std::max(worst_node, (s.displacement.row(q) - f.displacement.row(q)).norm());
  }
  EXPECT_LT(worst_normal, 0.03 * kH);
  EXPECT_LT(worst_node, 1e-12);
  EXPECT_GT(inside, f.resolution * f.resolution / 2);
  // Rebuild at the feature's own vertices through the bilinear grid.
  const FeatureSample at_vertices = sample_feature(f, f.uv);
  EXPECT_LT((at_vertices.position - f.V).rowwise().norm().maxCoeff(), 0.05 * kH);
}
