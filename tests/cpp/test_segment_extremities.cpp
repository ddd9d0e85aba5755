// Extremity segmentation by area stretch (features/segment_extremities,
// thesis 3.5.1) and the smaller-regions-merge-first pass (features/merge_regions).
#include <gtest/gtest.h>

#include <set>

#include "common/errors.h"
#include "features/merge_regions.h"
#include "features/peak_regions.h"
#include "features/segment_extremities.h"
#include "param/spherical/sphere_quality.h"
#include "test_meshes.h"

using namespace paramorph;
using namespace paramorph::features;

namespace {
/// Every face labelled in 0..R-1, region areas summing to the surface area,
/// adjacency pairs ordered, distinct, and each backed by a shared edge.
void expect_consistent(const TriMesh& mesh, const Segmentation& s) {
  ASSERT_EQ(Index(s.face_labels.size()), mesh.num_faces());
  EXPECT_EQ(s.face_labels.minCoeff(), 0);
  EXPECT_EQ(s.face_labels.maxCoeff(), s.regions() - 1);
  std::set<int> used(s.face_labels.data(), s.face_labels.data() + s.face_labels.size());
  EXPECT_EQ(Index(used.size()), s.regions());  // no empty region
  const double total = spherical::face_areas(mesh.V(), mesh.F()).sum();
  EXPECT_NEAR(s.area.sum(), total, 1e-9 * total);
  std::set<std::pair<Index, Index>> shared;
  const Csr& edge_faces = mesh.edge_faces();
  for (Index e = 0; e < edge_faces.rows(); ++e)
    if (edge_faces.size(e) == 2) {
      const Index a = s.face_labels[edge_faces.items[edge_faces.begin(e)]];
      const Index b = s.face_labels[edge_faces.items[edge_faces.begin(e) + 1]];
      if (a != b) shared.emplace(std::min(a, b), std::max(a, b));
    }
  const std::set<std::pair<Index, Index>> listed(s.adjacency.begin(), s.adjacency.end());
  EXPECT_EQ(listed, shared);
  for (std::size_t i = 1; i < s.adjacency.size(); ++i) EXPECT_LT(s.adjacency[i - 1], s.adjacency[i]);
}

/// An icosphere with `limbs` limbs pulled out along ±x and ±y (in that order).
std::pair<MatrixX3d, MatrixX3i> limbed_blob(int limbs, int levels = 4) {
  auto [V, F] = test_meshes::icosphere(levels);
  const Eigen::Vector3d dirs[4] = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}};
  for (Index v = 0; v < V.rows(); ++v) {
    const Eigen::Vector3d p = V.row(v).normalized();
    double pull = 0;
    for (int i = 0; i < limbs; ++i) pull = std::max(pull, std::max(0.0, p.dot(dirs[i]) - 0.85) / 0.15);
    V.row(v) = (p * (1.0 + 2.5 * pull)).transpose();
  }
  return {V, F};
}

Index region_at(const TriMesh& mesh, const Segmentation& s, Index vertex) {
  const Csr& corners = mesh.vertex_corners();
  return s.face_labels[corners.items[corners.begin(vertex)] / 3];
}

Index farthest_along(const MatrixX3d& V, const Eigen::Vector3d& d) {
  Index tip = 0;
  (V * d).maxCoeff(&tip);
  return tip;
}
}  // namespace

TEST(SegmentExtremities, GrowsTwoRegionsAcrossAStretchStep) {
  auto [V, F] = test_meshes::bumpy_grid(12);
  const TriMesh mesh(V, F);
  VectorXd stretch(V.rows());
  for (Index v = 0; v < V.rows(); ++v) stretch[v] = V(v, 0) > 0.5 ? 10.0 : 1.0;
  const Segmentation s = grow_stretch_regions(mesh, stretch, 0.5);
  expect_consistent(mesh, s);
  ASSERT_EQ(s.regions(), 2);
  EXPECT_GT(V(s.seeds[0], 0), 0.5);  // the higher stretch seeds first
  EXPECT_EQ(s.adjacency.size(), 1u);
  for (Index f = 0; f < mesh.num_faces(); ++f) {
    int high = 0;
    for (int k = 0; k < 3; ++k) high += V(F(f, k), 0) > 0.5;
    if (high == 3) {
      EXPECT_EQ(s.face_labels[f], 0) << f;
    }
    if (high == 0) {
      EXPECT_EQ(s.face_labels[f], 1) << f;
    }
  }
}

TEST(SegmentExtremities, EachLimbOfABlobIsItsOwnRegionAndTheBodyAnother) {
  for (int limbs : {1, 2, 4}) {
    auto [V, F] = limbed_blob(limbs);
    const Segmentation s = segment_extremities(V, F);
    const TriMesh mesh(V, F);
    expect_consistent(mesh, s);
    const Eigen::Vector3d dirs[4] = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}};
    std::set<Index> regions{region_at(mesh, s, farthest_along(V, {0, 0, 1}))};  // the body
    for (int i = 0; i < limbs; ++i) regions.insert(region_at(mesh, s, farthest_along(V, dirs[i])));
    EXPECT_EQ(Index(regions.size()), limbs + 1) << limbs << " limbs";
    EXPECT_EQ(s.regions(), limbs + 1) << limbs << " limbs";
  }
}

TEST(SegmentExtremities, AConvexBlobIsOneRegion) {
  auto [V, F] = test_meshes::lumpy_blob(3);
  const Segmentation s = segment_extremities(V, F);
  EXPECT_EQ(s.regions(), 1);
}

TEST(SegmentExtremities, BadInputRaisesTheMatchingError) {
  auto [V, F] = test_meshes::bumpy_grid(6);
  EXPECT_THROW(segment_extremities(V, F), NotClosedError);
  const TriMesh mesh(V, F);
  EXPECT_THROW(grow_stretch_regions(mesh, VectorXd::Ones(V.rows()), 0.0), InvalidInputError);
  EXPECT_THROW(grow_stretch_regions(mesh, VectorXd::Ones(V.rows()), 1.0, 1.5), InvalidInputError);
  VectorXd stretch = VectorXd::Ones(V.rows());
  stretch[3] = -1.0;
  EXPECT_THROW(grow_stretch_regions(mesh, stretch, 0.5), InvalidInputError);
  ExtremityOptions o;
  o.sphere = MatrixX3d::Zero(2, 3);
  EXPECT_THROW(segment_extremities(V, F, o), InvalidInputError);
}

TEST(MergeSmallRegions, SmallestGoesToTheNearestDescriptorFirst) {
  // Four strips across a grid; 1 is the smallest and nearer (descriptor) to
  // 2 than to 0. Merged into 0 it would make a region big enough to stay;
  // merged into 2, region 0 is left too small and follows it.
  auto [V, F] = test_meshes::bumpy_grid(12);
  const TriMesh mesh(V, F);
  Segmentation s;
  s.face_labels.resize(mesh.num_faces());
  const double x_min = V.col(0).minCoeff(), width = V.col(0).maxCoeff() - x_min;
  for (Index f = 0; f < mesh.num_faces(); ++f) {
    const double x = (V(F(f, 0), 0) + V(F(f, 1), 0) + V(F(f, 2), 0)) / 3.0;
    const double t = (x - x_min) / width;
    s.face_labels[f] = t < 0.17 ? 0 : t < 0.25 ? 1 : t < 0.7 ? 2 : 3;
  }
  s.seeds = {0, 1, 2, 3};
  summarise_regions(mesh, s);
  const double total = s.area.sum();
  ASSERT_LT(s.area[1], s.area[0]);
  ASSERT_LT(s.area[0], 0.2 * total);
  ASSERT_GE(s.area[0] + s.area[1], 0.2 * total);
  Eigen::MatrixXd descriptor(4, 1);
  descriptor << 0.0, 5.0, 4.0, 10.0;
  const VectorXi before = s.face_labels;
  merge_small_regions(mesh, s, descriptor, 0.2 * total);
  expect_consistent(mesh, s);
  ASSERT_EQ(s.regions(), 2);
  for (Index f = 0; f < mesh.num_faces(); ++f)
    EXPECT_EQ(s.face_labels[f], before[f] == 3 ? 1 : 0) << f;
  EXPECT_EQ(s.seeds[0], 2);  // the absorbing region keeps its seed
  EXPECT_EQ(s.seeds[1], 3);
  EXPECT_THROW(merge_small_regions(mesh, s, Eigen::MatrixXd::Zero(5, 1), 1.0), InvalidInputError);
}

TEST(PeakRegions, TwoFingersAPalmAndTheBaseEachConnected) {
  // Along x: base ~0 at both ends, two peaks of 4 joined by a saddle at 2.28.
  auto [V, F] = test_meshes::bumpy_grid(40);
  const TriMesh mesh(V, F);
  VectorXd level(V.rows());
  for (Index v = 0; v < V.rows(); ++v) {
    const double x = V(v, 0);
    level[v] = std::max(4.0 * std::exp(-std::pow((x - 0.35) / 0.2, 2)),
                        4.0 * std::exp(-std::pow((x - 0.65) / 0.2, 2)));
  }
  Segmentation s = peak_regions(mesh, level, 0.0, 1.0);
  expect_consistent(mesh, s);
  // The saddle line itself makes slivers of a few faces; merged away here.
  Eigen::MatrixXd face_level(mesh.num_faces(), 1);
  for (Index f = 0; f < mesh.num_faces(); ++f)
    face_level(f, 0) = (level[F(f, 0)] + level[F(f, 1)] + level[F(f, 2)]) / 3.0;
  merge_small_regions(mesh, s, region_means(mesh, s, face_level), 0.01 * s.area.sum());
  expect_consistent(mesh, s);
  auto region_near = [&](double x) {
    Index best = 0;
    (V.col(0).array() - x).abs().minCoeff(&best);
    return region_at(mesh, s, best);
  };
  const Index finger_a = region_near(0.35), finger_b = region_near(0.65);
  EXPECT_NE(finger_a, finger_b);
  // Each finger reaches down to the saddle (x = 0.5) on its inner side only.
  EXPECT_NE(region_near(0.16), finger_a);
  EXPECT_NE(region_near(0.84), finger_b);
  // The flanks below the saddle on both sides and the two base strips: every
  // region is one connected piece, so 2 fingers + 2 flanks + 2 base strips.
  EXPECT_NE(region_near(0.1), region_near(0.9));
  EXPECT_NE(region_near(0.0), region_near(1.0));
  EXPECT_NE(region_near(0.16), region_near(0.84));
  EXPECT_EQ(s.regions(), 6);
  for (Index r = 0; r < s.regions(); ++r) {
    int seed_faces = 0;
    const Csr& corners = mesh.vertex_corners();
    for (Index k = corners.begin(s.seeds[r]); k < corners.end(s.seeds[r]); ++k)
      seed_faces += s.face_labels[corners.items[k] / 3] == r;
    EXPECT_GT(seed_faces, 0) << "region " << r << " does not touch its seed";
  }
}
